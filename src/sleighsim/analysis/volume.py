"""Phase-space volume along a sampled orbit: the mean of the flow's divergence (the trace of its Jacobian, whose
time mean is the sum of the Lyapunov exponents) over whole spike cycles.

Quadrature. Between two samples the orbit is the quintic Hermite interpolant of the state, its first and second
time derivatives at both samples (the flow gives them: y' = f(y), y'' = J f); the observable is integrated on it
by Gauss-Legendre with ``NODES`` points. The cubic interpolant (values and first derivatives only) is integrated
the same way; their difference, far above the quintic's own error, is quoted as the quadrature error. On the
sleigh the rotor angle turns by about 1.7 rad per sample at dt = 0.5, so the trapezoid rule on the samples aliases
(its error on one cycle's mean is about 4e-7 there, the cubic's 2e-8, the quintic's 1e-9).

Cycles. Over a window that is not a whole number of cycles the mean carries the change of ln det of the flow
within a cycle, divided by the window (about 1e-4 over 3e4 time units on the torus at eps = 0.1, against about
1e-7 over whole cycles), so every mean runs from a spike to a spike. Uncertainty: the standard error over
``windows`` consecutive windows, each from its first spike to its last. Times in the flow's time unit, the
divergence in 1/time.
"""

from __future__ import annotations

import math

import numpy as np

NAN = math.nan
#: Gauss-Legendre points per sample interval.
NODES = 8
#: Sample intervals interpolated at once (memory: NODES x 4 doubles each, several arrays).
BLOCK = 100_000

#: Written into the datasets that store a cycle mean (attribute divergence_rule).
CYCLE_MEAN_RULE = (
    "mean divergence: trace J integrated on the quintic Hermite interpolant of the orbit's samples (their values, "
    f"f and J f) by {NODES}-point Gauss-Legendre per interval, from the orbit's first spike to its last (whole "
    "cycles), over their time; quadrature error: its difference from the cubic Hermite interpolant's (values and f "
    "only); uncertainty: whole-cycle means of K consecutive windows of the orbit (K its finest split), their "
    "standard error std / sqrt(K)"
)


def _hermite_weights(order: int, nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """The Hermite basis at the Gauss-Legendre points of [0, 1] (rows: value, h f, h^2 J f at the left sample,
    then at the right; cubic: four rows) and the points' weights (summing to 1)."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    s = (x + 1) / 2
    if order == 3:
        basis = [2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2]
    else:
        basis = [1 - 10 * s**3 + 15 * s**4 - 6 * s**5, s - 6 * s**3 + 8 * s**4 - 3 * s**5,
                 (s**2 - 3 * s**3 + 3 * s**4 - s**5) / 2, 10 * s**3 - 15 * s**4 + 6 * s**5,
                 -4 * s**3 + 7 * s**4 - 3 * s**5, (s**3 - 2 * s**4 + s**5) / 2]
    return np.array(basis), w / 2


def _block_integrals(t, Y, dY, d2Y, observable, order: int) -> np.ndarray:
    """Per sample interval of one block, the integral of observable (scalar or with trailing axes) on the Hermite
    interpolant of ``order``."""
    basis, w = _hermite_weights(order, NODES)
    h = np.diff(t)
    left = [Y[:-1], h[:, None] * dY[:-1], h[:, None] ** 2 * d2Y[:-1]]
    right = [Y[1:], h[:, None] * dY[1:], h[:, None] ** 2 * d2Y[1:]]
    terms = left[:2] + right[:2] if order == 3 else left + right
    states = sum(b[None, :, None] * v[:, None, :] for b, v in zip(basis, terms))
    values = np.tensordot(observable(states), w, axes=([1], [0]))  # the node axis summed
    return values * h.reshape(-1, *[1] * (values.ndim - 1))


def hermite_integrals(t, Y, dY, d2Y, observable, coarse: bool = True):
    """The integral of ``observable`` (a function of states (..., k) -> (...) or (..., m)) over each interval
    between samples ``t`` (n,) of an orbit ``Y`` (n, k) with derivatives ``dY`` and ``d2Y`` (continuous: unwrap
    angles first): on the quintic Hermite interpolant, each (n - 1,) or (n - 1, m), and with ``coarse`` also on
    the cubic one (else None in its place)."""
    t = np.asarray(t, float)
    if t.ndim != 1 or any(np.shape(a) != (t.size, np.shape(Y)[-1]) for a in (Y, dY, d2Y)):
        raise ValueError(f"t (n,) and Y, dY, d2Y (n, k) of one n, got {t.shape}, {np.shape(Y)}, {np.shape(dY)}, "
                         f"{np.shape(d2Y)}")
    out = {5: [], 3: []} if coarse else {5: []}
    for start in range(0, t.size - 1, BLOCK):
        sl = slice(start, min(start + BLOCK, t.size - 1) + 1)
        for order in out:
            out[order].append(_block_integrals(t[sl], Y[sl], dY[sl], d2Y[sl], observable, order))
    return np.concatenate(out[5]), np.concatenate(out[3]) if coarse else None


def cumulative(integrals) -> np.ndarray:
    """The running sum of per-interval integrals along the first axis, from 0 at the first sample."""
    integrals = np.asarray(integrals, float)
    return np.concatenate([np.zeros((1, *integrals.shape[1:])), np.cumsum(integrals, axis=0)])


def _span(t, cum, a: float, b: float) -> float:
    """The mean over the samples from time a to time b (cum: the integrals' prefix sums; NaN if a == b)."""
    i, j = int(np.searchsorted(t, a)), int(np.searchsorted(t, b))
    return float((cum[j] - cum[i]) / (t[j] - t[i])) if j > i else NAN


def cycle_mean(t, integrals, spikes, windows: int, coarse=None) -> dict:
    """The mean of an observable over whole cycles, from its ``integrals`` over the intervals between samples
    ``t`` (increasing): from the first of ``spikes`` (times within t) to the last, and over each of ``windows``
    (>= 2) equal consecutive windows of [t[0], t[-1]] from its first spike to its last (NaN with fewer than 2).
    ``coarse``: the same integrals by a cruder rule; the quadrature error is the two means' difference (NaN
    without). Returns mean, quadrature, stderr (over the finite windows' means), cycles, window_mean.
    ValueError on mismatched lengths, too few windows or spikes outside t."""
    t, integrals, spikes = np.asarray(t, float), np.asarray(integrals, float), np.asarray(spikes, float)
    if t.ndim != 1 or integrals.shape != (t.size - 1,):
        raise ValueError(f"t (n,) and integrals (n - 1,) expected, got shapes {t.shape} and {integrals.shape}")
    if int(windows) != windows or windows < 2:
        raise ValueError(f"windows = {windows} must be an integer >= 2")
    if spikes.size and (spikes.min() < t[0] or spikes.max() > t[-1]):
        raise ValueError("every spike time must lie within the samples' times")
    cum = cumulative(integrals)
    whole = spikes.size >= 2
    mean = _span(t, cum, spikes[0], spikes[-1]) if whole else NAN
    quad = NAN
    if coarse is not None and whole:
        quad = abs(mean - _span(t, cumulative(coarse), spikes[0], spikes[-1]))
    edges = np.linspace(t[0], t[-1], int(windows) + 1)
    per = np.array([_span(t, cum, s[0], s[-1]) if s.size >= 2 else NAN
                    for s in (spikes[(spikes >= lo) & (spikes <= hi)] for lo, hi in zip(edges[:-1], edges[1:]))])
    ok = per[np.isfinite(per)]
    stderr = float(ok.std(ddof=1) / math.sqrt(ok.size)) if ok.size >= 2 else NAN
    return {"mean": mean, "quadrature": quad, "stderr": stderr, "cycles": max(int(spikes.size) - 1, 0),
            "window_mean": per}
