"""The faithfulness gauge's gain on orbits followed in double-double or triple-double: ln G of each spike
cycle (:func:`sleighsim.chaos.faithfulness.cycle_gains`) of several orbits at once, each orbit four lanes of
the batched engine (:class:`sleighsim.engine.ddbatch.DDBatch` or :class:`sleighsim.engine.tdtaylor.TDBatch`)
carrying the columns of its 4 x 4 tangent map.

Every ``tau`` the four lanes of an orbit stop; their tangent vectors, grown from an orthonormal set, are
re-orthonormalised by QR (the R factor kept, as the gauge's own heyoka run does) and all four restart from the
first lane's state, so the four carry one orbit. The caller places the cycles: the orbit's spike times (from a
run of its own, refined), each at the first QR step ending at or after it.

Conventions: times in the flow's time unit from each orbit's start; ln G dimensionless.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.faithfulness import cycle_gains
from sleighsim.engine.ddbatch import DDBatch


def _lanes(batch, state, rows):
    """The states of the orbits ``rows`` (four lanes each) in the batch's form: (hi, lo) or triples."""
    idx = np.repeat(rows, 4)
    return (state[0][idx], state[1][idx]) if isinstance(batch, DDBatch) else state[idx]


def _segment(batch, y, V, tau: float):
    """(end states in the batch's form, ln of the tangent norms, their directions) of every lane after tau."""
    if isinstance(batch, DDBatch):
        hi, lo, ln, d = batch.propagate_tangent_grid(y, V, [tau])
        return (hi[:, -1], lo[:, -1]), ln[:, -1], d[:, -1]
    s, ln, d = batch.propagate_tangent_grid(y, V, [tau])
    return s[:, -1], ln[:, -1], d[:, -1]


def _store(batch, state, k: int, end, lane: int) -> None:
    """Orbit k's state from the end state of ``lane``."""
    if isinstance(batch, DDBatch):
        state[0][k], state[1][k] = end[0][lane], end[1][lane]
    else:
        state[k] = end[lane]


def tangent_runs(batch, starts, horizons, *, tau: float) -> list[dict]:
    """Each orbit of ``starts`` ((hi, lo) (orbits, 4) for a DDBatch, (orbits, 4, 3) for a TDBatch) over its
    horizon with its tangent map (:mod:`this module <sleighsim.chaos.lane_gain>`): per orbit t (the QR step
    ends) and R (steps, 4, 4)."""
    state = (np.array(starts[0], float), np.array(starts[1], float)) if isinstance(batch, DDBatch) \
        else np.array(starts, float)
    horizons = np.asarray(horizons, float)
    n = horizons.size
    V = np.tile(np.eye(4), (n, 1, 1))
    R = [[] for _ in range(n)]
    for i in range(int(math.ceil(horizons.max() / tau))):
        rows = np.flatnonzero(horizons > i * tau)
        end, ln, d = _segment(batch, _lanes(batch, state, rows), V[rows].reshape(-1, 4), tau)
        for j, k in enumerate(rows):
            q, r = np.linalg.qr((d[4 * j: 4 * j + 4] * np.exp(ln[4 * j: 4 * j + 4])[:, None]).T)
            V[k], R[k] = q.T, R[k] + [r]
            _store(batch, state, k, end, 4 * j)
    return [{"t": tau * np.arange(1, len(R[k]) + 1), "R": np.array(R[k])} for k in range(n)]


def lane_gains(batch, starts, horizons, spikes, *, tau: float) -> list[dict]:
    """ln G of every complete spike cycle of each orbit (:func:`tangent_runs`; ``spikes``: per orbit its spike
    times from its start): per orbit ln_gain (array) and ln_gain_max (NaN without a complete cycle)."""
    out = []
    for run, s in zip(tangent_runs(batch, starts, horizons, tau=tau), spikes):
        steps = np.searchsorted(run["t"], np.asarray(s, float))
        ln = cycle_gains(run["R"], steps) if steps.size >= 2 else np.array([])
        out.append({"ln_gain": ln, "ln_gain_max": float(ln.max()) if ln.size else math.nan})
    return out
