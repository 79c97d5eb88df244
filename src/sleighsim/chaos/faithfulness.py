"""Does an arithmetic follow the exact orbit? The gain of the tangent map over each spike cycle.

Once per spike cycle the sleigh's flow amplifies a perturbation by up to the largest singular value
G of the tangent map over one period (maximised over where in the cycle the period starts: most of
the gain builds up over the slow approach before each spike). An integration whose unit
roundoff is r injects errors of relative size r at every step, so it follows the exact orbit
through the cycle only where G r << 1; where G r is of order 1 or more, the computed orbit is one
realization of the rounding, not the exact dynamics. :data:`FAITHFUL_MAX` is the bound this
project uses (G r below 1e-3: the amplified rounding stays a thousand times below the state).

Conventions: time in the flow's time unit, G dimensionless (ln G stored), r the unit roundoff of
each precision (``Precision.rounding``: 2^-53, 2^-64, 2^-113). The tangent map is propagated with the
orbit (heyoka's variational equations, 4 vectors) and re-orthonormalised every ``tau`` by QR; the
map over a cycle is Q_end (R_m ... R_1) Q_start^T, so its singular values are those of the product
of the R factors between the two spikes, which never holds the full growth in the state that
heyoka's step control sees.
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
            prods = R_steps[starts + offset] @ prods
            scale = np.abs(prods).max(axis=(1, 2))
            prods, log_scale = prods / scale[:, None, None], log_scale + np.log(scale)  # finite over any cycle
        out.append(float(np.max(log_scale + np.log(np.linalg.svd(prods, compute_uv=False)[:, 0]))))
    return np.array(out)


def follows(ln_gain: float, rounding: float, limit: float = FAITHFUL_MAX) -> str:
    """Whether an arithmetic of unit roundoff ``rounding`` follows the exact orbit through a cycle of
    gain exp(ln_gain): FOLLOWS when G r < limit, DOES_NOT_FOLLOW when G r >= limit, UNKNOWN when
    the gain was not measured (NaN: no complete cycle)."""
    if not math.isfinite(ln_gain):
        return UNKNOWN
    return FOLLOWS if ln_gain + math.log(rounding) < math.log(limit) else DOES_NOT_FOLLOW


#: How far below what an indicator resolves the amplified rounding must stay (G x rounding at most
#: RESOLVED_MARGIN times the smallest relative quantity the indicator's verdict rests on).
RESOLVED_MARGIN = 1e-2
#: The indicators whose limit depends on the smallest relative quantity they resolve.
RESOLVING = ("frequency", "birkhoff")


# the docstring is written into the chaos_verdict dataset (attribute indicator_limit_rule)
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


def indicator_follows(ln_gain_max: float, arithmetic: dict, resolved: dict | None = None) -> dict:
    """{indicator: does its arithmetic follow the orbit closely enough for it (``follows`` with
    ``indicator_limit``)}. ``arithmetic``: indicator -> the arithmetic (a Precision or its name) its
    verdict was judged in; ``resolved``: indicator -> the relative quantity it resolves (optional)."""
    resolved = resolved or {}
    return {name: follows(ln_gain_max, Precision.parse(a).rounding, indicator_limit(name, resolved.get(name, math.nan)))
            for name, a in arithmetic.items()}


def tangent_run(ta, y0, *, T: float, tau: float, component: int = 1) -> dict:
    """Propagate the orbit from ``y0`` with the 4 x 4 tangent map of ``ta`` (``integrators.sleigh_tangent``
    with k = 4, parameters set) over T in steps of tau, re-orthonormalising by QR after each step.
    Returns t (the step ends), x (component ``component`` of the state there: Omega by default) and
    R (n_steps, 4, 4), the R factors in double."""
    from sleighsim.chaos.propagate import _propagate

    n = 4
    n_steps = int(round(T / tau))
    if not (tau > 0 and n_steps >= 2):
        raise ValueError(f"need tau > 0 and T >= 2 tau (T={T}, tau={tau})")
    callback = integrators.bounded(ta)
    ta.time = 0.0
    integrators.load(ta, np.asarray(y0))
    ta.state[n:] = np.eye(n).ravel()
    x, R_steps = np.empty(n_steps), np.empty((n_steps, n, n))
    for i in range(n_steps):
        _propagate(ta, tau, callback, i * tau)
        ta.time = 0.0  # autonomous: keep the clock small
        q, r = np.linalg.qr(np.asarray(ta.state[n:], float).reshape(n, n))
        ta.state[n:] = q.ravel()
        R_steps[i] = r
        x[i] = float(ta.state[component])
    return {"t": tau * np.arange(1, n_steps + 1), "x": x, "R": R_steps}


def spike_cycle_gains(ta, y0, *, T: float, tau: float = 5.0, spike_factor: float = 1.8) -> dict:
    """The gain of every complete spike cycle along the orbit from ``y0`` over T (``tangent_run``;
    spikes of Omega by ``transient.spike_times`` on the step ends). Returns spike_times, ln_gain (one
    per cycle; empty with fewer than two spikes), ln_gain_max (NaN without a cycle) and, per
    precision (keyed by :class:`Precision`), log10 of G_max x rounding and whether it follows the orbit."""
    run = tangent_run(ta, y0, T=T, tau=tau)
    spikes = transient.spike_times(run["t"], run["x"], factor=spike_factor, block=10 * tau)
    steps = np.searchsorted(run["t"], spikes)
    ln_gain = cycle_gains(run["R"], steps) if len(steps) >= 2 else np.array([])
    ln_max = float(ln_gain.max()) if ln_gain.size else math.nan
    return {
        "spike_times": spikes, "ln_gain": ln_gain, "ln_gain_max": ln_max,
        "log10_gain_rounding": {p: (ln_max + math.log(p.rounding)) / math.log(10) for p in Precision},
        "follows": {p: follows(ln_max, p.rounding) for p in Precision},
    }
