"""C18's contraction rule on orbits of known mean divergence (sleighsim.claims.volume_power): the exact circle
flow, the rule's answer on each side, and the committed audit's record."""

import math

import numpy as np
import pytest
import yaml

from sleighsim.claims import volume_power as vp
from sleighsim.claims.faithful import contracts

SMALL = dict(vp.ORBITS, T=2000.0, period=100.0)


def test_the_circle_flow_is_exact():
    """theta' = w (1 + a sin theta): the returned f is the flow at theta, a turn takes 2 pi / (s w), and f, theta''
    match the finite differences of the samples."""
    w, a = 3.0, 0.6
    t = np.linspace(0.0, 10.0, 20001)
    theta, f, g = vp.circle(t, w, a, 1.0)
    assert theta[0] == pytest.approx(1.0) and np.allclose(f, w * (1 + a * np.sin(theta)), rtol=0, atol=1e-12)
    assert np.allclose(np.gradient(theta, t)[1:-1], f[1:-1], rtol=1e-6)
    assert np.allclose(np.gradient(f, t)[1:-1], g[1:-1], rtol=0, atol=1e-5)
    P = 2 * math.pi / (math.sqrt(1 - a * a) * w)
    turn = vp.circle(np.linspace(0.0, P, 1001), w, a, 1.0)[0]
    assert turn[-1] - turn[0] == pytest.approx(2 * math.pi, abs=1e-9)


@pytest.mark.parametrize("c", [0.0, 2e-3])
def test_a_known_orbits_mean_divergence_is_minus_c_within_its_sigma(c):
    out = vp.known_orbit(c, np.random.default_rng(1), SMALL)
    sigma = math.hypot(out["stderr"], out["quadrature"])
    assert out["cycles"] >= 15 and abs(out["mean"] + c) <= 3 * sigma and sigma < 2e-3


def test_the_rule_contracts_only_below_minus_k_sigma_and_the_audit_counts_both_ways():
    assert list(contracts([-1.0, -1.0, 1.0], [0.1, 0.6, 0.1])) == [True, False, False]
    rows = vp.audit([6.0], 3, seed=2, cfg=SMALL)
    assert [r["orbits"] for r in rows] == [3, 3] and rows[0]["c"] == 0.0 and rows[1]["c_over_sigma"] == 6.0
    assert rows[1]["c"] == pytest.approx(6.0 * rows[0]["median_sigma"])
    assert rows[1]["contracts"] == 3 and rows[1]["expands"] == 0 and 0 < rows[1]["bound"] < 1
    assert rows[0]["contracts"] + rows[0]["expands"] <= 1 and rows[0]["bound"] > 0.5  # 3 orbits bound nothing


def test_the_committed_audit_bounds_the_rules_false_rate_and_power():
    """benchmarks/volume_power.yaml (python benchmarks/volume_power.py): the null's false rate and the power at 4
    sigma are bounded from 200 orbits each."""
    from pathlib import Path

    record = yaml.safe_load((Path(__file__).resolve().parents[2] / "benchmarks" / "volume_power.yaml").read_text())
    assert record["schema"] == "sleighsim.volume_power/1" and not record["quick"]
    null, *rest = record["rates"]
    assert null["c"] == 0.0 and null["orbits"] >= 200 and 0 < null["bound"] < 0.1
    four = next(r for r in rest if r["c_over_sigma"] == 4.0)
    assert four["orbits"] >= 200 and four["bound"] > 0.9
