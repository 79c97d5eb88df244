"""Compiled heyoka integrators: every builder of the project (the flow, its tangent and MEGNO extensions, the
section events, the divergence quadrature, the perturbation hierarchy, the printed equations), one cache per
process, and the angles each keeps bounded.

An integrator is compiled once per process for its structure (system, tolerance, mode) and reused; parameters are
runtime par[] and states are set per run. heyoka also keeps compiled code in its on-disk cache (heyoka.llvm_state),
so a new process reuses earlier compilations.

Bounded angles. heyoka sizes its steps from the infinity norm of the whole state, so an angle that grows without
bound (delta = theta - beta decreases by about 3.4 per time unit at eps = 0.1) loosens the accuracy of u and Omega
in proportion to it. The equations depend on delta only through sin and cos, so reducing it by whole turns is an
exact symmetry: every integrator registers its angles here, and every propagation passes :func:`bounded` as its step
callback (heyoka's compiled angle reducer, which brings them back to [0, 2 pi) after every step, at no measurable
cost per step). The sleigh's integrators store delta + pi, so the reduced angle is delta in [-pi, pi) and never
exceeds |omega| (about 3.4 on the attractor) in that norm; :func:`load`, :func:`read` and :func:`samples` convert to
and from the model's variables.

JIT cache. heyoka's on-disk cache is on by default (~/.cache/heyoka); ``SLEIGHSIM_JIT_CACHE`` points it elsewhere,
e.g. node-local storage on a cluster (the cache does not support network file systems). Either must be a directory
only this user controls (sleighsim.io.cachedir), since heyoka runs the code it finds there. Measured per process on this
machine (CPU seconds, median of 3, benchmarks/startup.py): building the plain flow 0.76 s without the cache, 0.22 s
with it (0.09 s of that lambdifies the polynomial form's coefficients, once per process); the 4-lane tangent batch
0.59 s, 0.04 s. (Measured over 1e6 time units from the reference state at tol 2.2e-16: energy drift 1.0e-12 with
delta in [0, 2 pi), 5.9e-13 with delta in [-pi, pi); 2.3e-12 within 1e4 time units when delta is left to grow.)
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable

import numpy as np

from sleighsim.io.cachedir import private_directory
from sleighsim.model.params import positive
from sleighsim.precision import Precision

#: The sleigh's angle as its compiled integrators store it: delta + DELTA_SHIFT, in [0, 2 pi).
DELTA_SHIFT = math.pi
#: Angle variables of the sleigh's integrators: name -> (state index, stored shift).
SLEIGH_ANGLES = {"delta": (3, DELTA_SHIFT)}

_CACHE: dict = {}
_ANGLES: dict = {}


def compiled(key: tuple, build: Callable, angles: dict = SLEIGH_ANGLES):
    """(integrator, compile seconds) for ``key``: built by ``build()`` on first use in this process;
    ``angles`` (name -> (state index, stored shift)) are the variables :func:`bounded` keeps in [0, 2 pi)."""
    if key not in _CACHE:
        guarded_heyoka()
        start = time.perf_counter()
        ta = build()
        _CACHE[key] = (ta, time.perf_counter() - start)
        register(ta, angles)
    return _CACHE[key]


def guarded_heyoka():
    """heyoka, its on-disk cache pointed at $SLEIGHSIM_JIT_CACHE when set (else heyoka's default), a
    directory only this user controls (:func:`sleighsim.io.cachedir.private_directory`: created 0700,
    refused when another user owns or can write it, since heyoka runs the code it finds there). Every
    heyoka build calls it first."""
    import heyoka as hy

    if not hy.llvm_state.get_diskcache_enabled():
        return hy
    path = os.environ.get("SLEIGHSIM_JIT_CACHE")
    what = "SLEIGHSIM_JIT_CACHE" if path else "heyoka's default cache directory"
    path = str(private_directory(path or hy.llvm_state.get_diskcache_path(), what))
    if hy.llvm_state.get_diskcache_path() != path:
        hy.llvm_state.set_diskcache_path(path)
    return hy


def register(ta, angles: dict) -> None:
    """Make :func:`bounded` reduce ``angles`` (name -> (state index, stored shift)) of ``ta`` after every step."""
    import heyoka as hy

    reducer = hy.callback.angle_reducer([hy.make_vars(a) for a in angles]) if angles else None
    _ANGLES[id(ta)] = (reducer, [(i, shift) for i, shift in angles.values() if shift])


def copy_angles(source, target) -> None:
    """Give ``target`` (an object holding a copy of ``source``'s state) ``source``'s stored angle
    shifts, so :func:`load` and :func:`read` convert its state the same way."""
    _ANGLES[id(target)] = (None, _shifts(source))


def bounded(ta):
    """The step callback that keeps the registered angles of ``ta`` in [0, 2 pi) (None when it has none)."""
    return _ANGLES.get(id(ta), (None, []))[0]


def _shifts(ta):
    return _ANGLES.get(id(ta), (None, []))[1]


def load(ta, y) -> None:
    """Set the leading components of ``ta``'s state (rows, for a batch integrator) from y, given in
    the model's variables."""
    y = np.array(y, dtype=ta.state.dtype)
    for i, shift in _shifts(ta):
        y[i] += y.dtype.type(shift)
    ta.state[: y.shape[0]] = y


def read(ta, n: int) -> np.ndarray:
    """The first n components of ``ta``'s state (rows, for a batch integrator) in the model's variables."""
    y = np.array(ta.state[:n])
    for i, shift in _shifts(ta):
        y[i] -= y.dtype.type(shift)
    return y


def samples(ta, Y) -> np.ndarray:
    """Samples of ``ta``'s state (one row per time, as propagate_grid returns them) in the model's variables."""
    Y = np.array(Y)
    for i, shift in _shifts(ta):
        Y[:, i] -= Y.dtype.type(shift)
    return Y


def set_pars(ta, params) -> None:
    """Give the compiled sleigh ``ta`` the runtime parameters of ``params`` (model.heyoka_pars, in
    ta's floating-point type; the same in every lane of a batch integrator)."""
    from sleighsim.model.equations import heyoka_pars

    values = heyoka_pars(params, ta.pars.dtype)
    ta.pars[:] = values[:, None] if ta.pars.ndim == 2 else values


def flow(kinematics: bool, tol: float, precision: Precision = Precision.DOUBLE):
    """The sleigh (with (theta, x, y) when ``kinematics``), in double, long double (80-bit on
    x86-64, machine epsilon 1.1e-19) or quadruple precision (heyoka's real128, machine epsilon
    1.9e-34). Full (not compact) mode in double and long double, compact mode in quad, whichever
    steps faster there (benchmarks/precision_cost.yaml: costs per time unit and compile times per
    precision and mode). Returns (integrator, compile seconds)."""
    fp, quad = precision.fp_type, precision is Precision.QUAD

    def build():
        import heyoka as hy

        from sleighsim.model.equations import compile_pars, heyoka_system

        n = 7 if kinematics else 4
        y0 = np.array([0.0, 0.1, 1.0, DELTA_SHIFT] + [0.0] * (n - 4)).astype(fp)
        return hy.taylor_adaptive(heyoka_system(kinematics, DELTA_SHIFT), y0, tol=fp(tol),
                                  pars=compile_pars(fp), fp_type=fp, compact_mode=quad)

    return compiled(("flow", kinematics, tol, precision), build)


def rhs_function(kinematics: bool = False, k: int = 0, params=None):
    """The sleigh's right-hand side compiled by heyoka (``heyoka.cfunc``): f(y, pars) for the flow
    (with the path when ``kinematics``) or, with k > 0, for the flow plus k tangent vectors (the
    state (n + n k), vectors stored (n, k) row-major). With ``params`` their values
    (model.heyoka_pars) are compiled in as numbers and f takes y alone: a single call then costs
    about 3 microseconds against 10 with ``pars=`` (heyoka's handling of the argument), and SciPy's
    RK45 runs 1.2x faster (its own bookkeeping is most of a step; one compilation per parameter
    set, about 0.02 s, kept in the disk cache). Compiled once per process."""
    from sleighsim.model.equations import heyoka_pars

    values = None if params is None else tuple(float(v) for v in heyoka_pars(params))

    def build():
        import heyoka as hy

        from sleighsim.model.equations import heyoka_system

        sys = heyoka_system(kinematics)
        if k:
            sys = list(hy.var_ode_sys(sys, [v for v, _ in sys[:k]], order=1).sys)
        exprs = [e for _, e in sys]
        if values is not None:
            exprs = hy.subs(exprs, {hy.par[i]: hy.expression(v) for i, v in enumerate(values)})
        return hy.cfunc(exprs, vars=[v for v, _ in sys])

    return compiled(("cfunc", kinematics, k, values), build, angles={})[0]


def _tangent(sys, k: int, make):
    """(ta, n, compile_s) of ``make(vsys, n)``: heyoka's first-order variational equations of ``sys``
    (list of (var, expr)) with respect to its first k variables, built by ``make``."""
    hy = guarded_heyoka()

    sys = list(sys)
    n = len(sys)
    if not 1 <= k <= n:
        raise ValueError(f"k = {k} is outside the admissible range [1, {n}]")
    start = time.perf_counter()
    vsys = hy.var_ode_sys(sys, [v for v, _ in sys[:k]], order=1)
    return make(vsys, n), n, time.perf_counter() - start


def tangent_integrator(sys, k: int, tol: float = 2.0**-52, pars=(), compact_mode: bool = True,
                       precision: Precision = Precision.DOUBLE):
    """heyoka integrator for ``sys`` (list of (var, expr)) plus k tangent vectors, in ``precision``.

    Returns (ta, n, compile_s); the state is [y (n), V (n x k, row-major)]."""
    import heyoka as hy

    fp = precision.fp_type
    return _tangent(sys, k, lambda vsys, n: hy.taylor_adaptive(
        vsys, np.full(n, 0.1, dtype=fp), tol=fp(tol), pars=np.array(pars, dtype=fp), compact_mode=compact_mode,
        fp_type=fp))


def tangent_integrator_batch(sys, batch_size: int, tol: float = 2.0**-52, npars: int = 0,
                             compact_mode: bool = True, k: int = 1):
    """heyoka batch integrator (SIMD lanes, double) for ``sys`` plus k tangent vectors per lane.

    Returns (ta, n, compile_s); the state has shape (n + n k, batch_size), the tangent
    vectors stored as (n, k) row-major below the state."""
    import heyoka as hy

    return _tangent(sys, k, lambda vsys, n: hy.taylor_adaptive_batch(
        vsys, np.full((n + n * k, batch_size), 0.1), tol=tol, pars=np.zeros((npars, batch_size)),
        compact_mode=compact_mode))


def sleigh_tangent(k: int, tol: float, compact: bool, precision: Precision = Precision.DOUBLE):
    """The sleigh plus k tangent vectors in ``precision``, compiled once per process.
    compact_mode compiles in 0.1-1 s; full mode steps 1.3-2.3x faster here but its first
    compilation takes seconds to about a minute (45 s for 8 lanes and 4 vectors; later ones come
    from heyoka's on-disk cache). Returns (ta, compile_s)."""
    from sleighsim.model import equations

    def build():
        return tangent_integrator(equations.heyoka_system(delta_shift=DELTA_SHIFT), k, tol,
                                  equations.compile_pars(precision.fp_type), compact_mode=compact,
                                  precision=precision)[0]

    return compiled(("tangent", k, tol, compact, precision), build)


def sleigh_tangent_batch(batch_size: int, tol: float, compact: bool, k: int = 1):
    """The sleigh plus k tangent vectors in ``batch_size`` SIMD lanes, compiled once per process.
    Returns (ta, compile_s)."""
    from sleighsim.model import equations

    def build():
        return tangent_integrator_batch(equations.heyoka_system(delta_shift=DELTA_SHIFT), batch_size, tol,
                                        npars=equations.n_heyoka_pars(), compact_mode=compact, k=k)[0]

    return compiled(("tangent_batch", batch_size, tol, compact, k), build)


def megno_integrator(sys, pars=(), tol=None, compact_mode=True, precision: Precision = Precision.DOUBLE):
    """heyoka integrator for ``sys`` (list of (var, expr)), one tangent vector and the MEGNO
    quadratures.

    State layout: [y (n), delta (n), I, J] with delta the variational vector (heyoka's
    derivatives with respect to the first initial condition, overwritten by ``chaos.megno.megno``),
    I' = t (delta_dot . delta) / (delta . delta) and J' = 2 I / t, so that
    Y(t) = 2 I / t and <Y>(t) = J / t (t = heyoka's time, which must start > 0), in the arithmetic
    ``precision``. Returns (ta, n).
    """
    hy = guarded_heyoka()

    fp_type = precision.fp_type
    sys = list(sys)
    n = len(sys)
    if n == 0:
        raise ValueError("sys is empty")
    names = {str(v) for v, _ in sys}
    if {"megno_I", "megno_J"} & names:
        raise ValueError("sys must not use the variable names megno_I / megno_J")
    vsys = hy.var_ode_sys(sys, [sys[0][0]], order=1)
    eqs = list(vsys.sys)
    if len(eqs) != 2 * n:
        raise RuntimeError(f"var_ode_sys returned {len(eqs)} equations, expected {2 * n}")
    delta = [v for v, _ in eqs[n:]]
    ddot = [e for _, e in eqs[n:]]
    qi, qj = hy.make_vars("megno_I", "megno_J")
    num = hy.sum([d * f for d, f in zip(delta, ddot)])
    den = hy.sum([d * d for d in delta])
    eqs += [(qi, hy.time * num / den), (qj, 2.0 * qi / hy.time)]
    kw = {"pars": np.array(pars, dtype=fp_type), "compact_mode": compact_mode, "fp_type": fp_type}
    if tol is not None:
        kw["tol"] = fp_type(positive("tol", tol))
    ta = hy.taylor_adaptive(eqs, np.array([0.1] * n + [1.0] * n + [0.0, 0.0], dtype=fp_type), **kw)
    return ta, n


def sleigh_megno(tol: float, precision: Precision = Precision.DOUBLE, compact: bool = True):
    """The sleigh, one tangent vector and the MEGNO quadratures (:func:`megno_integrator`, in
    compact or full mode), in ``precision`` (long double: 80-bit on x86-64, machine epsilon
    1.1e-19, about 5x the cost of double), compiled once per process. Returns (ta, compile_s)."""
    from sleighsim.model import equations

    def build():
        return megno_integrator(equations.heyoka_system(delta_shift=DELTA_SHIFT),
                                pars=equations.compile_pars(precision.fp_type), tol=tol, precision=precision,
                                compact_mode=compact)[0]

    return compiled(("megno", tol, precision, compact), build)


def divergence(tol):
    """The sleigh (in double) plus a quadrature D' = trace J(y): D(T)/T is the mean phase-space
    contraction, computed without tangent vectors. Compiled once per process; returns the integrator."""
    from sleighsim.model import equations

    def build():
        import heyoka as hy

        sys = equations.heyoka_system(delta_shift=DELTA_SHIFT)
        trace = hy.sum([hy.diff(e, v) for v, e in sys])
        return hy.taylor_adaptive(sys + [(hy.make_vars("D"), trace)], [0.0, 0.1, 1.0, 0.0, 0.0], tol=tol,
                                  pars=equations.compile_pars())

    return compiled(("divergence", tol), build)[0]


class EventRecorder:
    """Event callback of :func:`events`: stores (local t, u, Omega, omega, delta, time offset) in ``hits``."""

    def __init__(self):
        self.hits, self.offset = [], 0.0  # hits: list of tuples; offset: the chunk's absolute start time

    def __call__(self, ta, t, d_sgn):
        """Record the dense state at the event time ``t`` (heyoka's non-terminal event callback)."""
        ta.update_d_output(t)
        self.hits.append((t, *ta.d_output[:4], self.offset))


def events(tol: float, precision: Precision = Precision.DOUBLE):
    """The sleigh with the sin(2 delta) = 0 event (an :class:`EventRecorder`, ``ta.nt_events[0].callback``)
    in ``precision``, compiled once per process. Returns (ta, compile_s)."""
    fp = precision.fp_type

    def build():
        import heyoka as hy

        from sleighsim.model import equations

        sys = equations.heyoka_system(delta_shift=DELTA_SHIFT)
        stored = sys[3][0]  # delta + pi: sin(2 (delta + pi)) = sin(2 delta)
        y0 = np.array([0.0, 0.1, 1.0, DELTA_SHIFT]).astype(fp)
        return hy.taylor_adaptive(sys, y0, pars=equations.compile_pars(fp), tol=fp(tol), fp_type=fp,
                                  nt_events=[hy.nt_event(hy.sin(2.0 * stored), EventRecorder(), fp_type=fp)])

    return compiled(("events", tol, precision), build)


def printed(tol: float):
    """The paper's equations as printed (``model.printed``, audit only), compiled once per process: (ta, compile_s)."""
    import heyoka as hy

    from sleighsim.model.printed import heyoka_system  # here, not at the top: SymPy costs start-up time

    y0, pars = [0.0, 0.1, 1.0, 0.0], [0.1, 1.0, 1.1]  # pars: (eps, b, K2); delta unshifted, kept in [0, 2 pi)
    return compiled(("printed", tol), lambda: hy.taylor_adaptive(heyoka_system(), y0, pars=pars, tol=tol),
                    angles={"delta": (3, 0.0)})


def hierarchy(order: int, tol: float):
    """The perturbation hierarchy to ``order`` (``model.perturbation.hierarchy``; delta0 kept in
    [0, 2 pi)), compiled once per process. Returns (ta, compile_s)."""
    return compiled(("hierarchy", order, tol), lambda: _build_hierarchy(order, tol), angles={"delta0": (3, 0.0)})


def _build_hierarchy(order: int, tol: float):
    import heyoka as hy
    import sympy as sp  # here, not at the top: SymPy costs start-up time every other integrator saves

    from sleighsim.model import mechanics as mech
    from sleighsim.model import perturbation as pert

    x = pert.symbols(order)
    names = pert.state_names(order)
    hv = dict(zip(names, hy.make_vars(*names)))
    smap = {x[v][k]: hv[f"{v}{k}"] for v in pert.VARS for k in range(order + 1)}
    smap.update({mech.b: hy.par[0], mech.K2: hy.par[1], pert.kappa: hy.par[2]})
    h = pert.hierarchy(order)

    def convert(e):
        """SymPy -> heyoka. Rationals with non-dyadic denominators become doubles; integer
        powers above 2 become explicit products, because heyoka's general pow recurrence
        divides by the base, which starts at zero (orders >= 1, sin(delta0))."""
        if e == 0:
            return hy.expression(0.0)
        e = e.xreplace({r: sp.Float(r, 17) for r in e.atoms(sp.Rational) if r.q & (r.q - 1)})
        local = dict(smap)
        for z in sorted((z for z in e.atoms(sp.Pow) if z.exp.is_Integer and z.exp > 2), key=sp.default_sort_key):
            base = hy.from_sympy(z.base, smap)
            prod = base
            for _ in range(int(z.exp) - 1):
                prod = prod * base
            d = sp.Dummy()
            local[d] = prod
            e = e.xreplace({z: d})
        return hy.from_sympy(e, local)

    sys = [(hv[f"{v}{k}"], convert(h[v][k])) for k in range(order + 1) for v in pert.VARS]
    return hy.taylor_adaptive(sys, [0.0] * len(names), pars=[1.0, 1.1, 1.0], tol=tol, compact_mode=order > 2)
