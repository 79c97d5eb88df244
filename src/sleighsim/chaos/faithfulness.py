"""Does an arithmetic follow the exact orbit? The gain of the tangent map over each spike cycle, and the
rounding an arithmetic injects over it.

Once per spike cycle the sleigh's flow amplifies a perturbation by up to the largest singular value
G of the tangent map over one period (maximised over where in the cycle the period starts: most of
the gain builds up over the slow approach before each spike). An integration whose unit roundoff is r
injects an error of relative size r at every Taylor step, n steps per cycle: at most n r per cycle
(errors that add coherently; a random walk gives about sqrt(n) r), each amplified by at most G. So the
separation of the computed orbit from the exact one grows by at most G n r per cycle
(:func:`injected_rounding`), and the arithmetic follows the orbit through the cycle only where that is
small; where it is of order 1 or more, the computed orbit is one realization of the rounding, not the
exact dynamics. :data:`FAITHFUL_MAX` is the bound this project uses (G n r below 1e-3: the amplified
rounding stays a thousand times below the state). The count is validated against the measured
separation of two arithmetics over a cycle (``benchmarks/gauge_count.py``).

Conventions: time in the flow's time unit, G dimensionless (ln G stored), r the unit roundoff of
each precision (``Precision.rounding``: 2^-53, 2^-64, 2^-106, 2^-113), n the Taylor steps of one
cycle, counted in the gauge's own double run and taken for every arithmetic (heyoka's order grows like
-ln(tolerance) / 2 at a tolerance of the arithmetic's epsilon, so its step length hardly changes with
the arithmetic). The tangent map is propagated with the orbit (heyoka's variational equations, 4
vectors) and re-orthonormalised every ``tau`` by QR; the map over a cycle is Q_end (R_m ... R_1)
Q_start^T, so its singular values are those of the product of the R factors between the two spikes,
which never holds the full growth in the state that heyoka's step control sees.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.loschmidt import LOSCHMIDT_GAIN_ROUNDING_MAX
from sleighsim.engine import integrators, transient
from sleighsim.precision import Precision

#: An arithmetic follows the exact orbit through a cycle when G x rounding is below this.
FAITHFUL_MAX = 1e-3
FOLLOWS, DOES_NOT_FOLLOW, UNKNOWN = "follows", "does not follow", "unknown"


#: What ``cycle_gains and follows`` does (the text a dataset records for the rule; its docstring says the same).
GAIN_RULE = (
    'ln G of each cycle: the largest singular value of the one-period tangent map Phi(t + P, t), maximised over '
    "the start times t in the cycle (P the cycle's length), i.e. the most that one cycle of the flow amplifies an"
    ' error injected anywhere in it. ``R_steps`` (n_steps, k, k) are the R factors of the successive QR '
    're-orthonormalisations, ``spike_steps`` the step indices at which the spikes lie (increasing); cycle j runs '
    'over steps spike_steps[j] + 1 ... spike_steps[j + 1] and the map from step i covers steps i + 1 ... i + m (m'
    ' steps in the cycle). A cycle whose last window does not end within the run is left out, so the result has '
    'at most len(spike_steps) - 2 values. Whether an arithmetic of unit roundoff ``rounding`` follows the exact '
    'orbit through a cycle of gain exp(ln_gain) and ``steps_per_cycle`` Taylor steps: FOLLOWS when G x steps x '
    'rounding < limit, DOES_NOT_FOLLOW when it is at or above, UNKNOWN when the gain or the steps were not '
    'measured (NaN: no complete cycle).'
)


def cycle_gains(R_steps, spike_steps) -> np.ndarray:
    """ln G of each cycle: the largest singular value of the one-period tangent map Phi(t + P, t),
    maximised over the start times t in the cycle (P the cycle's length), i.e. the most that one
    cycle of the flow amplifies an error injected anywhere in it. ``R_steps`` (n_steps, k, k) are the
    R factors of the successive QR re-orthonormalisations, ``spike_steps`` the step indices at which
    the spikes lie (increasing); cycle j runs over steps spike_steps[j] + 1 ... spike_steps[j + 1]
    and the map from step i covers steps i + 1 ... i + m (m steps in the cycle). A cycle whose last
    window does not end within the run is left out, so the result has at most len(spike_steps) - 2
    values."""
    R_steps = np.asarray(R_steps, float)
    k = R_steps.shape[1]
    out = []
    for a, b in zip(spike_steps[:-1], spike_steps[1:]):
        if not 0 <= a < b:
            raise ValueError(f"spike steps must increase (got {a}, {b})")
        m = b - a
        if b + m > len(R_steps):
            break
        starts = np.arange(a, b)
        prods, log_scale = np.broadcast_to(np.eye(k), (m, k, k)).copy(), np.zeros(m)
        for offset in range(1, m + 1):
            prods, log_scale = _times(R_steps[starts + offset], prods, log_scale)
        out.append(_ln_sigma_1(prods, log_scale))
    return np.array(out)


def _times(R, prods, log_scale) -> tuple[np.ndarray, np.ndarray]:
    """R @ prods for stacks of maps held as (prods, log_scale) = (map / e^log_scale, log_scale), renormalised by
    each map's largest entry: finite over any cycle or window."""
    prods = R @ prods
    scale = np.abs(prods).max(axis=(1, 2))
    return prods / scale[:, None, None], log_scale + np.log(scale)


def _ln_sigma_1(prods, log_scale) -> float:
    """ln of the largest singular value over a stack of maps held as :func:`_times` holds them."""
    return float(np.max(log_scale + np.log(np.linalg.svd(prods, compute_uv=False)[:, 0])))


def injected_rounding(rounding: float, steps_per_cycle: float) -> float:
    """The relative error an arithmetic of unit roundoff ``rounding`` injects over one cycle of
    ``steps_per_cycle`` Taylor steps, counted coherently: steps x rounding (NaN when the steps are not
    known)."""
    if not (math.isfinite(steps_per_cycle) and steps_per_cycle >= 1):
        return math.nan
    return float(steps_per_cycle) * rounding


def follows(ln_gain: float, rounding: float, limit: float = FAITHFUL_MAX, *, steps_per_cycle: float) -> str:
    """Whether an arithmetic of unit roundoff ``rounding`` follows the exact orbit through a cycle of
    gain exp(ln_gain) and ``steps_per_cycle`` Taylor steps: FOLLOWS when G x steps x rounding < limit,
    DOES_NOT_FOLLOW when it is at or above, UNKNOWN when the gain or the steps were not measured (NaN: no
    complete cycle)."""
    injected = injected_rounding(rounding, steps_per_cycle)
    if not (math.isfinite(ln_gain) and math.isfinite(injected)):
        return UNKNOWN
    return FOLLOWS if ln_gain + math.log(injected) < math.log(limit) else DOES_NOT_FOLLOW


def state_origin(settled_by: Precision, follows_settled: str, spike_period: float) -> str:
    """What a settled steady state is, from whether ``settled_by``, the arithmetic that settled it from its
    start, follows the start's orbit (``follows_settled``, this gauge's answer) and its spike interval
    (time units): the start's own steady state, or a torus the arithmetic's rounding selected (the
    integration error decides where the orbit lands: a hypersensitive family of tori)."""
    interval = f" (spike interval {spike_period:.0f})" if math.isfinite(spike_period) else ""
    if follows_settled == FOLLOWS:
        return (f"the steady state of its start's orbit{interval}: {settled_by.value}, which settled it, follows "
                "that orbit")
    if follows_settled == DOES_NOT_FOLLOW:
        return (f"a torus that {settled_by.value}'s rounding selected{interval}: {settled_by.value}, which settled it, "
                "does not follow its start's orbit, so the integration error picked where the orbit landed")
    return f"unknown: whether {settled_by.value}, which settled it, follows its start's orbit was not measured"


def log10_gain_rounding(ln_gain: float, rounding: float, steps_per_cycle: float) -> float:
    """log10(G x steps x rounding), NaN when unknown."""
    injected = injected_rounding(rounding, steps_per_cycle)
    return (ln_gain + math.log(injected)) / math.log(10) if math.isfinite(ln_gain + injected) else math.nan


#: How far below what an indicator resolves the amplified rounding must stay (G x rounding at most
#: RESOLVED_MARGIN times the smallest relative quantity the indicator's verdict rests on).
RESOLVED_MARGIN = 1e-2
#: The indicators whose limit depends on the smallest relative quantity they resolve.
RESOLVING = ("frequency", "birkhoff")


def indicator_limit(name: str, resolved: float = math.nan) -> float:
    """The largest G x rounding at which indicator ``name`` is judged: an arithmetic must follow the
    orbit more closely than the indicator resolves. The tangent-based indicators and the two nearby
    orbits measure growth of perturbations from a followed orbit: FAITHFUL_MAX (1e-3). The Loschmidt
    test: ``chaos.loschmidt.LOSCHMIDT_GAIN_ROUNDING_MAX`` (1e-4: its return error must stay two decades
    below saturation after a spike). An indicator that resolves a small relative quantity (the
    frequency analysis: the spread D of its window frequencies at the longest window; the weighted
    Birkhoff average: 10^-digits) needs G x rounding below RESOLVED_MARGIN (1e-2) times that quantity:
    the rounding, amplified by G, moves the frequencies by about G x rounding (measured on the
    sleigh's main state: long double, G x rounding = 10^-3.5, left D flat at 5e-5 while quad's D fell
    to 1e-8), so a smaller spread measures the arithmetic, not the orbit. Without a resolved quantity
    (NaN, e.g. no window kept) such an indicator gets FAITHFUL_MAX."""
    if name == "loschmidt":
        return LOSCHMIDT_GAIN_ROUNDING_MAX
    if name in RESOLVING and math.isfinite(resolved) and resolved > 0:
        return min(FAITHFUL_MAX, RESOLVED_MARGIN * resolved)
    return FAITHFUL_MAX


def indicator_follows(ln_gain_max: float, arithmetic: dict, resolved: dict | None = None, *,
                      steps_per_cycle: float) -> dict:
    """{indicator: does its arithmetic follow the orbit closely enough for it (``follows`` with
    ``indicator_limit``)}. ``arithmetic``: indicator -> the arithmetic (a Precision or its name) its
    verdict was judged in; ``resolved``: indicator -> the relative quantity it resolves (optional);
    ``steps_per_cycle``: the Taylor steps of one cycle (NaN: not measured, every answer UNKNOWN)."""
    resolved = resolved or {}
    return {name: follows(ln_gain_max, Precision.parse(a).rounding, indicator_limit(name, resolved.get(name, math.nan)),
                          steps_per_cycle=steps_per_cycle)
            for name, a in arithmetic.items()}


def tangent_run(ta, y0, *, T: float, tau: float, component: int = 1) -> dict:
    """Propagate the orbit from ``y0`` with the 4 x 4 tangent map of ``ta`` (``integrators.sleigh_tangent``
    with k = 4, parameters set) over T in steps of tau, re-orthonormalising by QR after each step.
    Returns t (the step ends), x (component ``component`` of the state there: Omega by default), R
    (n_steps, 4, 4), the R factors in double, and steps (heyoka's Taylor steps in all)."""
    import heyoka as hy

    n = 4
    n_steps = int(round(T / tau))
    if not (tau > 0 and n_steps >= 2):
        raise ValueError(f"need tau > 0 and T >= 2 tau (T={T}, tau={tau})")
    callback = integrators.bounded(ta)
    ta.time = 0.0
    integrators.load(ta, np.asarray(y0))
    ta.state[n:] = np.eye(n).ravel()
    x, R_steps, taylor_steps = np.empty(n_steps), np.empty((n_steps, n, n)), 0
    for i in range(n_steps):
        res = ta.propagate_for(tau, callback=callback)
        if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(ta.state)):
            raise RuntimeError(f"gauge run stopped at t = {i * tau:.6g} (+{float(ta.time):.6g}): {res[0]}")
        taylor_steps += int(res[3])
        ta.time = 0.0  # autonomous: keep the clock small
        q, r = np.linalg.qr(np.asarray(ta.state[n:], float).reshape(n, n))
        ta.state[n:] = q.ravel()
        R_steps[i] = r
        x[i] = float(ta.state[component])
    return {"t": tau * np.arange(1, n_steps + 1), "x": x, "R": R_steps, "steps": taylor_steps}


def window_gain(R_steps) -> float:
    """ln G of a whole window: the largest singular value of the tangent map Phi(t_j, t_i) over every pair of
    step ends t_i < t_j in it (``R_steps`` (n_steps, k, k): the R factors of the successive QR
    re-orthonormalisations), i.e. the most the flow amplifies an error injected anywhere in the window by any
    later time in it. For an orbit with no complete spike cycle within the window (the bound then covers the
    window the data span, not a cycle)."""
    R_steps = np.asarray(R_steps, float)
    n, k = R_steps.shape[0], R_steps.shape[1]
    if n < 1:
        raise ValueError("need at least one step")
    prods, log_scale, best = np.broadcast_to(np.eye(k), (n, k, k)).copy(), np.zeros(n), -math.inf
    for offset in range(1, n + 1):  # prods[i]: the map from step end i - 1 over `offset` steps (start i = 0: t = 0)
        m = n - offset + 1
        prods, log_scale = _times(R_steps[offset - 1:offset - 1 + m], prods[:m], log_scale[:m])
        best = max(best, _ln_sigma_1(prods, log_scale))
    return best


def _gauge(ln_gain, steps: float, spikes) -> dict:
    """The gauge's answer from the gains ``ln_gain`` of its spans (cycles or the window) of ``steps`` Taylor
    steps each: ln_gain_max and, per precision, G x steps x rounding, G x rounding and whether it follows."""
    ln_max = float(np.max(ln_gain)) if len(ln_gain) else math.nan
    return {
        "spike_times": spikes, "ln_gain": np.asarray(ln_gain, float), "ln_gain_max": ln_max, "steps_per_cycle": steps,
        "log10_gain_rounding": {p: log10_gain_rounding(ln_max, p.rounding, steps) for p in Precision},
        "log10_gain_unit_rounding": {p: (ln_max + math.log(p.rounding)) / math.log(10) for p in Precision},
        "follows": {p: follows(ln_max, p.rounding, steps_per_cycle=steps) for p in Precision},
    }


def window_gains(ta, y0, *, T: float, tau: float = 5.0) -> dict:
    """The gauge over the whole window [0, T] from ``y0`` (``tangent_run``, :func:`window_gain`) with the keys of
    :func:`spike_cycle_gains`: ln_gain holds the window's one value, steps_per_cycle the window's Taylor steps,
    spike_times is empty. An arithmetic that follows by it follows the orbit through the whole window."""
    run = tangent_run(ta, y0, T=T, tau=tau)
    return _gauge([window_gain(run["R"])], float(run["steps"]), np.array([]))


def spike_cycle_gains(ta, y0, *, T: float, tau: float = 5.0, spike_factor: float = 1.8) -> dict:
    """The gain of every complete spike cycle along the orbit from ``y0`` over T (``tangent_run``;
    spikes of Omega by ``transient.spike_times`` on the step ends). Returns spike_times, ln_gain (one
    per cycle; empty with fewer than two spikes), ln_gain_max (NaN without a cycle), steps_per_cycle (the
    run's Taylor steps per time unit times the mean spike interval; NaN without a cycle) and, per
    precision (keyed by :class:`Precision`), log10 of G_max x steps x rounding, log10 of G_max x rounding
    (one rounding, not counted per step) and whether it follows the orbit."""
    run = tangent_run(ta, y0, T=T, tau=tau)
    spikes = transient.spike_times(run["t"], run["x"], factor=spike_factor, block=10 * tau)
    steps = np.searchsorted(run["t"], spikes)
    ln_gain = cycle_gains(run["R"], steps) if len(steps) >= 2 else np.array([])
    per_time = run["steps"] / (run["t"].size * tau)
    per_cycle = per_time * float(np.mean(np.diff(spikes))) if len(spikes) >= 2 else math.nan
    return _gauge(ln_gain, per_cycle, spikes)


def settled_gains(params, y0, *, tol: float, compact_mode: bool, T: float, tau: float, spike_factor: float,
                  window: bool = False) -> dict:
    """The gauge along the orbit from ``y0`` at ``params`` (:class:`~sleighsim.model.params.Params`), in double
    at ``tol``: :func:`spike_cycle_gains` or, with ``window``, :func:`window_gains` over [0, T] in steps of tau."""
    ta, _ = integrators.sleigh_tangent(4, tol, compact_mode)
    integrators.set_pars(ta, params)
    if window:
        return window_gains(ta, np.asarray(y0, float), T=T, tau=tau)
    return spike_cycle_gains(ta, np.asarray(y0, float), T=T, tau=tau, spike_factor=spike_factor)
