"""Two nearby trajectories: a chaos indicator without tangent dynamics, and its judge.

Engine (times in the flow's own time unit, exponents lambda in 1/time, natural logs):
``two_trajectory``: largest exponent from a reference and a partner orbit a distance d0 apart,
renormalised every tau. Judges: ``judge_two_trajectory`` with ``d0_independent``
(``two_trajectory_indicator`` on runs at several d0). States that contain angles reduced by a
callback should be compared with a ``difference(a, b)`` that wraps angle differences (default:
``a - b``). Engine conventions: ``propagate``; verdict conventions: ``verdicts``.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.common import _n_intervals, _state, linfit
from sleighsim.chaos.propagate import _propagate
from sleighsim.chaos.verdicts import (
    CHAOTIC,
    REGULAR,
    UNDECIDED,
    _check_judge,
    _g,
    polynomial_rate_bound,
)
from sleighsim.model.params import positive


def two_trajectory(ta, y0, *, d0, tau, T, project=None, callback=None, seed=0, n_blocks=10,
                   difference=None, t_align=0.0, n_record=60):
    """Largest Lyapunov exponent from two nearby orbits, without tangent dynamics.

    A partner at distance ``d0`` (random unit direction from ``seed``; then
    ``project(y_ref, y_partner) -> y_partner`` if given, e.g. back onto the energy surface;
    then rescaled to distance d0) and the reference are propagated alternately with the
    same integrator ``ta`` over each interval ``tau``. After each interval the Euclidean
    separation d is measured, log(d / d0) recorded, and the partner reset to
    ref + (partner - ref) d0 / d, projected, and rescaled to d0 again. ``t_align`` (a
    multiple of tau, default 0) is run first without recording so the separation turns
    into the most unstable direction. ``difference(a, b)`` (default a - b) measures the
    separation, e.g. wrapping reduced angles.

    Choice of d0: too small and the separation is dominated by rounding of the two
    orbits (relative eps ~ 1e-16 of the state per step, amplified over tau); too large
    and the growth over tau leaves the linear regime and saturates (rate biased low).
    Keep d0 * exp(lambda tau) well below the scale of the dynamics and d0 well above
    1e-16 * |y| * (number of steps per tau); d0 ~ 1e-8 |y| is usually safe.

    Returns dict: ``rate`` (1/time, over T = n tau), ``stderr`` (from ``n_blocks``
    consecutive block rates, std / sqrt(n_blocks)), ``block_rates``, ``log_growth`` (per
    interval, length n), ``tau``, ``T_grid`` / ``running`` (running rate on a log grid),
    ``running_slope`` / ``running_slope_err`` (log-log slope of |running| against T over
    the last decade of the grid, textbook stderr ignoring serial correlation: about 0 for
    chaos, about -1 + 1/ln T for regular orbits), ``final_state`` (reference, in the
    integrator's precision: double or long double).
    """
    d0, tau, n_blocks, n, n_align = _two_trajectory_args(d0, tau, T, n_blocks, t_align)
    dim = len(ta.state)
    ref = _state("y0", y0, dim).astype(ta.state.dtype)
    diff = difference if difference is not None else (lambda a, b: a - b)
    u = np.random.default_rng(seed).normal(size=dim)
    partner = _reset(ref, ref + d0 * u / np.linalg.norm(u), 0.0, d0, diff, project)
    g = np.empty(n)
    t = 0.0
    for k in range(-n_align, n):
        ref, partner = _pair_leg(ta, ref, partner, tau, callback, t)
        t += tau
        d = float(np.linalg.norm(np.asarray(diff(partner, ref), float)))
        if not (math.isfinite(d) and d > 0):
            raise RuntimeError(f"separation is {d} at t = {t:.6g}")
        if k >= 0:
            g[k] = math.log(d / d0)
        partner = _reset(ref, partner, t, d0, diff, project)
    return _two_trajectory_rates(g, tau, n_blocks, n_record, d0, ref)


def _two_trajectory_args(d0, tau, T, n_blocks, t_align):
    """The checked settings of ``two_trajectory``: (d0, tau, n_blocks, intervals in T, intervals in t_align)."""
    d0 = positive("d0", d0)
    tau = positive("tau", tau)
    T = positive("T", T)
    if int(n_blocks) != n_blocks or n_blocks < 2:
        raise ValueError(f"n_blocks must be an integer >= 2, got {n_blocks!r}")
    n_blocks = int(n_blocks)
    n = _n_intervals(T, tau)
    if n < n_blocks:
        raise ValueError(f"T = {T} holds {n} intervals tau, fewer than n_blocks = {n_blocks}")
    if not (math.isfinite(t_align) and t_align >= 0):
        raise ValueError(f"t_align must be >= 0, got {t_align!r}")
    n_align = 0 if t_align == 0 else _n_intervals(t_align, tau, "t_align")
    return d0, tau, n_blocks, n, n_align


def _rescaled(ref, partner, t, d0, diff):
    """The partner moved along diff(partner, ref) to distance d0 from ref."""
    dv = np.asarray(diff(partner, ref), float)
    d = float(np.linalg.norm(dv))
    if not (math.isfinite(d) and d > 0):
        raise RuntimeError(f"separation is {d} at t = {t:.6g}: cannot renormalise the partner")
    return ref + dv * (d0 / d)


def _reset(ref, partner, t, d0, diff, project):
    """Partner at distance d0 from ref along (partner - ref); projected, then rescaled."""
    partner = _rescaled(ref, partner, t, d0, diff)
    if project is not None:
        partner = _rescaled(ref, np.asarray(project(ref.copy(), partner.copy()), float), t, d0, diff)
    return partner


def _pair_leg(ta, ref, partner, tau, callback, t):
    """The reference, then the partner, propagated over tau from time 0 with the same integrator:
    (reference, partner) at the end, in the integrator's precision."""
    for which in (0, 1):
        ta.time = ta.state.dtype.type(0)  # double, or long double for an extended-precision integrator
        ta.state[:] = ref if which == 0 else partner
        _propagate(ta, tau, callback, t)
        if which == 0:
            new_ref = ta.state.copy()
        else:
            partner = ta.state.copy()
    return new_ref, partner


def _two_trajectory_rates(g, tau, n_blocks, n_record, d0, ref) -> dict:
    """The result of ``two_trajectory`` from the log growth g per interval tau."""
    n = g.size
    rate = float(g.sum() / (n * tau))
    blocks = np.array([b.sum() / (b.size * tau) for b in np.array_split(g, n_blocks)])
    stderr = float(blocks.std(ddof=1) / math.sqrt(n_blocks))
    k = np.unique(np.geomspace(1, n, min(n_record, n)).astype(int))
    T_grid = k * tau
    running = np.cumsum(g)[k - 1] / T_grid
    sel = (T_grid >= T_grid[-1] / 10.0) & (running > 0)
    if sel.sum() >= 2:
        slope, slope_err, _, _ = linfit(np.log(T_grid[sel]), np.log(running[sel]))
    else:
        slope, slope_err = math.nan, math.nan
    return {"rate": rate, "stderr": stderr, "block_rates": blocks, "log_growth": g, "tau": tau,
            "T": n * tau, "d0": d0, "T_grid": T_grid, "running": running, "running_slope": slope,
            "running_slope_err": slope_err, "final_state": ref}


def judge_two_trajectory(rate, stderr, T, tau, running_slope, running_slope_err, *, sigma=3.0, degree=2.0,
                         slope_chaotic_min=-0.3, slope_regular_max=-0.6):
    """Verdict from ``two_trajectory`` (rate, stderr, T, tau, running_slope(_err)).

    chaotic: rate - sigma * stderr > polynomial_rate_bound(T, tau, degree) AND the running
    rate has levelled off (running_slope - sigma * err > slope_chaotic_min);
    regular: the running rate decays like 1/T up to a log (running_slope + sigma * err <
    slope_regular_max; ln T / T gives about -1 + 1/ln T). Otherwise undecided.
    """
    chk = _check_judge([("rate", rate), ("stderr", stderr), ("T", T), ("tau", tau),
                        ("running_slope", running_slope), ("running_slope_err", running_slope_err)],
                       [("stderr", stderr), ("running_slope_err", running_slope_err)], sigma)
    if chk:
        return chk
    bound = polynomial_rate_bound(T, tau, degree)
    lo = rate - sigma * stderr
    s_lo = running_slope - sigma * running_slope_err
    s_hi = running_slope + sigma * running_slope_err
    nums = (f"rate {_g(rate)} +- {_g(stderr)} /time over T = {_g(T)}, polynomial bound {_g(bound)}, "
            f"running-rate slope {_g(running_slope)} +- {_g(running_slope_err)}, sigma {_g(sigma)}")
    if lo > bound and s_lo > slope_chaotic_min:
        return CHAOTIC, f"separation grows exponentially (rate - sigma err = {_g(lo)} > bound) at a steady rate; {nums}"
    if s_hi < slope_regular_max:
        return REGULAR, (f"running rate decays like T^{_g(running_slope)} (slope + sigma err = {_g(s_hi)} < "
                         f"{_g(slope_regular_max)}): no steady exponential growth; {nums}")
    return UNDECIDED, f"rate not resolved above the polynomial bound with a steady running rate, nor decaying; {nums}"


#: Written into the chaos_verdict dataset (attribute d0_rule).
D0_INDEPENDENT_RULE = (
    "Is a two-trajectory rate a Lyapunov exponent? Only if it does not depend on the separation: the rates "
    "measured at the initial separations ``d0s`` must agree pairwise within sigma combined standard errors. A "
    "rate that changes with d0 is dominated by rounding noise or finite size (on the sleigh, noise off the "
    "leading direction amplified by many orders at every spike). Returns (True | False, reason); a non-finite "
    "rate or fewer than two d0 fail the check."
)


def d0_independent(d0s, rates, stderrs, *, sigma=3.0):
    """Applies :data:`D0_INDEPENDENT_RULE`, the rule as the datasets record it (just above)."""
    d0s, rates, stderrs = (np.atleast_1d(np.asarray(v, float)) for v in (d0s, rates, stderrs))
    if not (d0s.size == rates.size == stderrs.size):
        raise ValueError(f"d0s, rates and stderrs differ in length ({d0s.size}, {rates.size}, {stderrs.size})")
    listed = ", ".join(f"{_g(r)} +- {_g(e)} at d0 = {_g(d)}" for d, r, e in zip(d0s, rates, stderrs))
    if d0s.size < 2:
        return False, f"rate at one d0 only ({listed}): its independence of d0 is not checked"
    if not (np.all(np.isfinite(rates)) and np.all(np.isfinite(stderrs))):
        return False, f"a rate is not finite ({listed})"
    i, j = np.triu_indices(rates.size, 1)
    gap = np.abs(rates[i] - rates[j]) - sigma * np.hypot(stderrs[i], stderrs[j])
    if np.any(gap > 0):
        return False, f"rate depends on d0 ({listed}; sigma {_g(sigma)}): not a Lyapunov exponent"
    return True, f"rate independent of d0 within {_g(sigma)} combined standard errors ({listed})"


def two_trajectory_indicator(tts: list, d0s, tau: float, sigma: float) -> dict:
    """The two-trajectory indicator from ``two_trajectory`` runs at the separations d0s (in that
    order): the middle run judged (``judge_two_trajectory``), and undecided unless the rates are
    ``d0_independent``. Returns value and error (the middle run's rate and stderr) and verdict
    ((verdict, reason))."""
    tt = tts[len(tts) // 2]
    verdict = judge_two_trajectory(tt["rate"], tt["stderr"], tt["T"], tau, tt["running_slope"],
                                   tt["running_slope_err"], sigma=sigma)
    independent, why = d0_independent(d0s, [t["rate"] for t in tts], [t["stderr"] for t in tts], sigma=sigma)
    if not independent:
        v, r = verdict
        verdict = (UNDECIDED, f"{why}; at d0 = {tt['d0']:g} alone: {v}: {r}")
    return {"value": tt["rate"], "error": tt["stderr"], "verdict": verdict}
