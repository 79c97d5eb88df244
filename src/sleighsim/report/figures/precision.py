"""The precision ladder: the spike train of each steady state per precision, from one settled
point, and how soon the orbits of neighbouring precisions separate."""

from __future__ import annotations

import numpy as np

from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import ARITHMETIC_COLOUR, PRECISION_STYLE, finish, subplots
from sleighsim.report.figures.figure import Figure


def _interval_label(ds, k: int, j: int) -> str:
    """``precision: mean +- sd`` of state k's intervals in precision j, or what is missing."""
    p, m, sd = ds.precision.values[j], ds.interval_mean.values[k, j], ds.interval_sd.values[k, j]
    if not np.isfinite(m):
        return f"{p}: fewer than two spikes"
    return f"{p}: {m:.1f} +- {sd:.1f}" if np.isfinite(sd) else f"{p}: {m:.1f} (one interval)"


def _intervals(ax, ds, k: int) -> None:
    """State k's spike intervals against spike time per precision; without two spikes in any precision,
    the panel says so with no empty axes."""
    st = ds.state.values[k]
    ax.set_title(f"{st}: converged precision: {ds.converged_precision.values[k]}", loc="left")
    if not np.isfinite(ds.interval_mean.values[k]).any():
        ax.axis("off")
        ax.text(0.5, 0.5, f"{st}: fewer than two spikes within T = {ds.attrs['T']:g} in every precision",
                transform=ax.transAxes, ha="center", va="center")
        return
    for j, p in enumerate(ds.precision.values):
        t = ds.spike_time.values[k, j]
        t = t[np.isfinite(t)]
        ax.plot(t[1:], np.diff(t), "o-", ms=3, color=ARITHMETIC_COLOUR[Precision.parse(str(p))],
                label=_interval_label(ds, k, j))
    ax.set_xlabel("spike time after the settled point (time units)")
    ax.set_ylabel("spike interval (time units)")
    ax.legend(title="mean +- sd of the intervals")


def precision(sources):
    """Left: spike interval against spike time per precision, one row per state; right: the
    separation of neighbouring precisions' orbits (log scale) with the level SEPARATED.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    n = ds.sizes["state"]
    fig, axes = subplots(10, 1 + 2.8 * n, n, 2, squeeze=False)
    for k in range(n):
        ax, bx = axes[k]
        _intervals(ax, ds, k)
        for i, pair in enumerate(ds.pair.values):
            bx.semilogy(ds.t_separation.values, ds.separation.values[k, i], label=str(pair))
        bx.axhline(1e-3, color="0.5", ls=":", lw=1)
        bx.set_xlabel("time after the settled point (time units)")
        bx.set_ylabel("separation of the orbits (relative)")
        bx.legend()
    return finish(fig, ds.attrs)


def trigger(sources):
    """The first (and second) Omega spike against the Taylor tolerance, per arithmetic; filled
    markers: runs in the fit (rounding far below the tolerance, one per tolerance); the fitted law.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    a = ds.attrs
    fig, ax = subplots(8, 5.5)
    for p, style in PRECISION_STYLE.items():
        sel = ds.precision.values == p
        if not sel.any():
            continue
        fit = sel & (ds.in_fit.values == 1)
        for which, marker in (("first_spike", "o"), ("second_spike", "s")):
            ax.semilogx(ds.tol.values[sel], ds[which].values[sel], marker, mfc="none", **style)
            ax.semilogx(ds.tol.values[fit], ds[which].values[fit], marker, label=f"{p}: {which.replace('_', ' ')}",
                        **style)
    if np.isfinite(a["law_slope"]):
        x = np.logspace(np.log10(ds.tol.values.min()), np.log10(ds.tol.values.max()), 50)
        ax.semilogx(x, a["law_intercept"] + a["law_slope"] * np.log10(x), "k--", lw=0.8,
                    label=f"first spike: {a['law_slope']:.3g} +- {a['law_slope_stderr']:.2g} per decade "
                          f"({a['law_n_fit']} runs)")
    ax.set_xlabel("Taylor tolerance (relative; the injected error where rounding lies far below it)")
    ax.set_ylabel("spike time (time units)")
    ax.set_title(f"From y0 = ({a['y0_u']:g}, {a['y0_Omega']:g}, {a['y0_omega']:g}, {a['y0_delta']:g}):\nopen markers: "
                 f"not fitted (rounding within {a['far']:g}x of the tolerance, or the tolerance fitted in a finer "
                 "arithmetic)")
    ax.legend()
    return finish(fig, a)


PRECISION = Figure("precision", precision, ("precision_ladder",),
                   title="Does the arithmetic decide the steady state? Spike intervals per precision from one "
                         "settled point, and the orbits' separation",
                   steady=("precision_ladder",), section="sec:chaos")
TRIGGER = Figure("trigger", trigger, ("trigger_law",), title="What triggers the steady state? The first spike against "
                                                            "the size of the injected error (C04)",
                 section="sec:simulation")
