"""Integration engine: one call runs the model and returns a sampled xarray Dataset.

Backends:
- ``heyoka`` (default): adaptive Taylor integrator. Parameters enter as par[],
  so one compiled integrator per (kinematics, tol) serves every parameter set;
  it is compiled once per process and reused.
- ``scipy``: ``scipy.integrate`` one-step solvers (DOP853 by default), the
  independent reference, driven step by step so steps are counted.

Every dataset carries its parameters, initial state, energy, numerical
settings, step count, wall time and maximum relative energy drift (provenance is added
when a dataset is written, :func:`sleighsim.io.netcdf.write_dataset`).
"""

from __future__ import annotations

import logging
import math
import time
from functools import partial

import numpy as np
import xarray as xr

from sleighsim.engine import integrators
from sleighsim.model import equations
from sleighsim.model.attrs import UNITS, state_attrs
from sleighsim.model.params import Params, finite, integer
from sleighsim.precision import Precision

log = logging.getLogger("sleighsim")

DEFAULT_TOL = 2.0**-52  # heyoka's default: double-precision epsilon
#: The largest step limit (and progress count) accepted: heyoka counts steps in a signed 64-bit integer.
MAX_STEPS = 2**63 - 1
SCIPY_METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
TWO_PI = 2.0 * math.pi


class IntegrationError(RuntimeError):
    """The integrator stopped early (step-size underflow, non-finite state, ...)."""


def final_state(ds: xr.Dataset) -> np.ndarray:
    """(u, Omega, omega, delta) at the last sample of a trajectory dataset."""
    return np.array([ds[v].values[-1] for v in equations.STATE_NAMES])


def sample_grid(t_start: float, t_end: float, dt: float) -> np.ndarray:
    """Uniform grid t_start, t_start + dt, ... up to t_end (inclusive within dt/1000)."""
    if not (math.isfinite(t_start) and math.isfinite(t_end) and math.isfinite(dt)):
        raise ValueError("sample grid bounds and dt must be finite")
    if dt <= 0:
        raise ValueError(f"dt = {dt} is outside the admissible range (0, inf)")
    if t_end < t_start:
        raise ValueError(f"t_end = {t_end} is before t_start = {t_start}")
    n = int(math.floor((t_end - t_start) / dt + 1e-3)) + 1
    return t_start + dt * np.arange(n)


def check_tol(tol, precision: Precision = Precision.DOUBLE) -> None:
    """A heyoka tolerance in [epsilon of ``precision``, 1) (Precision.epsilon: double 2.2e-16, long
    double 1.08e-19, quad 1.93e-34): a finer one asks for more than the arithmetic holds, and the
    integrator then steps without end. TypeError or ValueError naming ``tol`` and the range."""
    eps = precision.epsilon
    if not eps <= finite("tol", tol) < 1:
        raise ValueError(f"tol = {tol} is outside the admissible range [{eps:.3g}, 1) of {precision} "
                         f"(not below its machine epsilon)")


#: SciPy raises a relative tolerance below this (100 x double's epsilon) to it, with a warning.
SCIPY_MIN_RTOL = 100 * 2.0**-52


def _check_scipy(precision, method, rtol, atol) -> None:
    """The SciPy backend's arithmetic (double only), ``method``, ``rtol`` and ``atol``: TypeError or
    ValueError naming the argument and its admissible range, before any work."""
    if precision is not Precision.DOUBLE:
        raise ValueError(f"precision {precision.value!r}: the SciPy backend runs in double only")
    if method not in SCIPY_METHODS:
        raise ValueError(f"unknown SciPy method {method!r}; choose one of {sorted(SCIPY_METHODS)}")
    if not SCIPY_MIN_RTOL <= finite("rtol", rtol) < 1:
        raise ValueError(f"rtol = {rtol} is outside the admissible range [{SCIPY_MIN_RTOL:.3g}, 1) (SciPy raises "
                         "a smaller one to 100 x double's machine epsilon)")
    if not finite("atol", atol) > 0:
        raise ValueError(f"atol = {atol} is outside the admissible range (0, inf)")


def _sample_times(times, t0) -> tuple[np.ndarray, float]:
    """The sample times as a float array and the start time (default: the first sample), checked."""
    times = np.asarray(times, dtype=float).ravel()
    if times.size == 0 or not np.all(np.isfinite(times)) or np.any(np.diff(times) <= 0):
        raise ValueError("sample times must be a non-empty, finite, strictly increasing sequence")
    t0 = float(times[0]) if t0 is None else float(t0)
    if not (math.isfinite(t0) and t0 <= times[0]):
        raise ValueError(f"t0 = {t0} is outside the admissible range (-inf, first sample time {times[0]}]")
    return times, t0


def _initial_state(y0, kinematics: bool) -> np.ndarray:
    """``y0`` as a float array of 4 (or with the path 7) finite real numbers; TypeError naming it when
    it holds anything but real numbers (complex, strings, objects), ValueError for its size or a NaN."""
    try:
        values = np.asarray(y0)
    except (TypeError, ValueError):  # ragged
        values = np.asarray(None)
    if values.dtype.kind not in "iuf" or values.ndim == 0:
        raise TypeError(f"y0 = {y0!r} must be a sequence of numbers (u, Omega, omega, delta), all real")
    y0 = values.astype(float).ravel()
    want = 7 if kinematics else 4
    if y0.size == 4 and kinematics:
        y0 = np.concatenate([y0, np.zeros(3)])
    if y0.size != want:
        extra = " or 7 with (theta, x, y)" if kinematics else ""
        raise ValueError(f"y0 (initial state) has {y0.size} components; expected 4 (u, Omega, omega, delta){extra}")
    if not np.all(np.isfinite(y0)):
        raise ValueError(f"y0 = {y0.tolist()} (initial state) is not finite")
    return y0


def _label(scene: str) -> str:
    """How the log names a run: its scene, or what it is when its caller named none."""
    return scene or "an unnamed run (its caller gave no scene)"


def _fail(scene, t, state, why):
    """Raise IntegrationError naming the scene, the time and state reached (shown as doubles: a
    real128 time or state has no format of its own) and why."""
    raise IntegrationError(f"scene {scene or '?'}: integration failed at t = {float(t):.6g}, "
                           f"state = {np.asarray(state, dtype=float).tolist()}: {why}")


def bound(y, kinematics: bool) -> tuple[np.ndarray, np.ndarray]:
    """The state with delta reduced to [-pi, pi) and, with the path, theta reduced by whole turns
    and the centre (x, y) moved to the origin: all exact symmetries of the equations. Returns the
    bounded state and the shift to add to later samples (theta's turns, x and y; delta is reported
    reduced). Extended-precision states keep their type (delta, already kept in [-pi, pi) by the
    integrator, then changes by rounding in that type only)."""
    y = np.array(y)
    y = y.astype(float) if y.dtype.kind in "iub" else y
    shift, fp = np.zeros_like(y), y.dtype.type
    if not -math.pi <= y[equations.DELTA] < math.pi:  # the integrators keep it there; a given start may not be
        y[equations.DELTA] = (y[equations.DELTA] + fp(math.pi)) % fp(TWO_PI) - fp(math.pi)
    if kinematics:
        turns = math.floor(float(y[equations.THETA]) / TWO_PI)
        y[equations.THETA] -= fp(turns * TWO_PI)
        shift[equations.THETA] = fp(turns * TWO_PI)
        shift[5:7], y[5:7] = y[5:7], 0.0
    return y, shift


class _Path:
    """Chunk length for runs with the path: the centre moves by at most about pi (and theta turns by
    about pi) between re-origins, so |x|, |y| and |theta| never set the error scale. Adapted from
    the last chunk's displacement (factor between 1/2 and 2)."""

    def __init__(self):
        self.span = 1.0

    def adapt(self, y_end, theta_start) -> None:
        moved = max(abs(y_end[5]), abs(y_end[6]), abs(y_end[equations.THETA] - theta_start), 1e-300)
        self.span *= min(2.0, max(0.5, math.pi / moved))


def _run_dd(params, y0, t0, times, kinematics, scene, progress, max_steps, *, tol):
    """Double-double (sleighsim.engine.ddtaylor at ``tol``, which has no heyoka type): (samples in double,
    info attributes). The path (theta, x, y) is not in its program: kinematics is refused."""
    from sleighsim.engine.ddtaylor import DDFlow

    if kinematics:
        raise ValueError("kinematics: the double-double engine integrates (u, Omega, omega, delta) only")
    flow = DDFlow(params, tol=tol, max_steps=max_steps)
    log.info("%s: double-double over %.6g time units, %d samples", _label(scene), times[-1] - t0, times.size)
    hi, lo = flow.propagate_grid(y0[:4], times - t0)
    return hi + lo, {"backend": "sleighsim.engine.ddtaylor", "method": "double-double Taylor",
                     "precision": Precision.DOUBLE_DOUBLE.value, "tol": tol, "order": flow.order, "steps": flow.steps}


def _run_heyoka(params, y0, t0, times, kinematics, scene, progress, max_steps, *, tol, precision):
    """heyoka's Taylor integrator at ``tol`` in ``precision``: (samples in double, info attributes)."""
    import heyoka as hy

    ta, compile_s = integrators.flow(kinematics, tol, precision)
    fp = ta.state.dtype.type  # times handed to heyoka are in the integrator's own type
    callback = integrators.bounded(ta)
    integrators.set_pars(ta, params)
    state, shift = bound(y0, kinematics)
    integrators.load(ta, state)
    ta.time, origin = fp(0), t0  # the local clock restarts at every chunk; origin is its absolute time
    nsteps, min_h, max_h = 0, math.inf, 0.0

    def advance(call, arg):
        """Run one propagation on the local clock; on failure report the last finite state before it."""
        nonlocal nsteps, min_h, max_h
        t_before, y_before = origin + ta.time, integrators.read(ta, y0.size) + shift
        res = call(arg, max_steps=max(1, max_steps - nsteps), callback=callback)
        outcome, lo, hi, n = res[0], res[1], res[2], res[3]
        nsteps += n
        if n:
            min_h, max_h = min(min_h, lo), max(max_h, hi)
        if outcome != hy.taylor_outcome.time_limit or not np.all(np.isfinite(ta.state)):
            _fail(scene, t_before, y_before, f"heyoka outcome {outcome.name} (last finite state shown)")
        return res

    out = np.empty((times.size, y0.size))
    every = (times[-1] - t0) / max(1, progress)
    next_log = t0 + every
    path = _Path() if kinematics else None
    pos = 0
    while pos < times.size:
        end = min(times[-1], next_log if path is None else min(next_log, origin + path.span))
        stop = int(np.searchsorted(times, end, side="right"))
        theta_start = ta.state[equations.THETA] if kinematics else 0.0  # theta is stored as it is
        if stop == pos:  # no sample in this chunk
            advance(ta.propagate_until, fp(end - origin))
        else:
            if times[pos] > origin:
                advance(ta.propagate_until, fp(times[pos] - origin))
            res = advance(ta.propagate_grid, (times[pos:stop] - origin).astype(ta.state.dtype))
            out[pos:stop] = (integrators.samples(ta, res[5]) + shift).astype(float)
            pos, end = stop, times[stop - 1]
        if kinematics:
            path.adapt(ta.state, theta_start)
            state, moved = bound(integrators.read(ta, y0.size), kinematics)
            integrators.load(ta, state)
            shift += moved
        ta.time, origin = fp(0), end
        if origin >= next_log or pos == times.size:
            log.info("%s: t = %.6g / %.6g (%d steps)", _label(scene), origin, times[-1], nsteps)
            next_log += every
    info = dict(backend="heyoka", method="taylor_adaptive", tol=tol, precision=precision.value, order=int(ta.order),
                compile_time_s=compile_s, steps=nsteps, min_step=float(min_h) if nsteps else float("nan"),
                max_step=float(max_h))
    return out, info


def _run_scipy(params, y0, t0, times, kinematics, scene, progress, max_steps, *, method, rtol, atol, compiled):
    """SciPy's one-step ``method`` at ``rtol``/``atol``, stepped one step at a time: (samples, info attributes)."""
    from scipy.integrate import _ivp

    solvers = {m: getattr(_ivp, m) for m in SCIPY_METHODS}

    if compiled:
        f = integrators.rhs_function(kinematics, params=params)
        rhs = lambda _, z: f(z)  # noqa: E731
    else:
        rhs = lambda _, z: equations.full_rhs(z, params)  # noqa: E731

    def start(t, y, first_step=None):
        return solvers[method](rhs, t, y, float(times[-1]), rtol=rtol, atol=atol, first_step=first_step)

    state, shift = bound(y0, kinematics)
    solver, nfev = start(t0, state), 0
    out = np.empty((len(times), len(y0)))
    i = 0
    while i < len(times) and times[i] <= t0:
        out[i] = y0
        i += 1
    nsteps, report_every = 0, max(1, len(times) // max(1, progress))
    next_report = report_every
    while i < len(times):
        msg = solver.step()
        if solver.status == "failed" or not np.all(np.isfinite(solver.y)):
            _fail(scene, solver.t, solver.y + shift, f"SciPy {method}: {msg}")
        nsteps += 1
        if nsteps >= max_steps and solver.t < times[-1]:
            _fail(scene, solver.t, solver.y + shift, f"SciPy {method}: step limit {max_steps} reached")
        j = i
        while j < len(times) and times[j] <= solver.t:
            j += 1
        if j > i:
            out[i:j] = solver.dense_output()(times[i:j]).T + shift
            i = j
        if i >= next_report:
            log.info("%s: t = %.6g / %.6g (%d steps)", _label(scene), solver.t, times[-1], nsteps)
            next_report += report_every
        y = solver.y
        if i < len(times) and (not -math.pi <= y[equations.DELTA] < math.pi
                               or (kinematics and (not 0 <= y[equations.THETA] < TWO_PI
                                                   or max(abs(y[5]), abs(y[6])) > math.pi))):
            # SciPy's error control is per component, but rtol |delta| still loosens delta itself:
            # restart from the bounded state with the step size reached.
            state, moved = bound(y, kinematics)
            shift += moved
            nfev += solver.nfev
            room = float(times[-1]) - solver.t
            solver = start(solver.t, state, first_step=min(solver.step_size, room) if solver.step_size else None)
    info = dict(backend="scipy", method=method, rtol=rtol, atol=atol, steps=nsteps,
                rhs_evaluations=int(nfev + solver.nfev), rhs="heyoka cfunc" if compiled else "SymPy lambdify (NumPy)")
    return out, info


def integrate(
    params: Params,
    y0,
    times,
    *,
    t0: float | None = None,
    kinematics: bool = False,
    backend: str = "heyoka",
    tol: float = DEFAULT_TOL,
    precision: Precision | str = Precision.DOUBLE,
    method: str = "DOP853",
    rtol: float = 1e-12,
    atol: float = 1e-14,
    compiled: bool = False,
    scene: str = "",
    progress: int = 20,
    max_steps: int = 10**9,
) -> xr.Dataset:
    """Integrate from ``y0`` at ``t0`` (default ``times[0]``) and sample at ``times``.

    ``y0``: (u, Omega, omega, delta), or with (theta, x, y) appended when
    ``kinematics`` (zeros if omitted). ``tol`` is heyoka's tolerance and ``precision`` its
    arithmetic (a :class:`~sleighsim.precision.Precision` or its name, "quad"; samples are returned in
    double); ``method``,
    ``rtol``, ``atol`` apply to the SciPy backend, whose right-hand side is the lambdified
    NumPy one (independent of heyoka) or, with ``compiled``, heyoka's cfunc (for speed
    studies of the integrator itself). Progress is logged ``progress``
    times. Raises :class:`IntegrationError` naming scene, time and state on failure,
    including when ``max_steps`` steps do not reach the end. ``max_steps`` is an integer in
    [1, 2**63 - 1], ``progress`` one in [0, 2**63 - 1]; ``y0`` holds real numbers only (a complex or
    object array is refused, naming it).

    The state is kept bounded by exact symmetries (:func:`bound`, sleighsim.engine.integrators): delta
    is kept in [-pi, pi) after every step (and reported in [0, 2 pi)), theta is reduced by whole
    turns and (x, y) moved to the origin between chunks short enough that the path never sets
    the error scale of the dynamics; the samples of theta, x and y are the unwrapped, absolute
    values.
    """
    if not isinstance(params, Params):
        raise TypeError(f"params = {params!r} must be a Params (Params.paper or Params.physical)")
    equations.check_coefficients(params)
    precision = Precision.parse(precision)
    max_steps, progress = integer("max_steps", max_steps, 1, MAX_STEPS), integer("progress", progress, 0, MAX_STEPS)
    if backend == "heyoka" and precision is Precision.DOUBLE_DOUBLE:
        run = partial(_run_dd, tol=tol)
    elif backend == "heyoka":
        check_tol(tol, precision)
        run = partial(_run_heyoka, tol=tol, precision=precision)
    elif backend == "scipy":
        _check_scipy(precision, method, rtol, atol)
        run = partial(_run_scipy, method=method, rtol=rtol, atol=atol, compiled=compiled)
    else:
        raise ValueError(f"unknown backend {backend!r}; choose 'heyoka' or 'scipy'")
    times, t0 = _sample_times(times, t0)
    y0 = _initial_state(y0, kinematics)

    start = time.perf_counter()
    states, info = run(params, y0, t0, times, kinematics, scene, progress, max_steps)
    wall = time.perf_counter() - start
    ds = _record(params, y0, t0, times, states, kinematics, scene, wall, info)
    log.info("%s: done in %.3g s, %d steps, max relative energy drift %.3g", _label(scene), wall, info["steps"],
             ds.attrs["energy_max_rel_drift"])
    return ds


def _record(params, y0, t0, times, states, kinematics, scene, wall, info) -> xr.Dataset:
    """The sampled ``states`` as a Dataset (delta reported in [0, 2 pi)) with the parameters, initial
    state, energy drift, wall time [s] and the backend's ``info`` as attributes."""
    states[:, equations.DELTA] %= TWO_PI

    E0 = float(equations.energy(bound(y0, kinematics)[0][:4], params))
    E = equations.energy(states[:, :4], params)
    drift = float(np.max(np.abs(E - E0)) / E0) if E0 > 0 else float(np.max(np.abs(E)))

    names = equations.STATE_NAMES + (equations.KINEMATIC_NAMES if kinematics else ())
    ds = xr.Dataset(
        {n: ("time", states[:, i], {"long_name": UNITS[n][0], "units": UNITS[n][1]}) for i, n in enumerate(names)},
        coords={"time": ("time", times, {"long_name": "time", "units": "time"})},
    )
    ds.attrs.update(state_attrs(params, y0[:4]))
    ds.attrs.update({f"y0_{n}": float(v) for n, v in zip(names[4:], y0[4:])})
    ds.attrs.update(
        scene=scene, t0=t0, t_end=float(times[-1]), n_samples=int(times.size),
        energy_max_rel_drift=drift, wall_time_s=wall, **info,
    )
    return ds


def orbit_samples(params: Params, y, n: int, spacing: float, *, tol: float = DEFAULT_TOL,
                  precision: Precision = Precision.DOUBLE,
                  samples_per_spacing: int = 400, scene: str = "") -> tuple[np.ndarray, xr.Dataset]:
    """n states along the orbit from y (in ``precision`` at ``tol``), ``spacing`` time units apart (the
    first is y, bounded; returned in double), and the sampled record of that stretch
    (``samples_per_spacing`` samples per spacing)."""
    record = integrate(params, y, sample_grid(0.0, spacing * n, spacing / samples_per_spacing), tol=tol,
                       precision=precision, scene=f"{scene}.orbit", progress=1)
    picks = np.arange(n) * samples_per_spacing
    return np.stack([record[v].values[picks] for v in equations.STATE_NAMES], axis=1), record

