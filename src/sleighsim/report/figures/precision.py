"""The precision ladder: the spike train of each steady state per precision, from one settled
point, and how soon the orbits of neighbouring precisions separate."""

from __future__ import annotations

import numpy as np

from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import ARITHMETIC_COLOUR, finish, subplots
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


PRECISION = Figure("precision", precision, ("precision_ladder",),
                   title="Does the arithmetic decide the steady state? Spike intervals per precision from one "
                         "settled point, and the orbits' separation",
                   steady=("precision_ladder",), section="sec:chaos")
