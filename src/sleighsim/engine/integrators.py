"""Compiled heyoka integrators: one cache per process, and the angles each keeps bounded.

An integrator is compiled once per process for its structure (system, tolerance, mode) and
reused; parameters are runtime par[] and states are set per run. heyoka also keeps compiled
code in its on-disk cache (heyoka.llvm_state), so a new process reuses earlier compilations.

Bounded angles. heyoka sizes its steps from the infinity norm of the whole state, so an angle
that grows without bound (delta = theta - beta decreases by about 3.4 per time unit at
eps = 0.1) loosens the accuracy of u and Omega in proportion to it. The equations depend on
delta only through sin and cos, so reducing it by whole turns is an exact symmetry: every
integrator registers its angles here, and every propagation passes :func:`bounded` as its
step callback (heyoka's compiled angle reducer, which brings them back to [0, 2 pi) after
every step, at no measurable cost per step). The sleigh's integrators store delta + pi, so
the reduced angle is delta in [-pi, pi) and never exceeds |omega| (about 3.4 on the attractor)
in that norm; :func:`load`, :func:`read` and :func:`samples` convert to and from the model's
variables.

JIT cache. heyoka's on-disk cache is on by default (~/.cache/heyoka); ``SLEIGHSIM_JIT_CACHE``
points it elsewhere, e.g. node-local storage on a cluster (the cache does not support network
file systems). Measured per process on this machine (CPU seconds, median of 3,
benchmarks/startup.py): building the plain flow 0.76 s without the cache, 0.22 s with it (0.09 s
of that lambdifies the polynomial form's coefficients, once per process); the 4-lane tangent
batch 0.59 s, 0.04 s. (Measured over 1e6 time units from the reference state at tol 2.2e-16: energy
drift 1.0e-12 with delta in [0, 2 pi), 5.9e-13 with delta in [-pi, pi); 2.3e-12 within 1e4
time units when delta is left to grow.)
"""

from __future__ import annotations

import math
import os
import time
from typing import Callable

import numpy as np

from sleighsim.engine.precision import Precision

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
        _jit_cache_path()
        start = time.perf_counter()
        ta = build()
        _CACHE[key] = (ta, time.perf_counter() - start)
        register(ta, angles)
    return _CACHE[key]


def _jit_cache_path() -> None:
    """Point heyoka's on-disk cache at $SLEIGHSIM_JIT_CACHE when set (created if missing)."""
    path = os.environ.get("SLEIGHSIM_JIT_CACHE")
    if path:
        import heyoka as hy

        os.makedirs(path, exist_ok=True)
        if hy.llvm_state.get_diskcache_path() != path:
            hy.llvm_state.set_diskcache_path(path)


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
