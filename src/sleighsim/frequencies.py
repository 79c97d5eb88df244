"""Frequency analysis of a sampled signal (Laskar 1990, Icarus 88, 266; Laskar 1993, Physica D
67, 257): the frequency of the signal's largest line per window, and how much it changes from
window to window. On a torus the lines are fixed and the refined frequency converges fast as the
window grows (Hann window: error falling like W^-2 or faster); on a chaotic orbit it wanders
(spread falling no faster than W^-1/2). Frequencies in cycles per time unit; dt, W in time units.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

# relative precision of a refined frequency: 100 x the Brent tolerance (1e-13); a spread of the
# window frequencies at or below it is converged
PRECISION = 1e-11


def _check(x, dt, n_min):
    x = np.asarray(x, float)
    if x.ndim != 1 or x.size < n_min:
        raise ValueError(f"x must be a 1-d series of at least {n_min} samples, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("x contains non-finite samples")
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be positive and finite, got {dt}")
    return x


def leading_frequency(x, dt: float, band=None) -> float:
    """Frequency of the largest line of x (sampled every dt, mean removed): the largest bin of the
    Hann-windowed DFT (zero excluded; within band = (f_lo, f_hi) if given), refined by maximising
    |sum_k x_k w_k exp(-2 pi i f t_k)| over f within one bin either side (bounded Brent, to
    PRECISION / 100 relative). NaN when that bin is not a local maximum of the spectrum (the line
    lies outside the band) or the refined maximum sits on the edge of its bracket."""
    x = _check(x, dt, 8)
    x = x - x.mean()
    n = x.size
    w = np.hanning(n)
    xw = x * w
    F = np.abs(np.fft.rfft(xw))
    df = 1.0 / (n * dt)
    allowed = np.arange(F.size) >= 1
    if band is not None:
        f_bins = np.arange(F.size) * df
        allowed &= (f_bins >= band[0]) & (f_bins <= band[1])
        if not allowed.any():
            raise ValueError(f"no DFT bin in band {band} (resolution {df:.3g})")
    k = int(np.flatnonzero(allowed)[np.argmax(F[allowed])])
    if (k > 1 and F[k - 1] > F[k]) or (k + 1 < F.size and F[k + 1] > F[k]):
        return math.nan
    f0 = k * df
    t = np.arange(n) * dt

    def minus_amplitude(f):
        return -abs(np.dot(xw, np.exp(-2j * math.pi * f * t)))

    lo, hi = max(f0 - df, 0.5 * df), f0 + df
    r = minimize_scalar(minus_amplitude, bounds=(lo, hi), method="bounded", options={"xatol": 1e-2 * PRECISION * f0})
    return float(r.x) if lo + 1e-6 * df < r.x < hi - 1e-6 * df else math.nan


def window_frequencies(x, dt: float, n_windows: int, band=None) -> np.ndarray:
    """``leading_frequency`` (within band, if given) of each of n_windows consecutive equal windows
    of x (a remainder of fewer than n_windows samples at the end is dropped)."""
    x = _check(x, dt, 8 * n_windows)
    if int(n_windows) != n_windows or n_windows < 1:
        raise ValueError(f"n_windows must be a positive integer, got {n_windows}")
    m = x.size // n_windows
    return np.array([leading_frequency(x[i * m:(i + 1) * m], dt, band) for i in range(n_windows)])


def drift(x, dt: float, splits=(2, 4, 8, 16), *, min_cycles: float = 8.0) -> dict:
    """How the leading frequency of x changes between windows, for windows of length W = T / K,
    K in ``splits`` (T = the series' length): D(W) = sample standard deviation of the K window
    frequencies / their mean, and its convergence exponent between the longest and the shortest
    windows, slope = ln(D(W_max) / D(W_min)) / ln(W_max / W_min) (D ~ W^slope; a torus gives about
    -4 with the Hann window, a wandering frequency -1/2 or more).

    One line is followed in every window: f_ref is the median of the leading frequencies of the
    finest split's windows, and each window's line is the largest within (f_ref / 2, 3 f_ref / 2),
    so windows do not hop between lines of similar amplitude (a harmonic, or a fast line). Splits
    whose windows hold fewer than min_cycles periods of f_ref, or in which a window has no line
    in the band (NaN), are left out (a window of a few periods does not define a frequency);
    slope and slope_err are NaN when fewer than two remain.

    Uncertainty: ln D of K windows is given the standard error 1/sqrt(2 (K - 1)), that of a sample
    standard deviation of K independent values (window frequencies of a chaotic orbit are nearly
    independent once W exceeds its correlation time; on a torus D is deterministic, so the error
    is an upper bound there); the slope's error combines the two ends' errors. When D(W_max) is at
    or below PRECISION the frequency has converged as far as the refinement resolves: slope is
    then -inf. Returns splits (those used), W, D, D_log_err, slope, slope_err, f_ref, f (the mean
    window frequency of the finest split used; NaN if none) and frequencies (one array per split
    used)."""
    splits = sorted({int(k) for k in splits})
    if not splits or splits[0] < 2:
        raise ValueError(f"splits must be window counts >= 2, got {splits}")
    if not (math.isfinite(min_cycles) and min_cycles > 0):
        raise ValueError(f"min_cycles must be positive, got {min_cycles}")
    x = _check(x, dt, 8 * splits[-1])
    T = x.size * dt
    f_ref = window_frequencies(x, dt, splits[-1])
    f_ref = float(np.nanmedian(f_ref)) if np.isfinite(f_ref).any() else math.nan
    freqs = {k: window_frequencies(x, dt, k, (0.5 * f_ref, 1.5 * f_ref)) for k in splits
             if math.isfinite(f_ref) and f_ref * T / k >= min_cycles}
    splits = [k for k, v in freqs.items() if np.all(np.isfinite(v))]
    freqs = [freqs[k] for k in splits]
    W = np.array([T / k for k in splits])
    D = np.array([v.std(ddof=1) / abs(v.mean()) for v in freqs])
    D_log_err = np.array([1.0 / math.sqrt(2.0 * (k - 1)) for k in splits])
    if len(splits) < 2:
        slope, slope_err = math.nan, math.nan
    elif D[0] <= PRECISION:
        slope, slope_err = -math.inf, 0.0
    else:
        lever = math.log(W[0] / W[-1])
        slope = math.log(D[0] / max(D[-1], PRECISION)) / lever
        slope_err = math.hypot(D_log_err[0], D_log_err[-1]) / lever
    return {"splits": np.array(splits, int), "W": W, "D": D, "D_log_err": D_log_err, "slope": float(slope),
            "slope_err": float(slope_err), "f_ref": f_ref, "f": float(freqs[-1].mean()) if freqs else math.nan, "frequencies": freqs}
