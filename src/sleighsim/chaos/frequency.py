"""Frequency analysis (Laskar 1990, Icarus 88, 266; Laskar 1993, Physica D 67, 257) as a chaos
indicator without tangent dynamics, and its judge.

The analysis of a sampled signal: the frequency of its largest line per window
(``leading_frequency``, ``window_frequencies``) and how much it changes from window to window
(``drift``). On a torus the lines are fixed and the refined frequency converges fast as the window
grows (Hann window: error falling like W^-2 or faster); on a chaotic orbit it wanders (spread
falling about like W^-1/2, or not at all).

Engine: ``frequency_drift``: that analysis of one component of the orbit. Judge:
``judge_frequency`` on one or more runs of one orbit in precisions of decreasing rounding
(``judged_run``, ``frequency_log_ratio``); it says regular or undecided, never chaotic.

Times (dt, W, T) in the flow's own time unit, frequencies in cycles per time unit, natural logs.
Engine conventions: ``propagate``; verdict conventions: ``verdicts``.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.common import _state, check_splits
from sleighsim.chaos.verdicts import REGULAR, UNDECIDED, _g, _is_finite
from sleighsim.engine.orbits import grid_samples
from sleighsim.model.params import positive

# relative precision of a refined frequency: on a pure cosine sampled 28 times a period the error is
# 4.5e-12 over 280 periods, 3e-14 over 1100 and 2e-16 over 4500 (tests/test_frequencies.py; the Hann
# window's leakage from the line at -f dominates short windows, rounding long ones); a spread of the
# window frequencies at or below PRECISION is converged
PRECISION = 1e-11
MIN_SAMPLES = 8  # samples a window needs at least
MIN_WINDOWS = 4  # windows a split needs to enter the convergence exponent (slope)


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
    |S(f)| = |sum_k x_k w_k exp(-2 pi i f t_k)| over f within one bin either side (t from the
    window's centre): the root of d|S|^2/df (Brent, to 1e-6 PRECISION relative) where it changes
    sign across those bins, else bounded Brent on |S| itself. NaN when that bin is not a local
    maximum of the spectrum (the line lies outside the band) or is the first bin (a line not
    resolved from zero frequency)."""
    from scipy.optimize import brentq, minimize_scalar

    x = _check(x, dt, MIN_SAMPLES)
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
    if k == 1 or F[k - 1] > F[k] or (k + 1 < F.size and F[k + 1] > F[k]):
        return math.nan
    f0 = k * df
    t = (np.arange(n) - (n - 1) / 2) * dt  # from the window's centre: |amplitude| is the same, phases half as large

    def terms(s):  # s: offset from the bin centre f0
        return xw * np.exp(-2j * math.pi * (f0 + s) * t)

    def slope(s):  # d|S|^2/df / (4 pi), S(f) = sum_k xw_k exp(-2 pi i f t_k)
        e = terms(s)
        return float(np.imag(np.conj(np.sum(e)) * np.sum(t * e)))

    # numpy's pairwise sums, not np.dot: BLAS sums in an order that depends on its thread count, and
    # the last digits (which decide a torus's convergence exponent) followed the number of cores
    tol = 1e-6 * PRECISION * f0
    if slope(-df) > 0 > slope(df):  # the maximum as the root of the derivative: to rounding, not to sqrt(rounding)
        return float(f0 + brentq(slope, -df, df, xtol=tol))
    r = minimize_scalar(lambda s: -abs(np.sum(terms(s))), bounds=(-df, df), method="bounded", options={"xatol": tol})
    return float(f0 + r.x)


def window_frequencies(x, dt: float, n_windows: int, band=None) -> np.ndarray:
    """``leading_frequency`` (within band, if given) of each of n_windows consecutive equal windows
    of x (a remainder of fewer than n_windows samples at the end is dropped)."""
    x = _check(x, dt, MIN_SAMPLES * n_windows)
    if int(n_windows) != n_windows or n_windows < 1:
        raise ValueError(f"n_windows must be a positive integer, got {n_windows}")
    m = x.size // n_windows
    return np.array([leading_frequency(x[i * m:(i + 1) * m], dt, band) for i in range(n_windows)])


def _convergence(splits, W, D, D_log_err) -> tuple[float, float]:
    """(slope, slope_err) of D ~ W^slope between the longest and shortest windows of the splits with
    at least MIN_WINDOWS windows (see :func:`drift`)."""
    fit = [i for i, k in enumerate(splits) if k >= MIN_WINDOWS]
    if len(fit) < 2:
        return math.nan, math.nan
    a, b = fit[0], fit[-1]
    if D[a] <= PRECISION:
        return -math.inf, math.nan
    lever = math.log(W[a] / W[b])
    return math.log(D[a] / max(D[b], PRECISION)) / lever, math.hypot(D_log_err[a], D_log_err[b]) / lever


#: Written into the chaos_verdict dataset (attribute frequency_method).
DRIFT_RULE = (
    "How the leading frequency of x changes between windows, for windows of length W = T / K, K in ``splits`` "
    "(T = the series' length): D(W) = sample standard deviation of the K window frequencies / their mean, and "
    "its convergence exponent between the longest and the shortest windows, slope = ln(D(W_max) / D(W_min)) / "
    "ln(W_max / W_min) (D ~ W^slope; a torus gives about -4 with the Hann window; a wandering frequency about "
    "-1/2: measured -0.6 to +0.3 on the chaotic textbook orbits). One line is followed in every window: f_ref "
    "is the median of the leading frequencies of the finest split's windows, and each window's line is the "
    "largest within (f_ref / 2, 3 f_ref / 2), so windows do not hop between lines of similar amplitude (a "
    "harmonic, or a fast line). Splits whose windows hold fewer than min_cycles periods of f_ref, or in which a"
    " window has no line in the band (NaN), are left out (a window of a few periods does not define a "
    "frequency); slope and slope_err are NaN when fewer than two remain. Uncertainty: ln D of K windows is "
    "given the standard error 1/sqrt(2 (K - 1)), that of a sample standard deviation of K independent values "
    "(window frequencies of a chaotic orbit are nearly independent once W exceeds its correlation time; on a "
    "torus D is deterministic, so the error is an upper bound there); the slope's error combines the two ends' "
    "errors. A split of fewer than MIN_WINDOWS windows keeps its D but does not enter the slope: with K = 2, D "
    "is one difference |f_1 - f_2|, whose logarithm has a heavy lower tail that this error does not cover, so "
    "one chance coincidence of two window frequencies would fake convergence. When D(W_max) is at or below "
    "PRECISION the frequency has converged as far as the refinement resolves: slope is then -inf and slope_err "
    "NaN. Returns splits (those used), W, D, D_log_err, slope, slope_err, f_ref, f (the mean window frequency "
    "of the finest split used; NaN if none) and frequencies (one array per split used)."
)


def drift(x, dt: float, splits=(2, 4, 8, 16), *, min_cycles: float = 8.0) -> dict:
    """Applies :data:`DRIFT_RULE`, the rule as the datasets record it (just above)."""
    splits = check_splits(splits)
    if not (math.isfinite(min_cycles) and min_cycles > 0):
        raise ValueError(f"min_cycles must be positive, got {min_cycles}")
    x = _check(x, dt, MIN_SAMPLES * splits[-1])
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
    slope, slope_err = _convergence(splits, W, D, D_log_err)
    return {"splits": np.array(splits, int), "W": W, "D": D, "D_log_err": D_log_err, "slope": float(slope),
            "slope_err": float(slope_err), "f_ref": f_ref, "f": float(freqs[-1].mean()) if freqs else math.nan,
            "frequencies": freqs}


def frequency_drift(ta, y0, *, T, dt, component, splits=(2, 4, 8, 16), min_cycles=8.0, callback=None):
    """Frequency analysis of the orbit from y0 (no tangent dynamics): component ``component``
    sampled every dt over T (one propagate_grid run in the integrator's precision: double, long
    double or real128), then ``drift`` over windows T / K, K in ``splits``. Returns
    that dict with ``T``, ``dt`` and ``final_state``."""
    dim = len(ta.state)
    y0 = _state("y0", y0, dim)
    T, dt = positive("T", T), positive("dt", dt)
    splits = check_splits(splits)
    if not (isinstance(component, (int, np.integer)) and 0 <= component < dim):
        raise ValueError(f"component must be an index into the state (0..{dim - 1}), got {component!r}")
    n = round(T / dt)
    if n < MIN_SAMPLES * splits[-1]:
        raise ValueError(f"T / dt = {n} samples: too few for {splits[-1]} windows of at least {MIN_SAMPLES}")
    ta.state[:] = np.asarray(y0).astype(ta.state.dtype)
    samples = grid_samples(ta, n, dt, callback)[0].astype(float)  # n samples: T = n dt (any precision)
    out = drift(samples[:, component], dt, splits, min_cycles=min_cycles)
    out.update(T=float(n * dt), dt=float(dt), final_state=ta.state.copy())
    return out


#: Written into the chaos_verdict dataset (attribute frequency_rule).
JUDGE_FREQUENCY_RULE = (
    "Verdict from frequency analysis (``frequency_drift``) of one orbit in one or more precisions, in order of "
    "decreasing rounding: ``runs`` is a list of dicts with ``precision`` (a name), ``slope`` and ``slope_err`` "
    "(the convergence exponent of the spread D ~ W^slope of the leading frequency), ``D`` (the spread at the "
    "longest window) and, from the second run on, ``log_ratio`` +- ``log_ratio_err`` (ln of the previous run's "
    "D over this one's, ``frequency_log_ratio``) and ``rounding_ratio`` (the previous run's tolerance over this"
    " one's). regular: the window frequencies converge faster than 1/W in some run (slope + sigma err < "
    "converged_max, or slope = -inf: at the refinement's precision): a torus's refined frequency converges like"
    " W^-2 or faster, while a frequency that wanders on a chaotic orbit spreads like W^-1/2 or more slowly. "
    "Otherwise undecided. The test never says chaotic: a spread that neither converges nor depends on the "
    "rounding also appears on a torus whose windows are shorter than one of its slow periods (the smoke "
    "config's rotor states: D about 5e-3 at every window, equal in both precisions). When the drift shrinks "
    "with the rounding by more than the square root of the rounding ratio (log_ratio - sigma err > "
    "ln(rounding_ratio) / 2), the reason says so: the previous run's drift is then integration error, and the "
    "exact dynamics' drift is bounded by the last run's D, but that run's own drift is not explained, so the "
    "verdict stays undecided."
)


def judge_frequency(runs, *, sigma=3.0, converged_max=-1.0):
    """Applies :data:`JUDGE_FREQUENCY_RULE`, the rule as the datasets record it (just above)."""
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


#: Written into the chaos_verdict dataset (attribute frequency_rule).
FREQUENCY_LOG_RATIO_RULE = (
    "ln(D_coarse / D_fine) of two ``frequency_drift`` runs of one orbit (coarse: the larger rounding, e.g. "
    "double against long double) over the splits both used, weighted by K - 1 (the windows behind each D; a D "
    "below the refinement's precision counts as that precision), and its standard error: the same weighted mean"
    " of the splits' errors 1 / sqrt(K - 1) (that of the ratio of two independent sample standard deviations of"
    " K values), the error of the mean if the splits were fully correlated (they share the data). (NaN, NaN) "
    "when no split is shared."
)


def frequency_log_ratio(coarse: dict, fine: dict) -> tuple[float, float]:
    """Applies :data:`FREQUENCY_LOG_RATIO_RULE`, the rule as the datasets record it (just above)."""
    common = np.intersect1d(coarse["splits"], fine["splits"])
    if common.size == 0:
        return math.nan, math.nan
    da, db = (np.maximum([run["D"][list(run["splits"]).index(k)] for k in common], PRECISION)
              for run in (coarse, fine))
    w = common - 1.0
    return float(np.sum(w * np.log(da / db)) / np.sum(w)), float(np.sum(np.sqrt(w)) / np.sum(w))


def judged_run(precision: str, run: dict, **ratio) -> dict:
    """A ``frequency_drift`` run as ``judge_frequency`` takes it."""
    return {"precision": precision, "slope": run["slope"], "slope_err": run["slope_err"],
            "D": float(run["D"][0]) if run["D"].size else math.nan, **ratio}
