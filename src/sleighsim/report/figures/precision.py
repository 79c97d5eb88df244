"""The precision ladder: the spike train of each steady state per precision, from one settled
point, and how soon the orbits of neighbouring precisions separate."""

from __future__ import annotations

import numpy as np

from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import ARITHMETIC_COLOUR, finish, subplots
from sleighsim.report.figures.figure import Figure


def precision(sources):
    """Left: spike interval against spike time per precision, one row per state; right: the
    separation of neighbouring precisions' orbits (log scale) with the level SEPARATED.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    n = ds.sizes["state"]
    fig, axes = subplots(10, 1 + 2.8 * n, n, 2, squeeze=False)
    for k, st in enumerate(ds.state.values):
        ax, bx = axes[k]
        for j, p in enumerate(ds.precision.values):
            t = ds.spike_time.values[k, j]
            t = t[np.isfinite(t)]
            ax.plot(t[1:], np.diff(t), "o-", ms=3, color=ARITHMETIC_COLOUR[Precision.parse(str(p))],
                    label=f"{p}: {ds.interval_mean.values[k, j]:.1f} +- {ds.interval_sd.values[k, j]:.1f}")
        ax.set_title(f"{st}: converged precision: {ds.converged_precision.values[k]}")
        if not np.isfinite(ds.interval_mean.values[k]).any():
            ax.text(0.5, 0.5, f"fewer than two spikes within T = {ds.attrs['T']:g}", transform=ax.transAxes,
                    ha="center")
        ax.set_xlabel("spike time after the settled point (time units)")
        ax.set_ylabel("spike interval (time units)")
        ax.legend(title="mean +- sd of the intervals")
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
