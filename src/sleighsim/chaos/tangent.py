"""Tangent-based chaos indicators and their judges.

Engines (all times in the flow's own time unit, exponents lambda in 1/time, natural logs):

* ``finite_time_exponents``: statistics of finite-time Lyapunov exponents (FTLEs) over
  non-overlapping windows of length W of a renormalised tangent vector's log growth.
* ``megno`` (on ``engine.integrators.megno_integrator``): MEGNO (Cincotta & Simo 2000, A&AS 147, 205) computed
  exactly as extra quadratures of heyoka's variational equations.

Judges: ``judge_ftle``, ``judge_megno`` (``judge_megno_run`` on a ``megno`` run), ``judge_benettin``
(the replicas' lambda_1 of ``benettin.replica_exponents``), ``megno_in_long_double`` and
``growth_confirmed`` (the long-double precision check). Engine conventions: ``propagate``;
verdict conventions: ``verdicts``.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.common import _n_intervals, _positive, _state, linfit
from sleighsim.chaos.propagate import _propagate_until
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED, _check_judge, _g, polynomial_rate_bound

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
    g = _skipped_log_growth(log_growth, tau, t_skip)
    W = np.atleast_1d(np.asarray(windows, dtype=float)).ravel()
    if W.size == 0:
        raise ValueError("windows is empty")
    m = np.array([_n_intervals(_positive("windows", w), tau, "windows entry", "tau") for w in W])
    n_win = g.size // m
    mean, std = _window_statistics(g, W, m, n_win)
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


def _skipped_log_growth(log_growth, tau, t_skip):
    """The checked log growth series without its first t_skip time units (a multiple of tau)."""
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
    return g[n_skip:]


def _window_statistics(g, W, m, n_win):
    """Mean and standard deviation (ddof=1) of the FTLEs over the n_win[i] windows of length W[i]
    (m[i] intervals each); NaN where there are fewer than 2 windows."""
    mean = np.full(W.size, np.nan)
    std = np.full(W.size, np.nan)
    for i, (mi, nw) in enumerate(zip(m, n_win)):
        if nw < 2:
            continue
        ftle = g[: nw * mi].reshape(nw, mi).sum(axis=1) / W[i]
        mean[i] = ftle.mean()
        std[i] = ftle.std(ddof=1)
    return mean, std


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


def _megno_args(ta, n, y0, T, n_samples, tau):
    """The checked arguments of ``megno``: (T, n_samples, tau, n, y0, number of intervals tau in T)."""
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
    return T, n_samples, tau, n, y0, n_steps


# ----------------------------------------------------------------------------- judges


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


# the docstring is written into the chaos_verdict dataset (attribute megno_rule)
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


def judge_megno_run(m: dict, T: float, sigma: float) -> tuple[str, str]:
    """``judge_megno`` on a ``megno`` run over T."""
    return judge_megno(m["final"], m["resid"], m["slope"], m["slope_err"], T, sigma=sigma)


# the docstring is written into the chaos_verdict dataset (attribute benettin_rule)
def judge_benettin(res: dict, tau: float, sigma: float) -> tuple[str, str]:
    """The replicas' lambda_1: chaotic when resolved above the rate polynomial growth can fake over
    the horizon (lambda_1 - sigma stderr > 2 ln(T / tau) / T); regular when the replica run says so
    (lambda_1 + sigma stderr below that rate, itself below the configured floor); else undecided."""
    lam, err, T = float(res["exponents"][0]), float(res["stderr"][0]), float(res["T"])
    bound = polynomial_rate_bound(T, tau)
    text = f"lambda_1 = {lam:.3g} +- {err:.2g} over T = {T:.3g} per replica ({res['status']}); bound {bound:.2g}"
    if not (math.isfinite(lam) and math.isfinite(err)):
        return UNDECIDED, "undetermined: " + text
    if lam - sigma * err > bound:
        return CHAOTIC, "exponential growth resolved: " + text
    if res["status"] == "regular":
        return REGULAR, "no growth beyond polynomial: " + text
    return UNDECIDED, "neither resolved: " + text


def growth_confirmed(g, tau: float, T: float, sigma: float, n_blocks: int) -> tuple[float, float, float, bool]:
    """Does one tangent vector grow exponentially? Its lambda_1 (the log growth g per interval tau
    over the time g covers) and stderr (``n_blocks`` consecutive block rates, std / sqrt(n_blocks)):
    confirmed when lambda_1 - sigma stderr > polynomial_rate_bound(T, tau). Returns (lambda_1,
    stderr, bound, confirmed)."""
    blocks = np.array([b.sum() / (b.size * tau) for b in np.array_split(g, n_blocks)])
    lam, err = float(g.sum() / (g.size * tau)), float(blocks.std(ddof=1) / math.sqrt(n_blocks))
    bound = polynomial_rate_bound(T, tau)
    ok = math.isfinite(lam) and math.isfinite(err) and lam - sigma * err > bound
    return lam, err, bound, ok


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
