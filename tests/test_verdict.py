"""The chaos verdict's rule on each branch, and the reversibility it rests on."""

import math

import numpy as np
import pytest

from sleighsim import model
from sleighsim.params import Params
from sleighsim.scenes.verdict import decide

RULE = dict(sigma=3.0, slope_limit=0.5, K_threshold=0.5, lambda_floor=1e-4, min_lyapunov_times=100.0, min_samples=1000)


@pytest.mark.parametrize("lam, err, slope, K, n, record, want, why", [
    (5e-4, 1e-5, -0.1, 0.95, 5000, 2e6, "chaotic", "both say chaotic"),
    (1e-7, 1e-6, -1.0, 0.05, 5000, 2e6, "quasi-periodic", "both say regular"),
    (1e-7, 1e-6, -1.0, 0.05, 5000, 1e4, "undecided", "too short"),  # 1 Lyapunov time at the floor rate
    (1e-7, 1e-6, -1.0, 0.05, 50, 2e6, "undecided", "too short"),  # too few iterates
    (5e-4, 1e-5, -0.1, 0.05, 5000, 2e6, "undecided", "disagree"),
    (5e-4, 1e-5, -0.1, math.nan, 5000, 2e6, "undecided", "NaN"),
    (math.nan, 1e-5, -0.1, 0.9, 5000, 2e6, "undecided", "NaN"),
])
def test_decide_on_each_branch(lam, err, slope, K, n, record, want, why):
    v, reason = decide(lam, err, slope, K, n, record, **RULE)
    assert v == want and why in reason


def test_a_larger_uncertainty_never_makes_regular_easier():
    regular = decide(1e-7, 1e-6, -1.0, 0.05, 5000, 5e5, **RULE)[0]
    for err in (1e-5, 1e-4, 1e-3):
        assert decide(1e-7, err, -1.0, 0.05, 5000, 5e5, **RULE)[0] == regular


def test_the_flow_is_reversible_under_R():
    """R(u, Omega, omega, delta) = (-u, -Omega, -omega, delta): if y(t) solves the equations so does
    R y(-t), i.e. f(R y) = -R f(y) at every state."""
    p = Params.paper(eps=0.1)
    rng = np.random.default_rng(3)
    y = np.c_[rng.uniform(-1, 1, (200, 3)), rng.uniform(-np.pi, np.pi, 200)]
    R = np.array([-1.0, -1.0, -1.0, 1.0])
    lhs = model.rhs(y * R, p)
    rhs = -model.rhs(y, p) * R
    assert np.max(np.abs(lhs - rhs)) < 1e-14
    # and it is not a symmetry the other way round (the test can fail)
    assert np.max(np.abs(model.rhs(y * R, p) - model.rhs(y, p) * R)) > 1e-3
