"""One long orbit cut into windows: a finite-time exponent and samples per window, and the rule
that says whether a per-window quantity has stopped drifting.

The orbit carries one tangent vector, renormalised every ``tau`` (its log growth summed per window
gives that window's finite-time exponent, 1/time); one state component is read every ``tau`` as a
sampled series. Windows are handed out one at a time, so a 1e7-long run never holds its whole
record in memory.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Iterator

import heyoka as hy
import numpy as np

from sleighsim.chaos import benettin
from sleighsim.chaos.common import linfit
from sleighsim.engine import integrators

log = logging.getLogger("sleighsim")

SETTLED, DRIFTING, UNDETERMINED = "settled", "drifting", "undetermined"


def windowed_orbit(ta, n: int, y0, *, n_windows: int, window: float, tau: float, component: int,
                   t_align: float = 0.0, seed: int = 0, label: str = "",
                   progress_every: float = 30.0) -> Iterator[dict]:
    """Yield, for each of ``n_windows`` consecutive windows of the orbit from y0 (model variables;
    ``ta`` is a one-vector tangent integrator with its pars set): ``index``, ``t_start``, ``t``
    and ``x`` (state[component] every tau), ``lambda_1`` (log growth of the tangent vector over the
    window / window), ``state`` (model variables at the window's end, in the integrator's precision)
    and ``steps``. The tangent
    vector starts as ``benettin.initial_directions(n, 1, seed)``, as in ``benettin.benettin``, and is
    aligned over t_align (renormalised every tau, not recorded; the windows' clock starts after it)."""
    per = window / tau
    if not (tau > 0 and window > 0 and n_windows >= 1 and abs(per - round(per)) < 1e-9 and round(per) >= 2):
        raise ValueError(f"need tau > 0, n_windows >= 1 and window a multiple (>= 2) of tau "
                         f"(n_windows={n_windows}, window={window}, tau={tau})")
    per = int(round(per))
    callback = integrators.bounded(ta)
    ta.time = ta.state.dtype.type(0)  # double, or long double for an extended-precision integrator
    integrators.load(ta, y0)
    ta.state[n:2 * n] = benettin.initial_directions(n, 1, seed).ravel()
    for _ in range(int(math.ceil(t_align / tau))):
        _step(ta, n, tau, callback, label)
    last = time.perf_counter()
    for w in range(n_windows):
        x = np.empty(per)
        growth, steps = 0.0, 0
        for i in range(per):
            log_norm, nsteps = _step(ta, n, tau, callback, label)
            steps += nsteps
            growth += log_norm
            x[i] = ta.state[component]
        t_start = w * window
        if time.perf_counter() - last > progress_every:
            last = time.perf_counter()
            log.info("%s: window %d / %d (t = %.4g), lambda_1 of the window %.3g", label, w + 1, n_windows,
                     t_start + window, growth / window)
        yield {"index": w, "t_start": t_start, "t": t_start + tau * np.arange(1, per + 1), "x": x,
               "lambda_1": growth / window, "state": integrators.read(ta, n), "steps": steps}


def _step(ta, n: int, tau: float, callback, label: str) -> tuple[float, int]:
    """Propagate for tau, renormalise the tangent vector; (log of its norm, steps taken)."""
    res = ta.propagate_for(ta.state.dtype.type(tau), callback=callback)
    if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(ta.state)):
        raise RuntimeError(f"{label}: run failed at t = {ta.time:.6g}: heyoka outcome {res[0].name}")
    v = ta.state[n:2 * n]
    norm = float(np.sqrt(v @ v))
    ta.state[n:2 * n] = v / norm
    return math.log(norm), res[3]


#: Written into the drift_windows dataset (attribute trend_rule).
TREND_RULE = (
    "Has x(t) (one value per window) stopped drifting? A straight line is fitted to the windows in the last "
    "``last_fraction`` of the run (least squares; the windows are treated as independent, which holds when a "
    "window spans many correlation times); change = slope x span of those windows. settled: |change| + sigma * "
    "stderr(change) <= rel_tol * |mean| (any drift left is resolved below the tolerance; the reason says when "
    "the slope itself is still resolved); drifting: |change| - sigma * stderr(change) > rel_tol * |mean| (a "
    "drift resolved above the tolerance); undetermined otherwise, or with fewer than min_points (>= 3) finite "
    "windows. Returns verdict, reason, slope (per time), slope_stderr, change, change_stderr, mean, n."
)


def trend(t, x, *, rel_tol: float, sigma: float, last_fraction: float = 0.5, min_points: int = 4) -> dict:
    """Applies :data:`TREND_RULE`, the rule as the datasets record it (just above)."""
    t, x = np.asarray(t, float), np.asarray(x, float)
    if t.shape != x.shape:
        raise ValueError(f"t and x differ in shape ({t.shape}, {x.shape})")
    if not (0 < last_fraction <= 1 and rel_tol > 0 and sigma >= 0 and min_points >= 3):
        raise ValueError(f"need 0 < last_fraction <= 1, rel_tol > 0, sigma >= 0, min_points >= 3 "
                         f"(got {last_fraction}, {rel_tol}, {sigma}, {min_points})")
    keep = (t >= t.min() + (1 - last_fraction) * (t.max() - t.min())) if t.size else t.astype(bool)
    keep &= np.isfinite(x) & np.isfinite(t)
    tk, xk = t[keep], x[keep]
    out = {"slope": math.nan, "slope_stderr": math.nan, "change": math.nan, "change_stderr": math.nan,
           "mean": float(xk.mean()) if xk.size else math.nan, "n": int(xk.size)}
    if xk.size < min_points:
        return {**out, "verdict": UNDETERMINED,
                "reason": f"{xk.size} finite windows in the last {last_fraction:g} of the run (need {min_points})"}
    slope, slope_err, _, _ = linfit(tk, xk)
    span = float(tk.max() - tk.min())
    change, change_err = slope * span, slope_err * span
    out.update(slope=slope, slope_stderr=slope_err, change=change, change_stderr=change_err)
    scale = rel_tol * abs(out["mean"])
    text = (f"over the last {last_fraction:g} of the run ({xk.size} windows, span {span:.4g}): change {change:.3g} "
            f"+- {change_err:.2g} against rel_tol x |mean| = {scale:.3g} (mean {out['mean']:.4g}, sigma {sigma:g})")
    if abs(change) + sigma * change_err <= scale:
        still = "; the slope itself is resolved (a slow drift goes on)" if abs(slope) > sigma * slope_err else ""
        return {**out, "verdict": SETTLED, "reason": "drift resolved below the tolerance: " + text + still}
    if abs(change) - sigma * change_err > scale:
        return {**out, "verdict": DRIFTING, "reason": "drift resolved above the tolerance: " + text}
    return {**out, "verdict": UNDETERMINED, "reason": "neither resolved: " + text}
