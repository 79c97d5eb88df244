"""Frequency analysis as a chaos indicator (no tangent dynamics), and its judge.

Engine: ``frequency_drift``: frequency analysis of one component of the orbit (Laskar 1993; no
tangent dynamics): how its leading frequency changes from window to window (the analysis itself:
``sleighsim.chaos.naff``). Times in the flow's own time unit, frequencies in cycles per time
unit, natural logs. Judge: ``judge_frequency`` on one or more runs of one orbit in precisions of
decreasing rounding (``judged_run``, ``frequency_log_ratio``); it says regular or undecided, never
chaotic. Engine conventions: ``propagate``; verdict conventions: ``verdicts``.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos import naff as frequencies
from sleighsim.chaos.common import _positive, _state
from sleighsim.chaos.verdicts import REGULAR, UNDECIDED, _g, _is_finite


def frequency_drift(ta, y0, *, T, dt, component, splits=(2, 4, 8, 16), min_cycles=8.0, callback=None):
    """Frequency analysis of the orbit from y0 (no tangent dynamics): component ``component``
    sampled every dt over T (one propagate_grid run in the integrator's precision: double, long
    double or real128), then ``frequencies.drift`` over windows T / K, K in ``splits``. Returns
    that dict with ``T``, ``dt`` and ``final_state``."""
    dim = len(ta.state)
    y0 = _state("y0", y0, dim)
    T, dt = _positive("T", T), _positive("dt", dt)
    splits = frequencies.check_splits(splits)
    if not (isinstance(component, (int, np.integer)) and 0 <= component < dim):
        raise ValueError(f"component must be an index into the state (0..{dim - 1}), got {component!r}")
    fp = ta.state.dtype.type
    n = round(T / dt)
    if n < frequencies.MIN_SAMPLES * splits[-1]:
        raise ValueError(f"T / dt = {n} samples: too few for {splits[-1]} windows of at least {frequencies.MIN_SAMPLES}")
    import heyoka as hy

    ta.time = fp(0)
    ta.state[:] = np.asarray(y0).astype(ta.state.dtype)
    grid = np.arange(n).astype(ta.state.dtype) * fp(dt)  # n samples: T = n dt (any precision, real128 too)
    res = ta.propagate_grid(grid) if callback is None else ta.propagate_grid(grid, callback=callback)
    samples = np.asarray(res[-1]).astype(float)
    if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(samples)):
        raise RuntimeError(f"integration stopped at t = {float(ta.time):.6g} (target {T:.6g}): heyoka outcome {res[0]}")
    out = frequencies.drift(samples[:, component], dt, splits, min_cycles=min_cycles)
    out.update(T=float(n * dt), dt=float(dt), final_state=ta.state.copy())
    return out


# the docstring is written into the chaos_verdict dataset (attribute frequency_rule)
def judge_frequency(runs, *, sigma=3.0, converged_max=-1.0):
    """Verdict from frequency analysis (``frequency_drift``) of one orbit in one or more
    precisions, in order of decreasing rounding: ``runs`` is a list of dicts with ``precision``
    (a name), ``slope`` and ``slope_err`` (the convergence exponent of the spread D ~ W^slope of
    the leading frequency), ``D`` (the spread at the longest window) and, from the second run on,
    ``log_ratio`` +- ``log_ratio_err`` (ln of the previous run's D over this one's,
    ``frequency_log_ratio``) and ``rounding_ratio`` (the previous run's tolerance over this one's).

    regular: the window frequencies converge faster than 1/W in some run (slope + sigma err <
    converged_max, or slope = -inf: at the refinement's precision): a torus's refined frequency
    converges like W^-2 or faster, while a frequency that wanders on a chaotic orbit spreads like
    W^-1/2 or more slowly. Otherwise undecided. The test never says chaotic: a spread that
    neither converges nor depends on the rounding also appears on a torus whose windows are
    shorter than one of its slow periods (the smoke config's rotor states: D about 5e-3 at every
    window, equal in both precisions). When the drift shrinks with the rounding by more than the
    square root of the rounding ratio (log_ratio - sigma err > ln(rounding_ratio) / 2), the
    reason says so: the previous run's drift is then integration error, and the exact dynamics'
    drift is bounded by the last run's D, but that run's own drift is not explained, so the
    verdict stays undecided."""
    if not (math.isfinite(sigma) and sigma >= 0):
        raise ValueError(f"sigma must be >= 0, got {sigma!r}")
    if not runs:
        raise ValueError("runs is empty")
    for r in runs:
        for k in ("slope_err", "log_ratio_err"):
            if _is_finite(r.get(k, math.nan)) and float(r[k]) < 0:
                raise ValueError(f"{r['precision']}: {k} must be >= 0, got {r[k]!r}")
    parts, notes = [], []
    for prev, r in zip([None, *runs[:-1]], runs):
        p, e = r["slope"], r["slope_err"]
        parts.append(f"{r['precision']}: slope {_g(p)} +- {_g(e)}, D {_g(r['D'])}")
        if p == -math.inf or (_is_finite(p) and _is_finite(e) and p + sigma * e < converged_max):
            return REGULAR, (f"the leading frequency converges faster than 1/W in {r['precision']} (D ~ W^slope, "
                             f"slope + sigma err < {_g(converged_max)}); {'; '.join(parts)}; sigma {_g(sigma)}")
        lr, le, rr = (r.get(k, math.nan) for k in ("log_ratio", "log_ratio_err", "rounding_ratio"))
        if prev is not None and all(_is_finite(v) for v in (lr, le, rr)) and rr > 1:
            shrinks = lr - sigma * le > 0.5 * math.log(rr)
            notes.append(f"from {prev['precision']} to {r['precision']} the drift shrinks by {_g(math.exp(lr))} "
                         f"(ln {_g(lr)} +- {_g(le)}) at {_g(rr)} times smaller rounding"
                         + (f": the {prev['precision']} drift is integration error, the exact dynamics' below "
                            f"{_g(r['D'])}" if shrinks else ""))
    return UNDECIDED, ("the leading frequency converges in no run; " + "; ".join(parts + notes)
                       + f"; sigma {_g(sigma)}")


# the docstring is written into the chaos_verdict dataset (attribute frequency_rule)
def frequency_log_ratio(coarse: dict, fine: dict) -> tuple[float, float]:
    """ln(D_coarse / D_fine) of two ``frequency_drift`` runs of one orbit (coarse: the larger
    rounding, e.g. double against long double) over the splits both used, weighted by K - 1 (the
    windows behind each D; a D below the refinement's precision counts as that precision), and
    its standard error: the same weighted mean of the splits' errors 1 / sqrt(K - 1) (that of the
    ratio of two independent sample standard deviations of K values), the error of the mean if
    the splits were fully correlated (they share the data). (NaN, NaN) when no split is shared."""
    common = np.intersect1d(coarse["splits"], fine["splits"])
    if common.size == 0:
        return math.nan, math.nan
    da, db = (np.maximum([run["D"][list(run["splits"]).index(k)] for k in common], frequencies.PRECISION)
              for run in (coarse, fine))
    w = common - 1.0
    return float(np.sum(w * np.log(da / db)) / np.sum(w)), float(np.sum(np.sqrt(w)) / np.sum(w))


def judged_run(precision: str, run: dict, **ratio) -> dict:
    """A ``frequency_drift`` run as ``judge_frequency`` takes it."""
    return {"precision": precision, "slope": run["slope"], "slope_err": run["slope_err"],
            "D": float(run["D"][0]) if run["D"].size else math.nan, **ratio}
