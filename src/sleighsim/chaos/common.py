"""Argument checks and the least-squares line shared by the chaos engines and judges.

Times in the flow's own time unit. Bad arguments raise ValueError naming the argument.
"""

from __future__ import annotations

import math

import numpy as np


def _state(name, y, n=None):
    y = np.array(y, dtype=float).ravel()
    if y.size == 0:
        raise ValueError(f"{name} is empty")
    if n is not None and y.size != n:
        raise ValueError(f"{name} has {y.size} components, expected {n}")
    if not np.all(np.isfinite(y)):
        raise ValueError(f"{name} has non-finite components: {y}")
    return y


def _n_intervals(T, tau, name_T="T", name_tau="tau"):
    """Number of intervals tau in T; T must be an integer multiple of tau (relative 1e-9)."""
    m = T / tau
    k = round(m)
    if k < 1 or abs(m - k) > 1e-9 * max(1.0, m):
        raise ValueError(f"{name_T} = {T} must be a positive integer multiple of {name_tau} = {tau}")
    return k


def check_splits(splits, least: int = 1) -> list[int]:
    """The window counts K (windows T / K of a record), sorted; ValueError unless there are at least
    ``least``, each an integer >= 2, none repeated."""
    try:
        out = sorted({int(k) for k in splits if int(k) == k})
    except (TypeError, ValueError):
        raise ValueError(f"splits must be integers >= 2, got {splits!r}") from None
    if len(out) < least or (out and out[0] < 2) or len(out) != len(list(splits)):
        raise ValueError(f"splits must be at least {least} distinct integers >= 2, got {splits!r}")
    return out


def linfit(x, y):
    """Least-squares line y = a + b x: (slope, slope stderr, rms residual, intercept).

    Stderr is the textbook one (independent residuals); NaN with fewer than 3 points."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    n = x.size
    if n < 2 or np.ptp(x) == 0:
        return math.nan, math.nan, math.nan, math.nan
    b, a = np.polyfit(x, y, 1)
    r = y - (a + b * x)
    rms = float(np.sqrt(np.mean(r**2)))
    if n < 3:
        return float(b), math.nan, rms, float(a)
    sxx = float(np.sum((x - x.mean()) ** 2))
    se = math.sqrt(float(np.sum(r**2)) / (n - 2) / sxx)
    return float(b), se, rms, float(a)
