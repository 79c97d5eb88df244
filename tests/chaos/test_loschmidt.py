"""The Loschmidt test (sleighsim.chaos.loschmidt), a chaos indicator without tangent dynamics: on
textbook systems with known answers (chaos_textbook), its fit, every branch of its judges on
synthetic inputs and the sleigh's Loschmidt indicator in double and long double."""

import math

import numpy as np
import pytest
from chaos_textbook import (
    HH_CHAOS,
    OSC0,
    _flip_momenta,
    _monotone_in_errors,
    _nan_each,
    _oscillators,
)

from sleighsim.chaos import loschmidt
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED

C, G, U = CHAOTIC, REGULAR, UNDECIDED


def _losch_verdict(L):
    return loschmidt.judge_loschmidt_run(L)[0]


# ----------------------------------------------------------------------------- Loschmidt

def test_loschmidt_chaotic_error_grows_exponentially(runs):
    # Henon-Heiles E = 1/6, T = 10..300 (30 values): return error 1e-14 -> O(1); exp fit
    # rate 0.115 +- 0.007 (about lambda), power fit would need T^9.8
    L = loschmidt.loschmidt(runs["hh_chaos"]["ta"], HH_CHAOS, np.linspace(10, 300, 30), _flip_momenta)
    assert L["error"][0] < 1e-10 and L["error"][-1] > 1e-3
    assert L["n_used"] >= 10 and L["better"] == "exponential"
    assert 0.05 < L["exp_rate"] < 0.3
    assert L["pow_exponent"] > 5
    assert _losch_verdict(L) == CHAOTIC
    np.testing.assert_allclose(L["rel_error"], L["error"] / np.max(np.abs(HH_CHAOS)))


@pytest.mark.parametrize("name", ["hh_regular", "quartic"])
def test_loschmidt_regular_error_grows_like_a_power(runs, name):
    # T = 100..1e5 (20 values): error 1e-15 -> 2e-10 (Henon-Heiles), 4e-9 (quartic); power fit
    # T^1.4 (14 usable points), T^1.7 (16); in the tail (last half) T^1.4-1.8
    y0 = runs[name]["y0"]
    L = loschmidt.loschmidt(runs[name]["ta"], y0, np.geomspace(100, 1e5, 20), _flip_momenta)
    assert np.max(L["rel_error"]) < 1e-7
    assert L["n_used"] >= 10 and 0.5 < L["pow_exponent"] < 3.0
    assert L["tail_n"] == math.ceil(L["n_used"] / 2) and 0.5 < L["tail_pow_exponent"] < 3.0
    assert _losch_verdict(L) == REGULAR


def test_loschmidt_sustained_growth_is_judged_in_the_tail():
    # two jumps of the return error (e.g. amplification at two spikes) followed by T^2 growth:
    # over all points faster than T^3, in the tail T^2: regular, not chaos
    T = np.geomspace(100, 2e4, 30)
    e = np.where(T < 300, 1e-12, np.where(T < 1200, 1e-9, 1e-6 * (T / 1200) ** 2))
    fit = loschmidt.loschmidt_fit(T, e, 1.0)
    assert fit["tail_n"] == 15 and np.array_equal(np.flatnonzero(fit["tail_used"]), np.arange(15, 30))
    assert fit["tail_pow_exponent"] == pytest.approx(2.0)
    whole = loschmidt.judge_loschmidt(*(fit[k] for k in ("n_used",) + loschmidt._FIT_KEYS))
    assert whole[0] == CHAOTIC
    v, reason = loschmidt.judge_loschmidt_run(fit)
    assert v == REGULAR and "power-law growth in the tail" in reason
    # exponential to saturation: chaotic over all points and in the tail
    T = np.linspace(10, 300, 30)
    fit = loschmidt.loschmidt_fit(T, 1e-15 * np.exp(0.1 * T), 1.0)
    assert fit["tail_exp_rate"] == pytest.approx(0.1)
    assert loschmidt.judge_loschmidt_run(fit)[0] == CHAOTIC
    # the tail has at least tail_min points, at most all usable ones
    fit = loschmidt.loschmidt_fit(np.geomspace(10, 1e4, 5), 1e-12 * np.geomspace(10, 1e4, 5), 1.0)
    assert fit["n_used"] == 5 and fit["tail_n"] == 4
    fit = loschmidt.loschmidt_fit(np.geomspace(10, 1e4, 5), 1e-12 * np.geomspace(10, 1e4, 5), 1.0, tail_min=9)
    assert fit["tail_n"] == 5
    with pytest.raises(ValueError, match="tail"):
        loschmidt.loschmidt_fit(T, 1e-15 * np.exp(0.1 * T), 1.0, tail=0.0)


def test_loschmidt_fit_stops_at_saturation_and_checks_its_settings():
    # after the first saturated horizon nothing counts, even an error that dips back below it
    T = np.geomspace(10, 1e4, 12)
    e = 1e-12 * T ** 2
    e[8], e[10] = 0.5, 1e-3
    fit = loschmidt.loschmidt_fit(T, e, 1.0)
    assert fit["n_used"] == 8 and not fit["used"][9:].any()
    with pytest.raises(ValueError, match="rounding"):
        loschmidt.loschmidt_fit(T, e, 1.0, rounding=0.0)
    with pytest.raises(ValueError, match="tail_min"):
        loschmidt.loschmidt_fit(T, e, 1.0, tail_min=1)


def test_judge_loschmidt_run_is_monotone_in_the_uncertainties():
    errs = ["exp_rate_err", "pow_exponent_err"]
    for whole, tail in ((LOS_CHAOS, LOS_CHAOS), (LOS_CHAOS, LOS_REG), (LOS_REG, LOS_REG)):
        base = _run_fits(whole, tail)
        for keys in (errs, [f"tail_{k}" for k in errs], errs + [f"tail_{k}" for k in errs]):
            s = _monotone_in_errors(lambda **kw: loschmidt.judge_loschmidt_run(kw), base, keys)
            assert s[-1] == UNDECIDED or keys == errs, (whole is LOS_CHAOS, tail is LOS_CHAOS, keys, s)


def _run_fits(whole, tail):
    return {**whole, **{f"tail_{k}": tail[k] for k in loschmidt._FIT_KEYS}, "tail_n": tail["n_used"]}


def test_judge_loschmidt_run_branches():
    mid = {**LOS_REG, "pow_exponent": 4.0}  # neither clearly exponential nor below T^3
    assert loschmidt.judge_loschmidt(**mid)[0] == UNDECIDED
    cases = [((LOS_CHAOS, LOS_CHAOS), CHAOTIC, "sustained into the tail"),
             ((LOS_CHAOS, LOS_REG), REGULAR, "power-law growth in the tail"),
             ((LOS_REG, LOS_REG), REGULAR, "power-law growth in the tail"),
             ((LOS_CHAOS, mid), UNDECIDED, "not sustained"),
             ((LOS_REG, mid), UNDECIDED, "neither"),
             ((LOS_REG, LOS_CHAOS), UNDECIDED, "neither")]
    for (whole, tail), want, words in cases:
        v, reason = loschmidt.judge_loschmidt_run(_run_fits(whole, tail))
        assert v == want and words in reason, (whole, tail, v, reason)
    v, reason = loschmidt.judge_loschmidt_run(_run_fits(LOS_CHAOS, {**LOS_CHAOS, "exp_rate": float("nan")}))
    assert v == UNDECIDED and "not finite: exp_rate" in reason
    v, reason = loschmidt.judge_loschmidt_run(_run_fits(LOS_CHAOS, {**LOS_CHAOS, "n_used": 2}))
    assert v == UNDECIDED and "2 return errors" in reason


def test_loschmidt_shares_one_forward_run_and_uses_the_integrators_precision(runs):
    import heyoka as hy

    ta = runs["quartic"]["ta"]
    a = loschmidt.loschmidt(ta, OSC0, [30.0, 10.0, 20.0], _flip_momenta)
    b = loschmidt.loschmidt(ta, OSC0, [10.0, 20.0, 30.0], _flip_momenta)
    np.testing.assert_array_equal(a["error"], b["error"][[2, 0, 1]])
    assert a["floor"] == pytest.approx(1e3 * np.finfo(float).eps * np.max(np.abs(OSC0)))
    ld = hy.taylor_adaptive(_oscillators(hy, True), np.array(OSC0, dtype=np.longdouble), fp_type=np.longdouble)
    c = loschmidt.loschmidt(ld, OSC0, [10.0, 20.0, 30.0], _flip_momenta)
    assert c["floor"] == pytest.approx(1e3 * float(np.finfo(np.longdouble).eps) * np.max(np.abs(OSC0)))
    assert np.all(c["error"] < 1e-3 * b["error"].max() + 1e-17)
    # horizons more than a factor 2 apart: the shared forward run still stops exactly at each T
    # (the same errors as separate runs from y0, to long double's rounding)
    Ts = [1.3, 7.77, 61.1]  # 61.1 - 7.77 is not exact in double: a relative step would miss T
    shared = loschmidt.loschmidt(ld, OSC0, Ts, _flip_momenta)["error"]
    alone = [loschmidt.loschmidt(ld, OSC0, [T], _flip_momenta)["error"][0] for T in Ts]
    np.testing.assert_allclose(shared, alone, rtol=0, atol=1e-16)
    with pytest.raises(ValueError, match="precision"):
        loschmidt.loschmidt(ld, OSC0, Ts, lambda z: np.asarray(_flip_momenta(z), float))


def test_loschmidt_fit_synthetic_and_bad_input(runs):
    T = np.linspace(10, 300, 20)
    fit = loschmidt.loschmidt_fit(T, 1e-15 * np.exp(0.1 * T), 1.0)
    assert fit["better"] == "exponential" and fit["exp_rate"] == pytest.approx(0.1)
    assert fit["n_used"] == int(np.sum((1e-15 * np.exp(0.1 * T) > 1e3 * 2.220446049250313e-16)
                                       & (1e-15 * np.exp(0.1 * T) < 1e-2)))
    fit = loschmidt.loschmidt_fit(np.geomspace(10, 1e4, 10), 1e-16 * np.geomspace(10, 1e4, 10) ** 1.5, 1.0)
    assert fit["better"] == "power" and fit["pow_exponent"] == pytest.approx(1.5)
    fit = loschmidt.loschmidt_fit([1.0, 2.0], [1e-10, 1e-9], 1.0)
    assert fit["better"] == "undetermined"
    ta = runs["quartic"]["ta"]
    with pytest.raises(ValueError, match="T_values"):
        loschmidt.loschmidt(ta, OSC0, [], _flip_momenta)
    with pytest.raises(ValueError, match="T_values"):
        loschmidt.loschmidt(ta, OSC0, [10.0, 0.0], _flip_momenta)
    with pytest.raises(ValueError, match="involution"):
        loschmidt.loschmidt(ta, OSC0, [10.0], None)
    with pytest.raises(ValueError, match="scale"):
        loschmidt.loschmidt(ta, [0.0] * 4, [10.0], _flip_momenta)


# ----------------------------------------------------------------------------- judge (synthetic)

LOS_CHAOS = {"n_used": 20, "exp_rate": 0.11, "exp_rate_err": 0.007, "exp_rms": 1.9, "pow_exponent": 9.8,
             "pow_exponent_err": 1.3, "pow_rms": 3.8}
LOS_REG = {"n_used": 6, "exp_rate": 5e-4, "exp_rate_err": 2e-4, "exp_rms": 1.1, "pow_exponent": 1.5,
           "pow_exponent_err": 0.1, "pow_rms": 0.3}


def test_judge_loschmidt_branches():
    v, reason = loschmidt.judge_loschmidt(**LOS_CHAOS)
    assert v == CHAOTIC and "exponentially" in reason
    # exponential not clearly better, but far steeper than any power law: chaotic
    v, reason = loschmidt.judge_loschmidt(**{**LOS_CHAOS, "exp_rms": 3.0})
    assert v == CHAOTIC and "faster than T^3" in reason
    assert loschmidt.judge_loschmidt(**LOS_REG)[0] == REGULAR
    # too few usable points
    v, reason = loschmidt.judge_loschmidt(**{**LOS_REG, "n_used": 2})
    assert v == UNDECIDED and "2 return errors" in reason
    # a steep power law that the exponential does not fit better: undecided
    assert loschmidt.judge_loschmidt(**{**LOS_REG, "pow_exponent": 4.0})[0] == UNDECIDED
    # exponential fits clearly better, but its rate is not resolved above zero: undecided
    assert loschmidt.judge_loschmidt(**{**LOS_CHAOS, "exp_rate_err": 0.1, "pow_exponent_err": 5.0})[0] == UNDECIDED
    _nan_each(loschmidt.judge_loschmidt, LOS_CHAOS, LOS_CHAOS.keys())
    _nan_each(loschmidt.judge_loschmidt, LOS_REG, LOS_REG.keys())
    s = _monotone_in_errors(loschmidt.judge_loschmidt, LOS_CHAOS, ["exp_rate_err", "pow_exponent_err"])
    assert s[0] == CHAOTIC and s[-1] == UNDECIDED
    s = _monotone_in_errors(loschmidt.judge_loschmidt, LOS_REG, ["exp_rate_err", "pow_exponent_err"])
    assert s[0] == REGULAR and s[-1] == UNDECIDED


# ----------------------------------------------------------------------------- the sleigh's Loschmidt indicator

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
    from sleighsim.chaos.loschmidt import loschmidt_indicator

    out = loschmidt_indicator(L, L_ld, 3.0)
    assert out["verdict"][0] == want == loschmidt.judge_loschmidt_run(L_ld)[0]
    assert out["verdict_double"] == loschmidt.judge_loschmidt_run(L)[0]
    assert (out["value"], out["error"]) == (L_ld["tail_exp_rate"], L_ld["tail_exp_rate_err"])
    assert out["verdict"][1].startswith("in long double: ")
    assert out["verdict"][1].endswith(f"in double: {out['verdict_double']}")
