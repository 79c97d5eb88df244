"""MEGNO, the Mean Exponential Growth factor of Nearby Orbits (Cincotta & Simo 2000, A&AS 147, 205),
and its judges.

* ``megno`` (on ``engine.integrators.megno_integrator``): Y(t) and its running mean <Y>(t) computed
  exactly as extra quadratures of heyoka's variational equations; ``megno_rate``: the exponent it
  implies (lambda ~ 2 slope of <Y>).
* ``judge_megno`` (``judge_megno_run`` on a ``megno`` run) and ``megno_in_long_double`` (the MEGNO
  indicator under the long-double precision check, ``tangent.growth_confirmed``).

Times in the flow's own time unit, exponents in 1/time, natural logs. Engine conventions:
``propagate``; verdict conventions: ``verdicts``.
"""

from __future__ import annotations

import numpy as np

from sleighsim.chaos.common import _n_intervals, _state, linfit
from sleighsim.chaos.propagate import _propagate_until
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED, _check_judge, _g
from sleighsim.model.params import positive

# ----------------------------------------------------------------------------- the series


def megno(ta, n, y0, *, T, n_samples, tau=None, callback=None, seed=0):
    """MEGNO Y(t) = (2/t) int_0^t s (delta_dot . delta)/(delta . delta) ds and its running
    mean <Y>(t) = (1/t) int_0^t Y ds (Cincotta & Simo 2000), integrated exactly.

    ``ta`` and ``n`` come from ``engine.integrators.megno_integrator``. The tangent vector starts in a random
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
    T, n_samples, tau, n, y0, n_steps = _megno_args(ta, n, y0, T, n_samples, tau)
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


def megno_from_log_norm(t, log_norm, n_samples: int) -> dict:
    """MEGNO from one tangent vector's sampled log-norm l(t) = ln |v(t)| (t[0] = 0 and l(0) = 0: a unit
    v0; e.g. ``engine.ddtaylor.DDFlow.propagate_tangent_grid``): by parts,
    Y(t) = (2/t) int_0^t s l'(s) ds = 2 l(t) - (2/t) int_0^t l ds and <Y>(t) = (1/t) int_0^t Y ds, the
    integrals by the trapezoid rule on the samples (their spacing must resolve l: the error is of order
    dt^2 l'' per unit time). Returns what ``megno`` returns (t, Y, Y_mean at n_samples equally spaced
    sample times, final, and over the second half slope, slope_err and resid), without log_growth."""
    from scipy.integrate import cumulative_trapezoid  # scipy.integrate: only this estimate needs it

    t, ell = np.asarray(t, float), np.asarray(log_norm, float)
    if t.ndim != 1 or t.shape != ell.shape or t.size < 2 * n_samples or t[0] != 0 or not np.all(np.diff(t) > 0):
        raise ValueError(f"t and log_norm must be increasing samples from t = 0, at least 2 n_samples = "
                         f"{2 * n_samples} of them (got {t.size})")
    if not np.all(np.isfinite(ell)):
        raise ValueError("log_norm must be finite")
    Y = np.zeros_like(t)
    Y[1:] = 2 * ell[1:] - 2 * cumulative_trapezoid(ell, t) / t[1:]
    Ym = np.zeros_like(t)
    Ym[1:] = cumulative_trapezoid(Y, t) / t[1:]
    rec = np.round(np.linspace(0, t.size - 1, n_samples + 1)[1:]).astype(int)
    t_s, Y_s, Ym_s = t[rec], Y[rec], Ym[rec]
    half = t_s >= t_s[-1] / 2
    slope, slope_err, resid, _ = linfit(t_s[half], Ym_s[half])
    return {"t": t_s, "Y": Y_s, "Y_mean": Ym_s, "final": float(Ym_s[-1]), "slope": slope, "slope_err": slope_err,
            "resid": resid}


def _megno_args(ta, n, y0, T, n_samples, tau):
    """The checked arguments of ``megno``: (T, n_samples, tau, n, y0, number of intervals tau in T)."""
    T = positive("T", T)
    if int(n_samples) != n_samples or n_samples < 4:
        raise ValueError(f"n_samples must be an integer >= 4, got {n_samples!r}")
    n_samples = int(n_samples)
    tau = T / n_samples if tau is None else positive("tau", tau)
    n = int(n)
    if len(ta.state) != 2 * n + 2:
        raise ValueError(f"n = {n} does not match an integrator state of size {len(ta.state)} (expected 2 n + 2)")
    y0 = _state("y0", y0, n)
    n_steps = _n_intervals(T, tau)
    if n_steps < n_samples:
        raise ValueError(f"tau = {tau} is longer than the sample spacing T / n_samples = {T / n_samples}")
    return T, n_samples, tau, n, y0, n_steps


def megno_rate(m: dict) -> tuple[float, float]:
    """The exponent a ``megno`` run implies and its error (1/time): twice the slope of <Y> against t
    over the second half (<Y> ~ lambda t / 2 on a chaotic orbit) and twice its stderr."""
    return 2 * m["slope"], 2 * m["slope_err"]


# ----------------------------------------------------------------------------- judges


#: What ``judge_megno`` does (the text a dataset records for the rule; its docstring says the same).
JUDGE_MEGNO_RULE = (
    'Verdict from ``megno`` (final <Y>, its rms residual, slope and slope_err over the second half, horizon T). '
    'chaotic: <Y> - sigma * y_err > y_chaotic_min AND slope - sigma * slope_err > 0 (<Y> keeps growing, ~ lambda '
    't / 2); regular: <Y> + sigma * y_err < y_regular_max (2 for a torus with shear, 0 for isochronous / periodic'
    ' motion) AND (slope + sigma * slope_err) * T < growth_max (no growth of <Y> over the horizon). A regular '
    'verdict bounds lambda only to about 2 y_regular_max / T. Otherwise undecided.'
)


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
    T = positive("T", T)
    nums = (f"<Y> = {_g(y_mean)} +- {_g(y_err)} at T = {_g(T)}, slope {_g(slope)} +- {_g(slope_err)} /time, "
            f"sigma {_g(sigma)}")
    if y_mean - sigma * y_err > y_chaotic_min and slope - sigma * slope_err > 0:
        return CHAOTIC, (f"<Y> above {_g(y_chaotic_min)} and growing (lambda ~ 2 slope = {_g(2 * slope)}); {nums}")
    if y_mean + sigma * y_err < y_regular_max and (slope + sigma * slope_err) * T < growth_max:
        return REGULAR, (f"<Y> below {_g(y_regular_max)} without growth over T (lambda below about "
                         f"{_g(2 * y_regular_max / T)}); {nums}")
    return UNDECIDED, (f"<Y> neither resolved above {_g(y_chaotic_min)} and growing nor settled below "
                       f"{_g(y_regular_max)}; {nums}")


def judge_megno_run(m: dict, T: float, sigma: float) -> tuple[str, str]:
    """``judge_megno`` on a ``megno`` run over T."""
    return judge_megno(m["final"], m["resid"], m["slope"], m["slope_err"], T, sigma=sigma)


def megno_in_long_double(v_ld: tuple[str, str], ld: dict, v_double: tuple[str, str], T_ld: float,
                         T_double: float) -> tuple[str, str]:
    """The MEGNO indicator when the long-double precision check ran: the long-double run's verdict
    (v_ld), under the same gate as every tangent-based verdict (chaotic stands only when the check
    confirmed exponential growth; else undecided); the double run's verdict (v_double) named in the
    reason."""
    v, r = v_ld
    if v == CHAOTIC and ld["check"] != "confirmed":
        v, r = UNDECIDED, f"{ld['reason']}; MEGNO alone: {r}"
    return v, f"in long double over T = {T_ld:.3g}: {r}; in double over T = {T_double:.3g}: {v_double[0]}"
