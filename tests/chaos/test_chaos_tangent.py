"""Tangent-based chaos indicators (sleighsim.chaos.tangent): finite-time exponents and MEGNO on
textbook systems with known answers (chaos_textbook), and every branch of their judges, of the
replicas' Benettin judge and of the long-double gate on MEGNO, on synthetic inputs."""

import math

import numpy as np
import pytest
from chaos_textbook import (
    LORENZ_LAMBDA,
    T_HAM,
    T_LOR,
    TAU_LOR,
    _monotone_in_errors,
    _nan_each,
)

from sleighsim.chaos import tangent, verdicts
from sleighsim.chaos.tangent import judge_benettin
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED
from sleighsim.engine import integrators

C, G, U = CHAOTIC, REGULAR, UNDECIDED


def _megno_verdict(m, T):
    return tangent.judge_megno(m["final"], m["resid"], m["slope"], m["slope_err"], T)[0]


def _ftle_verdict(f):
    return tangent.judge_ftle(f["rate"], f["rate_err"], f["T"], f["tau"], f["spread_slope"], f["spread_slope_err"])[0]


# ----------------------------------------------------------------------------- MEGNO

def test_megno_tends_to_2_on_sheared_tori_and_0_on_isochronous_one(runs):
    # T = 1e4: measured <Y> = 2.012 (quartic), 2.007 (Henon-Heiles E = 1/12), -6e-6 (linear)
    for name in ("quartic", "hh_regular"):
        m = runs[name]["megno"]
        assert abs(m["final"] - 2.0) < 0.05, name
        assert abs(m["slope"]) * T_HAM < 0.05, name  # <Y> no longer grows
        assert _megno_verdict(m, T_HAM) == REGULAR, name
    m = runs["linear"]["megno"]
    assert abs(m["final"]) < 0.05
    assert _megno_verdict(m, T_HAM) == REGULAR
    # Y(t) itself oscillates but stays O(1) on every torus
    for name in ("quartic", "hh_regular", "linear"):
        assert np.max(np.abs(runs[name]["megno"]["Y"])) < 10.0, name


def test_megno_grows_like_lambda_t_over_2_on_chaotic_orbits(runs):
    m = runs["lorenz"]["megno"]  # T = 1e3: slope 0.446 -> lambda 0.892
    assert 2.0 * m["slope"] == pytest.approx(LORENZ_LAMBDA, abs=0.06)
    assert m["final"] == pytest.approx(LORENZ_LAMBDA * T_LOR / 2.0, rel=0.1)
    assert _megno_verdict(m, T_LOR) == CHAOTIC
    m = runs["hh_chaos"]["megno"]  # T = 1e4: <Y> = 670, slope 0.060 -> lambda 0.12
    assert 0.07 < 2.0 * m["slope"] < 0.2
    assert m["final"] > 100.0
    assert _megno_verdict(m, T_HAM) == CHAOTIC


def test_megno_log_growth_is_the_benettin_series(runs):
    # the renormalised tangent vector gives lambda_1 of Lorenz directly (T = 1e3)
    m = runs["lorenz"]["megno"]
    assert m["log_growth"].size == round(T_LOR / TAU_LOR)
    assert m["log_growth"].sum() / T_LOR == pytest.approx(LORENZ_LAMBDA, abs=0.03)


def test_megno_rejects_bad_input(hy):
    x, v = hy.make_vars("x", "v")
    tm, n = integrators.megno_integrator([(x, v), (v, -x)])
    for kw, name in [({"T": 0.0}, "T"), ({"n_samples": 2}, "n_samples"), ({"tau": -1.0}, "tau"),
                     ({"tau": 0.3}, "T"), ({"tau": 5.0}, "tau")]:
        args = {"T": 10.0, "n_samples": 4, **kw}
        with pytest.raises(ValueError, match=name):
            tangent.megno(tm, n, [1.0, 0.0], **args)
    with pytest.raises(ValueError, match="n = 3"):
        tangent.megno(tm, 3, [1.0, 0.0, 0.0], T=10.0, n_samples=4)
    with pytest.raises(ValueError, match="sys"):
        integrators.megno_integrator([])


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


MEGNO_CHAOS = {"y_mean": 450.0, "y_err": 0.5, "slope": 0.45, "slope_err": 0.001, "T": 1000.0}
MEGNO_REG = {"y_mean": 2.01, "y_err": 0.01, "slope": -1e-7, "slope_err": 1e-7, "T": 1e4}


def test_judge_megno_branches():
    v, reason = tangent.judge_megno(**MEGNO_CHAOS)
    assert v == CHAOTIC and "0.9" in reason  # lambda ~ 2 slope
    assert tangent.judge_megno(**MEGNO_REG)[0] == REGULAR
    assert tangent.judge_megno(**{**MEGNO_REG, "y_mean": 0.0})[0] == REGULAR  # isochronous / periodic
    assert tangent.judge_megno(**{**MEGNO_REG, "y_mean": 3.0})[0] == UNDECIDED  # between 2.5 and 4
    # <Y> still at 2 but growing over the horizon: not regular
    assert tangent.judge_megno(**{**MEGNO_REG, "slope": 1e-4})[0] == UNDECIDED
    # large <Y> that no longer grows: not chaotic
    assert tangent.judge_megno(**{**MEGNO_CHAOS, "slope": -0.01})[0] == UNDECIDED
    _nan_each(tangent.judge_megno, MEGNO_CHAOS, MEGNO_CHAOS.keys())
    _nan_each(tangent.judge_megno, MEGNO_REG, MEGNO_REG.keys())
    s = _monotone_in_errors(tangent.judge_megno, MEGNO_CHAOS, ["y_err", "slope_err"])
    assert s[0] == CHAOTIC and s[-1] == UNDECIDED
    s = _monotone_in_errors(tangent.judge_megno, MEGNO_REG, ["y_err", "slope_err"])
    assert s[0] == REGULAR and s[-1] == UNDECIDED
    with pytest.raises(ValueError, match="y_err"):
        tangent.judge_megno(**{**MEGNO_REG, "y_err": -1.0})


# ----------------------------------------------------------------------------- the sleigh's Benettin judge and the long-double gate

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


@pytest.mark.parametrize("v_ld, check, want", [
    (C, "confirmed", C),        # long double confirms exponential growth: MEGNO may say chaotic
    (C, "not confirmed", U),    # the gate applies to the long-double MEGNO as well
    (G, "not confirmed", G),    # a regular long-double MEGNO stands
    (U, "confirmed", U),
])
def test_megno_judged_in_long_double_under_the_same_gate(v_ld, check, want):
    from sleighsim.chaos.tangent import megno_in_long_double

    ld = {"check": check, "reason": f"{check} in long double"}
    v, reason = megno_in_long_double((v_ld, "r"), ld, (C, "double says chaotic"), 2e5, 5e4)
    assert v == want
    assert reason.startswith("in long double over T = 2e+05") and reason.endswith("in double over T = 5e+04: chaotic")
    if (v_ld, want) == (C, U):
        assert "not confirmed in long double" in reason


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
