"""Lyapunov peers: the largest Lyapunov exponent by lyapax (JAX, Benettin/QR on the tangent map of a
fixed-step Runge-Kutta map, :func:`lyapax_max_le`) against Benettin's method on heyoka's variational
equations (:func:`heyoka_max_le`), on Lorenz (:func:`lyapax_lorenz` / :func:`heyoka_lorenz`) and on the
sleigh (:func:`lyapax_sleigh` / :func:`heyoka_sleigh`)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from sleighsim.engine.peer_jax import jax_x64, lorenz_jax, sleigh_jax
from sleighsim.engine.peers import DELTA, INSTALL_HINT, Y0_REFERENCE, PeerUnavailable, param_tuple, require, timed


@dataclass
class LyapunovRun:
    """The largest Lyapunov exponent from one engine: lambda_1, median wall time after a warm-up
    [s] (walls: every timed run), compile time [s], and the settings used."""

    engine: str
    lambda_1: float
    wall_s: float
    walls: list
    compile_s: float
    settings: dict = field(default_factory=dict)


def _lyapax():
    lyapax = require("lyapax")
    missing = [n for n in ("lyapunov_spectrum", "ode_step") if not hasattr(lyapax, n)]
    if missing:
        raise PeerUnavailable(f"lyapax {getattr(lyapax, '__version__', '?')} lacks {missing} "
                              f"(written for lyapax 0.3): {INSTALL_HINT}")
    return lyapax


def lyapax_max_le(rhs: Callable, y0, T: float, tau: float, *, dt: float = 0.01, t_transient: float = 0.0,
                  integrator: str = "rk4", angle_index: int | None = None, seed: int = 0, repeats: int = 3,
                  warmup: int = 1) -> LyapunovRun:
    """lambda_1 of ``rhs`` (a JAX function state -> dstate) by lyapax: Benettin's method on the
    tangent map (``jax.jvp``) of a fixed-step ``integrator`` map of step ``dt``, one tangent
    vector renormalised every ``tau`` (a multiple of dt) over T after a transient t_transient.
    The whole computation is jit-compiled ahead of time (compile_s) and then timed. The state
    component ``angle_index`` (an angle entering only through sin and cos) is reduced modulo
    2 pi after every step (its derivative is 1, so the tangent map is unchanged)."""
    lyapax = _lyapax()
    jax, jnp = jax_x64()
    every = int(round(tau / dt))
    if every < 1 or not math.isclose(every * dt, tau, rel_tol=1e-9):
        raise ValueError(f"tau = {tau} must be a positive multiple of dt = {dt}")
    n_steps = every * max(1, int(round(T / (every * dt))))
    step = lyapax.ode_step(rhs, dt, integrator=integrator)
    if angle_index is not None:
        raw_step = step

        def step(state):
            new = raw_step(state)
            return new.at[angle_index].set(jnp.remainder(new[angle_index], 2.0 * math.pi))

    def run(state0):
        res = lyapax.lyapunov_spectrum(step, state0, dt, n_steps, k=1, renorm_every=every,
                                       t_transient=t_transient, seed=seed)
        return res.exponents[0]

    y0 = jnp.asarray(y0, dtype=jnp.float64)
    start = time.perf_counter()
    compiled = jax.jit(run).lower(y0).compile()
    compile_s = time.perf_counter() - start
    lam, wall, walls = timed(lambda: float(compiled(y0)), repeats=repeats, warmup=warmup)
    return LyapunovRun("lyapax", lam, wall, walls, compile_s,
                       dict(T=n_steps * dt, tau=every * dt, dt=dt, t_transient=t_transient, integrator=integrator,
                            angle_index=angle_index))


def heyoka_max_le(sys, y0, T: float, tau: float, *, pars=(), t_transient: float = 0.0, tol: float | None = None,
                  compact_mode: bool = True, angle_index: int | None = None, seed: int = 0, repeats: int = 3,
                  warmup: int = 1) -> LyapunovRun:
    """lambda_1 of ``sys`` (heyoka's [(var, expr), ...]) by Benettin's method on heyoka's
    first-order variational equations: one tangent vector, renormalised every ``tau`` over T
    after a transient t_transient (renormalised, not accumulated). Taylor tolerance ``tol``
    (default: machine epsilon; relative to the state's size, hence ``angle_index``: that angle is
    reduced modulo 2 pi at every renormalisation, so it stays below 2 pi). compile_s is the
    integrator's construction time."""
    hy = require("heyoka")
    sys = list(sys)
    n = len(sys)
    start = time.perf_counter()
    vsys = hy.var_ode_sys(sys, [sys[0][0]], order=1)
    kw = {} if tol is None else {"tol": tol}
    ta = hy.taylor_adaptive(vsys, [0.0] * n, pars=list(pars), compact_mode=compact_mode, **kw)
    compile_s = time.perf_counter() - start
    n_align = int(math.ceil(t_transient / tau)) if t_transient > 0 else 0
    n_steps = max(1, int(round(T / tau)))
    v0 = np.random.default_rng(seed).normal(size=n)

    def run():
        ta.time = 0.0
        ta.state[:n] = np.asarray(y0, dtype=float)
        ta.state[n:] = v0 / np.linalg.norm(v0)
        total = 0.0
        for i in range(-n_align, n_steps):
            oc = ta.propagate_for(tau)[0]
            if oc != hy.taylor_outcome.time_limit:
                raise RuntimeError(f"heyoka Benettin run stopped at t = {ta.time:g}: {oc}")
            if angle_index is not None:
                ta.state[angle_index] %= 2.0 * math.pi
            norm = float(np.linalg.norm(ta.state[n:]))
            ta.state[n:] /= norm
            if i >= 0:
                total += math.log(norm)
        return total / (n_steps * tau)

    lam, wall, walls = timed(run, repeats=repeats, warmup=warmup)
    return LyapunovRun("heyoka", lam, wall, walls, compile_s,
                       dict(T=n_steps * tau, tau=tau, t_transient=n_align * tau, tol=tol, compact_mode=compact_mode,
                            angle_index=angle_index))


def lorenz_heyoka(sigma: float = 10.0, rho: float = 28.0, beta: float = 8.0 / 3.0):
    """Lorenz's system for heyoka: [(var, expr), ...]."""
    hy = require("heyoka")
    x, y, z = hy.make_vars("x", "y", "z")
    return [(x, sigma * (y - x)), (y, x * (rho - z) - y), (z, x * y - beta * z)]


def sleigh_heyoka():
    """The sleigh's system as our engine compiles it (model.heyoka_system: the polynomial form, its
    coefficients K_j runtime parameters after the physical ones; :func:`sleigh_heyoka_pars`)."""
    from sleighsim.model.equations import heyoka_system

    return heyoka_system()


def sleigh_heyoka_pars(param_values) -> list:
    """The runtime parameters of :func:`sleigh_heyoka` from the physical ones (mechanics.PHYSICAL
    order; checked as Params checks them, admitting the formal system's m_c <= 0)."""
    from sleighsim.model.equations import heyoka_pars
    from sleighsim.model.params import PARAM_NAMES, Params

    return list(heyoka_pars(Params(*param_tuple(param_values, len(PARAM_NAMES)), formal=True)))


LORENZ_Y0 = (1.0, 1.0, 1.0)
#: Published lambda_1 of Lorenz at sigma 10, rho 28, beta 8/3.
LORENZ_LAMBDA_1 = 0.906


def lyapax_lorenz(T: float = 500.0, tau: float = 1.0, dt: float = 0.01, t_transient: float = 50.0, **kw) -> LyapunovRun:
    """lyapax on Lorenz (sigma 10, rho 28, beta 8/3) from (1, 1, 1)."""
    _lyapax()
    return lyapax_max_le(lorenz_jax(), LORENZ_Y0, T, tau, dt=dt, t_transient=t_transient, **kw)


def heyoka_lorenz(T: float = 500.0, tau: float = 1.0, t_transient: float = 50.0, **kw) -> LyapunovRun:
    """heyoka's variational Benettin on Lorenz (sigma 10, rho 28, beta 8/3) from (1, 1, 1)."""
    return heyoka_max_le(lorenz_heyoka(), LORENZ_Y0, T, tau, t_transient=t_transient, **kw)


def lyapax_sleigh(param_values, y0=Y0_REFERENCE, T: float = 1000.0, tau: float = 1.0, dt: float = 0.01,
                  t_transient: float = 100.0, **kw) -> LyapunovRun:
    """lyapax on the sleigh (parameters bound), delta reduced modulo 2 pi after every step."""
    _lyapax()
    return lyapax_max_le(sleigh_jax(param_values), y0, T, tau, dt=dt, t_transient=t_transient, angle_index=DELTA, **kw)


def heyoka_sleigh(param_values, y0=Y0_REFERENCE, T: float = 1000.0, tau: float = 1.0, t_transient: float = 100.0,
                  **kw) -> LyapunovRun:
    """heyoka's variational Benettin on the sleigh, delta reduced modulo 2 pi every tau."""
    return heyoka_max_le(sleigh_heyoka(), y0, T, tau, pars=sleigh_heyoka_pars(param_values), t_transient=t_transient,
                         angle_index=DELTA, **kw)
