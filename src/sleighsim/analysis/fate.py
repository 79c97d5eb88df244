"""Where an escape lands: refined spike times on section data, the spike interval of the torus reached and
whether its train is strictly periodic (sleighsim.scenes.trigger).

Conventions. Section data are the crossings of delta = 0 (mod 2 pi), one per fast turn: times t_k and rows
X_k = (u, Omega, omega) there (sleighsim.engine.ddsection). On a 2-torus |Omega| on the section is a smooth
function of the slow angle, which advances linearly in time, so the peak of its envelope marks one point of
the section curve and comes strictly periodically, whatever the fast phase. Times in the flow's time unit.
"""

from __future__ import annotations

import math

import numpy as np

#: The peak's stencil: crossings on each side of the largest |Omega| and the polynomial's degree; and the
#: smaller stencil whose difference from it is the peak time's error.
STENCIL, ERROR_STENCIL = (5, 8), (4, 6)

#: Written into the trigger_law dataset (attribute peak_rule).
PEAK_RULE = (
    f"A spike's refined time: among the section crossings within half_width of the coarse spike (the transient "
    f"rule's, quantised at the sampling step), the one of largest |Omega| and its {STENCIL[0]} neighbours on each "
    f"side; the polynomial of degree {STENCIL[1]} in t through their |Omega| is maximised over the stencil's span "
    f"(the largest of its critical points there). Its error: the difference from the same on {ERROR_STENCIL[0]} "
    f"neighbours and degree {ERROR_STENCIL[1]} (a coarser stencil: its error bounds the finer one's). A spike whose "
    "stencil runs past the crossings' ends, or across a gap of more than half_width between crossings (past the "
    "crossings kept near it), is dropped."
)


def _peak(t, x, i: int, half: int, degree: int) -> float:
    """The maximum of the degree-``degree`` polynomial through (t, x) at rows i - half .. i + half."""
    tau = t[i - half: i + half + 1] - t[i]
    fit = np.polynomial.Polynomial.fit(tau, x[i - half: i + half + 1], degree, domain=[tau[0], tau[-1]])
    crit = [r.real for r in fit.deriv().roots() if abs(r.imag) < 1e-9 and tau[0] <= r.real <= tau[-1]]
    return float(t[i] + max(crit + [0.0], key=fit))


def refined_peaks(t_sec, x_sec, coarse, half_width: float) -> tuple[np.ndarray, np.ndarray]:
    """Applies :data:`PEAK_RULE`, the rule as the datasets record it (just above): (times, errors)."""
    t, signal = np.asarray(t_sec, float), np.abs(np.asarray(x_sec, float)[:, 1])
    half = STENCIL[0]
    times, errors = [], []
    for c in np.asarray(coarse, float):
        near = np.flatnonzero(np.abs(t - c) <= half_width)
        if near.size == 0:
            continue
        i = int(near[np.argmax(signal[near])])
        if i < half or i + half >= t.size or np.max(np.diff(t[i - half: i + half + 1])) > half_width:
            continue
        best = _peak(t, signal, i, *STENCIL)
        times.append(best)
        errors.append(abs(best - _peak(t, signal, i, *ERROR_STENCIL)))
    return np.array(times), np.array(errors)


PERIODIC, NOT_PERIODIC, UNDETERMINED = "strictly periodic", "not strictly periodic", "undetermined"
CLASSES = (PERIODIC, NOT_PERIODIC, UNDETERMINED)

#: Written into the trigger_law dataset (attribute class_rule).
TRAIN_RULE = (
    "The landed torus from its refined spikes t_0 .. t_N (PEAK_RULE, errors e_n): the intervals d_n = t_n+1 - t_n "
    "and their resolution, the rms over n of sqrt(e_n^2 + e_n+1^2). The approach: the fewest leading intervals k "
    "such that the rest (at least min_intervals of them) agree, their scatter (standard deviation, ddof 1) at most "
    "factor x their resolution; the train is then \"strictly periodic\" from interval k on, and the refined interval "
    "is the mean over those. \"not strictly periodic\" when no such rest exists (interval and scatter then over "
    "all N), \"undetermined\" with fewer than min_intervals intervals."
)


def _tail(d, e, k: int) -> tuple[float, float, float]:
    """(mean, scatter, resolution) of the intervals d[k:] with spike errors e[k:]."""
    d, e = d[k:], e[k:]
    S = float(np.sqrt(np.mean(e[1:] ** 2 + e[:-1] ** 2))) if d.size else math.nan
    return (float(d.mean()) if d.size else math.nan), (float(d.std(ddof=1)) if d.size > 1 else math.nan), S


def train(times, errors, *, min_intervals: int, factor: float) -> dict:
    """Applies :data:`TRAIN_RULE`, the rule as the datasets record it (just above): interval, scatter,
    resolution, cycles (the intervals it rests on), approach (the leading intervals left out) and class."""
    times, errors = np.asarray(times, float), np.asarray(errors, float)
    d = np.diff(times)
    n, need = int(d.size), max(min_intervals, 2)
    for k in range(0, n - need + 1):
        mean, scatter, S = _tail(d, errors, k)
        if scatter <= factor * S:
            return {"interval": mean, "scatter": scatter, "resolution": S, "cycles": n - k, "approach": k,
                    "class": PERIODIC}
    mean, scatter, S = _tail(d, errors, 0)
    return {"interval": mean, "scatter": scatter, "resolution": S, "cycles": n, "approach": 0,
            "class": NOT_PERIODIC if n >= need else UNDETERMINED}
