"""The trigger law as measured (sleighsim.scenes.trigger): which runs are saturated, and the first spike's
local slope per range of adjacent levels of injected error.

Conventions. A run is one (arithmetic, Taylor tolerance tol); its level is log10 tol, the decade of the error
it injects where its arithmetic's rounding lies far below tol. Times (first spikes) in the flow's time unit;
slopes in time units per decade of injected error (negative: a smaller error delays the spike); drifts are
the runs' maximum relative energy drifts.
"""

from __future__ import annotations

import math

import numpy as np

#: Written into the trigger_law dataset (attribute saturation_rule).
SATURATION_RULE = (
    "A run is saturated when the run of the same arithmetic at an adjacent tolerance of its ladder (the next "
    "coarser or the next finer) gives the same first spike and the same drift: first spikes within `spike` time "
    "units and maximum relative energy drifts within a factor `drift` of each other. Where the tolerance sets "
    "the injected error a decade finer moves the first spike by tens of time units and cuts the drift about "
    "tenfold; both the same means the arithmetic's rounding, not the tolerance, set the error. Both runs of "
    "such a pair are saturated; a run without a first spike is never the same as another."
)


def saturated(arithmetic, tol, first, drift, *, spike: float, drift_factor: float) -> np.ndarray:
    """Applies :data:`SATURATION_RULE`, the rule as the datasets record it (just above): one bool per run."""
    arithmetic, tol = np.asarray(arithmetic, dtype=object), np.asarray(tol, float)
    first, drift = np.asarray(first, float), np.asarray(drift, float)
    out = np.zeros(tol.size, dtype=bool)
    for a in dict.fromkeys(arithmetic):
        runs = sorted(np.flatnonzero(arithmetic == a), key=lambda i: -tol[i])
        for i, j in zip(runs[:-1], runs[1:]):
            ratio = max(drift[i], drift[j]) / min(drift[i], drift[j])
            if abs(first[i] - first[j]) <= spike and ratio <= drift_factor:
                out[[i, j]] = True
    return out


#: Written into the trigger_law dataset (attribute slopes_rule).
SLOPES_RULE = (
    "The runs in the slopes, ordered from the largest tolerance to the smallest, cut into ranges of adjacent "
    "levels: one arithmetic's consecutive runs, split where they span more than `decades` decades of tol (into "
    "the fewest ranges of at most that span; a range holds at least two runs), and between two consecutive "
    "ranges a bridge of their adjacent ends. Per range the least-squares slope of the first spike against "
    "log10 tol; its standard error s / sqrt(Sxx) (Sxx: the range's sum of squared deviations of log10 tol), "
    "s the scatter of the first spikes about their range's line pooled over the ranges of three or more runs "
    "(n - 2 degrees of freedom each): the spread one level's first spike has about the local law. NaN where no "
    "range has a residual. Nothing is extrapolated: a range's slope holds between its two ends."
)


def _split(levels, decades: float) -> list[list[int]]:
    """Consecutive positions of one arithmetic's levels (decreasing) in the fewest pieces of at most
    ``decades`` span, each of at least two levels (a lone one joins its neighbour)."""
    pieces, start = [], 0
    for k in range(1, len(levels) + 1):
        if k == len(levels) or levels[start] - levels[k] > decades:
            pieces.append(list(range(start, k)))
            start = k
    merged = []
    for piece in pieces:
        if merged and (len(piece) < 2 or len(merged[-1]) < 2):
            merged[-1] += piece
        else:
            merged.append(piece)
    return merged


def ranges(arithmetic, log10_tol, decades: float) -> list[tuple[str, np.ndarray]]:
    """The ranges of :data:`SLOPES_RULE` over runs given in decreasing tolerance: (label, positions) each,
    labelled by the arithmetic ("a -> b" for a bridge), in order of decreasing tolerance."""
    arithmetic, x = list(arithmetic), np.asarray(log10_tol, float)
    groups, start = [], 0
    for k in range(1, len(x) + 1):
        if k == len(x) or arithmetic[k] != arithmetic[start]:
            groups += [(arithmetic[start], np.array(p) + start) for p in _split(x[start:k], decades)]
            start = k
    out = []
    for g, (label, pos) in enumerate(groups):
        if g:
            prev_label, prev = groups[g - 1]
            out.append((f"{prev_label} -> {label}" if prev_label != label else label, np.array([prev[-1], pos[0]])))
        out.append((label, pos))
    return out


def slopes(arithmetic, log10_tol, first, decades: float) -> dict:
    """Applies :data:`SLOPES_RULE` to runs given in decreasing tolerance (the runs in the slopes only): ranges
    (per range its label, tol_max, tol_min, n, slope and slope_stderr), the pooled scatter and its degrees of
    freedom."""
    x, y = np.asarray(log10_tol, float), np.asarray(first, float)
    found = []
    for label, pos in ranges(arithmetic, x, decades):
        if pos.size < 2:
            continue
        xs, ys = x[pos], y[pos]
        sxx = float(np.sum((xs - xs.mean()) ** 2))
        slope = float(np.sum((xs - xs.mean()) * (ys - ys.mean())) / sxx)
        resid = ys - ys.mean() - slope * (xs - xs.mean())
        found.append((label, pos, sxx, slope, float(np.sum(resid**2))))
    dof = sum(pos.size - 2 for _, pos, *_ in found)
    s = math.sqrt(sum(r[4] for r in found if r[1].size > 2) / dof) if dof else math.nan
    return {"ranges": [{"label": label, "tol_max": 10.0 ** x[pos].max(), "tol_min": 10.0 ** x[pos].min(),
                        "n": int(pos.size), "slope": slope, "slope_stderr": s / math.sqrt(sxx)}
                       for label, pos, sxx, slope, _ in found],
            "scatter": s, "dof": dof}
