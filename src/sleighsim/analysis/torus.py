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


def refine_spikes(t, signal, coarse, half_width: float) -> np.ndarray:
    """Spike times refined to the peak of a smooth envelope: for each coarse spike time, the sample of
    ``signal`` (e.g. |Omega| on the delta = 0 section, one sample per fast turn, at times ``t``) largest
    within half_width of it, and the vertex of the parabola through it and its two neighbours. A spike
    whose largest sample has no neighbour on both sides (at a record's end) is dropped."""
    t, signal = np.asarray(t, float), np.asarray(signal, float)
    out = []
    for c in np.asarray(coarse, float):
        near = np.flatnonzero(np.abs(t - c) <= half_width)
        if near.size == 0:
            continue
        i = near[np.argmax(signal[near])]
        if i == 0 or i == t.size - 1:
            continue
        a, b, _ = np.polyfit(t[i - 1: i + 2] - t[i], signal[i - 1: i + 2], 2)
        out.append(t[i] - b / (2 * a) if a < 0 else t[i])
    return np.array(out)


def _design(phase, order: int) -> np.ndarray:
    """Columns 1, cos(k phi), sin(k phi) for k = 1..order."""
    phase = np.asarray(phase, float)[:, None]
    k = np.arange(1, order + 1)[None, :]
    return np.hstack([np.ones_like(phase), np.cos(k * phase), np.sin(k * phase)])


def section_curve(phase, points, max_order: int) -> dict:
    """The closed curve x(phi) through the spike-section points: per coordinate a Fourier series of
    order min(max_order, (n - 2) // 4) fitted by least squares (so at least twice as many points as
    coefficients). ``floor``: the median over the points of the leave-one-out residual's norm (each
    point against the fit without it), the curve's own thickness in the points' units."""
    phase, points = np.asarray(phase, float), np.atleast_2d(np.asarray(points, float))
    order = min(max_order, (phase.size - 2) // 4)
    if order < 1:
        raise ValueError(f"a closed curve needs at least 6 section points, got {phase.size}")
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


# the docstring is written into the torus_stability dataset (attribute classification_rule)
def classify(D, n_spikes: int, dT: float, dT_err: float, floor: float, *, min_spikes: int, leave: float,
             change: float, same: float, sigma: float, period_floor: float) -> tuple[str, str]:
    """The class of a perturbed orbit from its distances D_n to the reference's spike-section curve
    (relative), its spike count and its mean spike interval's difference dT +- dT_err from the
    reference's (dT_err: both standard errors combined). D_early, D_late: medians over the first and
    last quarter of the spikes. "leaves" when fewer than min_spikes spikes came, or D_late >= leave, or
    D grew (D_late / D_early >= change); "same torus" when D decayed (D_late / D_early <= 1 / change),
    or when D_late is within same x floor (the reference curve's own relative thickness) and the periods
    agree (|dT| <= max(sigma dT_err, period_floor), the latter the resolution of the integration's spike
    times); else "neighbouring torus" (regular, at an offset that neither grows
    nor decays by the factor change, or on the curve to its resolution at a measurably different period)."""
    if n_spikes < min_spikes:
        return "leaves", f"{n_spikes} spikes (fewer than {min_spikes}): the spike train stopped"
    early, late = quarters(D)
    ratio = late / early if early > 0 else math.inf
    facts = f"D early {early:.3g}, late {late:.3g} (x{ratio:.3g}); period difference {dT:.4g} +- {dT_err:.2g}"
    if late >= leave:
        return "leaves", f"{facts}: D late >= {leave:g}"
    if ratio >= change:
        return "leaves", f"{facts}: D grew by {change:g} or more"
    if ratio <= 1.0 / change:
        return "same torus", f"{facts}: D decayed by {change:g} or more, back onto the reference curve"
    on_curve = late <= same * floor
    if on_curve and abs(dT) <= max(sigma * dT_err, period_floor):
        return "same torus", f"{facts}: on the reference curve (floor {floor:.3g}) at the same period"
    why = f"on the curve to its resolution (floor {floor:.3g}) but the period differs" if on_curve else \
        "offset neither grows nor decays"
    return "neighbouring torus", f"{facts}: {why}"
