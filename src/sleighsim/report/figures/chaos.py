"""Is the steady state chaotic? The verdict of each indicator per state as a coloured table, the
rates with their uncertainties, and the three indicators that are curves: MEGNO, Loschmidt, frequency."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.ticker import NullFormatter

from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import LABELS, RATE, WIDTH, finish
from sleighsim.report.figures.figure import Figure
from sleighsim.report.page import CHAOS_COLOURS

#: The chaotic classes of a state (chaos.rule.classify), drawn in the chaotic colour.
CHAOTIC_CLASSES = ("strange attractor", "conservative-type chaos", "mixed dynamics")
PRECISION_LINES = {Precision.DOUBLE: "o:", Precision.LONG_DOUBLE: "s-", Precision.DOUBLE_DOUBLE: "d-.",
                   Precision.QUAD: "^--"}


def _shade(word: str) -> str:
    """The cell colour of a verdict or class, as the report colours verdicts (page.CHAOS_COLOURS):
    the chaotic classes as chaotic, "undetermined" and any word it does not know as undecided."""
    return CHAOS_COLOURS.get("chaotic" if word in CHAOTIC_CLASSES else word, CHAOS_COLOURS["undecided"])


def _cell(ds, k: int, j: int) -> str:
    """Indicator j of state k: its verdict, then its rate +- standard error (the frequency indicator:
    the convergence slopes of its precisions, each distinct one once; Loschmidt: also the power of its tail)."""
    name = str(ds.indicator.values[j])
    v, e = ds.indicator_value.values[k, j], ds.indicator_uncertainty.values[k, j]
    lines = [str(ds.indicator_verdict.values[k, j])]
    if name == "frequency":
        slopes = dict.fromkeys(f"{s:.2g}" for s in ds.frequency_slope.values[k] if np.isfinite(s))
        lines.append("slope " + " / ".join(slopes) if slopes else "not run")
    elif np.isfinite(v):
        lines.append(f"{v:.2g} ± {e:.1g}" if np.isfinite(e) else f"{v:.2g}")
    if name == "loschmidt" and np.isfinite(ds.loschmidt_tail_power.values[k]):
        lines.append(f"tail ~T^{ds.loschmidt_tail_power.values[k]:.2g}")
    return "\n".join(lines)


def _verdict_table(ax, ds) -> None:
    """One row per state: each indicator's verdict (cell colour) with its number, the sum of the
    exponents, the state's verdict and class."""
    ind = [str(n) for n in ds.indicator.values]
    header = [n.replace("_", " ") + (" (t)" if t else "") for n, t in zip(ind, ds.tangent_based.values)]
    text, colours = [], []
    for k in range(ds.sizes["state"]):
        verdict, cls = str(ds.verdict.values[k]), str(ds.state_class.values[k])
        total = f"{ds.sum_exponents.values[k]:.2g}\n± {ds.sum_exponents_stderr.values[k]:.1g}"
        text.append([_cell(ds, k, j) for j in range(len(ind))] + [total, verdict, cls])
        colours.append([_shade(str(ds.indicator_verdict.values[k, j])) for j in range(len(ind))]
                       + ["white", _shade(verdict), _shade(cls)])
    table = ax.table(cellText=text, cellColours=colours, rowLabels=[str(s) for s in ds.state.values],
                     colLabels=header + ["sum of\nexponents", "verdict", "class"], cellLoc="center",
                     bbox=(0.06, 0, 0.94, 1))
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    ax.axis("off")
    ax.set_title(f"verdict per indicator (red chaotic, blue regular, grey undecided); numbers: rate ± standard "
                 f"error ({RATE}); (t) tangent-based", loc="left")


def _rate_columns(ds) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(label, value per state, standard error per state) of every rate: the indicators but the
    frequency, the two-trajectory rate at each d0, and the long-double Benettin replica."""
    cols = [(n.replace("_", " ") + (" (t)" if t else ""), ds.indicator_value.values[:, j],
             ds.indicator_uncertainty.values[:, j])
            for j, (n, t) in enumerate(zip(map(str, ds.indicator.values), ds.tangent_based.values)) if n != "frequency"]
    cols += [(f"two trajectory\nd0 = {d0:.0e}", ds.two_trajectory_rate.values[:, i],
              ds.two_trajectory_stderr.values[:, i])
             for i, d0 in enumerate(ds.d0.values)]
    if np.isfinite(ds.lambda_1_long_double.values).any():
        cols.append(("benettin (t)\nlong double", ds.lambda_1_long_double.values,
                     ds.lambda_1_long_double_stderr.values))
    return cols


def _rates(ax, ds) -> None:
    """Every rate with 3 standard errors, states side by side (colour: state)."""
    cols = _rate_columns(ds)
    n = ds.sizes["state"]
    for k, st in enumerate(ds.state.values):
        x = np.arange(len(cols)) + (k - (n - 1) / 2) * 0.6 / n
        v = np.array([c[1][k] for c in cols])
        e = np.array([c[2][k] for c in cols])
        ax.errorbar(x, v, yerr=np.where(np.isfinite(e), 3 * e, 0), fmt="o", ms=4, capsize=3, color=f"C{k}",
                    label=str(st))
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xticks(range(len(cols)), [c[0] for c in cols])
    ax.set_ylabel(f"rate ({RATE}); bars: 3 standard errors")
    ax.legend(title="state", ncol=n)
    ax.set_title("the rates side by side: the two-trajectory rate must not depend on d0", loc="left")


def _megno(ax, ds) -> None:
    """MEGNO's running mean <Y>(t) per state, in double and (dashed) long double."""
    for k in range(ds.sizes["state"]):
        ax.plot(ds.megno_t.values[k], ds.megno_Y_mean.values[k], "-", color=f"C{k}")
        if np.isfinite(ds.megno_Y_mean_long_double.values[k]).any():
            ax.plot(ds.megno_t_long_double.values[k], ds.megno_Y_mean_long_double.values[k], "--", color=f"C{k}")
    ax.axhline(2.0, color="0.5", lw=0.8, ls=":")
    ax.set_xlabel(LABELS["t"])
    ax.set_ylabel("MEGNO <Y> (unitless)")
    ax.set_title("MEGNO: 2 on a torus (dotted),\ngrows like lambda t / 2 under chaos", loc="left")
    if np.isfinite(ds.megno_Y_mean_long_double.values).any():
        ax.legend(handles=[Line2D([], [], color="k", ls="-", label=Precision.DOUBLE),
                           Line2D([], [], color="k", ls="--", label=Precision.LONG_DOUBLE)])


def _loschmidt(ax, ds) -> None:
    """The Loschmidt return error against T per state, in double and long double (the one judged)."""
    for k in range(ds.sizes["state"]):
        ax.loglog(ds.T_loschmidt.values, ds.loschmidt_rel_error.values[k], PRECISION_LINES[Precision.DOUBLE], ms=3,
                  color=f"C{k}")
        ax.loglog(ds.T_loschmidt.values, ds.loschmidt_rel_error_long_double.values[k],
                  PRECISION_LINES[Precision.LONG_DOUBLE], ms=3, color=f"C{k}")
    ax.set_xlabel("T (time units; forward T, apply R, forward T)")
    ax.set_ylabel("return error (relative)")
    ax.set_title("Loschmidt: a power of T when regular,\nexponential up to saturation under chaos", loc="left")
    ax.legend(handles=[Line2D([], [], color="k", ls=":", marker="o", ms=3, label=Precision.DOUBLE),
                       Line2D([], [], color="k", ls="-", marker="s", ms=3, label="long double (judged)")])


def _frequency(ax, ds) -> None:
    """The spread of the leading frequency against the window length, per state and precision."""
    handles = {}
    for k in range(ds.sizes["state"]):
        for j, prec in enumerate(map(str, ds.frequency_precision.values)):
            D = ds.frequency_drift.values[k, j]
            if np.isfinite(D).any():
                style = PRECISION_LINES.get(prec, "x-")
                ax.loglog(ds.frequency_window.values[k, j], D, style, ms=3, color=f"C{k}")
                handles[prec] = Line2D([], [], color="k", ls=style[1:], marker=style[0], ms=3, label=prec)
    windows = np.unique(ds.frequency_window.values[np.isfinite(ds.frequency_window.values)])
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xticks(windows, [f"{w:g}" for w in windows])
    ax.set_xlabel("window W (time units)")
    ax.set_ylabel("spread of the leading frequency (relative)")
    ax.set_title("frequency: spread falls ~W^-2 on a torus;\nrounding-dependent: integration error", loc="left")
    if handles:
        ax.legend(handles=list(handles.values()))


def _decisive_states(ds) -> list[int]:
    """The states the decisive stage ran for."""
    if "decisive_verdict" not in ds.data_vars:
        return []
    return [k for k, v in enumerate(ds.decisive_verdict.values) if str(v) != "not run"]


def _section_run(ds) -> bool:
    """Whether the decisive stage ran its return map's MEGNO (a tangent-based judge of the stage votes)
    and measured it for a state."""
    if not int(ds.attrs.get("decisive_tangent", 1)) or "decisive_section_Y_mean" not in ds.data_vars:
        return False
    return any(np.isfinite(np.asarray(ds.decisive_section_Y_mean.values[k], float)).any()
               for k in _decisive_states(ds))


def _section_note(ds) -> str:
    """Why the decisive stage's return-map MEGNO has no panel (its vote horizon NaN: no audited one lets
    a judge vote)."""
    horizon = float(ds.attrs.get("decisive_vote_horizon", 1.0))
    if not np.isfinite(horizon):
        return "the map's MEGNO not run: no audited tangent judge votes"
    return f"the map's MEGNO not run: no tangent judge votes at horizon {horizon:g}"


def _section_megno(ax, ds) -> None:
    """The decisive stage: the return map's MEGNO <Y> after each return to the spike section, per state."""
    for k in _decisive_states(ds):
        y = np.asarray(ds.decisive_section_Y_mean.values[k], float)
        ax.plot(np.arange(1, y.size + 1), y, "-", color=f"C{k}", label=str(ds.state.values[k]))
    ax.axhline(2.0, color="0.5", lw=0.8, ls=":")
    ax.set_xlabel("returns to the spike section (count)")
    ax.set_ylabel("map's MEGNO <Y> (unitless)")
    ax.set_title(f"decisive stage ({ds.attrs.get('decisive_precision', '')}):\nthe return map's MEGNO "
                 "(2 on a torus, dotted)", loc="left")


def _birkhoff(ax, ds) -> None:
    """The decisive stage: digits of the weighted Birkhoff averages against the window length."""
    for k in _decisive_states(ds):
        W = ds.attrs["decisive_T"] / ds.decisive_split.values
        ax.semilogx(W, ds.decisive_birkhoff_digits.values[k], "o-", ms=4, color=f"C{k}",
                    label=str(ds.state.values[k]))
    ax.set_xlabel("window W (time units)")
    ax.set_ylabel("agreement of consecutive windows (decimal digits)")
    ax.set_title("Birkhoff averages: digits rise fast\non a torus, 0.5 per decade if chaotic", loc="left")


def _spike_train(ax, ds, note: str = "") -> None:
    """The decisive stage: the spike intervals of the decisive orbit (which torus the state is on);
    ``note``: a second title line (why a panel of the stage is left out)."""
    title = "spike train of the decisive orbit" + (f"\n({note})" if note else "")
    ax.set_title(title, loc="left")
    trains = {k: np.asarray(ds.decisive_spike_interval.values[k], float) for k in _decisive_states(ds)}
    trains = {k: iv[np.isfinite(iv)] for k, iv in trains.items() if np.isfinite(iv).any()}
    if not trains:  # no interval to draw: say so, no empty axes
        ax.axis("off")
        ax.text(0.5, 0.5, "no spike interval within the decisive orbit", transform=ax.transAxes, ha="center")
        return
    for k, iv in trains.items():
        ax.plot(np.arange(1, iv.size + 1), iv, ".-", ms=3, color=f"C{k}", label=str(ds.state.values[k]))
    ax.set_xlabel("spike cycle (count)")
    ax.set_ylabel("spike interval (time units)")


def chaos(sources):
    """Per steady state (one colour each): the verdict table, the rates with their uncertainties,
    MEGNO's running mean, the Loschmidt return error and the spread of the leading frequency; for the
    states of the decisive stage, its return map's MEGNO, Birkhoff digits and spike train.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    (ds,) = (read_dataset(s) for s in sources)
    table_h = 0.5 * (ds.sizes["state"] + 1)
    rows = [["table"] * 6, ["rates"] * 6, ["megno"] * 2 + ["loschmidt"] * 2 + ["frequency"] * 2]
    heights = [table_h, 3.0, 3.6]
    section = _section_run(ds)
    if _decisive_states(ds):  # no empty panel: without the map's MEGNO the other two take the row
        rows.append(["section_megno"] * 2 + ["birkhoff"] * 2 + ["spike_train"] * 2 if section
                    else ["birkhoff"] * 3 + ["spike_train"] * 3)
        heights.append(3.6)
    fig, axd = plt.subplot_mosaic(rows, figsize=(WIDTH, sum(heights) + 0.4), height_ratios=heights,
                                  layout="constrained")
    _verdict_table(axd["table"], ds)
    _rates(axd["rates"], ds)
    _megno(axd["megno"], ds)
    _loschmidt(axd["loschmidt"], ds)
    _frequency(axd["frequency"], ds)
    if _decisive_states(ds):
        if section:
            _section_megno(axd["section_megno"], ds)
        _birkhoff(axd["birkhoff"], ds)
        _spike_train(axd["spike_train"], ds, note="" if section else _section_note(ds))
    return finish(fig, ds.attrs)


CHAOS = Figure("chaos", chaos, ("chaos_verdict",), title="Is the steady state chaotic? Indicators per state",
               steady=("chaos_verdict",), section="sec:chaos")
