"""Is an orbit on a 2-torus, and on which one of a family? The cycle events, the train test, the
identity and the family's laws of the torus-stability scene (sleighsim.scenes.torus_stability), on
sampled section data.

Conventions. An orbit with a fast angle is cut by the section where that angle is 0 mod 2 pi: crossing
times t_k and states X_k (rows), many per slow cycle. On a 2-torus the section is a closed curve
that the crossings walk along by a fixed rotation of the slow angle, so a smooth coordinate X[:, c]
of the crossings is a smooth function of the slow angle, which advances linearly in time: the times at
which it crosses a level (interpolated between crossings) mark one fixed point of the section curve
and come strictly periodically, whatever the fast phase. A train of such event times is the orbit's
refined train; its intervals are the torus' slow period. Times in the flow's time unit.
"""

from __future__ import annotations

import math

import numpy as np

PERIODIC, REPEATING, NOT_SHOWN = "torus (periodic train)", "torus (k-interval train)", "not shown to be a torus"
CLASSES = (PERIODIC, REPEATING, NOT_SHOWN)
REFERENCE, SAME, ANOTHER = "reference", "the reference's torus", "another torus of the family"
UNDETERMINED = "undetermined"
IDENTITIES = (REFERENCE, SAME, ANOTHER, UNDETERMINED)
HALF_POINTS = 4  # section crossings on each side of an event: the interpolant has degree 2 x 4 - 1 = 7

#: Written into the torus_stability dataset (attribute crossing_rule).
CROSSING_RULE = (
    "Events of the section data (times t_k, rows X_k): each k where column c goes from below to at or above "
    "level (direction +1; from above to at or below for -1) between crossings k and k + 1; the polynomial of "
    "degree 2 m - 1 through the crossings k - m + 1 .. k + m (m = 4) in t, per column, is solved for the "
    "level in [t_k, t_k+1] (Brent) and gives the event time and the event point (every column there). An "
    "event whose stencils run past the record's ends is dropped. Its time's error: the largest difference from "
    "the same solved on the stencils k - m + 2 .. k + m - 1 (degree 5; truncation) and k - m .. k + m - 1, "
    "k - m + 2 .. k + m + 1 (shifted by one crossing: other samples, so their noise shows), at least one unit "
    "in the last place of the time (the times are doubles); its point's error: the difference from the "
    "degree-5 stencil's."
)


def _event(t, X, k: int, lo: int, hi: int, column: int, level: float) -> tuple[float, np.ndarray]:
    """(time, point): the interpolants of degree hi - lo - 1 through rows k + lo .. k + hi - 1 at column's
    level crossing in [t_k, t_k+1] (the end nearer the level when rounding leaves no sign change)."""
    sl = slice(k + lo, k + hi)
    fits = [np.polynomial.Polynomial.fit(t[sl] - t[k], X[sl, j], hi - lo - 1) for j in range(X.shape[1])]
    from scipy.optimize import brentq  # local: scipy.optimize is slow to import (the catalog's start-up)

    h = t[k + 1] - t[k]
    fa, fb = fits[column](0.0) - level, fits[column](h) - level
    if fa * fb <= 0:
        r = brentq(lambda x: fits[column](x) - level, 0.0, h, xtol=1e-15 * h, rtol=4 * np.finfo(float).eps)
    else:
        r = 0.0 if abs(fa) < abs(fb) else h
    return t[k] + r, np.array([f(r) for f in fits])


#: The stencils (first, last + 1 row relative to k) of an event: the event's, then its error's.
STENCILS = ((-HALF_POINTS + 1, HALF_POINTS + 1), (-HALF_POINTS + 2, HALF_POINTS),
            (-HALF_POINTS, HALF_POINTS), (-HALF_POINTS + 2, HALF_POINTS + 2))


def crossings(t, X, column: int, level: float, direction: int) -> dict:
    """Applies :data:`CROSSING_RULE`, the rule as the datasets record it (just above). Returns times (n,),
    points (n, columns), time_err (n,) and point_err (n, columns)."""
    t, X = np.asarray(t, float), np.atleast_2d(np.asarray(X, float))
    if direction not in (-1, 1):
        raise ValueError(f"direction must be +1 or -1, got {direction!r}")
    s = direction * (X[:, column] - level)
    m = HALF_POINTS
    ks = [k for k in np.flatnonzero((s[:-1] < 0) & (s[1:] >= 0)) if k - m >= 0 and k + m + 1 < t.size]
    found = [[_event(t, X, k, lo, hi, column, level) for lo, hi in STENCILS] for k in ks]
    ev = np.array([[time for time, _ in row] for row in found]).reshape(-1, len(STENCILS))
    pts = np.array([[point for _, point in row[:2]] for row in found]).reshape(len(ks), 2, X.shape[1])
    return {"times": ev[:, 0], "points": pts[:, 0],
            "time_err": np.maximum(np.abs(ev[:, 1:] - ev[:, :1]).max(axis=1), np.spacing(np.abs(ev[:, 0]))),
            "point_err": np.abs(pts[:, 0] - pts[:, 1])}


def train_fit(times, k: int) -> tuple[float, float, float]:
    """(P, R, c): least squares t_n = a_(n mod k) + n P over the train (k offsets, one period per event);
    R the residuals' rms with n - k - 1 degrees of freedom, c = sqrt((A^T A)^-1) for P (P's standard
    error is c times the residuals' scale)."""
    times = np.asarray(times, float)
    n = np.arange(times.size)
    A = np.zeros((n.size, k + 1))
    A[n, n % k] = 1.0
    A[:, k] = n
    coef, *_ = np.linalg.lstsq(A, times - times[0], rcond=None)
    dof = n.size - k - 1
    R = float(np.sqrt(np.sum((times - times[0] - A @ coef) ** 2) / dof)) if dof > 0 else math.nan
    return float(coef[k]), R, float(math.sqrt(np.linalg.inv(A.T @ A)[k, k]))


#: Written into the torus_stability dataset (attribute train_rule).
TRAIN_RULE = (
    "The class of an orbit from its refined train t_0 .. t_N (event times, CROSSING_RULE) and their errors "
    "e_n: resolution S = rms of e_n. \"not shown to be a torus\" when N < min_intervals. For k = 1, 2, .. "
    "max_intervals (while every offset class holds at least 3 events), the least-squares fit t_n = "
    "a_(n mod k) + n P and its residual rms R_k (n - k - 1 degrees of freedom): the first k with R_k <= factor "
    "x S is the class, \"torus (periodic train)\" for k = 1 (every interval P), \"torus (k-interval train)\" "
    "for k > 1 (k intervals repeating, k P together); else \"not shown to be a torus\". On a 2-torus the "
    "train is strictly periodic (the events mark one point of the section curve), and a train that repeats "
    "only after k intervals marks k points of it. The period P +- c max(R_k, S) (c from the fit's normal "
    "equations) from the chosen fit, from k = 1 when none fits."
)


def classify(times, errors, *, min_intervals: int, factor: float, max_intervals: int) -> dict:
    """Applies :data:`TRAIN_RULE`, the rule as the datasets record it (just above). Returns torus_class,
    train_intervals (k; 0 when not shown), period, period_err, train_residual (R_k), train_resolution (S)
    and class_reason."""
    times, errors = np.asarray(times, float), np.asarray(errors, float)
    ok = np.isfinite(times)
    times, errors = times[ok], errors[ok]
    N = times.size - 1
    S = float(np.sqrt(np.mean(errors**2))) if errors.size else math.nan
    out = {"torus_class": NOT_SHOWN, "train_intervals": 0, "period": math.nan, "period_err": math.nan,
           "train_residual": math.nan, "train_resolution": S}
    if N < max(min_intervals, 2):
        return {**out, "class_reason": f"{N} intervals, fewer than {min_intervals}"}
    tried = []
    for k in range(1, max_intervals + 1):
        if times.size < 3 * k:
            break
        P, R, c = train_fit(times, k)
        tried.append(f"R_{k} {R:.3g}")
        if k == 1 or R <= factor * S:
            out.update(period=P, period_err=c * max(R, S), train_residual=R)
        if R <= factor * S:
            what = "every interval" if k == 1 else f"{k} intervals repeating"
            return {**out, "torus_class": PERIODIC if k == 1 else REPEATING, "train_intervals": k,
                    "class_reason": f"{N} intervals: {what} to R_{k} {R:.3g} <= {factor:g} x resolution {S:.3g}"}
    return {**out, "class_reason": f"{N} intervals: no train of 1 .. {len(tried)} repeating intervals fits "
                                   f"({', '.join(tried)} against {factor:g} x resolution {S:.3g})"}


#: Written into the torus_stability dataset (attribute identity_rule).
IDENTITY_RULE = (
    "Which torus a perturbed orbit shown to be on one is on: \"the reference's torus\" when its period differs "
    "from the reference's by at most sigma combined standard errors and its spike point lies within sigma "
    "combined scatters of the reference's (relative distance, the scatters: each orbit's median distance of "
    "its spike points from their median); else \"another torus of the family\"; \"undetermined\" for an "
    "orbit not shown to be on a torus."
)


def identity(klass: str, dP: float, dP_err: float, offset: float, offset_err: float, sigma: float) -> tuple[str, str]:
    """Applies :data:`IDENTITY_RULE`, the rule as the datasets record it (just above)."""
    if klass == NOT_SHOWN:
        return UNDETERMINED, "not shown to be a torus"
    facts = f"period difference {dP:.6g} +- {dP_err:.2g}, spike-point offset {offset:.3g} +- {offset_err:.2g}"
    if abs(dP) <= sigma * dP_err and offset <= sigma * offset_err:
        return SAME, f"{facts}: both within {sigma:g} standard errors"
    return ANOTHER, f"{facts}: {'the period' if abs(dP) > sigma * dP_err else 'the spike point'} differs"


#: Written into the torus_stability dataset (attribute law_rule).
LAW_RULE = (
    "A law y = s log10(a) + b of the family, per direction (the perturbed orbits of one seeded direction, "
    "one per amplitude a in the law's range, each shown to be on a torus): s by least squares when the "
    "direction has at least two amplitudes. The law's slope: the mean of the directions' s, its uncertainty "
    "their standard deviation over sqrt(K) (K directions, independent replicas; NaN for K < 2); its "
    "residual: the rms of the points about their own direction's line (how far the law is from straight)."
)


def family_law(log10_a, y, direction) -> dict:
    """Applies :data:`LAW_RULE`, the rule as the datasets record it (just above), on finite points. Returns
    slope, slope_err, residual, K and per_direction ({direction: s})."""
    x, y, d = (np.asarray(v, float) for v in (log10_a, y, direction))
    ok = np.isfinite(x) & np.isfinite(y)
    slopes, res = {}, []
    for k in np.unique(d[ok]):
        sel = ok & (d == k)
        if np.unique(x[sel]).size >= 2:
            p = np.polyfit(x[sel], y[sel], 1)
            slopes[int(k)] = float(p[0])
            res.extend(y[sel] - np.polyval(p, x[sel]))
    s = np.array(list(slopes.values()))
    return {"slope": float(s.mean()) if s.size else math.nan,
            "slope_err": float(s.std(ddof=1) / math.sqrt(s.size)) if s.size >= 2 else math.nan,
            "residual": float(np.sqrt(np.mean(np.square(res)))) if res else math.nan, "K": int(s.size),
            "per_direction": slopes}
