"""Figures of the Lyapunov analysis: against energy (F10), on the (eps, b) grid (F11), the spectrum and the verdict."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ...io import read_dataset
from .common import PRECISION_STYLE, finer_precisions, finish


def fig10(sources, png, pdf) -> None:
    """Max Lyapunov exponent against energy label, with the time-scaling law: double (the paper's
    arithmetic) and, beside it (shifted right by 8% in E), every finer precision from the same settled state."""
    ds, *others = (read_dataset(s) for s in sources)
    fig, ax = plt.subplots(figsize=(7, 5))
    lam, err, E = ds.lambda_1.values, ds.stderr.values, ds.label.values
    pos = lam > 0
    ax.errorbar(E[pos], lam[pos], yerr=err[pos], fmt="o", capsize=3, label="direct (Benettin, k = 1), double",
                **PRECISION_STYLE["double"])
    for k, ((_, precision), other) in enumerate(finer_precisions(others).items(), start=1):
        ok = other.lambda_1.values > 0
        ax.errorbar(other.label.values[ok] * 1.08**k, other.lambda_1.values[ok], yerr=other.stderr.values[ok], fmt="s",
                    ms=4, capsize=2, label=precision, **PRECISION_STYLE[precision])
    if (~pos).any():
        ax.plot(E[~pos], np.abs(lam[~pos]), "x", color="tab:red", label="|lambda_1| where lambda_1 <= 0")
    ax.loglog(E, np.abs(ds.law.values), "-", color="0.4",
              label=f"law $\\lambda \\propto E^{{1/2}}$ from E = {ds.attrs['reference_label']:g}")
    ax.set_xlabel("energy label $E$")
    ax.set_ylabel(r"max Lyapunov exponent $\lambda_1$")
    ax.set_title(f"$\\epsilon$ = {ds.attrs['param_eps']:.3g}, b = {ds.attrs['param_b']:.3g}: fitted exponent "
                 f"{ds.attrs['fitted_exponent']:.4f} +- {ds.attrs['fitted_exponent_stderr']:.2g} (law: 0.5)\n"
                 f"T = {ds.attrs['T_reference']:g} time units at E = {ds.attrs['reference_label']:g}, scaled by the law",
                 fontsize=8)
    ax.legend(fontsize=7)
    finish(fig, ds.attrs, png, pdf)


def _every_other_tick(axis, values) -> None:
    """Label every other grid value on a log axis, without matplotlib's crowded minor labels."""
    from matplotlib.ticker import NullFormatter

    axis.set_minor_formatter(NullFormatter())
    axis.set_ticks(values[::2], [f"{v:.2g}" for v in values[::2]])


def fig11(sources, png, pdf) -> None:
    """Max Lyapunov exponent on the (eps, b) grid (log colour scale; b is an exact symmetry, so each
    row is one value), flagged rows marked; and lambda_1 against eps with the replicas' standard error,
    in double (the paper's arithmetic) and, beside it (shifted right by 5% in eps), every finer precision
    whose rows' steady parts ran in it from the same settled states."""
    from matplotlib.colors import LogNorm

    ds, *others = (read_dataset(s) for s in sources)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.8), gridspec_kw={"width_ratios": [1.3, 1]})
    grid = ds.lambda_1_grid.values
    positive = grid[grid > 0]
    norm = LogNorm(vmin=positive.min(), vmax=positive.max()) if positive.size else None
    mesh = ax.pcolormesh(ds.b.values, ds.eps.values, np.where(grid > 0, grid, np.nan), shading="nearest",
                         cmap="viridis", norm=norm)
    fig.colorbar(mesh, ax=ax, label=r"$\lambda_1$ (1/time; non-positive values blank)")
    flagged = ds.flagged.values.astype(bool)
    for e in ds.eps.values[flagged]:
        ax.axhline(e, color="w", lw=0.8, ls="--")
    ax.plot([], [], "w--", label="flagged row: transient, steadiness or lambda_1 not resolved")
    ax.set_xscale("log")
    ax.set_yscale("log")
    _every_other_tick(ax.xaxis, ds.b.values)
    _every_other_tick(ax.yaxis, ds.eps.values)
    ax.set_xlabel("$b$")
    ax.set_ylabel(r"$\epsilon$")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), facecolor="0.6")
    ax.set_title(f"E label {ds.attrs['energy_label']:g}: {ds.attrs['n_rows']} rows x {ds.sizes['b']} b, "
                 f"{100 * ds.attrs['fraction_flagged']:.0f}% of rows flagged\nb checked directly on the reference row: "
                 f"difference {ds.attrs['b_check_max_diff']:.2g}, allowed {ds.attrs['b_check_bound']:.2g}", fontsize=8)
    eps, lam, err = ds.eps.values, ds.lambda_1.values, ds.stderr.values
    for status, marker in (("converged", "o"), ("regular", "s"), ("capped", "x")):
        sel = ds.status.values == status
        if sel.any():
            bx.errorbar(eps[sel], np.abs(lam[sel]), yerr=err[sel], fmt=marker, ms=5, capsize=3,
                        label=f"|lambda_1|, {status}", **PRECISION_STYLE["double"])
    for k, ((_, precision), other) in enumerate(finer_precisions(others).items(), start=1):
        bx.errorbar(other.eps.values * 1.05**k, np.abs(other.lambda_1.values), yerr=other.stderr.values, fmt="d", ms=4,
                    capsize=2, label=f"|lambda_1|, {precision}", **PRECISION_STYLE[precision])
    bx.axhline(1e-4, color="0.5", ls=":", label="paper: smallest value > 1e-4")
    bx.set_xscale("log")
    bx.set_yscale("log")
    _every_other_tick(bx.xaxis, eps)
    bx.set_xlabel(r"$\epsilon$")
    bx.set_ylabel(r"$|\lambda_1|$ (1/time), +- standard error over replicas")
    bx.legend(fontsize=7)
    bx.set_title(f"reference row (eps {ds.attrs['reference_eps']:.3g}): stderr / lambda_1 = "
                 f"{ds.attrs['reference_rel_err']:.2f}\nstandard error of the mean over independent replicas", fontsize=8)
    finish(fig, ds.attrs, png, pdf)


def lyapunov(sources, png, pdf) -> None:
    """lambda_i(T) on log-log axes and the paper-protocol spread."""
    spec, prot = (read_dataset(s) for s in sources)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [1.6, 1]})
    T = spec["T"].values
    for i in range(4):
        lam = spec.running.values[:, i]
        line, = ax.loglog(T, np.where(lam > 0, lam, np.nan), "-", label=f"$\\lambda_{i + 1}(T) > 0$")
        ax.loglog(T, np.where(lam < 0, -lam, np.nan), "--", color=line.get_color(), label=f"$-\\lambda_{i + 1}(T)$")
    ax.loglog(T, 1.0 / T, ":", color="k", label="$1/T$")
    ax.axhline(abs(spec.attrs["mean_divergence"]), color="0.5", lw=0.8,
               label=f"|mean divergence| = {abs(spec.attrs['mean_divergence']):.2g}")
    ax.set_xlabel("accumulation time $T$")
    ax.set_ylabel(r"$|\lambda_i(T)|$")
    ax.legend(fontsize=6, ncol=2)
    lam = spec.exponent.values
    err = spec.stderr.values
    ax.set_title("exponents at T = %g per replica: %s\n+- %s (%d replicas)" % (
        spec.attrs["T"], np.array2string(lam, precision=2), np.array2string(err, precision=1), spec.attrs["replicas"]),
        fontsize=8)
    for j in range(prot.sizes["state"]):
        bx.plot(np.arange(1, 5), prot.exponent.values[j], "o-", ms=4, label=f"state {j}")
    bx.axhline(0, color="k", lw=0.6)
    bx.set_xticks(range(1, 5))
    bx.set_xlabel("index $i$")
    bx.set_ylabel(r"$\lambda_i$ (paper protocol)")
    bx.set_title(f"paper protocol: T = {prot.attrs['T']:g} after {prot.attrs['t_transient']:g}, tau = "
                 f"{prot.attrs['tau']:g}\nspread of lambda_1 over states: {prot.attrs['spread_lambda_1']:.2g}",
                 fontsize=8)
    bx.legend(fontsize=6)
    finish(fig, spec.attrs, png, pdf)



VERDICT_COLOURS = {"chaotic": "tab:red", "regular": "tab:blue", "undecided": "0.5"}


def chaos(sources, png, pdf) -> None:
    """Per steady state: each indicator's rate with its uncertainty (colour: the indicator's verdict),
    the verdict and the class; below, MEGNO's running mean <Y>(t), the Loschmidt return error
    against T and the spread of the leading frequency against the window length for every state."""
    (ds,) = (read_dataset(s) for s in sources)
    states, ind = list(ds.state.values), list(ds.indicator.values)
    n = len(states)
    fig, axd = plt.subplot_mosaic([[f"s{k}" for k in range(n) for _ in range(3)], ["m"] * n + ["l"] * n + ["f"] * n],
                                  figsize=(4.2 * max(n, 3), 7.5), height_ratios=(1.2, 1))
    axes = [axd[f"s{k}"] for k in range(n)]
    for k, (ax, st) in enumerate(zip(axes, states)):
        v, e = ds.indicator_value.values[k], ds.indicator_uncertainty.values[k]
        for j, name in enumerate(ind):
            c = VERDICT_COLOURS.get(str(ds.indicator_verdict.values[k, j]), "k")
            if name == "frequency":  # a relative drift, not an exponent: shown in its own panel below
                ax.annotate("see below", (j, 0), color=c, fontsize=6, ha="center", va="bottom", rotation=90)
                continue
            ax.errorbar(j, v[j], yerr=3 * e[j] if np.isfinite(e[j]) else None, fmt="o", color=c, capsize=4)
            if name == "benettin" and np.isfinite(ds.lambda_1_long_double.values[k]):
                ax.errorbar(j + 0.25, ds.lambda_1_long_double.values[k], yerr=3 * ds.lambda_1_long_double_stderr.values[k],
                            fmt="D", color="k", mfc="w", capsize=3, label="one replica in long double")
            if name == "two_trajectory":
                for d0, r, re in zip(ds.d0.values, ds.two_trajectory_rate.values[k], ds.two_trajectory_stderr.values[k]):
                    ax.errorbar(j + 0.25, r, yerr=3 * re, fmt="_", color="0.3", capsize=2)
                    ax.annotate(f"d0 {d0:.0e}", (j + 0.3, r), fontsize=5, va="center")
        if np.isfinite(ds.lambda_1_long_double.values[k]):
            ax.legend(fontsize=6, loc="upper left")
        ax.axhline(0, color="k", lw=0.6)
        ax.set_xticks(range(len(ind)))
        ax.set_xticklabels([f"{n}{' (t)' if t else ''}" for n, t in zip(ind, ds.tangent_based.values)], fontsize=6,
                           rotation=25)
        ax.set_title(f"{st}: {ds.verdict.values[k]}\n{ds.state_class.values[k]}; sum of exponents "
                     f"{ds.sum_exponents.values[k]:.2g} +- {ds.sum_exponents_stderr.values[k]:.1g}", fontsize=8)
    axes[0].set_ylabel("rate (1/time), bars: 3 standard errors")
    mx, lx, fx = axd["m"], axd["l"], axd["f"]
    for k, st in enumerate(states):
        colour = None
        for j, prec in enumerate(ds.frequency_precision.values):
            D = ds.frequency_drift.values[k, j]
            if np.isfinite(D).any():
                line, = fx.loglog(ds.frequency_window.values[k, j], D, ("o:", "s-", "^--")[j % 3], ms=3, color=colour,
                                  label=f"{st}, {prec}: slope {ds.frequency_slope.values[k, j]:.2g}")
                colour = line.get_color()
        line, = mx.plot(ds.megno_t.values[k], ds.megno_Y_mean.values[k], label=f"{st}, double")
        if np.isfinite(ds.megno_Y_mean_long_double.values[k]).any():
            mx.plot(ds.megno_t_long_double.values[k], ds.megno_Y_mean_long_double.values[k], "--", color=line.get_color(),
                    label=f"{st}, long double")
        verdict = ds.indicator_verdict.values[k, ind.index("loschmidt")]
        line, = lx.loglog(ds.T_loschmidt.values, ds.loschmidt_rel_error.values[k], "o:", ms=2, label=f"{st}, double")
        lx.loglog(ds.T_loschmidt.values, ds.loschmidt_rel_error_long_double.values[k], "s-", ms=3, color=line.get_color(),
                  label=f"{st}, long double: tail ~T^{ds.loschmidt_tail_power.values[k]:.2g}, {verdict}")
    mx.axhline(2.0, color="0.5", lw=0.8, ls="--")
    mx.set_xlabel("t")
    mx.set_ylabel("MEGNO <Y>")
    mx.set_title("MEGNO: 2 on a torus (grey), grows like lambda t / 2 under chaos", fontsize=8)
    mx.legend(fontsize=6)
    lx.set_xlabel("T (forward T, apply R, forward T)")
    lx.set_ylabel("return error (relative)")
    lx.set_title("Loschmidt: a power of T when regular, exponential up to saturation under chaos", fontsize=8)
    lx.legend(fontsize=6)
    fx.set_xlabel("window W (time)")
    fx.set_ylabel("spread of the leading frequency (relative)")
    fx.set_title("frequency analysis: falls like W^-2 or faster on a torus;\n"
                 "a drift that shrinks with the rounding is integration error", fontsize=8)
    fx.legend(fontsize=6)
    fig.suptitle("indicator verdicts: red chaotic, blue regular, grey undecided; (t) tangent-based; the two-trajectory "
                 "rate at each d0 beside it (it must not depend on d0)", fontsize=8)
    finish(fig, ds.attrs, png, pdf)


def regimes(sources, png, pdf) -> None:
    """The regime diagram: lambda_1 (by status, flagged rows marked), the steady spike interval,
    and the P_2pi rotation number and curve thickness, against eps."""
    ds = read_dataset(sources[0])
    eps = ds.eps.values
    fig, (ax, bx, cx) = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    for status, marker in (("converged", "o"), ("regular", "s"), ("capped", "x")):
        sel = ds.status.values == status
        if sel.any():
            ax.errorbar(eps[sel], ds.lambda_1.values[sel], yerr=ds.stderr.values[sel], fmt=marker, ms=4, capsize=2,
                        label=f"lambda_1, {status}")
    flagged = ds.flagged.values.astype(bool)
    ax.plot(eps[flagged], ds.lambda_1.values[flagged], "o", mfc="none", mec="r", ms=9, label="flagged row")
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set_yscale("symlog", linthresh=1e-5)
    ax.set_ylabel(r"$\lambda_1$ (1/time), +- stderr")
    ax.legend(fontsize=7)
    ax.set_title(f"E label {ds.attrs['energy_label']:g}: {eps.size} eps, {int(flagged.sum())} flagged "
                 "(transient, steadiness or lambda_1 not resolved)", fontsize=8)
    bx.errorbar(eps, ds.spike_interval.values, yerr=ds.spike_interval_std.values, fmt="o", ms=3, capsize=2)
    bx.set_yscale("log")
    bx.set_ylabel("steady spike interval (time)")
    cx.plot(eps, ds.rotation_number.values, "o-", ms=3, label="P_2pi rotation number")
    cx.set_ylabel("rotation number")
    tx = cx.twinx()
    tx.plot(eps, ds.curve_thickness.values, "s--", ms=3, color="C1", label="curve thickness")
    tx.set_yscale("log")
    tx.set_ylabel("curve thickness (relative)", color="C1")
    cx.set_xscale("log")
    cx.set_xlabel(r"$\epsilon$")
    cx.legend(fontsize=7, loc="upper left")
    finish(fig, ds.attrs, png, pdf)


def drift(sources, png, pdf) -> None:
    """The long run in windows: spike interval (+- sd) and lambda_1 per window against time, each with
    its straight-line trend over the last part of the run and the trend verdict."""
    ds = read_dataset(sources[0])
    t = ds.t_mid.values
    fig, axes = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    for ax, name, label in ((axes[0], "spike_interval", "spike interval (time), +- sd"),
                            (axes[1], "lambda_1", r"$\lambda_1$ of the window (1/time, double)")):
        x = ds[name].values
        err = ds.spike_interval_sd.values if name == "spike_interval" else None
        ax.errorbar(t, x, yerr=err, fmt="o", ms=3, capsize=2, color="C0", lw=0.8)
        a = ds.attrs
        slope, mean = a[f"{name}_trend_slope"], a[f"{name}_trend_mean"]
        if np.isfinite(slope):
            sel = (t >= t.min() + (1 - a["last_fraction"]) * (t.max() - t.min())) & np.isfinite(x)
            tt = t[sel]  # the windows the trend was fitted to
            ax.plot(tt, mean + slope * (tt - tt.mean()), "r-", lw=1.5, label="trend over the last part")
            ax.legend(fontsize=7)
        ax.set_ylabel(label)
        ax.set_title(f"{name}: {a[f'{name}_trend_verdict']} (change {a[f'{name}_trend_change']:.3g} +- "
                     f"{a[f'{name}_trend_change_stderr']:.2g}, tolerance {a[f'rel_tol_{name}']:g} x mean)", fontsize=8)
    axes[1].axhline(0, color="0.5", lw=0.8)
    axes[1].set_xlabel(f"t after the transient (windows of {ds.attrs['window']:g})")
    finish(fig, ds.attrs, png, pdf)
