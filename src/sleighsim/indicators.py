"""Chaos indicators with and without tangent dynamics, their judges and one decision rule.

Engines (all times in the flow's own time unit, exponents lambda in 1/time, natural logs):

* ``finite_time_exponents``: statistics of finite-time Lyapunov exponents (FTLEs) over
  non-overlapping windows of length W of a renormalised tangent vector's log growth.
* ``two_trajectory``: largest exponent from a reference and a partner orbit a distance d0
  apart (no tangent dynamics), renormalised every tau.
* ``loschmidt``: reversibility test: forward T, apply the involution R, forward T again.
* ``megno_integrator`` / ``megno``: MEGNO (Cincotta & Simo 2000, A&AS 147, 205) computed
  exactly as extra quadratures of heyoka's variational equations.
* ``frequency_drift``: frequency analysis of one component of the orbit (Laskar 1993; no
  tangent dynamics): how its leading frequency changes from window to window.

Conventions: engines take a compiled heyoka integrator (parameters already set) and an
optional ``callback`` (e.g. ``heyoka.callback.angle_reducer``) passed to every propagate
call. The flows are assumed autonomous, so ``ta.time`` is reset to 0 before every leg,
except in ``megno``, whose quadratures use the time explicitly. Bad arguments raise
ValueError naming the argument; an integration that does not end with
``taylor_outcome.time_limit`` or ends with a non-finite state raises RuntimeError naming
the time. States that contain angles reduced by a callback should be compared with a
``difference(a, b)`` that wraps angle differences (default: ``a - b``).

Judges map measured numbers to ("chaotic" | "regular" | "undecided", reason). NaN inputs
give "undecided"; every uncertainty enters so that a larger uncertainty can only move a
verdict towards "undecided". ``decide`` combines judges by ``DECISION_RULE``.
"""

from __future__ import annotations

import math

import numpy as np

CHAOTIC, REGULAR, UNDECIDED = "chaotic", "regular", "undecided"
VERDICTS = (CHAOTIC, REGULAR, UNDECIDED)

DECISION_RULE = (
    "chaotic (regular) only if at least one tangent-based indicator and at least one indicator "
    "without tangent dynamics say chaotic (regular) and no indicator says regular (chaotic); "
    "otherwise undecided; the 0-1 test is not part of this rule"
)

# names under which the 0-1 test might be handed to ``decide``; it is excluded by the rule
_ZERO_ONE_NAMES = {"0-1", "01", "0_1", "zero_one", "zero-one", "zeroone", "z01", "01test", "0-1 test",
                   "zero_one_test", "0-1-test", "test01", "test_01"}

_EPS = float(np.finfo(float).eps)


# ----------------------------------------------------------------------------- helpers

def _positive(name, value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be positive and finite, got {value!r}")
    return v


def _state(name, y, n=None):
    y = np.array(y, dtype=float).ravel()
    if y.size == 0:
        raise ValueError(f"{name} is empty")
    if n is not None and y.size != n:
        raise ValueError(f"{name} has {y.size} components, expected {n}")
    if not np.all(np.isfinite(y)):
        raise ValueError(f"{name} has non-finite components: {y}")
    return y


def _n_intervals(T, tau, name_T="T", name_tau="tau"):
    """Number of intervals tau in T; T must be an integer multiple of tau (relative 1e-9)."""
    m = T / tau
    k = round(m)
    if k < 1 or abs(m - k) > 1e-9 * max(1.0, m):
        raise ValueError(f"{name_T} = {T} must be a positive integer multiple of {name_tau} = {tau}")
    return k


def _propagate(ta, dt, callback, t_label):
    """Propagate for dt (callback only if given); RuntimeError naming the time on failure."""
    import heyoka as hy

    dt = ta.state.dtype.type(dt)  # the integrator's precision (double or long double)
    res = ta.propagate_for(dt) if callback is None else ta.propagate_for(dt, callback=callback)
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"integration stopped at t = {t_label:.6g} (+{float(ta.time):.6g}): heyoka outcome {res[0]}")
    if not np.all(np.isfinite(ta.state)):
        raise RuntimeError(f"non-finite state at t = {t_label:.6g} (+{float(ta.time):.6g})")


def linfit(x, y):
    """Least-squares line y = a + b x: (slope, slope stderr, rms residual, intercept).

    Stderr is the textbook one (independent residuals); NaN with fewer than 3 points."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    n = x.size
    if n < 2 or np.ptp(x) == 0:
        return math.nan, math.nan, math.nan, math.nan
    b, a = np.polyfit(x, y, 1)
    r = y - (a + b * x)
    rms = float(np.sqrt(np.mean(r**2)))
    if n < 3:
        return float(b), math.nan, rms, float(a)
    sxx = float(np.sum((x - x.mean()) ** 2))
    se = math.sqrt(float(np.sum(r**2)) / (n - 2) / sxx)
    return float(b), se, rms, float(a)


def _g(v):
    return f"{float(v):.3g}"


# ----------------------------------------------------------------------------- engines

def finite_time_exponents(log_growth, tau, windows, *, t_skip=0.0, min_windows=10):
    """FTLE statistics over non-overlapping windows.

    ``log_growth``: per-interval log growth g_k (k = 0..n-1) of one tangent vector
    renormalised every ``tau`` (time units), e.g. ``megno(...)["log_growth"]``. The first
    ``t_skip`` time units (a multiple of tau) are dropped: for a regular orbit the growth
    of a continuing vector decays like 1/t, and its early, large values would otherwise
    add a W^-1/2 component to the spread. For each window length W in ``windows`` (a
    multiple of tau) the rest is cut into floor(n tau / W) consecutive windows; the FTLE of
    a window is sum(g in window) / W (1/time). Window lengths with fewer than 2 windows
    give NaN rows.

    Returns a dict of arrays ``W``, ``n_windows``, ``mean``, ``std`` (ddof=1), ``sem``
    (std / sqrt(n_windows)); the least-squares log-log slopes (with textbook stderr) of the
    spread against W (``spread_slope``: -1/2 for chaos once W exceeds the correlation
    time, -1 for the bounded oscillation of a regular orbit's growth) and of |mean|
    against W (``mean_slope``), over rows with finite, non-zero values (NaN with fewer than
    2 rows, stderr NaN with fewer than 3); ``rate`` (sum g / T), ``rate_err`` (``sem`` of
    the longest W with at least ``min_windows`` windows, which includes the windows'
    serial correlation; NaN if none), ``T`` (time covered) and ``tau``.
    With one continuing vector every window mean is the rate over the span the windows
    cover, so ``mean_slope`` is close to 0 for both classes: mean ~ ln W / W holds only for
    FTLEs started afresh in each window.
    """
    tau = _positive("tau", tau)
    g = np.asarray(log_growth, dtype=float).ravel()
    if g.size == 0:
        raise ValueError("log_growth is empty")
    if not np.all(np.isfinite(g)):
        raise ValueError("log_growth has non-finite entries")
    if not (math.isfinite(t_skip) and t_skip >= 0):
        raise ValueError(f"t_skip must be >= 0, got {t_skip!r}")
    n_skip = 0 if t_skip == 0 else _n_intervals(t_skip, tau, "t_skip")
    if n_skip >= g.size:
        raise ValueError(f"t_skip = {t_skip} leaves nothing of log_growth ({g.size} intervals of tau = {tau})")
    g = g[n_skip:]
    W = np.atleast_1d(np.asarray(windows, dtype=float)).ravel()
    if W.size == 0:
        raise ValueError("windows is empty")
    m = np.array([_n_intervals(_positive("windows", w), tau, "windows entry", "tau") for w in W])
    n_win = g.size // m
    mean = np.full(W.size, np.nan)
    std = np.full(W.size, np.nan)
    for i, (mi, nw) in enumerate(zip(m, n_win)):
        if nw < 2:
            continue
        ftle = g[: nw * mi].reshape(nw, mi).sum(axis=1) / W[i]
        mean[i] = ftle.mean()
        std[i] = ftle.std(ddof=1)
    sem = std / np.sqrt(np.maximum(n_win, 1))
    ok_s = np.isfinite(std) & (std > 0)
    ok_m = np.isfinite(mean) & (mean != 0)
    nan4 = (math.nan,) * 4
    s_slope, s_err, _, _ = linfit(np.log(W[ok_s]), np.log(std[ok_s])) if ok_s.sum() >= 2 else nan4
    m_slope, m_err, _, _ = linfit(np.log(W[ok_m]), np.log(np.abs(mean[ok_m]))) if ok_m.sum() >= 2 else nan4
    T = g.size * tau
    trusted = np.flatnonzero((n_win >= min_windows) & np.isfinite(sem))
    rate_err = float(sem[trusted[np.argmax(W[trusted])]]) if trusted.size else math.nan
    return {
        "W": W, "n_windows": n_win.astype(int), "mean": mean, "std": std, "sem": sem,
        "spread_slope": s_slope, "spread_slope_err": s_err,
        "mean_slope": m_slope, "mean_slope_err": m_err,
        "rate": float(g.sum() / T), "rate_err": rate_err, "T": T, "tau": tau,
    }


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
    d0 = _positive("d0", d0)
    tau = _positive("tau", tau)
    T = _positive("T", T)
    if int(n_blocks) != n_blocks or n_blocks < 2:
        raise ValueError(f"n_blocks must be an integer >= 2, got {n_blocks!r}")
    n_blocks = int(n_blocks)
    n = _n_intervals(T, tau)
    if n < n_blocks:
        raise ValueError(f"T = {T} holds {n} intervals tau, fewer than n_blocks = {n_blocks}")
    if not (math.isfinite(t_align) and t_align >= 0):
        raise ValueError(f"t_align must be >= 0, got {t_align!r}")
    n_align = 0 if t_align == 0 else _n_intervals(t_align, tau, "t_align")
    dim = len(ta.state)
    ref = _state("y0", y0, dim).astype(ta.state.dtype)
    diff = difference if difference is not None else (lambda a, b: a - b)

    def rescale(ref, partner, t):
        dv = np.asarray(diff(partner, ref), float)
        d = float(np.linalg.norm(dv))
        if not (math.isfinite(d) and d > 0):
            raise RuntimeError(f"separation is {d} at t = {t:.6g}: cannot renormalise the partner")
        return ref + dv * (d0 / d)

    def reset(ref, partner, t):
        """Partner at distance d0 from ref along (partner - ref); projected, then rescaled."""
        partner = rescale(ref, partner, t)
        if project is not None:
            partner = rescale(ref, np.asarray(project(ref.copy(), partner.copy()), float), t)
        return partner

    u = np.random.default_rng(seed).normal(size=dim)
    partner = reset(ref, ref + d0 * u / np.linalg.norm(u), 0.0)
    g = np.empty(n)
    t = 0.0
    for k in range(-n_align, n):
        for which in (0, 1):
            ta.time = ta.state.dtype.type(0)  # double, or long double for an extended-precision integrator
            ta.state[:] = ref if which == 0 else partner
            _propagate(ta, tau, callback, t)
            if which == 0:
                new_ref = ta.state.copy()
            else:
                partner = ta.state.copy()
        ref = new_ref
        t += tau
        d = float(np.linalg.norm(np.asarray(diff(partner, ref), float)))
        if not (math.isfinite(d) and d > 0):
            raise RuntimeError(f"separation is {d} at t = {t:.6g}")
        if k >= 0:
            g[k] = math.log(d / d0)
        partner = reset(ref, partner, t)
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


_FIT_KEYS = ("exp_rate", "exp_rate_err", "exp_rms", "pow_exponent", "pow_exponent_err", "pow_rms")


def _growth_fits(T, e) -> dict:
    """Least-squares fits of log(e) = a + rate T and log(e) = a + p log T: slope, stderr and rms
    residual (log units) of each; NaN with fewer than 2 points."""
    out = dict.fromkeys(_FIT_KEYS, math.nan)
    if T.size >= 2:
        le = np.log(e)
        out["exp_rate"], out["exp_rate_err"], out["exp_rms"], _ = linfit(T, le)
        out["pow_exponent"], out["pow_exponent_err"], out["pow_rms"], _ = linfit(np.log(T), le)
    return out


def loschmidt_fit(T_values, errors, scale, *, floor_factor=1e3, saturation=1e-2, rounding=_EPS, tail=0.5,
                  tail_min=4):
    """Classify return errors: exponential in T (chaos) or a power of T (regular).

    Uses the points with floor_factor * rounding * scale < error < saturation * scale (rounding:
    the integrator's machine epsilon) before the first horizon whose error reached saturation,
    fits log(error) = a + rate T and log(error) = a + p log T by least squares over all of them and
    again over the tail (the last ``tail`` fraction of them in T, at least tail_min: the longest
    horizons before saturation) and reports both (slope, stderr, rms residual in
    log units; the tail's under ``tail_``). ``better`` is "exponential" or "power"
    (smaller rms over all points), "undetermined" with fewer than 3 usable points.
    """
    T = np.asarray(T_values, float).ravel()
    e = np.asarray(errors, float).ravel()
    if T.size == 0:
        raise ValueError("T_values is empty")
    if e.size != T.size:
        raise ValueError(f"errors has {e.size} entries, T_values {T.size}")
    scale = _positive("scale", scale)
    if not 0 < tail <= 1:
        raise ValueError(f"tail must be in (0, 1], got {tail!r}")
    if not (isinstance(tail_min, int) and tail_min >= 2):
        raise ValueError(f"tail_min must be an integer >= 2, got {tail_min!r}")
    floor = floor_factor * _positive("rounding", rounding) * scale
    sat = saturation * scale
    saturated = np.isfinite(e) & (e >= sat)
    before = T < (T[saturated].min() if saturated.any() else np.inf)
    use = np.isfinite(e) & (e > floor) & (e < sat) & np.isfinite(T) & (T > 0) & before
    out = {"floor": floor, "saturation": sat, "used": use, "n_used": int(use.sum()), "better": "undetermined"}
    out.update(_growth_fits(T[use], e[use]))
    idx = np.flatnonzero(use)[np.argsort(T[use], kind="stable")]
    in_tail = np.zeros_like(use)
    in_tail[idx[-max(tail_min, math.ceil(tail * idx.size)):]] = True
    out["tail_used"], out["tail_n"] = in_tail, int(in_tail.sum())
    out.update({f"tail_{k}": v for k, v in _growth_fits(T[in_tail], e[in_tail]).items()})
    if use.sum() >= 3:
        out["better"] = "exponential" if out["exp_rms"] < out["pow_rms"] else "power"
    return out


def loschmidt(ta, y0, T_values, involution, callback=None, *, difference=None, scale=None,
              floor_factor=1e3, saturation=1e-2):
    """Loschmidt (time-reversal) test for a reversible flow with involution R.

    R maps a state to a state, and if y(t) solves the ODE so does R y(-t). For each T in
    ``T_values``: take y(T) on one forward run from y0, apply R, propagate forward T and compare
    with R(y0). In exact arithmetic the return is exact; numerically the return error grows like
    exp(lambda T) times the rounding level on a chaotic orbit and only like a power of T on a
    regular one. ``difference(a, b)`` (default a - b) compares states. Runs in the integrator's
    precision (double or long double; ``involution`` must keep the state's dtype, else ValueError);
    the rounding floor uses its machine epsilon.

    Returns dict: ``T``, ``error`` (infinity norm), ``rel_error`` (error / scale, scale =
    max|y0| unless given) and the classification of ``loschmidt_fit`` (floor
    floor_factor * eps * scale with eps the integrator's machine epsilon, saturation
    saturation * scale).
    """
    dim = len(ta.state)
    y0 = _state("y0", y0, dim)
    T_arr = np.atleast_1d(np.asarray(T_values, float)).ravel()
    if T_arr.size == 0:
        raise ValueError("T_values is empty")
    for Tk in T_arr:
        _positive("T_values entry", Tk)
    if not callable(involution):
        raise ValueError("involution must be callable")  # noqa: TRY004
    if scale is None:
        scale = float(np.max(np.abs(y0)))
        if scale == 0:
            raise ValueError("y0 is the zero state: pass scale explicitly")
    scale = _positive("scale", scale)
    diff = difference if difference is not None else (lambda a, b: a - b)
    target = np.asarray(involution(y0.copy()), float)
    fp = ta.state.dtype.type  # float, or np.longdouble for an extended-precision integrator
    order = np.argsort(T_arr, kind="stable")
    ahead = []  # y(T) for T in increasing order, from one forward run
    ta.time = fp(0)
    ta.state[:] = y0
    for i in order:
        if T_arr[i] > ta.time:
            _propagate_until(ta, fp(T_arr[i]), callback)  # the absolute time: each leg ends exactly at T
        ahead.append(ta.state.copy())
    err = np.empty(T_arr.size)
    for i, y_T in zip(order, ahead):
        ta.time = fp(0)
        back = np.asarray(involution(y_T.copy()))
        if back.dtype != y_T.dtype:
            raise ValueError(f"involution changed the state's precision ({y_T.dtype} -> {back.dtype})")
        ta.state[:] = back
        _propagate(ta, T_arr[i], callback, T_arr[i])
        err[i] = float(np.max(np.abs(np.asarray(diff(ta.state.copy(), target), float))))
    out = {"T": T_arr, "error": err, "rel_error": err / scale, "scale": scale}
    out.update(loschmidt_fit(T_arr, err, scale, floor_factor=floor_factor, saturation=saturation,
                             rounding=float(np.finfo(ta.state.dtype).eps)))
    return out


def frequency_drift(ta, y0, *, T, dt, component, splits=(2, 4, 8, 16), min_cycles=8.0, callback=None):
    """Frequency analysis of the orbit from y0 (no tangent dynamics): component ``component``
    sampled every dt over T (one propagate_grid run in the integrator's precision: double, long
    double or real128), then ``frequencies.drift`` over windows T / K, K in ``splits``. Returns
    that dict with ``T``, ``dt`` and ``final_state``."""
    from . import frequencies

    dim = len(ta.state)
    y0 = _state("y0", y0, dim)
    T, dt = _positive("T", T), _positive("dt", dt)
    splits = frequencies.check_splits(splits)
    if not (isinstance(component, (int, np.integer)) and 0 <= component < dim):
        raise ValueError(f"component must be an index into the state (0..{dim - 1}), got {component!r}")
    fp = ta.state.dtype.type
    n = round(T / dt)
    if n < frequencies.MIN_SAMPLES * splits[-1]:
        raise ValueError(f"T / dt = {n} samples: too few for {splits[-1]} windows of at least {frequencies.MIN_SAMPLES}")
    import heyoka as hy

    ta.time = fp(0)
    ta.state[:] = np.asarray(y0).astype(ta.state.dtype)
    grid = np.arange(n).astype(ta.state.dtype) * fp(dt)  # n samples: T = n dt (any precision, real128 too)
    res = ta.propagate_grid(grid) if callback is None else ta.propagate_grid(grid, callback=callback)
    samples = np.asarray(res[-1]).astype(float)
    if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(samples)):
        raise RuntimeError(f"integration stopped at t = {float(ta.time):.6g} (target {T:.6g}): heyoka outcome {res[0]}")
    out = frequencies.drift(samples[:, component], dt, splits, min_cycles=min_cycles)
    out.update(T=float(n * dt), dt=float(dt), final_state=ta.state.copy())
    return out


def megno_integrator(sys, pars=(), tol=None, compact_mode=True, fp_type=float):
    """heyoka integrator for ``sys`` (list of (var, expr)), one tangent vector and the MEGNO
    quadratures.

    State layout: [y (n), delta (n), I, J] with delta the variational vector (heyoka's
    derivatives with respect to the first initial condition, overwritten by ``megno``),
    I' = t (delta_dot . delta) / (delta . delta) and J' = 2 I / t, so that
    Y(t) = 2 I / t and <Y>(t) = J / t (t = heyoka's time, which must start > 0). ``fp_type``:
    float, or np.longdouble for an extended-precision integrator. Returns (ta, n).
    """
    import heyoka as hy

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
        kw["tol"] = fp_type(_positive("tol", tol))
    ta = hy.taylor_adaptive(eqs, np.array([0.1] * n + [1.0] * n + [0.0, 0.0], dtype=fp_type), **kw)
    return ta, n


def megno(ta, n, y0, *, T, n_samples, tau=None, callback=None, seed=0):
    """MEGNO Y(t) = (2/t) int_0^t s (delta_dot . delta)/(delta . delta) ds and its running
    mean <Y>(t) = (1/t) int_0^t Y ds (Cincotta & Simo 2000), integrated exactly.

    ``ta`` and ``n`` come from ``megno_integrator``. The tangent vector starts in a random
    unit direction (``seed``) and is renormalised to unit length every ``tau`` (default
    T / n_samples; T must be a multiple of it), which leaves the integrand unchanged; its
    log norm before each renormalisation is the one-vector Benettin series
    (``log_growth``, input for ``finite_time_exponents``). The run starts at t = 1e-9 tau
    (the quadrature for <Y> has 2 I / t, 0/0 at t = 0; the offset changes <Y> by
    O(1e-9 tau / t)). <Y> -> 2 for quasi-periodic orbits with shear, -> 0 for
    periodic / isochronous ones, and ~ lambda t / 2 for chaotic ones.

    Returns dict: ``t``, ``Y``, ``Y_mean`` at n_samples equally spaced times up to T,
    ``final`` (<Y>(T)), over the second half (t >= T/2): ``slope`` of <Y> against t
    (chaotic: about lambda / 2), its textbook ``slope_err`` and the rms residual
    ``resid``; ``log_growth``, ``tau``, ``final_state`` (y only).
    """
    T = _positive("T", T)
    if int(n_samples) != n_samples or n_samples < 4:
        raise ValueError(f"n_samples must be an integer >= 4, got {n_samples!r}")
    n_samples = int(n_samples)
    tau = T / n_samples if tau is None else _positive("tau", tau)
    n = int(n)
    if len(ta.state) != 2 * n + 2:
        raise ValueError(f"n = {n} does not match an integrator state of size {len(ta.state)} (expected 2 n + 2)")
    y0 = _state("y0", y0, n)
    n_steps = _n_intervals(T, tau)
    if n_steps < n_samples:
        raise ValueError(f"tau = {tau} is longer than the sample spacing T / n_samples = {T / n_samples}")
    rec = np.unique(np.round(np.linspace(n_steps / n_samples, n_steps, n_samples)).astype(int))
    u = np.random.default_rng(seed).normal(size=n)
    fp = ta.state.dtype.type  # float, or np.longdouble for an extended-precision integrator
    t0 = 1e-9 * tau
    ta.time = fp(t0)
    ta.state[:n] = y0
    ta.state[n:2 * n] = u / np.linalg.norm(u)
    ta.state[2 * n:] = 0.0
    g = np.empty(n_steps)
    t_s, Y, Ym = [], [], []
    r = 0
    for k in range(1, n_steps + 1):
        t_end = k * tau
        _propagate_until(ta, fp(t_end), callback)
        d = ta.state[n:2 * n]
        nrm = np.sqrt(np.sum(d * d))  # in the integrator's precision
        if not (np.isfinite(nrm) and nrm > 0):
            raise RuntimeError(f"tangent vector norm is {nrm} at t = {t_end:.6g}")
        g[k - 1] = float(np.log(nrm))
        ta.state[n:2 * n] = d / nrm
        if r < rec.size and k == rec[r]:
            t = ta.time
            t_s.append(float(t))
            Y.append(float(2 * ta.state[2 * n] / t))
            Ym.append(float(ta.state[2 * n + 1] / t))
            r += 1
    t_s, Y, Ym = np.array(t_s), np.array(Y), np.array(Ym)
    half = t_s >= T / 2
    slope, slope_err, resid, _ = linfit(t_s[half], Ym[half])
    return {"t": t_s, "Y": Y, "Y_mean": Ym, "final": float(Ym[-1]), "slope": slope, "slope_err": slope_err,
            "resid": resid, "log_growth": g, "tau": tau, "final_state": ta.state[:n].astype(float)}


def _propagate_until(ta, t_end, callback):
    import heyoka as hy

    res = ta.propagate_until(t_end) if callback is None else ta.propagate_until(t_end, callback=callback)
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"integration stopped at t = {float(ta.time):.6g} (target {float(t_end):.6g}): heyoka outcome "
                           f"{res[0]}")
    if not np.all(np.isfinite(ta.state)):
        raise RuntimeError(f"non-finite state at t = {float(ta.time):.6g}")


# ----------------------------------------------------------------------------- judges

def polynomial_rate_bound(T, tau, degree=2.0):
    """Largest apparent exponent (1/time) that polynomial growth can fake: a vector growing
    like (t / tau)^degree over a horizon T has log growth degree * ln(T / tau), i.e. an
    apparent rate degree * ln(T / tau) / T. Regular orbits (linear growth on a sheared
    torus) stay below it for degree >= 1; a chaotic verdict must exceed it."""
    T = _positive("T", T)
    tau = _positive("tau", tau)
    if not (math.isfinite(degree) and degree > 0):
        raise ValueError(f"degree must be positive, got {degree!r}")
    return degree * math.log(max(T / tau, math.e)) / T


def _check_judge(names_values, errors=(), sigma=3.0):
    """None if all finite (ValueError for negative uncertainties or sigma), else an
    "undecided" verdict naming the NaN inputs."""
    bad = [k for k, v in names_values if not _is_finite(v)]
    if bad:
        return UNDECIDED, "not finite: " + ", ".join(bad)
    if not (math.isfinite(sigma) and sigma >= 0):
        raise ValueError(f"sigma must be >= 0, got {sigma!r}")
    for k, v in errors:
        if float(v) < 0:
            raise ValueError(f"{k} must be >= 0, got {v!r}")
    return None


def _is_finite(v):
    try:
        return math.isfinite(float(v))
    except (TypeError, ValueError):
        return False


def judge_ftle(rate, rate_err, T, tau, spread_slope, spread_slope_err, *, sigma=3.0, degree=2.0,
               spread_slope_max=-0.5):
    """Verdict from a one-vector Benettin series (``finite_time_exponents`` output).

    chaotic: rate - sigma * rate_err > polynomial_rate_bound(T, tau, degree) (the vector
    grew faster than any polynomial of that degree, resolved by sigma standard errors);
    regular: rate + sigma * rate_err < that bound AND spread_slope + sigma *
    spread_slope_err < spread_slope_max (the spread falls faster than the chaotic W^-1/2;
    a regular orbit's is W^-1). The spread is not required for chaos: at accessible W it
    can still fall like 1/W on a chaotic attractor (Lorenz), before the W^-1/2 law sets in.
    Otherwise undecided. A regular verdict only bounds lambda below the stated bound.
    """
    chk = _check_judge([("rate", rate), ("rate_err", rate_err), ("T", T), ("tau", tau),
                        ("spread_slope", spread_slope), ("spread_slope_err", spread_slope_err)],
                       [("rate_err", rate_err), ("spread_slope_err", spread_slope_err)], sigma)
    if chk:
        return chk
    bound = polynomial_rate_bound(T, tau, degree)
    lo, hi = rate - sigma * rate_err, rate + sigma * rate_err
    s_hi = spread_slope + sigma * spread_slope_err
    nums = (f"rate {_g(rate)} +- {_g(rate_err)} /time over T = {_g(T)}, polynomial bound {_g(bound)} "
            f"(degree {_g(degree)}), spread slope {_g(spread_slope)} +- {_g(spread_slope_err)}, sigma {_g(sigma)}")
    if lo > bound:
        return CHAOTIC, f"exponential growth resolved: rate - sigma err = {_g(lo)} > bound; {nums}"
    if hi < bound and s_hi < spread_slope_max:
        return REGULAR, (f"no growth beyond polynomial (rate + sigma err = {_g(hi)} < bound, so lambda < "
                         f"{_g(bound)}) and spread falls like W^{_g(spread_slope)} (< W^{_g(spread_slope_max)}); {nums}")
    return UNDECIDED, f"neither exponential growth resolved nor a regular spread law; {nums}"


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


def judge_megno(y_mean, y_err, slope, slope_err, T, *, sigma=3.0, y_chaotic_min=4.0, y_regular_max=2.5,
                growth_max=0.5):
    """Verdict from ``megno`` (final <Y>, its rms residual, slope and slope_err over the
    second half, horizon T).

    chaotic: <Y> - sigma * y_err > y_chaotic_min AND slope - sigma * slope_err > 0 (<Y>
    keeps growing, ~ lambda t / 2); regular: <Y> + sigma * y_err < y_regular_max (2 for a
    torus with shear, 0 for isochronous / periodic motion) AND (slope + sigma * slope_err)
    * T < growth_max (no growth of <Y> over the horizon). A regular verdict bounds lambda
    only to about 2 y_regular_max / T. Otherwise undecided.
    """
    chk = _check_judge([("y_mean", y_mean), ("y_err", y_err), ("slope", slope), ("slope_err", slope_err),
                        ("T", T)], [("y_err", y_err), ("slope_err", slope_err)], sigma)
    if chk:
        return chk
    T = _positive("T", T)
    nums = (f"<Y> = {_g(y_mean)} +- {_g(y_err)} at T = {_g(T)}, slope {_g(slope)} +- {_g(slope_err)} /time, "
            f"sigma {_g(sigma)}")
    if y_mean - sigma * y_err > y_chaotic_min and slope - sigma * slope_err > 0:
        return CHAOTIC, (f"<Y> above {_g(y_chaotic_min)} and growing (lambda ~ 2 slope = {_g(2 * slope)}); {nums}")
    if y_mean + sigma * y_err < y_regular_max and (slope + sigma * slope_err) * T < growth_max:
        return REGULAR, (f"<Y> below {_g(y_regular_max)} without growth over T (lambda below about "
                         f"{_g(2 * y_regular_max / T)}); {nums}")
    return UNDECIDED, f"<Y> neither resolved above {_g(y_chaotic_min)} and growing nor settled below {_g(y_regular_max)}; {nums}"


def judge_frequency(runs, *, sigma=3.0, converged_max=-1.0):
    """Verdict from frequency analysis (``frequency_drift``) of one orbit in one or more
    precisions, in order of decreasing rounding: ``runs`` is a list of dicts with ``precision``
    (a name), ``slope`` and ``slope_err`` (the convergence exponent of the spread D ~ W^slope of
    the leading frequency), ``D`` (the spread at the longest window) and, from the second run on,
    ``log_ratio`` +- ``log_ratio_err`` (ln of the previous run's D over this one's,
    ``frequency_log_ratio``) and ``rounding_ratio`` (the previous run's tolerance over this one's).

    regular: the window frequencies converge faster than 1/W in some run (slope + sigma err <
    converged_max, or slope = -inf: at the refinement's precision): a torus's refined frequency
    converges like W^-2 or faster, while a frequency that wanders on a chaotic orbit spreads like
    W^-1/2 or more slowly. Otherwise undecided. The test never says chaotic: a spread that
    neither converges nor depends on the rounding also appears on a torus whose windows are
    shorter than one of its slow periods (the smoke config's rotor states: D about 5e-3 at every
    window, equal in both precisions). When the drift shrinks with the rounding by more than the
    square root of the rounding ratio (log_ratio - sigma err > ln(rounding_ratio) / 2), the
    reason says so: the previous run's drift is then integration error, and the exact dynamics'
    drift is bounded by the last run's D, but that run's own drift is not explained, so the
    verdict stays undecided."""
    if not (math.isfinite(sigma) and sigma >= 0):
        raise ValueError(f"sigma must be >= 0, got {sigma!r}")
    if not runs:
        raise ValueError("runs is empty")
    for r in runs:
        for k in ("slope_err", "log_ratio_err"):
            if _is_finite(r.get(k, math.nan)) and float(r[k]) < 0:
                raise ValueError(f"{r['precision']}: {k} must be >= 0, got {r[k]!r}")
    parts, notes = [], []
    for prev, r in zip([None, *runs[:-1]], runs):
        p, e = r["slope"], r["slope_err"]
        parts.append(f"{r['precision']}: slope {_g(p)} +- {_g(e)}, D {_g(r['D'])}")
        if p == -math.inf or (_is_finite(p) and _is_finite(e) and p + sigma * e < converged_max):
            return REGULAR, (f"the leading frequency converges faster than 1/W in {r['precision']} (D ~ W^slope, "
                             f"slope + sigma err < {_g(converged_max)}); {'; '.join(parts)}; sigma {_g(sigma)}")
        lr, le, rr = (r.get(k, math.nan) for k in ("log_ratio", "log_ratio_err", "rounding_ratio"))
        if prev is not None and all(_is_finite(v) for v in (lr, le, rr)) and rr > 1:
            shrinks = lr - sigma * le > 0.5 * math.log(rr)
            notes.append(f"from {prev['precision']} to {r['precision']} the drift shrinks by {_g(math.exp(lr))} "
                         f"(ln {_g(lr)} +- {_g(le)}) at {_g(rr)} times smaller rounding"
                         + (f": the {prev['precision']} drift is integration error, the exact dynamics' below "
                            f"{_g(r['D'])}" if shrinks else ""))
    return UNDECIDED, ("the leading frequency converges in no run; " + "; ".join(parts + notes)
                       + f"; sigma {_g(sigma)}")


def frequency_log_ratio(coarse: dict, fine: dict) -> tuple[float, float]:
    """ln(D_coarse / D_fine) of two ``frequency_drift`` runs of one orbit (coarse: the larger
    rounding, e.g. double against long double) over the splits both used, weighted by K - 1 (the
    windows behind each D; a D below the refinement's precision counts as that precision), and
    its standard error: the same weighted mean of the splits' errors 1 / sqrt(K - 1) (that of the
    ratio of two independent sample standard deviations of K values), the error of the mean if
    the splits were fully correlated (they share the data). (NaN, NaN) when no split is shared."""
    from .frequencies import PRECISION

    common = np.intersect1d(coarse["splits"], fine["splits"])
    if common.size == 0:
        return math.nan, math.nan
    da, db = (np.maximum([run["D"][list(run["splits"]).index(k)] for k in common], PRECISION)
              for run in (coarse, fine))
    w = common - 1.0
    return float(np.sum(w * np.log(da / db)) / np.sum(w)), float(np.sum(np.sqrt(w)) / np.sum(w))


def judge_loschmidt(n_used, exp_rate, exp_rate_err, exp_rms, pow_exponent, pow_exponent_err, pow_rms, *,
                    sigma=3.0, fit_ratio=1.5, p_max=3.0, min_points=3):
    """Verdict from ``loschmidt`` / ``loschmidt_fit`` (fits over the n_used points between
    the rounding floor and saturation; rms residuals are goodness of fit in log units, the
    stderr's are the uncertainties).

    chaotic: n_used >= min_points, exp_rate - sigma * exp_rate_err > 0 and either the
    exponential fit is better by fit_ratio (exp_rms * fit_ratio <= pow_rms) or the error
    grows faster than any plausible power (pow_exponent - sigma * pow_exponent_err > p_max);
    regular: n_used >= min_points, the exponential fit is not better by fit_ratio
    (pow_rms < exp_rms * fit_ratio) and the error grows at most like T^p_max
    (pow_exponent + sigma * pow_exponent_err < p_max; rounding on a torus gives about T^1
    to T^1.5, Brouwer's law). Otherwise undecided. The chaotic return errors scatter by
    about a factor e around the exponential, so use many T values (tens) across the window
    between floor and saturation, which spans about ln(1e-2 / 1e-13) / lambda = 25 / lambda in
    double (32 / lambda in long double).
    """
    if not _is_finite(n_used):
        return UNDECIDED, "not finite: n_used"
    if int(n_used) < min_points:
        return UNDECIDED, f"only {int(n_used)} return errors between rounding floor and saturation (need {min_points})"
    chk = _check_judge([("exp_rate", exp_rate), ("exp_rate_err", exp_rate_err), ("exp_rms", exp_rms),
                        ("pow_exponent", pow_exponent), ("pow_exponent_err", pow_exponent_err), ("pow_rms", pow_rms)],
                       [("exp_rate_err", exp_rate_err), ("pow_exponent_err", pow_exponent_err),
                        ("exp_rms", exp_rms), ("pow_rms", pow_rms)], sigma)
    if chk:
        return chk
    nums = (f"{int(n_used)} points; exp fit rate {_g(exp_rate)} +- {_g(exp_rate_err)} /time, rms {_g(exp_rms)}; "
            f"power fit T^{_g(pow_exponent)} +- {_g(pow_exponent_err)}, rms {_g(pow_rms)}; sigma {_g(sigma)}")
    if exp_rate - sigma * exp_rate_err > 0:
        if exp_rms * fit_ratio <= pow_rms:
            return CHAOTIC, f"return error grows exponentially (exp fit better by >= {_g(fit_ratio)}x); {nums}"
        if pow_exponent - sigma * pow_exponent_err > p_max:
            return CHAOTIC, f"return error grows faster than T^{_g(p_max)} (exponential amplification); {nums}"
    if pow_rms < exp_rms * fit_ratio and pow_exponent + sigma * pow_exponent_err < p_max:
        return REGULAR, f"return error grows at most like T^{_g(p_max)}; {nums}"
    return UNDECIDED, f"return error neither clearly exponential nor bounded by T^{_g(p_max)}; {nums}"


def judge_loschmidt_run(L: dict, *, sigma=3.0) -> tuple[str, str]:
    """``judge_loschmidt`` on a ``loschmidt`` run, over all usable points and over their tail (the
    longest horizons before saturation, ``loschmidt_fit``'s tail_ fits). chaotic: chaotic over all points
    and in the tail (the growth is still exponential, or faster than T^3, where the error
    approaches saturation: a few early jumps of the error followed by power-law growth are not
    chaos); regular: regular in the tail (early transient amplification does not hide the
    power-law growth that follows); otherwise undecided, with both reasons."""
    whole = judge_loschmidt(*(L[k] for k in ("n_used",) + _FIT_KEYS), sigma=sigma)
    tail = judge_loschmidt(L["tail_n"], *(L[f"tail_{k}"] for k in _FIT_KEYS), sigma=sigma)
    both = f"over all usable points: {whole[0]}: {whole[1]}; in the tail: {tail[0]}: {tail[1]}"
    if whole[0] == CHAOTIC and tail[0] == CHAOTIC:
        return CHAOTIC, f"exponential growth sustained into the tail; {both}"
    if tail[0] == REGULAR:
        return REGULAR, f"power-law growth in the tail; {both}"
    if whole[0] == CHAOTIC:
        return UNDECIDED, f"exponential growth not sustained into the tail; {both}"
    return UNDECIDED, f"neither sustained exponential growth nor power-law growth in the tail; {both}"


def d0_independent(d0s, rates, stderrs, *, sigma=3.0):
    """Is a two-trajectory rate a Lyapunov exponent? Only if it does not depend on the separation:
    the rates measured at the initial separations ``d0s`` must agree pairwise within sigma combined
    standard errors. A rate that changes with d0 is dominated by rounding noise or finite size (on
    the sleigh, noise off the leading direction amplified by many orders at every spike). Returns
    (True | False, reason); a non-finite rate or fewer than two d0 fail the check."""
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


def decide(verdicts, tangent_based):
    """Combine per-indicator verdicts by ``DECISION_RULE``.

    ``verdicts``: {name: (verdict, reason)}; ``tangent_based``: names of the indicators
    that use tangent dynamics (all others count as indicators without). The 0-1 test is
    refused. Returns (verdict, reason, DECISION_RULE)."""
    if not isinstance(verdicts, dict) or not verdicts:
        raise ValueError("verdicts must be a non-empty dict {name: (verdict, reason)}")
    tangent_based = set(tangent_based)
    by = {CHAOTIC: [], REGULAR: [], UNDECIDED: []}
    for name, item in verdicts.items():
        key = str(name).strip().lower().replace(" ", "")
        if key in {z.replace(" ", "") for z in _ZERO_ONE_NAMES}:
            raise ValueError(f"verdicts: {name!r} looks like the 0-1 test, which is not part of this rule")
        try:
            v, _reason = item
        except (TypeError, ValueError):
            raise ValueError(f"verdicts[{name!r}] must be a (verdict, reason) pair") from None
        if v not in VERDICTS:
            raise ValueError(f"verdicts[{name!r}] = {v!r} is not one of {VERDICTS}")
        by[v].append(name)

    def names(lst):
        return ", ".join(sorted(map(str, lst))) or "none"

    tail = f"undecided: {names(by[UNDECIDED])}"
    if by[CHAOTIC] and by[REGULAR]:
        return (UNDECIDED, f"indicators disagree: chaotic: {names(by[CHAOTIC])}; regular: {names(by[REGULAR])}; {tail}",
                DECISION_RULE)
    for v in (CHAOTIC, REGULAR):
        if not by[v]:
            continue
        tan = [k for k in by[v] if k in tangent_based]
        non = [k for k in by[v] if k not in tangent_based]
        if tan and non:
            return v, (f"{v}: tangent-based {names(tan)}; without tangent dynamics {names(non)}; "
                       f"none says otherwise; {tail}"), DECISION_RULE
        missing = "a tangent-based indicator" if not tan else "an indicator without tangent dynamics"
        return UNDECIDED, f"only {names(by[v])} say {v}; missing: {missing} saying {v}; {tail}", DECISION_RULE
    return UNDECIDED, f"no indicator reached a verdict ({tail})", DECISION_RULE
