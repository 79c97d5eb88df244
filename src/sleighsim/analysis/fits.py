"""Least-squares fits: power laws (log-log), a line plus one sinusoid, a phase.

Power laws: :func:`loglog`. Line plus sinusoid: x(t) ~ c0 + r t + A sin(w t) + B cos(w t), w free
(scipy.optimize.curve_fit started from the periodogram peak near a guess, scipy.signal.periodogram;
samples uniform in t). The record is deterministic, so the formal standard errors of the fit
understate the error of the model; the uncertainty reported is the larger of the formal error and
the half-difference between fits on the two halves of the window (a window-sensitivity estimate).
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.common import linfit

METHOD = ("least-squares fit of c0 + r t + A sin(w t) + B cos(w t), w free (scipy curve_fit); uncertainty = "
          "max(formal standard error, half-difference of the fits on the two halves of the window)")


def _model(t, c0, r, A, B, w):
    return c0 + r * t + A * np.sin(w * t) + B * np.cos(w * t)


def refine_frequency(t, x, w_guess: float) -> float:
    """Angular frequency (rad per unit of t) of the largest periodogram peak of x within a factor 1.5
    of w_guess: scipy.signal.periodogram, linear trend removed, Hann window, zero-padded 16 times
    (samples uniform in t); w_guess when no padded bin lies in that band. A start the nonlinear
    fit cannot miss."""
    from scipy.signal import periodogram  # here: at the top it costs every job start-up (scenes.catalog)

    f, power = periodogram(x, fs=1.0 / (t[1] - t[0]), window="hann", nfft=16 * t.size, detrend="linear")
    w = 2 * np.pi * f
    band = (w > w_guess / 1.5) & (w < w_guess * 1.5)
    return float(w[band][np.argmax(power[band])]) if band.any() else w_guess


def _fit(t, x, w_guess):
    from scipy.optimize import curve_fit  # here: at the top it costs every job start-up (scenes.catalog)

    A0 = 0.5 * (np.max(x) - np.min(x))
    w_guess = refine_frequency(t, x, w_guess)
    p, cov = curve_fit(_model, t, x, p0=[float(np.mean(x)), 0.0, A0, A0, w_guess], maxfev=20000)
    return p, np.sqrt(np.diag(cov))


def _derived(p):
    return {"period": 2 * math.pi / abs(p[4]), "amplitude": float(np.hypot(p[2], p[3])), "slope": float(p[1]),
            "mean": float(p[0])}


def line_plus_sinusoid(t, x, w_guess: float) -> dict:
    """Fit on the whole window; returns period, amplitude, slope, mean (and *_uncertainty)."""
    t, x = np.asarray(t, float), np.asarray(x, float)
    if t.size < 20:
        raise ValueError(f"a line-plus-sinusoid fit needs at least 20 samples; got {t.size}")
    p, se = _fit(t, x, w_guess)
    out = _derived(p)
    half = t.size // 2
    halves = [_derived(_fit(t[s], x[s], p[4])[0]) for s in (slice(0, half), slice(half, None))]
    w = abs(p[4])
    formal = {"period": 2 * math.pi * se[4] / w**2, "slope": se[1], "mean": se[0],
              "amplitude": float(np.hypot(se[2], se[3]))}
    for k in list(out):
        out[f"{k}_uncertainty"] = float(max(formal[k], 0.5 * abs(halves[0][k] - halves[1][k])))
    out["rms_residual"] = float(np.sqrt(np.mean((x - _model(t, *p)) ** 2)))
    return out


def phase_against(x, angle) -> dict:
    """Fit x ~ -A sin(angle + phi) (least squares in sin/cos of ``angle``); A >= 0, phi in (-pi, pi]."""
    M = np.c_[np.sin(angle), np.cos(angle)]
    (a, c), *_ = np.linalg.lstsq(M, np.asarray(x, float), rcond=None)
    # -A sin(angle + phi) = -A cos(phi) sin(angle) - A sin(phi) cos(angle)
    return {"amplitude": float(np.hypot(a, c)), "phase": float(math.atan2(-c, -a)),
            "rms_residual": float(np.sqrt(np.mean((x - M @ [a, c]) ** 2)))}


def loglog(x, y, yerr=None, *, min_points: int = 2) -> tuple[float, float, float]:
    """Power law y ~ exp(c) x^k by least squares of log y on log x. Returns (k, c, standard error of k).

    Unweighted unless ``yerr`` is given; then each point is weighted by (y / yerr)^2 (its relative
    error) and the slope's standard error is scaled by the reduced chi-square when that exceeds 1.
    All NaN when there are fewer than ``min_points`` points; the standard error needs three."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    nan = float("nan")
    if x.size < min_points:
        return nan, nan, nan
    lx, ly = np.log(x), np.log(y)
    if yerr is None:
        k, se, _, c = linfit(lx, ly)
        return k, c, se
    w = 1.0 / np.maximum(np.asarray(yerr, float) / y, 1e-12) ** 2
    X = np.c_[lx, np.ones(x.size)]
    cov = np.linalg.inv(X.T @ (w[:, None] * X))
    beta = cov @ X.T @ (w * ly)
    resid = ly - X @ beta
    scale = max(1.0, float(np.sum(w * resid**2) / max(1, x.size - 2)))
    return float(beta[0]), float(beta[1]), float(math.sqrt(cov[0, 0] * scale))
