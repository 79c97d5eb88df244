"""The precision ladder: the spike train of each steady state per precision, from one settled
point, and how soon the orbits of neighbouring precisions separate."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ...io import read_dataset
from .common import finish

COLOURS = {"double": "tab:red", "long double": "tab:blue", "quad": "k"}


def precision(sources, png, pdf) -> None:
    """Left: spike interval against spike time per precision, one row per state; right: the
    separation of neighbouring precisions' orbits (log scale) with the level SEPARATED."""
    ds = read_dataset(sources[0])
    n = ds.sizes["state"]
    fig, axes = plt.subplots(n, 2, figsize=(10, 2.6 * n), squeeze=False)
    for k, st in enumerate(ds.state.values):
        ax, bx = axes[k]
        for j, p in enumerate(ds.precision.values):
            t = ds.spike_time.values[k, j]
            t = t[np.isfinite(t)]
            ax.plot(t[1:], np.diff(t), "o-", ms=3, color=COLOURS.get(str(p), None),
                    label=f"{p}: {ds.interval_mean.values[k, j]:.1f} +- {ds.interval_sd.values[k, j]:.1f}")
        ax.set_title(f"{st}: converged precision: {ds.converged_precision.values[k]}", fontsize=9)
        if not np.isfinite(ds.interval_mean.values[k]).any():
            ax.text(0.5, 0.5, f"fewer than two spikes within T = {ds.attrs['T']:g}", transform=ax.transAxes,
                    ha="center", fontsize=9)
        ax.set_xlabel("spike time after the settled point (time units)")
        ax.set_ylabel("spike interval (time units)")
        ax.legend(fontsize=8, title="mean +- sd of the intervals", title_fontsize=8)
        for i, pair in enumerate(ds.pair.values):
            bx.semilogy(ds.t_separation.values, ds.separation.values[k, i], label=str(pair))
        bx.axhline(1e-3, color="0.5", ls=":", lw=1)
        bx.set_xlabel("time after the settled point (time units)")
        bx.set_ylabel("separation of the orbits (relative)")
        bx.legend(fontsize=8)
    finish(fig, ds.attrs, png, pdf)
