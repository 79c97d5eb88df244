"""Crossings of the section delta = 0 (mod 2 pi) of a sampled orbit, each solved on the double-double Taylor jet
of its nearest sample (:meth:`sleighsim.engine.ddbatch.DDBatch.jet`, every crossing a lane of one batch).

The samples may come from any arithmetic (given as (hi, lo) pairs of doubles): the jet is the exact flow's
series at the sample, so a crossing within half a sampling step of it is solved to far below any arithmetic's
error there. delta advances fast (deltadot = Omega - omega, about -3 per time unit on the sleigh's steady
states, a turn per 2 time units), so a sampling step near a half turn leaves the samples' own turn count
ambiguous: each step's multiple of 2 pi is taken nearest to the rate's prediction (the mean of deltadot at the
step's two ends times the step), which holds while the rate changes little over one step.

Conventions: times in the flow's time unit; states (u, Omega, omega, delta), delta the model's angle.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.engine.ddbatch import MAX_LANES, DDBatch

TWO_PI = 2.0 * math.pi


def unwrapped_delta(hi, grid) -> np.ndarray:
    """delta along the samples (rows of ``hi`` at times ``grid``) made continuous, each step's whole turns chosen
    nearest to the prediction (Omega - omega) dt of :mod:`this module <sleighsim.engine.ddsection>`."""
    hi, grid = np.asarray(hi, float), np.asarray(grid, float)
    rate = hi[:, 1] - hi[:, 2]
    step = np.diff(hi[:, 3])
    predicted = 0.5 * (rate[1:] + rate[:-1]) * np.diff(grid)
    step -= TWO_PI * np.round((step - predicted) / TWO_PI)
    return hi[0, 3] + np.r_[0.0, np.cumsum(step)]


def horner(coef, tau):
    """sum_k coef[..., k] tau^k, vectorised over the leading axes."""
    out = np.zeros(np.shape(tau))
    for k in range(coef.shape[-1] - 1, -1, -1):
        out = out * tau + coef[..., k]
    return out


def jets(batch: DDBatch, hi, lo) -> np.ndarray:
    """The normalised Taylor coefficients (rows, 4, order + 1) at the states (rows of ``hi``, ``lo``), summed to
    doubles, in batches of at most MAX_LANES lanes."""
    rows = np.arange(len(hi))
    parts = [np.add(*batch.jet((hi[r], lo[r]))) for r in np.array_split(rows, max(1, -(-rows.size // MAX_LANES)))]
    return np.concatenate(parts) if rows.size else np.empty((0, 4, batch.order + 1))


def _crossing_rows(hi, grid, period: float, near=(), half_width: float = math.inf):
    """The samples nearest each crossing of delta = 0 (mod ``period``, 2 pi / period a whole number) of the sampled
    orbit: their rows, delta's residual there from the section (the sample's own delta, wrapped into [-pi, pi))
    and the multiple of ``period`` crossed (its index)."""
    d = unwrapped_delta(hi, grid)
    turn = np.floor(d / period)
    k = np.flatnonzero(np.diff(turn) != 0)
    if len(near):
        k = k[np.any(np.abs(grid[k][:, None] - np.asarray(near, float)[None, :]) <= half_width, axis=1)]
    index = np.maximum(turn[k], turn[k + 1])
    target = index * period
    rows = np.where(np.abs(d[k] - target) <= np.abs(d[k + 1] - target), k, k + 1)
    # the residual from the sample's own delta, not the unwrapped sum (which loses digits as it grows)
    on_circle = np.mod(index, round(TWO_PI / period)) * period
    residual = np.mod(hi[rows, 3] - on_circle + math.pi, TWO_PI) - math.pi
    return rows, residual, index


def _jets_at(batch: DDBatch, hi, lo, rows, residual) -> np.ndarray:
    """The jets at the samples ``rows``, summed to doubles, delta's series taken relative to the crossing's turn
    (its order 0 the sample's ``residual`` from the section)."""
    J = jets(batch, hi[rows], lo[rows])
    J[:, :, 0] = hi[rows] + lo[rows]
    J[:, 3, 0] = residual + lo[rows, 3]
    return J


def crossings(batch: DDBatch, hi, lo, grid, near=(), half_width: float = math.inf) -> tuple[np.ndarray, np.ndarray]:
    """Crossings of delta = 0 (mod 2 pi) of the sampled orbit (rows of ``hi``, ``lo`` at ``grid``), only those
    within ``half_width`` of a time of ``near`` when given: times (n,) and states (n, 3) (u, Omega, omega),
    each by Newton's method on the jet of the sample nearest it (|tau| at most about half a step)."""
    hi, lo, grid = np.asarray(hi, float), np.asarray(lo, float), np.asarray(grid, float)
    rows, residual, _ = _crossing_rows(hi, grid, TWO_PI, near, half_width)
    return solve_on_jets(_jets_at(batch, hi, lo, rows, residual), grid[rows])


def quarter_crossings(batch: DDBatch, hi, lo, grid):
    """Crossings of delta = k pi/2 of the sampled orbit (rows of ``hi``, ``lo`` at ``grid``; at most a quarter
    turn per step): times (n,), states (n, 3) (u, Omega, omega), k mod 4 (the section class, as
    :func:`sleighsim.engine.poincare.crossings`) and the residual of delta's series there (rad)."""
    hi, lo, grid = np.asarray(hi, float), np.asarray(lo, float), np.asarray(grid, float)
    rows, residual, index = _crossing_rows(hi, grid, 0.5 * math.pi)
    J = _jets_at(batch, hi, lo, rows, residual)
    tau = newton(J)
    return grid[rows] + tau, _states(J, tau), index.astype(np.int64) % 4, np.abs(horner(J[:, 3], tau))


def solve_on_jets(J, t) -> tuple[np.ndarray, np.ndarray]:
    """The crossings from the jets J (rows, 4, order + 1) at the sample times ``t``, delta's series J[:, 3] taken
    relative to the crossing's turn (J[:, 3, 0] the sample's residual): Newton's method on it from the linear
    guess (8 steps), then the times t + tau and the states (u, Omega, omega) there."""
    tau = newton(J)
    return t + tau, _states(J, tau)


def _states(J, tau) -> np.ndarray:
    """(u, Omega, omega) from the jets J at the offsets tau."""
    return np.stack([horner(J[:, c], tau) for c in range(3)], axis=1)


def newton(J) -> np.ndarray:
    """tau, the root of delta's series J[:, 3] (relative to the crossing's turn) nearest 0: Newton's method from
    the linear guess, 8 steps."""
    tau = -J[:, 3, 0] / J[:, 3, 1]
    slope = J[:, 3, 1:] * np.arange(1, J.shape[2])
    for _ in range(8):
        tau = tau - horner(J[:, 3], tau) / horner(slope, tau)
    return tau
