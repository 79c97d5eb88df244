"""An orbit in any arithmetic: the one place an integrator for an arbitrary system is built and the
one place an orbit is sampled on a time grid.

- :func:`taylor`: heyoka's integrator for any system (list of (variable, expression)) in a heyoka
  arithmetic, compiled once per process (``integrators.compiled``), with the JIT cache checked;
- :func:`grid_samples`: a heyoka integrator of any system, its state set, sampled at t = 0, dt, ...,
  (n - 1) dt in one ``propagate_grid`` run, in the integrator's arithmetic;
- :func:`sleigh_orbit`: the sleigh from a state in the model's variables, sampled on such a grid, in
  any :class:`~sleighsim.precision.Precision` (heyoka's, or double-double through
  :class:`~sleighsim.engine.ddtaylor.DDFlow`).

Times in the flow's time unit; the flows are autonomous, so every run starts at t = 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sleighsim.engine import integrators
from sleighsim.precision import Precision


def taylor(name: str, build_sys, precision: Precision = Precision.DOUBLE, *, tol: float | None = None,
           compact: bool = True, angles: dict | None = None):
    """(integrator, compile seconds) of the system ``build_sys(heyoka)`` (list of (var, expr)) in the heyoka
    arithmetic ``precision`` at ``tol`` (heyoka's default, the arithmetic's epsilon, when None), compiled
    once per process under ``name``; ``angles`` as ``integrators.compiled`` (none by default)."""
    fp = precision.fp_type

    def build():
        hy = integrators.guarded_heyoka()
        sys = build_sys(hy)
        kw = {} if tol is None else {"tol": fp(tol)}
        return hy.taylor_adaptive(sys, np.full(len(sys), 0.1, dtype=fp), fp_type=fp, compact_mode=compact, **kw)

    return integrators.compiled(("taylor", name, precision, tol, compact), build, angles={} if angles is None
                                else angles)


def grid_samples(ta, n: int, dt: float, callback=None) -> tuple[np.ndarray, int]:
    """(samples, steps): the state of ``ta`` (its state and parameters set by the caller) at t = 0, dt, ...,
    (n - 1) dt, one row per time in ``ta``'s own arithmetic (double, long double or real128; the grid built
    in it too), from one ``propagate_grid`` run with ``callback`` (e.g. ``integrators.bounded(ta)``).
    RuntimeError naming the time when the run stops early or leaves the finite numbers."""
    import heyoka as hy

    fp = ta.state.dtype.type
    ta.time = fp(0)
    grid = np.arange(n).astype(ta.state.dtype) * fp(dt)
    res = ta.propagate_grid(grid) if callback is None else ta.propagate_grid(grid, callback=callback)
    out = np.asarray(res[-1])
    if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(out.astype(float))):
        raise RuntimeError(f"integration stopped at t = {float(ta.time):.6g} (target {float(grid[-1]):.6g}): "
                           f"heyoka outcome {res[0]}")
    return out, int(res[3])


@dataclass
class Orbit:
    """An orbit of the sleigh sampled on t = 0, dt, ...: ``t`` (n,), ``Y`` (n, 4) in the model's variables
    as doubles (double-double: the high parts), ``lo`` the low parts in double-double (None otherwise),
    ``steps`` the integrator's steps, ``precision`` and ``tol``."""

    t: np.ndarray
    Y: np.ndarray
    lo: np.ndarray | None
    steps: int
    precision: Precision
    tol: float


def sleigh_orbit(params, y, precision: Precision | str, tol: float, n: int, dt: float) -> Orbit:
    """The sleigh with ``params`` from ``y`` (model variables) at t = 0, dt, ..., (n - 1) dt in ``precision``
    (the type or its name) at ``tol``: heyoka's compiled flow (``integrators.flow``, the angle kept bounded)
    or, in double-double, ``ddtaylor.DDFlow``."""
    precision = Precision.parse(precision)
    if not precision.heyoka:
        from sleighsim.engine.ddtaylor import DDFlow

        flow = DDFlow(params, tol)
        t = np.arange(n) * dt
        hi, lo = flow.propagate_grid(np.asarray(y, float), t)
        return Orbit(t, hi, lo, flow.steps, precision, tol)
    ta, _ = integrators.flow(False, tol, precision)
    integrators.set_pars(ta, params)
    integrators.load(ta, np.asarray(y, float))
    raw, steps = grid_samples(ta, n, dt, integrators.bounded(ta))
    return Orbit(dt * np.arange(n), integrators.samples(ta, raw.astype(float)), None, steps, precision, tol)
