"""Is a perturbed orbit on the reference torus, on a neighbouring one, or gone? The spike section and
the classification rule of the torus-stability scene (sleighsim.scenes.torus_stability), on sampled data.

Conventions. A spike-cycling orbit is cut once per cycle at its spikes: the spike section holds, per
spike n, the fast phase phi_n in [0, 2 pi) (for the sleigh delta mod 2 pi at the spike) and a point x_n
(for the sleigh (u, Omega, omega) at the spike). On a 2-torus these points lie on one closed curve
x(phi), the spike-section curve. The reference's curve is a least-squares Fourier series in phi
(:func:`section_curve`); a perturbed orbit's distance to it is D_n = |x_n - x(phi_n)| / scale (scale:
the reference's velocity scale, so D is a relative distance like the perturbation's size).
Times in the flow's time unit.
"""

from __future__ import annotations

import math

import numpy as np

CLASSES = ("same torus", "neighbouring torus", "leaves")


#: Written into the torus_stability dataset (attribute spike_rule).
SPIKE_PEAKS_RULE = (
    "Spike times refined to the peak of a smooth envelope, and the section's state there: for each coarse spike"
    " time, the section crossing (rows of X, times t; one per fast turn) whose |X[:, 1]| is largest within "
    "half_width of it; polynomials of ``degree`` in t through it and its ``half_points`` neighbours on each "
    "side, per column of X; the spike time is the largest maximum of the fitted |X[:, 1]| among the fit "
    "window's critical points, and the spike point the fitted X there. A spike whose window runs past the "
    "record's ends is dropped. Returns (times (m,), points (m, columns))."
)


def spike_peaks(t, X, coarse, half_width: float, half_points: int = 3, degree: int = 4):
    """Applies :data:`SPIKE_PEAKS_RULE`, the rule as the datasets record it (just above)."""
    t, X = np.asarray(t, float), np.atleast_2d(np.asarray(X, float))
    signal, h = np.abs(X[:, 1]), half_points
    times, points = [], []
    for c in np.asarray(coarse, float):
        near = np.flatnonzero(np.abs(t - c) <= half_width)
        if near.size == 0:
            continue
        i = near[np.argmax(signal[near])]
        if i < h or i + h >= t.size:
            continue
        tau = t[i - h: i + h + 1] - t[i]
        fit = np.polynomial.Polynomial.fit(tau, signal[i - h: i + h + 1], degree, domain=[tau[0], tau[-1]])
        crit = [r.real for r in fit.deriv().roots() if abs(r.imag) < 1e-9 and tau[0] <= r.real <= tau[-1]]
        best = max(crit + [0.0], key=fit)
        times.append(t[i] + best)
        points.append([np.polynomial.Polynomial.fit(tau, X[i - h: i + h + 1, k], degree,
                                                    domain=[tau[0], tau[-1]])(best) for k in range(X.shape[1])])
    return np.array(times), np.array(points).reshape(len(times), X.shape[1])


def _design(phase, order: int) -> np.ndarray:
    """Columns 1, cos(k phi), sin(k phi) for k = 1..order."""
    phase = np.asarray(phase, float)[:, None]
    k = np.arange(1, order + 1)[None, :]
    return np.hstack([np.ones_like(phase), np.cos(k * phase), np.sin(k * phase)])


#: Written into the torus_stability dataset (attribute curve_rule).
SECTION_CURVE_RULE = (
    "The closed curve x(phi) through the spike-section points: per coordinate a Fourier series of order "
    "min(max_order, (n - 2) // 4, pi / (the largest gap between the points' phases)) fitted by least squares "
    "(at least twice as many points as coefficients, and no harmonic finer than the coverage resolves: points "
    "on a short arc give order 0, their mean). ``floor``: the median over the points of the leave-one-out "
    "residual's norm (each point against the fit without it), the curve's own thickness in the points' units."
)


def section_curve(phase, points, max_order: int) -> dict:
    """Applies :data:`SECTION_CURVE_RULE`, the rule as the datasets record it (just above)."""
    phase, points = np.asarray(phase, float), np.atleast_2d(np.asarray(points, float))
    if phase.size < 3:
        raise ValueError(f"a section curve needs at least 3 points, got {phase.size}")
    ordered = np.sort(np.mod(phase, 2 * math.pi))
    gap = max(np.max(np.diff(ordered), initial=0.0), ordered[0] + 2 * math.pi - ordered[-1])
    order = max(0, min(max_order, (phase.size - 2) // 4, int(math.pi / gap)))
    A = _design(phase, order)
    coef, *_ = np.linalg.lstsq(A, points, rcond=None)
    hat = np.einsum("ij,ji->i", A, np.linalg.pinv(A))
    loo = (points - A @ coef) / (1.0 - hat)[:, None]
    return {"order": order, "coef": coef, "floor": float(np.median(np.linalg.norm(loo, axis=1)))}


def curve_distance(curve: dict, phase, points) -> np.ndarray:
    """|x_n - x(phi_n)| of each section point from the fitted curve (the points' units)."""
    fit = _design(phase, curve["order"]) @ curve["coef"]
    return np.linalg.norm(np.atleast_2d(np.asarray(points, float)) - fit, axis=1)


def mean_interval(spikes) -> tuple[float, float]:
    """Mean spike interval and its standard error, std / sqrt(n) over the n intervals (NaN when fewer
    than two intervals)."""
    d = np.diff(np.asarray(spikes, float))
    if d.size < 2:
        return (float(d.mean()) if d.size else math.nan), math.nan
    return float(d.mean()), float(d.std(ddof=1) / math.sqrt(d.size))


def quarters(D) -> tuple[float, float]:
    """(early, late): medians of the first and last quarter (at least one value each) of a sequence."""
    D = np.asarray(D, float)
    q = max(1, D.size // 4)
    return float(np.median(D[:q])), float(np.median(D[-q:]))


def late_interval(spikes) -> tuple[float, float]:
    """:func:`mean_interval` over the second half of the spikes (where a returning orbit has converged)."""
    spikes = np.asarray(spikes, float)
    return mean_interval(spikes[spikes.size // 2:])


#: Written into the torus_stability dataset (attribute classification_rule).
CLASSIFY_RULE = (
    "The class of a perturbed orbit from its distances D_n to the reference's spike-section curve (relative), "
    "its spike count and the difference dT +- dT_err of its late mean spike interval (second half of its "
    "spikes) from the reference's mean (dT_err: both standard errors combined). D_early, D_late: medians over "
    "the first and last quarter of the spikes; the periods agree when |dT| <= max(sigma dT_err, period_floor), "
    "the latter the resolution of the spike times. \"leaves\" when fewer than min_spikes spikes came, or D_late "
    ">= leave, or D grew (D_late / D_early >= change); \"same torus\" when the periods agree and D came back: it "
    "decayed (D_late / D_early <= 1 / change, from D_early above same x floor) or it lies within same x floor "
    "(the reference curve's own relative thickness); else \"neighbouring torus\" (regular, at an offset that "
    "neither grows nor decays by the factor change, or at a measurably different period)."
)


def classify(D, n_spikes: int, dT: float, dT_err: float, floor: float, *, min_spikes: int, leave: float,
             change: float, same: float, sigma: float, period_floor: float) -> tuple[str, str]:
    """Applies :data:`CLASSIFY_RULE`, the rule as the datasets record it (just above)."""
    if n_spikes < min_spikes:
        return "leaves", f"{n_spikes} spikes (fewer than {min_spikes}): the spike train stopped"
    early, late = quarters(D)
    ratio = late / early if early > 0 else math.inf
    facts = (f"D early {early:.3g}, late {late:.3g} (x{ratio:.3g}), floor {floor:.3g}; late period difference "
             f"{dT:.4g} +- {dT_err:.2g}")
    if late >= leave:
        return "leaves", f"{facts}: D late >= {leave:g}"
    if ratio >= change:
        return "leaves", f"{facts}: D grew by {change:g} or more"
    agrees = abs(dT) <= max(sigma * dT_err, period_floor)
    decayed = ratio <= 1.0 / change and early > same * floor
    on_curve = late <= same * floor
    if agrees and (decayed or on_curve):
        return "same torus", f"{facts}: {'D decayed' if decayed else 'on the reference curve'}, same period"
    why = "the period differs" if decayed or on_curve else "offset neither grows nor decays"
    return "neighbouring torus", f"{facts}: {why}"
