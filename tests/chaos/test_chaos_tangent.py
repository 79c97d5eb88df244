"""Tangent-based chaos indicators (sleighsim.chaos.tangent): finite-time exponents on textbook
systems with known answers (chaos_textbook), and every branch of their judge, of the replicas'
Benettin judge and of the long-double growth check, on synthetic inputs. MEGNO: test_megno."""

import math

import numpy as np
import pytest
from chaos_textbook import (
    LORENZ_LAMBDA,
    _monotone_in_errors,
    _nan_each,
)

from sleighsim.chaos import tangent, verdicts
from sleighsim.chaos.tangent import judge_benettin
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED

C, G, U = CHAOTIC, REGULAR, UNDECIDED


def _ftle_verdict(f):
    return tangent.judge_ftle(f["rate"], f["rate_err"], f["T"], f["tau"], f["spread_slope"], f["spread_slope_err"])[0]


# ----------------------------------------------------------------------------- FTLE

def test_finite_time_exponents_on_textbook_orbits(runs):
    # Lorenz (second half, T = 500): rate 0.905 +- 0.015; the spread still falls like
    # 1/W (slope -0.98) for W <= 32: the W^-1/2 law is asymptotic, so the judge does not
    # require it for chaos.
    f = runs["lorenz"]["ftle"]
    assert f["rate"] == pytest.approx(LORENZ_LAMBDA, abs=0.05)
    assert f["spread_slope"] < -0.75
    assert _ftle_verdict(f) == CHAOTIC
    # Henon-Heiles E = 1/6 (T = 5e3 after skipping 5e3): rate 0.125 +- 0.011, spread ~ W^-0.21
    f = runs["hh_chaos"]["ftle"]
    assert 0.07 < f["rate"] < 0.2
    assert f["spread_slope"] > -0.75
    assert _ftle_verdict(f) == CHAOTIC
    # tori: rate ~ 1e-4, spread ~ W^-1 (measured -0.97 HH E = 1/12, -1.08 quartic)
    for name in ("hh_regular", "quartic"):
        f = runs[name]["ftle"]
        assert abs(f["rate"]) < 2e-3, name
        assert f["spread_slope"] == pytest.approx(-1.0, abs=0.25), name
        assert _ftle_verdict(f) == REGULAR, name
    # with one continuing vector the window mean is the same rate for every W
    f = runs["lorenz"]["ftle"]
    assert np.nanmax(f["mean"]) - np.nanmin(f["mean"]) < 0.01
    assert abs(f["mean_slope"]) < 0.05


def test_finite_time_exponents_synthetic_laws():
    rng = np.random.default_rng(1)
    tau = 0.5
    # i.i.d. growth: FTLE spread ~ W^-1/2 around lambda
    g = rng.normal(0.3 * tau, 0.2, size=40000)
    f = tangent.finite_time_exponents(g, tau, [5, 10, 20, 40, 80])
    assert f["rate"] == pytest.approx(0.3, abs=0.01)
    assert f["spread_slope"] == pytest.approx(-0.5, abs=0.1)
    assert np.all(f["n_windows"] == [4000, 2000, 1000, 500, 250])
    assert f["rate_err"] == pytest.approx(f["sem"][-1])
    # bounded oscillation of log|v| (a torus without net growth): spread ~ W^-1
    t = np.arange(40001) * tau
    lognorm = 0.5 * np.sin(t) + 0.3 * np.sin(math.sqrt(2) * t)
    f = tangent.finite_time_exponents(np.diff(lognorm), tau, [5, 10, 20, 40, 80])
    assert f["spread_slope"] == pytest.approx(-1.0, abs=0.1)
    # a window length with fewer than 2 windows gives NaN; t_skip drops the start
    f = tangent.finite_time_exponents(np.ones(10), 1.0, [2, 6], t_skip=2.0)
    assert f["n_windows"][0] == 4 and math.isnan(f["mean"][1]) and f["T"] == 8.0
    assert f["mean"][0] == pytest.approx(1.0) and f["std"][0] == pytest.approx(0.0)
    assert math.isnan(f["spread_slope"]) and math.isnan(f["rate_err"])  # < 10 windows anywhere


def test_finite_time_exponents_rejects_bad_input():
    with pytest.raises(ValueError, match="tau"):
        tangent.finite_time_exponents([0.1] * 10, 0.0, [2])
    with pytest.raises(ValueError, match="log_growth"):
        tangent.finite_time_exponents([], 1.0, [2])
    with pytest.raises(ValueError, match="log_growth"):
        tangent.finite_time_exponents([0.1, np.nan], 1.0, [2])
    with pytest.raises(ValueError, match="windows"):
        tangent.finite_time_exponents([0.1] * 10, 1.0, [])
    with pytest.raises(ValueError, match="windows"):
        tangent.finite_time_exponents([0.1] * 10, 1.0, [2.5])
    with pytest.raises(ValueError, match="windows"):
        tangent.finite_time_exponents([0.1] * 10, 1.0, [-2])
    with pytest.raises(ValueError, match="t_skip"):
        tangent.finite_time_exponents([0.1] * 10, 1.0, [2], t_skip=10.0)


# ----------------------------------------------------------------------------- judges (synthetic)

FTLE_CHAOS = {"rate": 0.12, "rate_err": 0.01, "T": 5000.0, "tau": 1.0, "spread_slope": -0.3, "spread_slope_err": 0.05}
FTLE_REG = {"rate": 2e-4, "rate_err": 3e-4, "T": 5000.0, "tau": 1.0, "spread_slope": -1.0, "spread_slope_err": 0.1}


@pytest.mark.parametrize("rate, tau, degree", [(1.55e-4, 38.2, 2.0), (5e-4, 10.0, 2.0), (1e-3, 1.0, 1.0)])
def test_resolving_horizon_is_where_the_polynomial_bound_meets_the_rate(rate, tau, degree):
    T = verdicts.resolving_horizon(rate, tau, degree)
    assert verdicts.polynomial_rate_bound(T, tau, degree) == pytest.approx(rate, rel=1e-9)
    assert verdicts.polynomial_rate_bound(0.99 * T, tau, degree) > rate  # the larger root: shorter is not enough


def test_resolving_horizon_of_a_rate_the_bound_never_reaches():
    assert verdicts.resolving_horizon(0.0, 10.0) == math.inf and verdicts.resolving_horizon(-1e-4, 10.0) == math.inf
    assert verdicts.resolving_horizon(math.nan, 10.0) == math.inf
    # above the bound's largest value (2 / (e tau)) the shortest horizon the bound is defined on
    assert verdicts.resolving_horizon(1.0, 10.0) == pytest.approx(math.e * 10.0)


def test_judge_ftle_branches():
    bound = verdicts.polynomial_rate_bound(5000.0, 1.0)
    assert bound == pytest.approx(2 * math.log(5000.0) / 5000.0)
    v, reason = tangent.judge_ftle(**FTLE_CHAOS)
    assert v == CHAOTIC and "0.12" in reason
    assert tangent.judge_ftle(**{**FTLE_CHAOS, "spread_slope": -1.0})[0] == CHAOTIC  # spread not needed
    assert tangent.judge_ftle(**FTLE_REG)[0] == REGULAR
    # undecided: growth bounded but the spread falls like W^-1/2
    assert tangent.judge_ftle(**{**FTLE_REG, "spread_slope": -0.5})[0] == UNDECIDED
    # undecided: rate straddles the polynomial bound
    assert tangent.judge_ftle(**{**FTLE_REG, "rate": bound, "rate_err": bound / 10})[0] == UNDECIDED
    # the bound scales with the degree
    assert tangent.judge_ftle(**{**FTLE_CHAOS, "rate": 0.01, "rate_err": 0.0}, degree=200)[0] != CHAOTIC
    _nan_each(tangent.judge_ftle, FTLE_CHAOS, FTLE_CHAOS.keys())
    _nan_each(tangent.judge_ftle, FTLE_REG, FTLE_REG.keys())
    s = _monotone_in_errors(tangent.judge_ftle, FTLE_CHAOS, ["rate_err", "spread_slope_err"])
    assert s[0] == CHAOTIC and s[-1] == UNDECIDED
    s = _monotone_in_errors(tangent.judge_ftle, FTLE_REG, ["rate_err", "spread_slope_err"])
    assert s[0] == REGULAR and s[-1] == UNDECIDED
    with pytest.raises(ValueError, match="rate_err"):
        tangent.judge_ftle(**{**FTLE_CHAOS, "rate_err": -1.0})
    with pytest.raises(ValueError, match="sigma"):
        tangent.judge_ftle(**FTLE_CHAOS, sigma=-1.0)
    with pytest.raises(ValueError, match="T"):
        tangent.judge_ftle(**{**FTLE_CHAOS, "T": 0.0})


# ----------------------------------------------------------------------------- Benettin judge, long-double check

def _res(lam1, err1, status, T=1e5):
    return {"exponents": np.array([lam1, 0, 0, -lam1]), "stderr": np.array([err1] * 4), "T": T, "status": status}


@pytest.mark.parametrize("lam, err, status, want", [
    (5e-4, 1e-5, "converged", C),   # bound 2 ln(1e4) / 1e5 = 1.8e-4
    (1e-5, 1e-6, "regular", G),
    (2e-4, 1e-4, "capped", U),
    (math.nan, 1e-5, "capped", U),
])
def test_judge_benettin_on_each_branch(lam, err, status, want):
    assert judge_benettin(_res(lam, err, status), 10.0, 3.0)[0] == want


def test_growth_confirmed_on_each_branch():
    """Exponential growth resolved above the polynomial bound is confirmed; a rate inside the bound,
    a noisy one, and a non-finite one are not."""
    tau, T = 1.0, 1.0e4
    bound = verdicts.polynomial_rate_bound(T, tau)
    steady = np.full(10000, 10 * bound * tau)
    lam, err, b, ok = tangent.growth_confirmed(steady, tau, T, 3.0, 10)
    assert ok and lam == pytest.approx(10 * bound) and err == pytest.approx(0.0, abs=1e-15) and b == bound
    assert not tangent.growth_confirmed(np.full(10000, 0.5 * bound * tau), tau, T, 3.0, 10)[3]
    noisy = np.zeros(10000)
    noisy[:1000] = 100 * bound * tau  # all growth in the first block: mean 10 bound, huge spread
    assert not tangent.growth_confirmed(noisy, tau, T, 3.0, 10)[3]
    assert not tangent.growth_confirmed(np.full(10000, np.nan), tau, T, 3.0, 10)[3]
