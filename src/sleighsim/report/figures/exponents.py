"""Figures of the Lyapunov analysis: against energy (F10), against eps with the b symmetry checked
(F11), the spectrum, the regime diagram and the drift of the main state."""

from __future__ import annotations

import textwrap

import numpy as np
from matplotlib.ticker import NullFormatter

from sleighsim.claims.faithful import Decided, decided, decided_rows, row_verdicts
from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import MIN_PT, PRECISION_STYLE, RATE, WIDTH, finer_precisions, finish, subplots
from sleighsim.report.figures.figure import Figure

LAMBDA_1 = rf"$\lambda_1$ ({RATE})"


def _same_model(ds, verdicts) -> bool:
    """Whether ``ds`` is at the parameters (eps, b, K2) of the chaos verdict ``verdicts``."""
    return all(np.isclose(float(ds.attrs[f"param_{k}"]), float(verdicts.attrs[f"param_{k}"]), rtol=1e-12, atol=0.0)
               for k in ("eps", "b", "K2"))


def _bound_label(d: Decided, how: str) -> str:
    """The legend of a decided state's exponent bound: arithmetic, verdict, realizations, how it is carried."""
    return textwrap.fill(f"{d.arithmetic.split(' (')[0]}, the decisive stage: {d.state} is {d.verdict} "
                         f"({d.agreeing} of {d.realizations} realizations): lambda_1 <= {d.lambda_max:.2g}{how}", 46)


def _faithful_labels(ax, ds, verdicts) -> None:
    """Beside double's lambda_1 (F10), the faithful answer: the state at the reference label as chaos_verdict's
    decisive stage decided it (``claims.faithful.decided``); when regular, its exponent bound carried to every
    label by the exact time-scaling law (lambda_1 <= bound sqrt(E / E0)), drawn as downward triangles; when not
    regular, or at other parameters, a legend entry saying no bound is drawn."""
    d, same = decided(verdicts), _same_model(ds, verdicts)
    if d.verdict != "regular" or not same:
        ax.plot([], [], " ", label=f"decisive stage: no bound drawn ({d.verdict if same else 'other parameters'})")
        return
    E = ds.label.values
    ax.plot(E, d.lambda_max * np.sqrt(E / float(verdicts.attrs["energy_label"])), "v", ms=7,
            label=_bound_label(d, f" at E = {float(verdicts.attrs['energy_label']):g}, carried to every label by "
                                  "the law"), **PRECISION_STYLE[Precision.DOUBLE_DOUBLE])


def _decided_rows(ax, ds, verdicts) -> None:
    """Beside double's lambda_1 (F11), the rows whose orbit is a state chaos_verdict decided regular
    (``claims.faithful.decided_rows``: same eps, K2 = 1 + eps, the same settled state): that state's exponent
    bound, a downward triangle."""
    for i, d in decided_rows(ds, verdicts).items():
        if d.verdict == "regular":
            ax.plot([ds.eps.values[i]], [d.lambda_max], "v", ms=8, label=_bound_label(d, " (this row's orbit)"),
                    **PRECISION_STYLE[Precision.DOUBLE_DOUBLE])


def _row_verdicts(ax, ds) -> None:
    """Beside double's lambda_1 (F11), each row's own verdict (``scenes.grid_verdict``, in the arithmetic its
    gauge accepts): a regular row's exponent bound as a downward triangle, a row judged but not decided (undecided
    or fragile) ringed at double's lambda_1; nothing for a grid without row verdicts or rows not judged."""
    words = row_verdicts(ds)
    regular, open_ = words == "regular", (words != "") & (words != "regular")
    eps, lam = ds.eps.values, np.abs(ds.lambda_1.values)
    if regular.any():
        arith = ", ".join(dict.fromkeys(map(str, ds.row_verdict_arithmetic.values[regular])))
        ax.plot(eps[regular], ds.row_lambda_max.values[regular], "v", ms=8, mfc="none", mew=1.5,
                label=f"the row's own verdict: regular in {arith}\n(all realizations): lambda_1 at most this",
                **PRECISION_STYLE[Precision.DOUBLE_DOUBLE])
    for word in dict.fromkeys(words[open_]):
        sel = words == word
        arith = ", ".join(dict.fromkeys(map(str, ds.row_verdict_arithmetic.values[sel])))
        ax.plot(eps[sel], lam[sel], "D", mfc="none", mec="tab:purple", ms=14, mew=1.2,
                label=f"the row's own verdict in {arith}: {word}")


def fig10(sources):
    """Max Lyapunov exponent against energy label, with the time-scaling law: double (the paper's
    arithmetic) and, beside it (shifted right by 8% in E), every finer precision from the same settled state;
    the faithful bound from the chaos verdict's decisive stage carried by the law (``_faithful_labels``).
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds, verdicts, *others = (read_dataset(s) for s in sources)
    fig, ax = subplots(WIDTH, 5.5)
    lam, err, E = ds.lambda_1.values, ds.stderr.values, ds.label.values
    pos = lam > 0
    ax.errorbar(E[pos], lam[pos], yerr=err[pos], fmt="o", capsize=3, label="direct (Benettin, k = 1), double",
                **PRECISION_STYLE[Precision.DOUBLE])
    for k, ((_, precision), other) in enumerate(finer_precisions(others).items(), start=1):
        ok = other.lambda_1.values > 0
        ax.errorbar(other.label.values[ok] * 1.08**k, other.lambda_1.values[ok], yerr=other.stderr.values[ok], fmt="s",
                    ms=4, capsize=2, label=precision, **PRECISION_STYLE[precision])
    if (~pos).any():
        ax.plot(E[~pos], np.abs(lam[~pos]), "x", color="tab:red", label="|lambda_1| where lambda_1 <= 0")
    ax.loglog(E, np.abs(ds.law.values), "-", color="0.4",
              label=f"law $\\lambda \\propto E^{{1/2}}$ from E = {ds.attrs['reference_label']:g}")
    _faithful_labels(ax, ds, verdicts)
    ax.set_xlabel("energy label $E$ (the paper's energy units)")
    ax.set_ylabel(f"max Lyapunov exponent {LAMBDA_1}, +- standard error")
    ax.set_title(f"$\\epsilon$ = {ds.attrs['param_eps']:.3g}, b = {ds.attrs['param_b']:.3g}: fitted exponent "
                 f"{ds.attrs['fitted_exponent']:.4f} +- {ds.attrs['fitted_exponent_stderr']:.2g} (law: 0.5)\n"
                 f"T = {ds.attrs['T_reference']:g} time units at E = {ds.attrs['reference_label']:g}, "
                 "scaled by the law")
    ax.legend()
    return finish(fig, ds.attrs)


def _grid_ticks(axis, values) -> None:
    """Label the grid values on a log axis (every other one past six), without matplotlib's minor labels."""
    axis.set_minor_formatter(NullFormatter())
    shown = values if len(values) <= 6 else values[::2]
    axis.set_ticks(shown, [f"{v:.2g}" for v in shown])


def _b_symmetry(ds) -> list[str]:
    """The b symmetry as the grid states it, and checked from the data: the largest spread of lambda_1
    across b in each row, and the direct recomputation at b_check, in standard errors of the row."""
    err = ds.stderr.values
    with np.errstate(invalid="ignore", divide="ignore"):
        spread = np.ptp(ds.lambda_1_grid.values, axis=1) / err
        direct, bound = ds.b_check_max_diff.values / err, ds.b_check_bound.values / err
    lines = [f"grid: {ds.lambda_1_grid.attrs.get('long_name', 'lambda_1(eps, b)')}"]
    if np.isfinite(spread).any() and np.nanmax(spread) == 0:
        lines.append(f"the {ds.sizes['b']} b columns are copies (filled by the symmetry, not computed): "
                     "only the recomputation tests it")
    elif np.isfinite(spread).any():
        lines.append(f"largest spread across the {ds.sizes['b']} b values of a row: {np.nanmax(spread):.2g} "
                     "standard errors of the row")
    if np.isfinite(direct).any():
        i = int(np.nanargmax(direct))
        b = ", ".join(f"{v:g}" for v in np.atleast_1d(ds.attrs["b_check"]))
        lines.append(f"recomputed at b = {b} (eps {ds.eps.values[i]:.3g}): difference "
                     f"{direct[i]:.2g} standard errors (allowed {bound[i]:.2g})")
    return lines


def _b_overlay(ax, ds) -> None:
    """|lambda_1| of the grid at a few b values (first, middle, last), each line thinner and darker
    than the one before, so that lines which coincide show as one layered line."""
    idx = sorted(set(np.linspace(0, ds.sizes["b"] - 1, 3).round().astype(int)))
    for i, (lw, grey, ls) in zip(idx, ((6, "0.85", "-"), (3, "0.6", "-"), (1, "k", "--"))):
        ax.plot(ds.eps.values, np.abs(ds.lambda_1_grid.values[:, i]), ls, color=grey, lw=lw,
                label=f"grid at b = {ds.b.values[i]:.3g}")


def _unfollowed(ax, ds) -> None:
    """Crosses on the rows whose orbit lambda_1's arithmetic does not follow (the row's faithfulness gauge:
    lambda_1 there measures the arithmetic's rounding, not the orbit), the arithmetics they need in the
    legend; grey squares on the rows whose gauge is unknown; nothing for a dataset without the gauge."""
    if "lambda_1_follows" not in ds.data_vars:
        return
    eps, lam, words = ds.eps.values, np.abs(ds.lambda_1.values), ds.lambda_1_follows.values
    bad, unknown = words == "does not follow", words == "unknown"
    if bad.any():
        needs = ", ".join(dict.fromkeys(map(str, ds.faithful_arithmetic.values[bad])))
        ax.plot(eps[bad], lam[bad], "x", color="k", ms=13, mew=1.5,
                label=f"double does not follow the row's orbit:\nits lambda_1 is not the orbit's (needs {needs})")
    if unknown.any():
        ax.plot(eps[unknown], lam[unknown], "s", mfc="none", mec="0.4", ms=12,
                label="the row's gauge unknown (no complete\nspike cycle within its T_gain)")


def fig11(sources):
    """|lambda_1| against eps with the replicas' standard error, by row status, flagged rows marked, rows double
    does not follow crossed (the row's faithfulness gauge; the arithmetics they need in the legend); the
    grid at a few b values over it, the b symmetry checked from the data in the title; in double (the
    paper's arithmetic) and, beside it (shifted right by 5% in eps), every finer precision whose rows'
    steady parts ran in it from the same settled states; a row whose orbit the chaos verdict decided, that
    decision's bound (``_decided_rows``).
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds, verdicts, *others = (read_dataset(s) for s in sources)
    fig, ax = subplots(WIDTH, 6)
    eps, lam, err = ds.eps.values, ds.lambda_1.values, ds.stderr.values
    _b_overlay(ax, ds)
    for status, marker in (("converged", "o"), ("regular", "s"), ("capped", "x")):
        sel = ds.status.values == status
        if sel.any():
            ax.errorbar(eps[sel], np.abs(lam[sel]), yerr=err[sel], fmt=marker, ms=5, capsize=3,
                        label=f"|lambda_1|, {status}, double", **PRECISION_STYLE[Precision.DOUBLE])
    for k, ((_, precision), other) in enumerate(finer_precisions(others).items(), start=1):
        ax.errorbar(other.eps.values * 1.05**k, np.abs(other.lambda_1.values), yerr=other.stderr.values, fmt="d",
                    ms=4, capsize=2, label=f"|lambda_1|, {precision}", **PRECISION_STYLE[precision])
    flagged = ds.flagged.values.astype(bool)
    ax.plot(eps[flagged], np.abs(lam[flagged]), "o", mfc="none", mec="r", ms=11,
            label="flagged row: transient, steadiness\nor lambda_1 not resolved")
    _unfollowed(ax, ds)
    _decided_rows(ax, ds, verdicts)
    _row_verdicts(ax, ds)
    ax.axhline(1e-4, color="0.5", ls=":", label="paper: smallest value > 1e-4")
    ax.set_xscale("log")
    ax.set_yscale("log")
    _grid_ticks(ax.xaxis, eps)
    ax.set_xlabel(r"$\epsilon$ (unitless)")
    ax.set_ylabel(f"$|\\lambda_1|$ ({RATE}), +- standard error over replicas")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1))
    words = list(ds.lambda_1_follows.values) if "lambda_1_follows" in ds.data_vars else []
    followed = (f" (double follows {words.count('follows')}, not {words.count('does not follow')}, unknown "
                f"{words.count('unknown')})") if words else ""
    head = (f"E label {ds.attrs['energy_label']:g}: {ds.attrs['n_rows']} rows{followed}, "
            f"{100 * ds.attrs['fraction_flagged']:.0f}% flagged; reference row (eps {ds.attrs['reference_eps']:.3g}): "
            "stderr / lambda_1 = "
            f"{ds.attrs['reference_rel_err']:.2f}")
    ax.set_title(head, loc="left")
    symmetry = _b_symmetry(ds)  # beside the axes, under the legend: the title stays one line
    sentences = (textwrap.fill(line[0].upper() + line[1:] + ".", 46) for line in symmetry)  # one per statement
    ax.text(1.01, 0.0, "\n".join(sentences), transform=ax.transAxes, ha="left", va="bottom", fontsize=MIN_PT)
    return finish(fig, ds.attrs)


def _spectrum(ax, spec) -> None:
    """lambda_i(T) on log-log axes (solid where positive, dashed where negative), the exponents at T in the legend."""
    T = spec["T"].values
    for i in range(spec.sizes["i"]):
        lam = spec.running.values[:, i]
        line, = ax.loglog(T, np.where(lam > 0, lam, np.nan), "-",
                          label=f"$\\lambda_{i + 1}$ = {spec.exponent.values[i]:.2g} +- {spec.stderr.values[i]:.1g}")
        ax.loglog(T, np.where(lam < 0, -lam, np.nan), "--", color=line.get_color())
    ax.loglog(T, 1.0 / T, ":", color="k", label="$1/T$")
    ax.axhline(abs(spec.attrs["mean_divergence"]), color="0.5", lw=0.8,
               label=f"|mean divergence| = {abs(spec.attrs['mean_divergence']):.2g}")
    ax.set_xlabel("accumulation time $T$ (time units)")
    ax.set_ylabel(f"$|\\lambda_i(T)|$ ({RATE})")
    ax.legend(ncol=2)
    ax.set_title(f"exponents at T = {spec.attrs['T']:g} per replica, +- standard error over {spec.attrs['replicas']} "
                 "replicas\nsolid: $\\lambda_i(T) > 0$; dashed: $-\\lambda_i(T)$ where negative")


def lyapunov(sources):
    """lambda_i(T) on log-log axes and the paper-protocol spread.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    spec, prot = (read_dataset(s) for s in sources)
    fig, (ax, bx) = subplots(WIDTH, 5, 1, 2, width_ratios=[1.6, 1])
    _spectrum(ax, spec)
    for j in range(prot.sizes["state"]):
        bx.plot(np.arange(1, 5), prot.exponent.values[j], "o-", ms=4, label=f"state {j}")
    bx.axhline(0, color="k", lw=0.6)
    bx.set_xticks(range(1, 5))
    bx.set_xlabel("index $i$ (unitless)")
    bx.set_ylabel(rf"$\lambda_i$, paper protocol ({RATE})")
    bx.set_title(f"paper protocol: T = {prot.attrs['T']:g} after {prot.attrs['t_transient']:g}, tau = "
                 f"{prot.attrs['tau']:g}\nspread of lambda_1 over states: {prot.attrs['spread_lambda_1']:.2g}")
    bx.legend()
    return finish(fig, spec.attrs)


def regimes(sources):
    """The regime diagram: lambda_1 (by status, flagged rows marked), the steady spike interval,
    and the P_2pi rotation number and curve thickness, against eps.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    eps = ds.eps.values
    fig, (ax, bx, cx) = subplots(8, 9, 3, 1, sharex=True)
    for status, marker in (("converged", "o"), ("regular", "s"), ("capped", "x")):
        sel = ds.status.values == status
        if sel.any():
            ax.errorbar(eps[sel], ds.lambda_1.values[sel], yerr=ds.stderr.values[sel], fmt=marker, ms=4, capsize=2,
                        label=f"lambda_1, {status}")
    flagged = ds.flagged.values.astype(bool)
    ax.plot(eps[flagged], ds.lambda_1.values[flagged], "o", mfc="none", mec="r", ms=9, label="flagged row")
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set_yscale("symlog", linthresh=1e-5)
    ax.set_ylabel(f"{LAMBDA_1}, +- stderr")
    ax.legend()
    ax.set_title(f"E label {ds.attrs['energy_label']:g}: {eps.size} eps, {int(flagged.sum())} flagged "
                 "(transient, steadiness or lambda_1 not resolved)")
    bx.errorbar(eps, ds.spike_interval.values, yerr=ds.spike_interval_std.values, fmt="o", ms=3, capsize=2)
    bx.set_yscale("log")
    bx.set_ylabel("steady spike interval (time units)")
    cx.plot(eps, ds.rotation_number.values, "o-", ms=3, label="P_2pi rotation number")
    cx.set_ylabel("rotation number (turns per iterate)")
    tx = cx.twinx()
    tx.plot(eps, ds.curve_thickness.values, "s--", ms=3, color="C1", label="curve thickness")
    tx.set_yscale("log")
    tx.set_ylabel("curve thickness (relative)", color="C1")
    cx.set_xscale("log")
    cx.set_xlabel(r"$\epsilon$ (unitless)")
    cx.legend(loc="upper left")
    return finish(fig, ds.attrs)


def drift(sources):
    """The long run in windows: spike interval (+- sd) and lambda_1 per window against time, each with
    its straight-line trend over the last part of the run and the trend verdict.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    t = ds.t_mid.values
    fig, axes = subplots(8, 6.5, 2, 1, sharex=True)
    for ax, name, label in ((axes[0], "spike_interval", "spike interval (time units), +- sd"),
                            (axes[1], "lambda_1", f"$\\lambda_1$ of the window ({RATE}, double)")):
        x = ds[name].values
        err = ds.spike_interval_sd.values if name == "spike_interval" else None
        ax.errorbar(t, x, yerr=err, fmt="o", ms=3, capsize=2, color="C0", lw=0.8)
        a = ds.attrs
        slope, mean = a[f"{name}_trend_slope"], a[f"{name}_trend_mean"]
        if np.isfinite(slope):
            sel = (t >= t.min() + (1 - a["last_fraction"]) * (t.max() - t.min())) & np.isfinite(x)
            tt = t[sel]  # the windows the trend was fitted to
            ax.plot(tt, mean + slope * (tt - tt.mean()), "r-", lw=1.5, label="trend over the last part")
            ax.legend()
        ax.set_ylabel(label)
        ax.set_title(f"{name}: {a[f'{name}_trend_verdict']} (change {a[f'{name}_trend_change']:.3g} +- "
                     f"{a[f'{name}_trend_change_stderr']:.2g}, tolerance {a[f'rel_tol_{name}']:g} x mean)")
    axes[1].axhline(0, color="0.5", lw=0.8)
    axes[1].set_xlabel(f"t after the transient (time units; windows of {ds.attrs['window']:g})")
    return finish(fig, ds.attrs)


FIG10 = Figure("fig10", fig10, ("lyap_energy", "chaos_verdict"), "F10", ("C20",), steady=("lyap_energy",),
               beside=True)
FIG11 = Figure("fig11", fig11, ("fig11_grid", "chaos_verdict"), "F11", ("C21",), steady=("fig11_grid",), beside=True)
LYAPUNOV = Figure("lyapunov", lyapunov, ("lyap_spectrum", "lyap_protocol"),
                  title="Lyapunov spectrum and the paper's protocol", section="sec:chaos")
REGIMES = Figure("regimes", regimes, ("regimes",), title="Regime diagram: lambda_1, spike interval and P_2pi rotation "
                                                        "number against eps (C27)", section="sec:chaos")
DRIFT = Figure("drift", drift, ("main_drift",), title="Does the main state's slow drift end? Spike interval and "
                                                     "lambda_1 per window", section="sec:chaos")
