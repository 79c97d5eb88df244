"""Peer engines for a fair speed comparison with the project's Taylor integrator (heyoka).

What a Python user would pick instead of heyoka for the sleigh's 4-D ODE:

* SciPy's ``solve_ivp`` with a Python right-hand side (:func:`numpy_rhs`: the SymPy
  expressions lambdified to NumPy) or with a compiled one (:func:`compiled_rhs`: numba's
  ``njit`` of the same lambdified code, or heyoka's ``cfunc``), run by :func:`scipy_run`;
* diffrax (JAX) with a jit-compiled adaptive solve (:func:`diffrax_solver`, :func:`diffrax_run`);
* for the largest Lyapunov exponent, lyapax (JAX, Benettin/QR on the tangent map of a
  fixed-step Runge-Kutta map, :func:`lyapax_max_le`) against Benettin's method on heyoka's
  variational equations (:func:`heyoka_max_le`).

Every engine function takes plain arguments (parameter values in ``mechanics.PHYSICAL`` order,
states as sequences) and imports its optional peer inside the function: a missing peer raises
:class:`PeerUnavailable`, an ``ImportError`` that says how to install it. Compile / JIT time is
always measured apart from run time; :func:`timed` (one warm-up call, then the median of
``repeats`` calls) is the one timer used everywhere. :func:`integration_table` runs the whole
end-state comparison; :func:`lyapax_lorenz` / :func:`heyoka_lorenz` and :func:`lyapax_sleigh` /
:func:`heyoka_sleigh` the Lyapunov one.
"""

from __future__ import annotations

import importlib
import math
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache, lru_cache

import numpy as np

#: Extra that installs every peer (pyproject's ``[project.optional-dependencies] bench``).
INSTALL_HINT = "pip install 'sleighsim[bench]'"
#: Index of the angle delta in the sleigh's state (enters only through sin and cos).
DELTA = 3
#: The reference initial state (u, Omega, omega, delta).
Y0_REFERENCE = (0.0, 0.1, 1.0, 0.0)
#: Peer packages (distribution names) reported by :func:`peer_versions`.
PEERS = ("numpy", "scipy", "sympy", "heyoka", "numba", "llvmlite", "jax", "jaxlib", "equinox", "diffrax", "lyapax")


class PeerUnavailable(ImportError):
    """An optional peer engine is not installed (or cannot be used as this module calls it)."""


def _require(module: str, package: str | None = None):
    """Import ``module`` or raise :class:`PeerUnavailable` with the install hint."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        name = package or module.split(".")[0]
        raise PeerUnavailable(f"{name} is not installed: {INSTALL_HINT} ({exc})") from exc


def peer_versions() -> dict:
    """Installed version of every peer package (None when not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for name in PEERS:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = None
    return out


# ----------------------------------------------------------------------------- timing


def timed(fn: Callable[[], object], repeats: int = 5, warmup: int = 1):
    """Call ``fn()`` ``warmup`` times untimed, then ``repeats`` (at least 1) times timed.

    Returns (result of the last call, median wall time [s], list of the timed walls [s])."""
    if repeats < 1 or warmup < 0:
        raise ValueError(f"need repeats >= 1 and warmup >= 0 (repeats={repeats}, warmup={warmup})")
    result = None
    for _ in range(warmup):
        result = fn()
    walls = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        walls.append(time.perf_counter() - start)
    return result, statistics.median(walls), walls


# ----------------------------------------------------------------------------- the sleigh's rhs


def _derivation():
    """The sleigh's rhs in the polynomial form heyoka integrates (mechanics.PolynomialForm, its
    coefficients written out in the physical parameters), so every peer evaluates the same formula."""
    from sleighsim.model import mechanics as m

    d = m.derive()
    return d.polynomial.explicit() + [d.rhs[3]], (*m.STATE, *m.PHYSICAL), len(m.STATE), len(m.PHYSICAL)


@cache
def _lambdified(modules: str):
    import sympy as sp

    exprs, symbols, _, _ = _derivation()
    return sp.lambdify(symbols, tuple(exprs), modules=modules, cse=True)


def _params(param_values, n_expected: int) -> tuple:
    p = tuple(float(v) for v in param_values)
    if len(p) != n_expected:
        raise ValueError(f"need {n_expected} parameter values (mechanics.PHYSICAL order); got {len(p)}")
    return p


def numpy_rhs(param_values) -> Callable:
    """The "Python right-hand side": f(t, y) -> ndarray (4,) for SciPy, the SymPy rhs lambdified
    to NumPy (with common subexpressions), the parameters bound."""
    _, _, _, n_par = _derivation()
    p = _params(param_values, n_par)
    lam = _lambdified("numpy")

    def f(t, y):
        return np.array(lam(*y, *p))

    f.compile_s = 0.0
    f.how = "numpy"
    return f


def compiled_rhs(param_values, how: str = "numba") -> Callable:
    """A compiled f(t, y) -> ndarray (4,) for SciPy: ``how="numba"`` jit-compiles the
    lambdified NumPy code (with common subexpressions) with ``numba.njit``; ``how="heyoka"``
    compiles the SymPy rhs with ``heyoka.cfunc``. The compile / JIT time [s] (including a first
    call, which numba needs to compile) is ``f.compile_s``."""
    _, _, n_state, n_par = _derivation()
    p = _params(param_values, n_par)
    y_probe = np.array(Y0_REFERENCE, dtype=float)
    if how == "numba":
        numba = _require("numba")
        lam = _lambdified("numpy")
        start = time.perf_counter()
        core = numba.njit(lam)

        # The parameters are frozen into the compiled code as constants (closure variables).
        if n_state != 4:  # pragma: no cover - the sleigh's state is 4-D
            raise NotImplementedError("compiled_rhs(how='numba') is written for a 4-D state")

        @numba.njit
        def f(t, y):
            r = core(y[0], y[1], y[2], y[3], *p)
            out = np.empty(4)
            out[0] = r[0]
            out[1] = r[1]
            out[2] = r[2]
            out[3] = r[3]
            return out

        f(0.0, y_probe)  # compile for (float, float64[:])
        f.compile_s = time.perf_counter() - start  # numba dispatchers take attributes: SciPy calls f itself
        f.how = "numba"
        return f
    if how == "heyoka":
        hy = _require("heyoka")
        exprs, symbols, _, _ = _derivation()
        start = time.perf_counter()
        hv = [hy.make_vars(str(s)) for s in symbols[:n_state]]
        smap = {s: v for s, v in zip(symbols[:n_state], hv)}
        # The parameters as numbers, like numba's constants: a cfunc called with pars=... costs
        # about 5 microseconds more per call (argument handling), doubling SciPy's time.
        smap.update({s: hy.expression(v) for s, v in zip(symbols[n_state:], p)})
        cf = hy.cfunc([hy.from_sympy(e, smap) for e in exprs], vars=hv)
        cf(y_probe)
        compile_s = time.perf_counter() - start

        def f(t, y):
            return cf(y)

        f.compile_s = compile_s
        f.how = "heyoka"
        return f
    raise ValueError(f"how must be 'numba' or 'heyoka'; got {how!r}")


def rhs_function(param_values, how: str) -> Callable:
    """f(t, y) for SciPy by name: "numpy", "numba" or "heyoka"."""
    return numpy_rhs(param_values) if how == "numpy" else compiled_rhs(param_values, how)


# ----------------------------------------------------------------------------- SciPy


def scipy_run(f, y0, t_end: float, method: str = "DOP853", rtol: float = 1e-10, atol: float = 1e-13):
    """``solve_ivp(f, (0, t_end), y0, method, rtol, atol)`` without dense output.

    Returns (end state (n,), number of rhs evaluations). Raises RuntimeError when SciPy reports
    a failure (its message says which: e.g. a step size below the spacing of t)."""
    from scipy.integrate import solve_ivp

    sol = solve_ivp(f, (0.0, float(t_end)), np.asarray(y0, dtype=float), method=method, rtol=rtol, atol=atol,
                    dense_output=False)
    if not sol.success:
        raise RuntimeError(f"solve_ivp({method}, rtol={rtol:g}) failed at t = {sol.t[-1]:.6g}: {sol.message}")
    return sol.y[:, -1].copy(), int(sol.nfev)


# ----------------------------------------------------------------------------- JAX / diffrax


def _jax():
    """jax and jax.numpy with float64 enabled (a process-wide JAX setting)."""
    jax = _require("jax")
    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    return jax, jnp


def sleigh_jax(param_values=None) -> Callable:
    """The sleigh's rhs as a JAX function of the state: ``rhs(y) -> (4,)`` with the parameters
    bound, or ``rhs(y, p)`` when ``param_values`` is None (SymPy lambdified with modules="jax")."""
    _, jnp = _jax()
    lam = _lambdified("jax")
    if param_values is None:
        def rhs(y, p):
            return jnp.stack(lam(y[0], y[1], y[2], y[3], *(p[i] for i in range(p.shape[0]))))

        return rhs
    _, _, _, n_par = _derivation()
    p = _params(param_values, n_par)

    def rhs(y):
        return jnp.stack(lam(y[0], y[1], y[2], y[3], *p))

    return rhs


@dataclass
class JaxSolve:
    """A compiled diffrax solve: ``fn(y0, p)`` returns (end state, accepted steps, rejected steps,
    success flag) as JAX arrays; ``compile_s`` is its trace + lower + XLA compile time."""

    fn: Callable
    compile_s: float
    solver: str
    rtol: float
    atol: float
    t_end: float
    max_steps: int

    def __call__(self, y0, param_values):
        _, jnp = _jax()
        out = self.fn(jnp.asarray(y0, dtype=jnp.float64), jnp.asarray(param_values, dtype=jnp.float64))
        y, n_acc, n_rej, ok = (np.asarray(o) for o in out)  # np.asarray blocks until ready
        if not bool(ok):
            raise RuntimeError(f"diffrax {self.solver} (rtol={self.rtol:g}) did not reach t = {self.t_end:g} "
                               f"(accepted {int(n_acc)} + rejected {int(n_rej)} steps of max_steps = {self.max_steps})")
        return y, int(n_acc), int(n_rej)


#: Generous: on the sleigh, t_end = 100 at rtol 1e-12 takes about 2.9e3 Tsit5 steps (5.3e2 Dopri8).
DIFFRAX_MAX_STEPS = 2**20


@lru_cache(maxsize=32)
def diffrax_solver(t_end: float, rtol: float, atol: float, solver: str = "Dopri8",
                   max_steps: int = DIFFRAX_MAX_STEPS) -> JaxSolve:
    """Compile (ahead of time, once per process and setting) a diffrax solve of the sleigh from
    0 to ``t_end`` with a PID step-size controller; the parameters and y0 are run-time inputs."""
    diffrax = _require("diffrax")
    jax, jnp = _jax()
    solvers = {"Dopri8": diffrax.Dopri8, "Tsit5": diffrax.Tsit5, "Dopri5": diffrax.Dopri5}
    if solver not in solvers:
        raise ValueError(f"solver must be one of {sorted(solvers)}; got {solver!r}")
    rhs = sleigh_jax(None)
    term = diffrax.ODETerm(lambda t, y, p: rhs(y, p))
    controller = diffrax.PIDController(rtol=rtol, atol=atol)

    def solve(y0, p):
        sol = diffrax.diffeqsolve(term, solvers[solver](), 0.0, float(t_end), None, y0, args=p,
                                  stepsize_controller=controller, saveat=diffrax.SaveAt(t1=True),
                                  max_steps=max_steps, throw=False, adjoint=diffrax.ForwardMode())
        ok = sol.result == diffrax.RESULTS.successful
        return sol.ys[-1], sol.stats["num_accepted_steps"], sol.stats["num_rejected_steps"], ok

    n_par = _derivation()[3]
    start = time.perf_counter()
    fn = jax.jit(solve).lower(jnp.zeros(len(Y0_REFERENCE)), jnp.zeros(n_par)).compile()
    return JaxSolve(fn, time.perf_counter() - start, solver, rtol, atol, float(t_end), max_steps)


def diffrax_run(param_values, y0, t_end: float, rtol: float, atol: float, solver: str = "Dopri8") -> np.ndarray:
    """End state of the sleigh from y0 over [0, t_end] by diffrax (``solver`` "Dopri8" or
    "Tsit5", PID controller at rtol/atol, float64). The jit-compiled solve is built on the first
    call for each (t_end, rtol, atol, solver) and reused: its compile time is
    ``diffrax_solver(t_end, rtol, atol, solver).compile_s``; later calls time the run only."""
    _require("diffrax")
    _require("jax")
    _, _, _, n_par = _derivation()
    return diffrax_solver(float(t_end), float(rtol), float(atol), solver)(y0, _params(param_values, n_par))[0]


# ----------------------------------------------------------------------------- Lyapunov exponents


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


def lorenz_jax(sigma: float = 10.0, rho: float = 28.0, beta: float = 8.0 / 3.0) -> Callable:
    """Lorenz's rhs as a JAX function of the state (lambda_1 about 0.906 at the defaults)."""
    _, jnp = _jax()

    def rhs(s):
        x, y, z = s[0], s[1], s[2]
        return jnp.stack([sigma * (y - x), x * (rho - z) - y, x * y - beta * z])

    return rhs


def _lyapax():
    lyapax = _require("lyapax")
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
    jax, jnp = _jax()
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
    hy = _require("heyoka")
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
    hy = _require("heyoka")
    x, y, z = hy.make_vars("x", "y", "z")
    return [(x, sigma * (y - x)), (y, x * (rho - z) - y), (z, x * y - beta * z)]


def sleigh_heyoka():
    """The sleigh's system as our engine compiles it (model.heyoka_system: the polynomial form, its
    coefficients K_j runtime parameters after the physical ones; :func:`sleigh_heyoka_pars`)."""
    from sleighsim.model.equations import heyoka_system

    return heyoka_system()


def sleigh_heyoka_pars(param_values) -> list:
    """The runtime parameters of :func:`sleigh_heyoka` from the physical ones (mechanics.PHYSICAL
    order; taken as given, like every peer's, so the formal system's m_c <= 0 passes too)."""
    from sleighsim.model.equations import heyoka_pars
    from sleighsim.model.params import PARAM_NAMES, Params

    return list(heyoka_pars(Params(*_params(param_values, len(PARAM_NAMES)))))


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


# ----------------------------------------------------------------------------- the comparison


def state_error(a, b, angle_index: int | None = DELTA) -> float:
    """max |a - b| over the components, the angle compared modulo 2 pi."""
    d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    if angle_index is not None:
        d[angle_index] = (d[angle_index] + math.pi) % (2.0 * math.pi) - math.pi
    return float(np.max(np.abs(d)))


def integration_table(param_values, y0=Y0_REFERENCE, t_end: float = 100.0, rtols=(1e-6, 1e-8, 1e-10, 1e-12),
                      atol_factor: float = 1e-3, scipy_methods=("DOP853", "RK45", "LSODA"),
                      rhs_kinds=("numpy", "numba", "heyoka"), diffrax_solvers=("Dopri8", "Tsit5"),
                      repeats: int = 3, warmup: int = 1, reference=None, log=print) -> list[dict]:
    """End-state error against a tight reference (default SciPy DOP853, rtol 1e-13, atol 1e-16,
    compiled heyoka rhs) and median wall time of every peer at every rtol (atol = rtol *
    atol_factor). A peer that is not installed or fails is a row with ``error`` set to None and
    ``note`` saying why. Returns one dict per (engine, rtol)."""
    rows = []
    fns, compile_s = {}, {}
    for kind in rhs_kinds:
        try:
            f = numpy_rhs(param_values) if kind == "numpy" else compiled_rhs(param_values, kind)
            fns[kind], compile_s[kind] = f, f.compile_s
        except PeerUnavailable as exc:
            log(f"skip rhs {kind}: {exc}")
    if reference is None:
        ref_f = fns.get("heyoka") or fns.get("numba") or fns["numpy"]
        reference, _ = scipy_run(ref_f, y0, t_end, "DOP853", 1e-13, 1e-16)
    for rtol in rtols:
        atol = rtol * atol_factor
        for method in scipy_methods:
            for kind, f in fns.items():
                row = dict(engine=f"scipy {method} + {kind} rhs", rtol=rtol, atol=atol, compile_s=compile_s[kind])
                try:
                    (y, nfev), wall, walls = timed(lambda f=f, m=method, r=rtol, a=atol: scipy_run(f, y0, t_end, m, r, a),
                                                   repeats=repeats, warmup=warmup)
                    row.update(error=state_error(y, reference), wall_s=wall, walls=walls, nfev=nfev, note="")
                except Exception as exc:  # a failed run is a result of the comparison
                    row.update(error=None, wall_s=None, walls=[], nfev=None, note=str(exc))
                rows.append(row)
                log(_row_text(row))
        for solver in diffrax_solvers:
            row = dict(engine=f"diffrax {solver}", rtol=rtol, atol=atol)
            try:
                js = diffrax_solver(float(t_end), float(rtol), float(atol), solver)
                p = _params(param_values, _derivation()[3])
                (y, n_acc, n_rej), wall, walls = timed(lambda js=js, p=p: js(y0, p), repeats=repeats, warmup=warmup)
                row.update(compile_s=js.compile_s, error=state_error(y, reference), wall_s=wall, walls=walls,
                           nfev=None, steps=n_acc + n_rej, note=f"{n_acc} accepted + {n_rej} rejected steps")
            except Exception as exc:
                row.update(compile_s=None, error=None, wall_s=None, walls=[], nfev=None, note=str(exc))
            rows.append(row)
            log(_row_text(row))
    return rows


def _row_text(row) -> str:
    err = "-" if row.get("error") is None else f"{row['error']:.2e}"
    wall = "-" if row.get("wall_s") is None else f"{row['wall_s'] * 1e3:.2f} ms"
    return f"{row['engine']:<34} rtol {row['rtol']:.0e}  error {err:>9}  wall {wall:>11}  nfev {row.get('nfev')}  {row.get('note', '')}"
