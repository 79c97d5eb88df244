"""The power and false rate of C18's contraction rule (``claims.faithful.contracts``, applied to
``analysis.volume``'s whole-cycle mean divergence) on orbits whose mean divergence is known exactly.

Known orbits. Two uncoupled circle flows theta_i' = w_i (1 + a_i sin theta_i), solved exactly (u = tan(theta / 2):
u + a = s tan(s w t / 2 + c0), s = sqrt(1 - a^2), one turn in 2 pi / (s w)): a fast one (the rotor of the sleigh's
torus: about 1.7 rad per sample at dt = 0.5) and a slow one whose turns are the cycles (the spike cycle, period
``period``). A third coordinate r' = -c r (1 + b cos theta_1) contracts volume at the known rate c: the flow's
divergence is w_1 a_1 cos theta_1 + w_2 a_2 cos theta_2 - c (1 + b cos theta_1), whose time mean over whole slow
cycles is exactly -c but for the fast part's residual, which falls like 1 / T (each circle flow's divergence,
and cos theta_1, average to 0 over their own turns). c = 0 is measure-preserving on average with a divergence that
swings by +-2 every fast turn: the null. Independent orbits: random phases and a fast frequency jittered by 5%.

The rule reads the orbit as the decisive stage reads the sleigh's: samples every dt with their f and J f, the
quintic Hermite quadrature, the cycles from the first slow turn to the last, the windows of the finest split.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.analysis.volume import cycle_mean, hermite_integrals
from sleighsim.chaos.power import lower_bound, upper_bound
from sleighsim.claims.faithful import contracts

#: The known orbits' settings: sampling step and horizon (time), fast turn per sample (rad), the circle flows'
#: a_1, a_2, the slow period (time), the contraction's modulation b, the windows of the split.
ORBITS = {"dt": 0.5, "T": 10000.0, "turn_per_sample": 1.7, "a_fast": 0.4, "a_slow": 0.9, "period": 250.0, "b": 0.5,
          "windows": 8}


def circle(t, w: float, a: float, theta0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The exact orbit of theta' = w (1 + a sin theta) from theta0 at the times t (one sample per less than half a
    turn): theta (unwrapped), theta' and theta''."""
    s = math.sqrt(1.0 - a * a)
    c0 = math.atan((math.tan(0.5 * theta0) + a) / s)
    theta = np.unwrap(2.0 * np.arctan(s * np.tan(0.5 * s * w * np.asarray(t, float) + c0) - a))
    theta += theta0 - theta[0]
    f = w * (1.0 + a * np.sin(theta))
    return theta, f, w * a * np.cos(theta) * f


def known_orbit(c: float, rng, cfg: dict = ORBITS) -> dict:
    """One orbit of the known flow at contraction rate ``c`` (1/time) with random phases and fast frequency: its
    whole-cycle mean divergence (``analysis.volume.cycle_mean``: mean, quadrature, stderr, cycles)."""
    t = np.arange(0.0, cfg["T"] + 0.5 * cfg["dt"], cfg["dt"])
    a1, a2, b = cfg["a_fast"], cfg["a_slow"], cfg["b"]
    w1 = cfg["turn_per_sample"] / cfg["dt"] / math.sqrt(1 - a1 * a1) * rng.uniform(0.95, 1.05)
    w2 = 2 * math.pi / cfg["period"] / math.sqrt(1 - a2 * a2)
    (th1, f1, g1), (th2, f2, g2) = (circle(t, w, a, p) for w, a, p in
                                    ((w1, a1, rng.uniform(0, 2 * math.pi)), (w2, a2, rng.uniform(0, 2 * math.pi))))

    def divergence(y):
        return w1 * a1 * np.cos(y[..., 0]) + w2 * a2 * np.cos(y[..., 1]) - c * (1 + b * np.cos(y[..., 0]))

    fine, coarse = hermite_integrals(t, np.c_[th1, th2], np.c_[f1, f2], np.c_[g1, g2], divergence)
    turns = np.floor((th2 - th2[0]) / (2 * math.pi))
    cycles = t[1:][np.diff(turns) > 0]  # the first sample after each slow turn, as a spike is found on samples
    return cycle_mean(t, fine, cycles, cfg["windows"], coarse=coarse)


def _row(c: float, runs: list[dict]) -> dict:
    """The rule's answers on ``runs`` at contraction rate c: counts, the bound on the rate it contracts (upper at
    c = 0: the false rate; lower at c > 0: the power), sigma's median and the error's."""
    mean = np.array([r["mean"] for r in runs])
    sigma = np.hypot([r["stderr"] for r in runs], [r["quadrature"] for r in runs])
    yes, n = int(np.sum(contracts(mean, sigma))), len(runs)
    return {"c": c, "orbits": n, "contracts": yes, "expands": int(np.sum(contracts(-mean, sigma))),
            "bound": upper_bound(yes, n) if c == 0 else lower_bound(yes, n), "median_sigma": float(np.median(sigma)),
            "median_error": float(np.median(np.abs(mean + c))),
            "error_over_sigma_max": float(np.max(np.abs(mean + c) / sigma))}


def audit(multiples, n: int, seed: int = 0, cfg: dict = ORBITS) -> list[dict]:
    """The rule on ``n`` independent known orbits at c = 0 (the null), then at c = k sigma_0 for each k of
    ``multiples`` (sigma_0: the null's median sigma, so the rates are where the rule's resolution lies). Per rate
    (``_row``): how many contract, expand (mean - K sigma > 0) or neither, the one-sided 95% Clopper-Pearson bound
    on the rate it contracts, the median sigma and error, the largest error in sigmas."""
    rng = np.random.default_rng(seed)
    rows = [_row(0.0, [known_orbit(0.0, rng, cfg) for _ in range(n)])]
    sigma0 = rows[0]["median_sigma"]
    for k in multiples:
        c = float(k) * sigma0
        rows.append({"c_over_sigma": float(k), **_row(c, [known_orbit(c, rng, cfg) for _ in range(n)])})
    return rows
