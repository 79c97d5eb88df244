"""Independent realizations of known class for the judge-power audit, each confirmed by a long reference,
and the runs the audit makes on them (``chaos.known_orbits`` holds the systems).

Chaotic realizations: per system, base orbits from its base state perturbed by 1e-6 (seeded, one per
base), each run through a burn-in of BURN_PERIODS periods P and then cut into WINDOWS_PER_BASE disjoint
windows of ``window`` time units separated by GAP_PERIODS P; realization k is window k % WINDOWS_PER_BASE
of base k // WINDOWS_PER_BASE. One tangent vector rides along the whole base orbit (renormalised every
P); a window is confirmed chaotic when the forward reference from its start over REFERENCE_PERIODS P has
lambda_1 - 3 stderr above the rate polynomial growth can fake (``tangent.growth_confirmed``); its own
finite-time exponent over the window (how sticky it is) is recorded beside.

Tori: independent seeded starts (``System.draw``); a start of a system that is not integrable is
confirmed a torus when the quadrature MEGNO of a reference over REFERENCE_PERIODS P stays below
TORUS_Y_MAX without growth (``megno.judge_megno`` regular): a start that fails is replaced by the
next draw of its stream (attempts recorded).

Runs: :func:`tangent_orbit` (the orbit sampled every dt with one tangent vector's log-norm, the input of
the decisive stage's estimators) and :func:`gauge` (ln G per cycle of length P and the Taylor steps per
cycle of the orbit in its arithmetic: the faithfulness gauge's inputs). Times in each system's own unit.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from sleighsim.chaos import faithfulness, megno, tangent
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, SYSTEMS, System, rng_for
from sleighsim.engine import integrators, orbits
from sleighsim.precision import Precision

BURN_PERIODS, GAP_PERIODS, REFERENCE_PERIODS = 100.0, 50.0, 2000.0
WINDOWS_PER_BASE = 6
TORUS_Y_MAX = 2.5  # a reference's <Y> below this, without growth: a torus (megno.judge_megno's regular)
MAX_ATTEMPTS = 20  # torus draws tried per realization
SIGMA = 3.0


@dataclass(frozen=True)
class Orbit:
    """One realization: ``system``, its start ``y0`` (doubles), ``index`` and the numbers that confirm its
    class (``confirm``: name -> float; ``confirmed`` 1 or 0)."""

    system: str
    y0: tuple
    index: int
    confirm: tuple = ()

    @property
    def known(self) -> System:
        """Its system."""
        return SYSTEMS[self.system]

    @property
    def confirmation(self) -> dict:
        """The confirmation numbers as a dict."""
        return dict(self.confirm)


# ----------------------------------------------------------------------------- the audit's integrators

@functools.cache
def flow(system: str, arithmetic: str, tangent_vectors: int = 0):
    """The audit's heyoka integrator of ``system`` in ``arithmetic`` at its machine epsilon: the flow alone
    (0) or with k tangent vectors (state [y, V row-major]), compiled once per process. The audit's one
    integrator factory (the sleigh's are ``engine.integrators``)."""
    p = Precision.parse(arithmetic)
    if tangent_vectors:
        sys = SYSTEMS[system].build(integrators.guarded_heyoka())
        return integrators.tangent_integrator(sys, tangent_vectors, p.epsilon, precision=p)[0]
    return orbits.taylor(f"audit {system}", SYSTEMS[system].build, p, tol=p.epsilon)[0]


def _load(ta, n: int, y, v=None) -> None:
    """Reset the clock and load y (and the tangent vector v) in the integrator's arithmetic."""
    fp = ta.state.dtype.type
    ta.time = fp(0)
    ta.state[:n] = np.asarray(y, float).astype(ta.state.dtype)
    if v is not None:
        ta.state[n:2 * n] = np.asarray(v, float).astype(ta.state.dtype)


def _unit(n: int, seed: int) -> np.ndarray:
    u = np.random.default_rng(seed).normal(size=n)
    return u / np.linalg.norm(u)


def tangent_orbit(system: str, y0, *, T: float, dt: float, seed: int, renorm: int) -> dict:
    """The orbit from y0 over T sampled every dt in the system's arithmetic, with one tangent vector (a
    random unit vector drawn with ``seed``) renormalised every ``renorm`` samples (its log-norm continued
    across). Returns t (0, dt, ..., T), X (states, doubles), log_norm (ln |v(t)|, 0 at t = 0) and steps."""
    s = SYSTEMS[system]
    ta, n = flow(system, s.arithmetic, 1), len(y0)
    fp = ta.state.dtype.type
    m = round(T / dt)
    grid = np.arange(m + 1).astype(ta.state.dtype) * fp(dt)
    _load(ta, n, y0, _unit(n, seed))
    X, ell, offset, steps = np.empty((m + 1, n)), np.zeros(m + 1), 0.0, 0
    for a in range(0, m, renorm):
        b = min(a + renorm, m)
        res = ta.propagate_grid(grid[a:b + 1])
        S = np.asarray(res[-1])
        nrm = np.sqrt(np.sum(S[:, n:2 * n] ** 2, axis=1))
        if not (_finished(res) and np.all(np.isfinite(S)) and np.all(nrm > 0)):
            raise RuntimeError(f"{system}: tangent orbit stopped at t = {float(ta.time):.6g} of {T:.6g} ({res[0]})")
        X[a:b + 1], ell[a:b + 1] = S[:, :n].astype(float), offset + np.log(nrm.astype(float))
        ta.state[n:2 * n] = ta.state[n:2 * n] / nrm[-1]
        offset, steps = float(ell[b]), steps + int(res[3])
    return {"t": dt * np.arange(m + 1), "X": X, "log_norm": ell, "steps": steps}


def _finished(res) -> bool:
    import heyoka as hy

    return res[0] == hy.taylor_outcome.time_limit


def gauge(system: str, y0, *, cycles: int = 4, per_cycle: int = 50) -> dict:
    """The faithfulness gauge on the orbit from y0: ln G of each of ``cycles`` cycles of length P
    (``faithfulness.cycle_gains`` on the QR factors of the full tangent map renormalised every P /
    per_cycle, in double) and the Taylor steps per cycle of the orbit alone in the system's arithmetic.
    Returns ln_gain (per cycle), ln_gain_max and steps_per_cycle."""
    s = SYSTEMS[system]
    n, P = len(np.asarray(y0)), s.period
    ta = flow(system, "double", n)
    _load(ta, n, y0)
    ta.state[n:] = np.eye(n).ravel()
    tau, R = P / per_cycle, np.empty(((cycles + 1) * per_cycle, n, n))
    for k in range(R.shape[0]):
        res = ta.propagate_for(tau)
        if not _finished(res):
            raise RuntimeError(f"{system}: gauge run stopped at t = {float(ta.time):.6g}")
        q, r = np.linalg.qr(np.asarray(ta.state[n:], float).reshape(n, n))
        ta.state[n:] = q.ravel()
        R[k] = r
    ln_gain = faithfulness.cycle_gains(R, np.arange(cycles + 1) * per_cycle)
    orbit = flow(system, s.arithmetic)
    _load(orbit, n, y0)
    res = orbit.propagate_for(orbit.state.dtype.type(cycles * P))
    return {"ln_gain": ln_gain, "ln_gain_max": float(ln_gain.max()), "steps_per_cycle": int(res[3]) / cycles}


# ----------------------------------------------------------------------------- chaotic windows

def base_orbit(system: str, stream: int, base: int, *, window: float, n_windows: int = WINDOWS_PER_BASE) -> dict:
    """Base orbit ``base`` of a chaotic ``system`` in ``stream``: its start (the base state perturbed,
    seeded), the states at the starts of its n_windows disjoint windows, and per window the confirmation
    (module docstring): lambda_1, stderr and bound of the forward reference, confirmed, and the window's
    own finite-time exponent. One run of the orbit with one tangent vector in the system's arithmetic."""
    s = SYSTEMS[system]
    P = s.period
    y = s.perturb(np.asarray(s.base, float), rng_for(system, stream, base))
    n = y.size
    step = math.ceil((window + GAP_PERIODS * P) / P)  # periods from one window start to the next
    first, per_ref, per_window = round(BURN_PERIODS), round(REFERENCE_PERIODS), math.ceil(window / P)
    total = first + step * (n_windows - 1) + max(per_ref, per_window)
    ta = flow(system, s.arithmetic, 1)
    _load(ta, n, y, _unit(n, 1000 + base))
    g, starts = np.empty(total), []
    for k in range(total):
        if k >= first and (k - first) % step == 0 and len(starts) < n_windows:
            starts.append(np.asarray(ta.state[:n], float).copy())
        res = ta.propagate_for(ta.state.dtype.type(P))
        v = ta.state[n:2 * n]
        nrm = float(np.sqrt(np.sum(v * v)))
        if not (_finished(res) and math.isfinite(nrm) and nrm > 0):
            raise RuntimeError(f"{system}: base orbit {base} stopped at t = {float(ta.time):.6g}")
        g[k] = math.log(nrm)
        ta.state[n:2 * n] = v / nrm
    out = []
    for w, y0 in enumerate(starts):
        a = first + w * step
        ref = g[a:a + per_ref]
        lam, err, bound, ok = tangent.growth_confirmed(ref, P, ref.size * P, SIGMA, 10)
        out.append({"y0": y0, "lambda_1": lam, "stderr": err, "bound": bound, "confirmed": float(ok),
                    "window_ftle": float(g[a:a + per_window].sum() / (per_window * P))})
    return {"start": y, "windows": out}


def chaotic_realization(system: str, stream: int, index: int, *, window: float) -> Orbit:
    """Realization ``index``: window index % WINDOWS_PER_BASE of base orbit index // WINDOWS_PER_BASE."""
    base, w = divmod(index, WINDOWS_PER_BASE)
    win = _base(system, stream, base, window)["windows"][w]
    return Orbit(system, tuple(float(v) for v in win["y0"]), index,
                 tuple((k, float(win[k])) for k in ("lambda_1", "stderr", "bound", "confirmed", "window_ftle")))


@functools.lru_cache(maxsize=4)
def _base(system: str, stream: int, base: int, window: float) -> dict:
    return base_orbit(system, stream, base, window=window)


# ----------------------------------------------------------------------------- tori

def torus_reference(system: str, y0) -> dict:
    """The reference that confirms a torus: quadrature MEGNO over REFERENCE_PERIODS P renormalised every P
    in the system's arithmetic; confirmed when ``megno.judge_megno`` (3 sigma) says regular with
    y_regular_max TORUS_Y_MAX."""
    s = SYSTEMS[system]
    tm, n = _megno_flow(system, s.arithmetic)
    T = round(REFERENCE_PERIODS) * s.period
    m = megno.megno(tm, n, np.asarray(y0, float), T=T, n_samples=100, tau=s.period, seed=0)
    v, _ = megno.judge_megno(m["final"], m["resid"], m["slope"], m["slope_err"], T, sigma=SIGMA,
                             y_regular_max=TORUS_Y_MAX)
    return {"Y_mean": float(m["final"]), "Y_resid": float(m["resid"]), "confirmed": float(v == "regular")}


@functools.cache
def _megno_flow(system: str, arithmetic: str):
    p = Precision.parse(arithmetic)
    return integrators.megno_integrator(SYSTEMS[system].build(integrators.guarded_heyoka()), precision=p,
                                        tol=p.epsilon)


def torus_realization(system: str, stream: int, index: int) -> Orbit:
    """Realization ``index`` of a torus system: the first confirmed of its draws (attempt a uses the
    generator of index MAX_ATTEMPTS x index + a); an integrable system's first draw."""
    s = SYSTEMS[system]
    for a in range(MAX_ATTEMPTS):
        y0 = s.draw(rng_for(system, stream, MAX_ATTEMPTS * index + a))
        ref = {"confirmed": 1.0} if s.integrable else torus_reference(system, y0)
        if ref["confirmed"]:
            return Orbit(system, tuple(float(v) for v in y0), index, tuple({**ref, "attempts": a + 1.0}.items()))
    raise RuntimeError(f"{system}: no confirmed torus in {MAX_ATTEMPTS} draws (realization {index})")


def realization(system: str, stream: int, index: int, *, window: float) -> Orbit:
    """Realization ``index`` of ``system`` in ``stream`` (chaotic: disjoint windows of length ``window``)."""
    if SYSTEMS[system].cls == CHAOTIC_ORBITS:
        return chaotic_realization(system, stream, index, window=window)
    return torus_realization(system, stream, index)
