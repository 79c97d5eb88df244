"""The per-state chaos verdict's rules on each branch, and the reversibility they rest on."""

import math

import numpy as np
import pytest

from sleighsim import indicators, model
from sleighsim.integrate import integrate, sample_grid
from sleighsim.params import Params
from sleighsim.scenes.verdict import R, classify, consistent, judge_benettin, r_image

C, G, U = indicators.CHAOTIC, indicators.REGULAR, indicators.UNDECIDED


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


@pytest.mark.parametrize("verdict, s, s_err, l1, l4, image, want", [
    (G, 0.0, 1e-6, 1e-6, -1e-6, "leaves", "regular"),
    (C, -1e-3, 1e-5, 5e-4, -1.5e-3, "leaves", "strange attractor"),
    (C, 1e-7, 1e-6, 5e-4, -5e-4, "stays", "conservative-type chaos"),
    (C, 1e-7, 1e-6, 5e-4, -5e-4, "leaves", "mixed dynamics"),
    (C, 1e-3, 1e-5, 5e-4, 5e-4, "leaves", "undetermined"),  # expanding on average: no class
    (U, -1e-3, 1e-5, 5e-4, -1.5e-3, "leaves", "undetermined"),
    (C, math.nan, 1e-5, 5e-4, -1.5e-3, "leaves", "undetermined"),
])
def test_classify_on_each_branch(verdict, s, s_err, l1, l4, image, want):
    assert classify(verdict, s, s_err, l1, l4, image, 3.0) == want


def test_r_image_stays_and_leaves():
    p = Params.paper(eps=0.1)
    y = np.array([0.05, 0.02, 0.8, 0.4])
    run = integrate(p, R * y, sample_grid(0.0, 100.0, 0.05), tol=1e-12)
    half = run.time.values >= 50.0
    own = -np.array([run.u.values[half].mean(), run.omega.values[half].mean()])  # what R(state) has, exactly
    assert r_image(p, y, own, T=100.0, tol=1e-12, rtol=0.01, scene="t")[0] == "stays"
    assert r_image(p, y, own * np.array([-1.0, 1.0]) + np.array([1.0, 0.0]), T=100.0, tol=1e-12, rtol=0.01,
                   scene="t")[0] == "leaves"


def test_the_flow_is_reversible_under_R():
    """R(u, Omega, omega, delta) = (-u, -Omega, -omega, delta): if y(t) solves the equations so does
    R y(-t), i.e. f(R y) = -R f(y) at every state."""
    p = Params.paper(eps=0.1)
    rng = np.random.default_rng(3)
    y = np.c_[rng.uniform(-1, 1, (200, 3)), rng.uniform(-np.pi, np.pi, 200)]
    assert np.max(np.abs(model.rhs(y * R, p) + model.rhs(y, p) * R)) < 1e-14
    # and not the other way round (the test can fail)
    assert np.max(np.abs(model.rhs(y * R, p) - model.rhs(y, p) * R)) > 1e-3
    # along a solution: R y(T) run forward for T returns to R y(0)
    y0 = np.array([0.05, 0.02, 0.8, 0.4])
    yT = integrate(p, y0, [0.0, 50.0], tol=1e-15)
    back = integrate(p, R * np.array([yT[v].values[-1] for v in model.STATE_NAMES]), [0.0, 50.0], tol=1e-15)
    assert np.max(np.abs(model.state_difference(R * np.array([back[v].values[-1] for v in model.STATE_NAMES]), y0))) < 1e-9


@pytest.mark.parametrize("verdict, a, others, want", [
    (C, (7.3e-4, 5.6e-5), {"two_trajectory": (8.5e-3, 3.2e-4)}, U),   # chaotic by both, rates 11x apart
    (C, (7.3e-4, 5.6e-5), {"two_trajectory": (8.0e-4, 9.0e-5)}, C),   # consistent rates
    (C, (7.3e-4, 1e-6), {"two_trajectory": (9.0e-4, 1e-6)}, C),       # resolved apart but within a factor 2
    (C, (7.3e-4, 5.6e-5), {"two_trajectory": (8.0e-4, 9.0e-5), "loschmidt": (5.9e-3, 1e-4)}, U),  # one of two off
    (C, (7.3e-4, 5.6e-5), {}, C),                                      # nothing to compare with
    (G, (7.3e-4, 5.6e-5), {"two_trajectory": (8.5e-3, 3.2e-4)}, G),   # only a chaotic verdict is checked
])
def test_chaotic_indicators_must_agree_on_the_rate(verdict, a, others, want):
    out = consistent(verdict, "r", *a, others, 3.0)
    assert out[0] == want
    if want == U:
        assert "disagree on the rate" in out[1]


@pytest.mark.parametrize("lam, spread, want", [
    (5e-4, 2e-5, "confirmed"),  # bound 2 ln(2e4) / 2e5 = 9.9e-5
    (4e-5, 1e-4, "not confirmed"),  # below the bound
    (3e-4, 2e-3, "not confirmed"),  # above it, but not by 3 standard errors
    (math.nan, 1e-5, "not confirmed"),
])
def test_precision_check_on_each_branch(monkeypatch, lam, spread, want):
    from sleighsim.scenes import verdict

    tau, T, t_align = 10.0, 2e5, 1000.0
    n = int(T / tau)
    rng = np.random.default_rng(0)
    g = lam * tau + spread * tau * rng.normal(size=n) * np.sqrt(n / 10)  # block means scatter by ~spread
    g[: int(t_align / tau)] = 5.0  # alignment of the vector: must be left out
    monkeypatch.setattr(verdict, "megno_run", lambda *a, **k: {"log_growth": g})
    cfg = dict(tau=tau, sigma=3.0, tol_long_double=1.08e-19, T_long_double=T, t_align=t_align)
    out = verdict.precision_check(Params.paper(eps=0.1), [0.0, 0.1, 1.0, 0.0], cfg, "s")
    assert out["check"] == want and out["reason"].startswith(want)
    if math.isfinite(lam):
        assert out["lambda_1"] == pytest.approx(lam, abs=4 * out["stderr"])


@pytest.mark.parametrize("v_ld, check, want", [
    (C, "confirmed", C),        # long double confirms exponential growth: MEGNO may say chaotic
    (C, "not confirmed", U),    # the gate applies to the long-double MEGNO as well
    (G, "not confirmed", G),    # a regular long-double MEGNO stands
    (U, "confirmed", U),
])
def test_megno_judged_in_long_double_under_the_same_gate(v_ld, check, want):
    from sleighsim.scenes.verdict import megno_in_long_double

    ld = {"check": check, "reason": f"{check} in long double"}
    v, reason = megno_in_long_double((v_ld, "r"), ld, (C, "double says chaotic"), 2e5, 5e4)
    assert v == want
    assert reason.startswith("in long double over T = 2e+05") and reason.endswith("in double over T = 5e+04: chaotic")
    if (v_ld, want) == (C, U):
        assert "not confirmed in long double" in reason


def _los(whole, tail):
    keys = ("n_used", "exp_rate", "exp_rate_err", "exp_rms", "pow_exponent", "pow_exponent_err", "pow_rms")
    return {**dict(zip(keys, whole)), **{f"tail_{k}": v for k, v in zip(keys[1:], tail[1:])}, "tail_n": tail[0]}


# (n, rate, err, rms, p, p_err, p_rms): exponential to saturation, and T^2 growth
_EXP = (12, 0.01, 1e-4, 0.5, 9.0, 0.5, 2.0)
_POW = (8, 3e-4, 5e-5, 0.5, 2.0, 0.1, 0.2)


@pytest.mark.parametrize("L, L_ld, want", [
    (_los(_EXP, _EXP), _los(_EXP, _POW), G),   # the long-double run judges (tail T^2), whatever double says
    (_los(_POW, _POW), _los(_EXP, _EXP), C),
    (_los(_EXP, _EXP), _los(_EXP, _EXP), C),
])
def test_loschmidt_indicator_is_judged_in_long_double(L, L_ld, want):
    from sleighsim.scenes.verdict import loschmidt_indicator

    out = loschmidt_indicator(L, L_ld, 3.0)
    assert out["verdict"][0] == want == indicators.judge_loschmidt_run(L_ld)[0]
    assert out["verdict_double"] == indicators.judge_loschmidt_run(L)[0]
    assert (out["value"], out["error"]) == (L_ld["tail_exp_rate"], L_ld["tail_exp_rate_err"])
    assert out["verdict"][1].startswith("in long double: ")
    assert out["verdict"][1].endswith(f"in double: {out['verdict_double']}")


def test_loschmidt_run_in_long_double_has_the_smaller_rounding():
    from sleighsim.scenes.verdict import loschmidt_run

    p = Params.paper(eps=0.1)
    cfg = dict(tol=2.0**-52, tol_long_double=1.0842021724855044e-19, loschmidt_T=[10.0, 40.0], loschmidt_n=3)
    y = np.array([0.05, 0.02, 0.8, 0.4])
    d, ld = loschmidt_run(p, y, cfg), loschmidt_run(p, y, cfg, long_double=True)
    np.testing.assert_allclose(d["T"], [10.0, 20.0, 40.0])
    assert ld["floor"] == pytest.approx(d["floor"] * float(np.finfo(np.longdouble).eps) / float(np.finfo(float).eps))
    assert np.all(d["rel_error"] < 1e-11) and np.all(ld["rel_error"] < 1e-3 * d["rel_error"].max())
