"""MEGNO of the return map to a section (Cincotta, Giordano and Simo 2003, Physica D 182, 151: MEGNO for
maps), from one tangent vector of the flow read at the section's crossings, and its judge.

A flow whose tangent vector swings by many e-folds within each return (the sleigh: a spike cycle
amplifies it by up to e^36 and the slow approach shrinks it back) keeps the continuous MEGNO <Y>(t) far
from its limit for hundreds of returns: Y(t) = 2 l(t) - (2/t) int l carries twice the swing. Read once
per return, at the same place of the cycle, the swing drops out: l_k = ln |v(t_k)| at the k-th crossing
is the log-norm of the return map's tangent vector up to a bounded factor (the component along the
flow), so the map's MEGNO Y(N) = (2/N) sum_{k=1..N} k (l_k - l_{k-1}) = 2 l_N - (2/N) sum_{k<N} l_k and
<Y>(N) = (1/N) sum_{k=1..N} Y(k) have the flow's limits with time counted in returns: 2 on a torus with
shear (l_k ~ ln k), 0 on an isochronous one, about lambda P N / 2 on a chaotic orbit (lambda P the
exponent per return of mean length P).

Engine: ``section_times`` (local maxima of a sampled observable: the section), ``log_norm_series`` (the
tangent log-norm and the state of a heyoka flow on a grid), ``section_megno``. Judge:
``judge_section_megno`` (``megno.judge_megno`` with the horizon in returns).
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.common import linfit
from sleighsim.chaos.megno import judge_megno
from sleighsim.chaos.propagate import _propagate_until
from sleighsim.chaos.verdicts import UNDECIDED
from sleighsim.model.params import positive

MIN_RETURNS = 8  # returns the map's MEGNO needs at least


def section_times(t, x) -> np.ndarray:
    """The times of the local maxima of x (sampled at increasing times t) that lie above x's mean, each
    refined by the parabola through the sample and its two neighbours: one crossing of the section
    "x at a maximum" per return."""
    t, x = np.asarray(t, float), np.asarray(x, float)
    if t.ndim != 1 or t.shape != x.shape or t.size < 3 or not np.all(np.diff(t) > 0):
        raise ValueError("t and x must be matching samples at increasing times (at least 3)")
    i = 1 + np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:]) & (x[1:-1] > x.mean()))
    a, b, c = x[i - 1], x[i], x[i + 1]
    den = a - 2 * b + c
    shift = np.where(den != 0, 0.5 * (a - c) / np.where(den != 0, den, 1.0), 0.0)
    return t[i] + shift * (t[i + 1] - t[i])


def log_norm_series(ta, n: int, y0, *, T: float, dt: float, seed: int = 0, callback=None) -> dict:
    """One tangent vector along the orbit from y0 over T, on ``ta`` (``engine.integrators.megno_integrator``
    of an n-dimensional system, parameters set; its quadratures are not used), renormalised every dt.
    Returns t (0, dt, ..., T), log_norm (ln |v(t)|, v(0) a random unit vector drawn with ``seed``) and X
    (the state at those times, in double)."""
    T, dt = positive("T", T), positive("dt", dt)
    steps = round(T / dt)
    if steps < 2:
        raise ValueError(f"T = {T} holds fewer than two steps dt = {dt}")
    fp = ta.state.dtype.type
    u = np.random.default_rng(seed).normal(size=n)
    ta.time = fp(1e-9 * dt)  # the quadratures divide by t
    ta.state[:n] = np.asarray(y0).astype(ta.state.dtype)
    ta.state[n:2 * n] = (u / np.linalg.norm(u)).astype(ta.state.dtype)
    ta.state[2 * n:] = 0
    ell, X = np.zeros(steps + 1), np.empty((steps + 1, n))
    X[0] = np.asarray(ta.state[:n], float)
    for k in range(1, steps + 1):
        _propagate_until(ta, fp(1e-9 * dt + k * dt), callback)
        d = ta.state[n:2 * n]
        nrm = np.sqrt(np.sum(d * d))
        ta.state[n:2 * n] = d / nrm
        ell[k], X[k] = ell[k - 1] + float(np.log(nrm)), np.asarray(ta.state[:n], float)
    return {"t": dt * np.arange(steps + 1), "log_norm": ell, "X": X}


def section_megno(t, log_norm, t_section) -> dict:
    """The return map's MEGNO from a flow's tangent log-norm (sampled at times t) read at the section
    crossings t_section (linear interpolation): Y and <Y> per return (module docstring). Returns n
    (returns 1 .. N), Y, Y_mean, final (<Y>(N)), over the second half slope (per return), slope_err
    and resid (as ``megno.megno``), and l (the log-norm at the crossings)."""
    t_section = np.asarray(t_section, float)
    if t_section.size < MIN_RETURNS + 1:
        raise ValueError(f"{t_section.size} crossings: the map's MEGNO needs at least {MIN_RETURNS + 1}")
    ell = np.interp(t_section, np.asarray(t, float), np.asarray(log_norm, float))
    ell = ell - ell[0]
    N = np.arange(1, ell.size)
    partial = np.cumsum(ell)[:-1]  # sum_{k < N} l_k
    Y = 2 * ell[1:] - 2 * partial / N
    Ym = np.cumsum(Y) / N
    half = N >= N[-1] / 2
    slope, slope_err, resid, _ = linfit(N[half].astype(float), Ym[half])
    return {"n": N, "Y": Y, "Y_mean": Ym, "final": float(Ym[-1]), "slope": slope, "slope_err": slope_err,
            "resid": resid, "l": ell}


def judge_section_megno(m: dict, sigma: float) -> tuple[str, str]:
    """``megno.judge_megno`` on the return map's MEGNO (``section_megno``) with the horizon counted in
    returns: chaotic when <Y>(N) - sigma resid > 4 and still growing, regular when <Y>(N) + sigma resid <
    2.5 without growth over the N returns; otherwise undecided (also with fewer than MIN_RETURNS)."""
    N = int(m["n"][-1]) if len(m["n"]) else 0
    if N < MIN_RETURNS:
        return UNDECIDED, f"only {N} returns to the section (at least {MIN_RETURNS} needed)"
    v, reason = judge_megno(m["final"], m["resid"], m["slope"], m["slope_err"], float(N), sigma=sigma)
    return v, f"return map over N = {N} returns: {reason.replace(' /time', ' per return')}"


def section_rate(m: dict, t_section) -> tuple[float, float]:
    """The exponent the map's MEGNO implies (2 slope per return over the mean return time) and its error,
    in 1/time."""
    P = float(np.mean(np.diff(np.asarray(t_section, float))))
    return (2 * m["slope"] / P, 2 * m["slope_err"] / P) if math.isfinite(P) and P > 0 else (math.nan, math.nan)
