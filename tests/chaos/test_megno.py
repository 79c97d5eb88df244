"""MEGNO (sleighsim.chaos.megno) on textbook systems with known answers (chaos_textbook), and every
branch of its judge and of the long-double gate on it, on synthetic inputs."""

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

from sleighsim.chaos import megno
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED
from sleighsim.engine import integrators

C, G, U = CHAOTIC, REGULAR, UNDECIDED


def _megno_verdict(m, T):
    return megno.judge_megno(m["final"], m["resid"], m["slope"], m["slope_err"], T)[0]


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
            megno.megno(tm, n, [1.0, 0.0], **args)
    with pytest.raises(ValueError, match="n = 3"):
        megno.megno(tm, 3, [1.0, 0.0, 0.0], T=10.0, n_samples=4)
    with pytest.raises(ValueError, match="sys"):
        integrators.megno_integrator([])


# ----------------------------------------------------------------------------- judges (synthetic)

MEGNO_CHAOS = {"y_mean": 450.0, "y_err": 0.5, "slope": 0.45, "slope_err": 0.001, "T": 1000.0}
MEGNO_REG = {"y_mean": 2.01, "y_err": 0.01, "slope": -1e-7, "slope_err": 1e-7, "T": 1e4}


def test_judge_megno_branches():
    v, reason = megno.judge_megno(**MEGNO_CHAOS)
    assert v == CHAOTIC and "0.9" in reason  # lambda ~ 2 slope
    assert megno.judge_megno(**MEGNO_REG)[0] == REGULAR
    assert megno.judge_megno(**{**MEGNO_REG, "y_mean": 0.0})[0] == REGULAR  # isochronous / periodic
    assert megno.judge_megno(**{**MEGNO_REG, "y_mean": 3.0})[0] == UNDECIDED  # between 2.5 and 4
    # <Y> still at 2 but growing over the horizon: not regular
    assert megno.judge_megno(**{**MEGNO_REG, "slope": 1e-4})[0] == UNDECIDED
    # large <Y> that no longer grows: not chaotic
    assert megno.judge_megno(**{**MEGNO_CHAOS, "slope": -0.01})[0] == UNDECIDED
    _nan_each(megno.judge_megno, MEGNO_CHAOS, MEGNO_CHAOS.keys())
    _nan_each(megno.judge_megno, MEGNO_REG, MEGNO_REG.keys())
    s = _monotone_in_errors(megno.judge_megno, MEGNO_CHAOS, ["y_err", "slope_err"])
    assert s[0] == CHAOTIC and s[-1] == UNDECIDED
    s = _monotone_in_errors(megno.judge_megno, MEGNO_REG, ["y_err", "slope_err"])
    assert s[0] == REGULAR and s[-1] == UNDECIDED
    with pytest.raises(ValueError, match="y_err"):
        megno.judge_megno(**{**MEGNO_REG, "y_err": -1.0})


@pytest.mark.parametrize("v_ld, check, want", [
    (C, "confirmed", C),        # long double confirms exponential growth: MEGNO may say chaotic
    (C, "not confirmed", U),    # the gate applies to the long-double MEGNO as well
    (G, "not confirmed", G),    # a regular long-double MEGNO stands
    (U, "confirmed", U),
])
def test_megno_judged_in_long_double_under_the_same_gate(v_ld, check, want):
    ld = {"check": check, "reason": f"{check} in long double"}
    v, reason = megno.megno_in_long_double((v_ld, "r"), ld, (C, "double says chaotic"), 2e5, 5e4)
    assert v == want
    assert reason.startswith("in long double over T = 2e+05") and reason.endswith("in double over T = 5e+04: chaotic")
    if (v_ld, want) == (C, U):
        assert "not confirmed in long double" in reason


def test_megno_rate_is_twice_the_slope():
    assert megno.megno_rate({"slope": 0.25, "slope_err": 0.5}) == (0.5, 1.0)
