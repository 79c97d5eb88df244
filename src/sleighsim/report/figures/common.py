"""What every figure shares: the style that keeps it legible in the report, axis labels with
units, the provenance footer, layout, atomic saving (PDFs with TrueType fonts and their dense point
clouds and curves rasterised, :data:`DENSE`), and the legibility rule the tests check."""

from __future__ import annotations

import re
import textwrap
import warnings
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.text import Text  # noqa: E402
from matplotlib.ticker import (  # noqa: E402
    AutoLocator,
    FuncFormatter,
    LogLocator,
    MaxNLocator,
    NullFormatter,
    ScalarFormatter,
)

from sleighsim.io.netcdf import atomic_path  # noqa: E402
from sleighsim.precision import Precision  # noqa: E402

#: The report shows a PNG at most 1100 px wide: a figure at most WIDTH inches wide is shown at 100 px
#: per inch or more, so no text under MIN_PT points renders under 11 px.
WIDTH, MIN_PT, DPI = 11.0, 8.0, 150

plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "axes.labelsize": 9, "xtick.labelsize": 8,
                     "ytick.labelsize": 8, "legend.fontsize": 8, "legend.title_fontsize": 8,
                     "figure.titlesize": 10, "axes.formatter.useoffset": False,
                     # TrueType (Type 42) fonts in PDF and PostScript: journals refuse Type 3 fonts
                     "pdf.fonttype": 42, "ps.fonttype": 42})
#: A point cloud (collection) with more points than DENSE, or a curve with more than DENSE_LINE, is
#: rasterised in the PDF (at PDF_DPI), the axes, text and sparse artists staying vector: a point cloud of
#: 1e5 points takes kilobytes, not megabytes.
DENSE, DENSE_LINE, PDF_DPI = 5000, 50000, 200
#: The most lines a title may take.
TITLE_LINES = 2

#: The model is nondimensional: lengths, times and angles in the flow's own units.
UNITS = {"u": "length/time unit", "Omega": "rad/time unit", "omega": "rad/time unit", "theta": "rad",
         "delta": "rad", "x": "length units", "y": "length units", "t": "time units"}
SYMBOLS = {"u": "u", "Omega": r"\Omega", "omega": r"\omega", "theta": r"\theta", "delta": r"\delta", "x": "x",
           "y": "y", "t": "t"}
LABELS = {name: f"${SYMBOLS[name]}$ ({unit})" for name, unit in UNITS.items()}
RATE = "1/time unit"
FREQUENCY = "cycles per time unit"


def subplots(width: float, height: float, *args, **kwargs):
    """``plt.subplots`` with constrained layout (no title collides with its neighbour)."""
    return plt.subplots(*args, figsize=(width, height), layout="constrained", **kwargs)


def rasterise_dense(fig) -> int:
    """Mark every collection of ``fig`` holding more than DENSE points and every line of more than
    DENSE_LINE as rasterised (in a vector format it is then drawn as an image); returns how many."""
    n = 0
    for ax in fig.axes:
        dense = [a for a in ax.lines if len(a.get_xdata()) > DENSE_LINE]
        for artist in dense + [a for a in ax.collections if len(a.get_offsets()) > DENSE]:
            with warnings.catch_warnings():  # a 3-D collection warns, and its axes rasterises it all the same
                warnings.filterwarnings("ignore", "Rasterization of", UserWarning)
                artist.set_rasterized(True)
            n += 1
    return n


def save_figure(fig, *paths, dpi: int = DPI) -> None:
    """Save to every path atomically (the format from its suffix; a PDF with its dense artists
    rasterised at PDF_DPI, :func:`rasterise_dense`), then close."""
    for path in map(Path, paths):
        vector = path.suffix in (".pdf", ".svg", ".eps")
        if vector:
            rasterise_dense(fig)
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=PDF_DPI if vector else dpi, format=path.suffix[1:])
    plt.close(fig)


def provenance(attrs: dict) -> str:
    """Parameters, integrator, tolerance, energy drift, commit."""
    parts = []
    if "param_eps" in attrs:
        parts.append(f"eps={attrs['param_eps']:.4g}, b={attrs['param_b']:.4g}, K2={attrs['param_K2']:.4g}")
    if "energy_label" in attrs:
        physical = f" (physical {attrs['energy_physical']:.4g})" if "energy_physical" in attrs else ""
        parts.append(f"E label={attrs['energy_label']:.4g}{physical}")
    if attrs.get("backend") == "heyoka":
        parts.append(f"heyoka tol={attrs['tol']:.2g}")
    elif "backend" in attrs:
        parts.append(f"{attrs['method']} rtol={attrs['rtol']:.2g}")
    if "energy_max_rel_drift" in attrs and np.isfinite(attrs["energy_max_rel_drift"]):
        parts.append(f"max |dE/E|={attrs['energy_max_rel_drift']:.2g}")
    if "git_commit" in attrs:
        parts.append(f"commit {str(attrs['git_commit'])[:12]}")
    return "; ".join(parts)


def plain_log_ticks(axis) -> None:
    """On a log axis spanning less than two decades (where matplotlib labels minor ticks, which then
    overlap): ticks at 1, 2, 5 x 10^k (every mantissa within one decade), labelled plainly."""
    lo, hi = sorted(axis.get_view_interval())
    if axis.get_scale() != "log" or not isinstance(axis.get_major_locator(), LogLocator) or not 0 < lo < hi < 100 * lo:
        return
    axis.set_major_locator(LogLocator(subs=(1, 2, 5) if hi >= 10 * lo else range(1, 10)))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def thin_ticks(fig) -> None:
    """Fewer ticks on every axis of ``fig`` whose tick labels overlap once drawn: down to 2 on a linear axis,
    to 1, 2, 5 and then 1 times the powers of ten on a log axis."""
    fig.canvas.draw()
    for ax in fig.axes:
        if ax.name == "3d" or not ax.get_visible():
            continue
        for axis in (ax.xaxis, ax.yaxis):
            fewer = ([LogLocator(subs=(1, 2, 5)), LogLocator(subs=(1,))] if axis.get_scale() == "log"
                     else [MaxNLocator(n) for n in (5, 4, 3, 2)])
            linear = isinstance(axis.get_major_locator(), (AutoLocator, MaxNLocator))
            while fewer and (linear or axis.get_scale() == "log") and _overlapping_ticks(ax, axis):
                axis.set_major_locator(fewer.pop(0))
                fig.canvas.draw()


def finish(fig, attrs: dict):
    """Plain ticks on short log axes, the provenance footer (wrapped to the figure's width) below the
    constrained layout, fewer ticks where their labels overlap (:func:`thin_ticks`); returns ``fig``."""
    for ax in fig.axes:
        if ax.name != "3d":
            plain_log_ticks(ax.xaxis)
            plain_log_ticks(ax.yaxis)
    lines = textwrap.wrap(provenance(attrs), int(fig.get_figwidth() * 72 / (0.6 * MIN_PT)))
    fig.text(0.01, 0.005, "\n".join(lines), fontsize=MIN_PT, color="0.4", ha="left", va="bottom")
    bottom = (1.3 * MIN_PT * len(lines) + 4) / (72 * fig.get_figheight())
    fig.get_layout_engine().set(rect=(0, bottom, 1, 1 - bottom))  # (left, bottom, width, height)
    thin_ticks(fig)
    return fig


#: One colour per arithmetic, in every figure.
ARITHMETIC_COLOUR = {Precision.DOUBLE: "tab:blue", Precision.LONG_DOUBLE: "tab:red",
                     Precision.DOUBLE_DOUBLE: "tab:green", Precision.QUAD: "black"}
#: Line styles of the precisions drawn beside double (the paper's arithmetic): their colour, the finer
#: ones a little transparent.
PRECISION_STYLE = {p: {"color": c} | ({} if p is Precision.DOUBLE else {"alpha": 0.7 if p is Precision.LONG_DOUBLE
                                                                              else 0.6})
                   for p, c in ARITHMETIC_COLOUR.items()}


def finer_precisions(datasets: list) -> dict:
    """{(scene, precision): dataset} of the datasets computed in a precision finer than double
    (a figure drawn beside its finer precisions receives them after its own datasets)."""
    return {(d.attrs["scene"], d.attrs["precision"]): d for d in datasets
            if d.attrs.get("precision", Precision.DOUBLE) != Precision.DOUBLE}


#: A numpy array or scalar printed as is: "[0.02 -0.01]", "array(", "np.float64(".
NUMPY_REPR = re.compile(r"array\(|np\.\w+\(|\[\s*[-+]?\d[\d.eE+-]*(?:\s+[-+]?\d[\d.eE+-]*)+\s*\]")
HAS_UNITS = re.compile(r"\(.+\)|unitless")


def _overlapping_ticks(ax, axis) -> bool:
    """Do two tick labels of ``axis`` (of a 2-D axes, after a draw) shown inside the axes overlap?"""
    box, horizontal = ax.get_window_extent(), axis is ax.xaxis
    lo, hi = (box.x0, box.x1) if horizontal else (box.y0, box.y1)
    shown = []
    for t in axis.get_majorticklabels() + axis.get_minorticklabels():
        b = t.get_window_extent()
        if t.get_text().strip() and lo - 1 <= ((b.x0 + b.x1) if horizontal else (b.y0 + b.y1)) / 2 <= hi + 1:
            shown.append(b)
    return any(a.overlaps(b) for i, a in enumerate(shown) for b in shown[i + 1:])


def _axes_problems(ax) -> list[str]:
    """Axis labels without units, axes with an additive offset, overlapping tick labels (after a draw)."""
    out = []
    for axis in (ax.xaxis, ax.yaxis, getattr(ax, "zaxis", None)):
        if axis is None or not axis.get_visible():
            continue
        label = axis.get_label_text()
        if label.strip() and not HAS_UNITS.search(label):
            out.append(f"axis label without units: {label!r}")
        fmt = axis.get_major_formatter()
        if isinstance(fmt, ScalarFormatter) and fmt.offset != 0:
            out.append(f"offset {fmt.offset:g} on the axis {label!r}")
        if ax.name != "3d" and _overlapping_ticks(ax, axis):
            out.append(f"overlapping tick labels on the axis {label!r}")
    return out


#: A number printed as NaN.
NAN_TEXT = re.compile(r"(?<![\w.])nan(?!\w)", re.IGNORECASE)


def _titles(fig) -> list[Text]:
    """Every title of ``fig``: its suptitle and each axes' three titles."""
    out = [fig._suptitle] if fig._suptitle is not None else []
    return out + [t for ax in fig.axes for t in (ax.title, ax._left_title, ax._right_title)]


def _covered(ax) -> list[str]:
    """The insets of ``ax`` (its child axes) that lie over its data: a point of its lines or collections
    inside an inset's box (after a draw)."""
    out = []
    for inset in ax.child_axes:
        box = inset.get_window_extent()
        points = [a.get_transform().transform(a.get_xydata()) for a in ax.lines if len(a.get_xdata())]
        points += [a.get_offset_transform().transform(a.get_offsets()) for a in ax.collections
                   if len(a.get_offsets())]
        if any(((p[:, 0] >= box.x0) & (p[:, 0] <= box.x1) & (p[:, 1] >= box.y0) & (p[:, 1] <= box.y1)).any()
               for p in points):
            out.append(f"an inset over the data of the axes {ax.get_title(loc='left') or ax.get_title()!r}")
    return out


def _inside(fig, text: Text) -> bool:
    """Whether ``text`` (drawn) lies within the figure (a pixel of slack)."""
    box, page = text.get_window_extent(), fig.bbox
    return box.x0 >= page.x0 - 1 and box.x1 <= page.x1 + 1 and box.y0 >= page.y0 - 1 and box.y1 <= page.y1 + 1


def _empty(ax) -> bool:
    """Whether the visible axes ``ax`` shows its frame and no data (an empty panel): no line, patch or point
    cloud in data coordinates holding a point (a reference line such as axhline does not count), no image,
    no table."""
    drawn = [a for a in (*ax.lines, *ax.patches)  # a patch's own transform holds its shape: ask its data's
             if getattr(a, "get_data_transform", a.get_transform)() == ax.transData
             and (len(a.get_xdata()) if hasattr(a, "get_xdata") else True)]
    clouds = [c for c in ax.collections if len(c.get_offsets()) or len(c.get_paths())]
    return ax.get_visible() and ax.axison and not (drawn or clouds or ax.images or ax.tables)


def legibility(fig) -> list[str]:
    """What breaks the report's rule in ``fig`` (drawn first): wider than WIDTH, a text under MIN_PT,
    a numpy repr or a NaN in a text, a title of more than TITLE_LINES lines, an empty panel, an inset
    over the data, an axis label without units in parentheses, an additive axis offset, overlapping tick
    labels."""
    fig.canvas.draw()
    out = [f"{fig.get_figwidth():g} in wide (at most {WIDTH:g})"] if fig.get_figwidth() > WIDTH else []
    texts = [t for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]
    texts += [c.get_text() for ax in fig.axes for table in ax.tables for c in table.get_celld().values()]
    for t in texts:
        if t.get_fontsize() < MIN_PT:
            out.append(f"{t.get_fontsize():.3g} pt: {t.get_text()!r}")
        if NUMPY_REPR.search(t.get_text()):
            out.append(f"numpy repr: {t.get_text()!r}")
        if NAN_TEXT.search(t.get_text()):
            out.append(f"NaN in a text: {t.get_text()!r}")
    out += [f"a title of {t.get_text().count(chr(10)) + 1} lines: {t.get_text()!r}" for t in _titles(fig)
            if t.get_text().count("\n") >= TITLE_LINES]
    words = [*_titles(fig), *fig.texts, *(t for ax in fig.axes for t in (*ax.texts, ax.xaxis.label, ax.yaxis.label))]
    out += [f"a text cut at the figure's edge: {t.get_text()!r}" for t in words
            if t.get_visible() and t.get_text().strip() and not _inside(fig, t)]
    out += [f"an empty panel: {ax.get_title(loc='left') or ax.get_title()!r}" for ax in fig.axes if _empty(ax)]
    out += [p for ax in fig.axes if ax.name != "3d" for p in _covered(ax)]
    return out + [p for ax in fig.axes if ax.get_visible() and ax.axison for p in _axes_problems(ax)]
