"""Figures of the steady state: Poincare maps on the attractor (F9), return times (F12), power spectra (F13, F14)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import colors
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator

from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import (
    FREQUENCY,
    LABELS,
    PRECISION_STYLE,
    SYMBOLS,
    UNITS,
    WIDTH,
    finer_precisions,
    finish,
    subplots,
)
from sleighsim.report.figures.figure import Figure


def _attractor_panel(ax, ds, title, iterates="ppi2"):
    """The attractor (grey) and the section's iterates, as one point cloud (one image in a PDF, where
    it is rasterised), the iterates coloured by class (P_pi/2) or by time (P_2pi)."""
    xyz = [np.concatenate([ds[f"attractor_{v}"].values, ds[f"{iterates}_{v}"].values]) for v in ("u", "Omega", "omega")]
    n = ds.attractor_u.size
    grey = np.tile(colors.to_rgba("0.7", 0.3), (n, 1))
    if iterates == "ppi2":
        cls = ds.ppi2_class.values.astype(int)
        own = np.array([colors.to_rgba(f"C{k}") for k in range(4)])[cls]
    else:
        t = ds.p2pi_time.values
        own = plt.get_cmap("viridis")((t - t.min()) / max(np.ptp(t), 1e-300))
    sizes = np.concatenate([np.full(n, 0.2), np.full(len(own), 2.0 if iterates == "ppi2" else 1.5)])
    ax.scatter(*xyz, s=sizes, c=np.vstack([grey, own]), depthshade=False)
    for axis, name in ((ax.xaxis, "u"), (ax.yaxis, "Omega"), (ax.zaxis, "omega")):
        axis.set_label_text(LABELS[name])
        axis.set_major_locator(MaxNLocator(4))
    ax.set_title(title)
    if not ds.attrs["transient_over"]:  # inside the panel: the title keeps its two lines
        ax.text2D(0.5, 0.98, "TRANSIENT NOT SHOWN OVER", transform=ax.transAxes, ha="center", va="top", color="r")


def fig9(sources):
    """(a) P_2pi iterates; (b) P_pi/2 iterates on the attractor; (c) higher energy; (d) eps = 0.01.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ref, high, small, scaling = (read_dataset(s) for s in sources)
    fig = plt.figure(figsize=(WIDTH, 10.5), layout="constrained")
    panels = [
        (ref, "p2pi", f"(a) $P_{{2\\pi}}$: {ref.attrs['n_p2pi']} iterates (colour: time)\n"
                      f"rotation number {ref.attrs['rotation_number']:.5g} turns/iterate"),
        (ref, "ppi2", f"(b) $P_{{\\pi/2}}$ on the attractor, E label {ref.attrs['energy_label']:.4g}: "
                      f"{ref.attrs['n_loops']} loops"),
        (high, "ppi2", f"(c) E label {high.attrs['energy_label']:.4g}, $\\epsilon$ = {high.attrs['param_eps']:.3g}: "
                       f"{high.attrs['n_loops']} loops; divided by c = {scaling.attrs['scale_factor_c']:.4g},\n"
                       f"median distance to (b) {scaling.attrs['distance_scaled_median']:.2g} of its size "
                       f"(unscaled {scaling.attrs['distance_unscaled_median']:.2g})"),
        (small, "ppi2", f"(d) $\\epsilon$ = {small.attrs['param_eps']:.3g}, E label {small.attrs['energy_label']:.4g}: "
                        f"{small.attrs['n_loops']} loops"),
    ]
    for i, (ds, kind, title) in enumerate(panels):
        ax = fig.add_subplot(2, 2, i + 1, projection="3d")
        _attractor_panel(ax, ds, title, kind)
    # the classes of (b)-(d) named once, above the panels (inside one it covered its data and its red mark)
    fig.legend(handles=[Line2D([], [], ls="", marker="o", ms=4, color=f"C{k}",
                               label=f"$P_{{\\pi/2}}$: $\\delta = {k}\\pi/2$ mod $2\\pi$") for k in range(4)],
               loc="outside upper center", ncols=4, frameon=False)
    return finish(fig, ref.attrs)


def fig12(sources):
    """Return times t_{n+1} - t_n of P_2pi for two values of eps: double (the paper's arithmetic)
    and, beside it, every finer precision computed from the same settled point.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    data = [read_dataset(s) for s in sources]
    finer = finer_precisions(data[2:])
    fig, axes = subplots(WIDTH, 4.4, 1, 2)
    for ax, ds, tag in zip(axes, data, "ab"):
        ax.plot(ds.return_time, ".", ms=1.2, label=Precision.DOUBLE, **PRECISION_STYLE[Precision.DOUBLE])
        for (scene, precision), other in finer.items():
            if scene == ds.attrs["scene"]:
                ax.plot(other.return_time, ".", ms=1.0, label=precision, **PRECISION_STYLE[precision])
        if len(finer):
            ax.legend(markerscale=6)
        ax.set_xlabel("iterate $n$ (count)")
        ax.set_ylabel("return time $t_{n+1} - t_n$ (time units)")
        ax.set_title(f"({tag}) $\\epsilon$ = {ds.attrs['param_eps']:.3g}, E label {ds.attrs['energy_label']:.4g}: "
                     f"range [{ds.attrs['return_time_min']:.5g}, {ds.attrs['return_time_max']:.5g}],\n"
                     f"min pairwise difference {ds.attrs['return_time_min_pairwise_difference']:.2g}"
                     + ("" if ds.attrs["transient_over"] else "; TRANSIENT NOT SHOWN OVER"))
    return finish(fig, ds.attrs)


def _near_zero(ax, ds, v: str) -> None:
    """The PSD of ``v`` near f = 0 (up to 20 times its lowest peak), in a panel of its own beside the
    full spectrum (never an inset over it)."""
    f, S = ds.frequency.values[1:], ds[f"psd_{v}"].values[1:]
    near = f < 20 * max(np.nan_to_num(ds.attrs[f"{v}_lowest_peak"], nan=1e-3), 1e-3)
    if not near.any():  # the record resolves no frequency that low: say so, no empty axes
        ax.axis("off")
        ax.text(0.5, 0.5, f"near f = 0: no frequency resolved\n(record {ds.attrs['record_duration']:g} time units)",
                transform=ax.transAxes, ha="center", va="center")
        return
    ax.semilogy(f[near], S[near], lw=0.6, **PRECISION_STYLE["double"])
    ax.xaxis.set_major_locator(MaxNLocator(3))
    ax.set_xlabel(f"$f$ ({FREQUENCY})")
    ax.set_title(f"near f = 0: {ds.attrs[f'{v}_n_peaks_near_zero']} peaks", loc="left")


def psd(sources):
    """Welch PSD of u and Omega with the band, and beside each the peaks near zero (F13, F14): double
    (the paper's arithmetic) and, beside it, every finer precision computed from the same settled point.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds, *others = (read_dataset(s) for s in sources)
    finer = finer_precisions(others)
    fig, axes = subplots(10, 7, 2, 2, width_ratios=[3, 1])
    for (ax, zoom), v in zip(axes, ("u", "Omega")):
        f, S = ds.frequency.values[1:], ds[f"psd_{v}"].values[1:]
        ax.semilogy(f, S, lw=0.5, label=Precision.DOUBLE, **PRECISION_STYLE[Precision.DOUBLE])
        for (_, precision), other in finer.items():
            ax.semilogy(other.frequency.values[1:], other[f"psd_{v}"].values[1:], lw=0.5, label=precision,
                        **PRECISION_STYLE[precision])
        lo, hi = ds.attrs[f"{v}_band_low"], ds.attrs[f"{v}_band_high"]
        ax.axvspan(lo, hi, color="tab:orange", alpha=0.25, label=f"band [{lo:.4g}, {hi:.4g}]")
        ax.set_xlim(0, min(f[-1], 2.5 * hi))
        ax.set_ylabel(f"PSD of ${SYMBOLS[v]}$ (({UNITS[v]})$^2$ per cycle/time unit)")
        ax.legend(loc="lower right")  # the spectra's floor: below their tails
        _near_zero(zoom, ds, v)
    axes[-1, 0].set_xlabel(f"frequency $f$ ({FREQUENCY})")
    status = "" if ds.attrs["transient_over"] else "  [TRANSIENT NOT SHOWN OVER]"
    axes[0, 0].set_title(f"$\\epsilon$ = {ds.attrs['param_eps']:.3g}, E label {ds.attrs['energy_label']:.4g}, "
                         f"record {ds.attrs['record_duration']:g} time units at dt = {ds.attrs['sample_dt']:g} "
                         f"after t = {ds.attrs['record_start']:g}{status}", loc="left")
    return finish(fig, ds.attrs)


FIG9 = Figure("fig9", fig9, ("fig9_ref", "fig9_highE", "fig9_eps001", "fig9_scaling"), "F9", ("C15", "C16", "C17"),
              steady=("fig9_ref", "fig9_highE", "fig9_eps001"))
FIG12 = Figure("fig12", fig12, ("fig9_ref", "fig9_eps001"), "F12", ("C22",), steady=("fig9_ref", "fig9_eps001"),
               beside=True)
FIG13 = Figure("fig13", psd, ("psd_eps01",), "F13", ("C23",), steady=("psd_eps01",), beside=True)
FIG14 = Figure("fig14", psd, ("psd_eps001",), "F14", ("C24",), steady=("psd_eps001",), beside=True)
