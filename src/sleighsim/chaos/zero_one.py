"""The 0-1 test for chaos (Gottwald and Melbourne): an indicator that uses no tangent dynamics."""

from __future__ import annotations

import math

import numpy as np


def zero_one_test(phi, *, n_c: int = 100, seed: int = 0, n_cut_fraction: float = 0.1) -> dict:
    """Gottwald-Melbourne 0-1 test (correlation method, 2009) on a sampled observable.

    K near 0: regular (periodic or quasi-periodic); near 1: chaotic. The median of
    K over n_c random c in (pi/5, 4 pi/5) is returned, with the spread."""
    phi = np.asarray(phi, float)
    phi = phi - phi.mean()
    N = len(phi)
    n_cut = max(2, int(n_cut_fraction * N))
    ns = np.arange(1, n_cut + 1)
    cs = np.random.default_rng(seed).uniform(math.pi / 5, 4 * math.pi / 5, n_c)
    Ks = np.empty(n_c)
    j = np.arange(1, N + 1)
    E2 = phi.mean() ** 2
    for m, c in enumerate(cs):
        p = np.cumsum(phi * np.cos(j * c))
        q = np.cumsum(phi * np.sin(j * c))
        M = np.array([np.mean((p[n:] - p[:-n]) ** 2 + (q[n:] - q[:-n]) ** 2) for n in ns])
        D = M - E2 * (1 - np.cos(ns * c)) / (1 - np.cos(c))
        Ks[m] = np.corrcoef(ns, D)[0, 1]
    return {"K": float(np.median(Ks)), "K_q25": float(np.quantile(Ks, 0.25)), "K_q75": float(np.quantile(Ks, 0.75)),
            "n_samples": N, "n_c": n_c}
