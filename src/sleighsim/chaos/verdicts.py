"""The three verdicts and the helpers every judge uses.

Judges map measured numbers to ("chaotic" | "regular" | "undecided", reason). NaN inputs
give "undecided"; every uncertainty enters so that a larger uncertainty can only move a
verdict towards "undecided". Rates are in 1/time (the flow's own time unit), natural logs;
``sigma`` counts standard errors. ``rule.decide`` combines judges by ``rule.DECISION_RULE``.
"""

from __future__ import annotations

import math

from sleighsim.model.params import positive

CHAOTIC, REGULAR, UNDECIDED = "chaotic", "regular", "undecided"
VERDICTS = (CHAOTIC, REGULAR, UNDECIDED)


def _g(v):
    return f"{float(v):.3g}"


def polynomial_rate_bound(T, tau, degree=2.0):
    """Largest apparent exponent (1/time) that polynomial growth can fake: a vector growing
    like (t / tau)^degree over a horizon T has log growth degree * ln(T / tau), i.e. an
    apparent rate degree * ln(T / tau) / T. Regular orbits (linear growth on a sheared
    torus) stay below it for degree >= 1; a chaotic verdict must exceed it."""
    T = positive("T", T)
    tau = positive("tau", tau)
    if not (math.isfinite(degree) and degree > 0):
        raise ValueError(f"degree must be positive, got {degree!r}")
    return degree * math.log(max(T / tau, math.e)) / T


def resolving_horizon(rate, tau, degree=2.0) -> float:
    """The horizon T (time) from which polynomial_rate_bound(T, tau, degree) lies below ``rate``
    (1/time): the larger root of degree ln(T / tau) / T = rate (T >= e tau); inf for a rate that is
    not positive and finite."""
    tau = positive("tau", tau)
    if not (math.isfinite(rate) and rate > 0):
        return math.inf
    T = max(math.e * tau, degree / rate)
    for _ in range(200):  # the larger root attracts T -> degree ln(T / tau) / rate from above e tau
        T = max(math.e * tau, degree * math.log(T / tau) / rate)
    return T


def _check_judge(names_values, errors=(), sigma=3.0):
    """None if all finite (ValueError for negative uncertainties or sigma), else an
    "undecided" verdict naming the NaN inputs."""
    bad = [k for k, v in names_values if not _is_finite(v)]
    if bad:
        return UNDECIDED, "not finite: " + ", ".join(bad)
    if not (math.isfinite(sigma) and sigma >= 0):
        raise ValueError(f"sigma must be >= 0, got {sigma!r}")
    for k, v in errors:
        if float(v) < 0:
            raise ValueError(f"{k} must be >= 0, got {v!r}")
    return None


def _is_finite(v):
    try:
        return math.isfinite(float(v))
    except (TypeError, ValueError):
        return False
