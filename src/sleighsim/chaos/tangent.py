"""Tangent-based chaos indicators and their judges, besides MEGNO (``chaos.megno``).

Engine (all times in the flow's own time unit, exponents lambda in 1/time, natural logs):
``finite_time_exponents``: statistics of finite-time Lyapunov exponents (FTLEs) over
non-overlapping windows of length W of a renormalised tangent vector's log growth.

Judges: ``judge_ftle``, ``judge_benettin`` (the replicas' lambda_1 of
``benettin.replica_exponents``) and ``growth_confirmed`` (the long-double precision check).
Engine conventions: ``propagate``; verdict conventions: ``verdicts``.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.common import _n_intervals, linfit
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED, _check_judge, _g, polynomial_rate_bound
from sleighsim.model.params import positive

# ----------------------------------------------------------------------------- engines


def finite_time_exponents(log_growth, tau, windows, *, t_skip=0.0, min_windows=10):
    """FTLE statistics over non-overlapping windows.

    ``log_growth``: per-interval log growth g_k (k = 0..n-1) of one tangent vector
    renormalised every ``tau`` (time units), e.g. ``megno.megno(...)["log_growth"]``. The first
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
    tau = positive("tau", tau)
    g = _skipped_log_growth(log_growth, tau, t_skip)
    W = np.atleast_1d(np.asarray(windows, dtype=float)).ravel()
    if W.size == 0:
        raise ValueError("windows is empty")
    m = np.array([_n_intervals(positive("windows", w), tau, "windows entry", "tau") for w in W])
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
                         f"{_g(bound)}) and spread falls like W^{_g(spread_slope)} (< W^{_g(spread_slope_max)}); "
                         f"{nums}")
    return UNDECIDED, f"neither exponential growth resolved nor a regular spread law; {nums}"


#: Written into the chaos_verdict dataset (attribute benettin_rule).
JUDGE_BENETTIN_RULE = (
    "The replicas' lambda_1: chaotic when resolved above the rate polynomial growth can fake over the horizon "
    "(lambda_1 - sigma stderr > 2 ln(T / tau) / T); regular when the replica run says so (lambda_1 + sigma "
    "stderr below that rate, itself below the configured floor); else undecided."
)


def judge_benettin(res: dict, tau: float, sigma: float) -> tuple[str, str]:
    """Applies :data:`JUDGE_BENETTIN_RULE`, the rule as the datasets record it (just above)."""
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
