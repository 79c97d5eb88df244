"""Chaos indicators built on pairs of orbits, without tangent dynamics (sleighsim.chaos.two_trajectory,
sleighsim.chaos.loschmidt): two nearby trajectories and the Loschmidt return error on textbook systems with known answers
(chaos_textbook), every branch of their judges on synthetic inputs, and the engines' shared
propagation conventions (callbacks, failed integrations; MEGNO's too)."""

import math

import numpy as np
import pytest
from chaos_textbook import (
    HH_CHAOS,
    LORENZ_LAMBDA,
    OSC0,
    T_HAM,
    TAU_HAM,
    _flip_momenta,
    _hh_project,
    _monotone_in_errors,
    _nan_each,
    _oscillators,
)

from sleighsim.chaos import loschmidt, megno, two_trajectory
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED
from sleighsim.engine import integrators

C, G, U = CHAOTIC, REGULAR, UNDECIDED


def _two_verdict(r):
    return two_trajectory.judge_two_trajectory(r["rate"], r["stderr"], r["T"], r["tau"], r["running_slope"],
                                    r["running_slope_err"])[0]


def _losch_verdict(L):
    return loschmidt.judge_loschmidt_run(L)[0]


# ----------------------------------------------------------------------------- two trajectories

def test_two_trajectory_on_textbook_orbits(runs):
    r = runs["lorenz"]["two"]  # T = 1e3, tau = 0.1: 0.906 +- 0.004
    assert r["rate"] == pytest.approx(LORENZ_LAMBDA, abs=0.03)
    assert 0 < r["stderr"] < 0.02
    assert abs(r["running_slope"]) < 0.1
    assert _two_verdict(r) == CHAOTIC
    r = runs["hh_chaos"]["two"]  # T = 1e4: 0.112 +- 0.011
    assert 0.07 < r["rate"] < 0.2
    assert _two_verdict(r) == CHAOTIC
    # tori: running rate ~ ln T / T, log-log slope about -0.85 over the last decade
    for name in ("hh_regular", "quartic"):
        r = runs[name]["two"]
        assert r["rate"] < 2e-3 and -1.0 < r["running_slope"] < -0.7, name
        assert _two_verdict(r) == REGULAR, name
    # structure of the result
    r = runs["hh_chaos"]["two"]
    assert r["log_growth"].size == round(T_HAM / TAU_HAM) and r["block_rates"].size == 10
    assert r["rate"] == pytest.approx(r["log_growth"].sum() / T_HAM)
    assert r["running"][-1] == pytest.approx(r["rate"]) and r["T_grid"][-1] == pytest.approx(T_HAM)


def test_two_trajectory_with_energy_projection_agrees_and_is_d0_independent(hy, runs):
    ta = runs["hh_chaos"]["ta"]
    calls = []

    def project(ref, partner):
        calls.append(1)
        return _hh_project(ref, partner)

    # T = 1e4, d0 = 1e-9 and 1e-7 with projection: 0.1116 and 0.1116; 0.1121 without
    # (the reference orbit is the same; the block rates show a sticky episode, 0.031, in
    # t = 1000-2000, so shorter runs of this realisation give lower rates)
    r = two_trajectory.two_trajectory(ta, HH_CHAOS, d0=1e-9, tau=1.0, T=T_HAM, project=project, seed=3)
    assert len(calls) == round(T_HAM) + 1  # after every interval and at the start
    assert r["rate"] == pytest.approx(runs["hh_chaos"]["two"]["rate"], abs=0.01)
    r2 = two_trajectory.two_trajectory(ta, HH_CHAOS, d0=1e-7, tau=1.0, T=T_HAM, project=_hh_project, seed=4)
    assert r2["rate"] == pytest.approx(r["rate"], abs=0.01)
    # the reference orbit is exactly the one of a plain integration in steps of tau
    r3 = two_trajectory.two_trajectory(ta, HH_CHAOS, d0=1e-8, tau=1.0, T=100.0)
    np.testing.assert_array_equal(r3["final_state"], _plain_orbit(ta, HH_CHAOS, 100, 1.0))


def _plain_orbit(ta, y0, n, tau):
    ta.time = 0.0
    ta.state[:] = y0
    for _ in range(n):
        ta.time = 0.0
        ta.propagate_for(tau)
    return ta.state.copy()


def test_two_trajectory_rejects_bad_input(runs):
    ta = runs["quartic"]["ta"]
    for kw, name in [({"d0": 0.0}, "d0"), ({"d0": -1e-8}, "d0"), ({"tau": 0.0}, "tau"), ({"T": -1.0}, "T"),
                     ({"T": 10.5}, "T"), ({"T": 5.0}, "n_blocks"), ({"n_blocks": 1}, "n_blocks"),
                     ({"t_align": 1.5}, "t_align")]:
        args = {"d0": 1e-8, "tau": 1.0, "T": 20.0, **kw}
        with pytest.raises(ValueError, match=name):
            two_trajectory.two_trajectory(ta, OSC0, **args)
    with pytest.raises(ValueError, match="y0"):
        two_trajectory.two_trajectory(ta, [1.0, 0.0], d0=1e-8, tau=1.0, T=20.0)


def test_two_trajectory_runs_in_the_integrators_precision(runs):
    import heyoka as hy

    ta = runs["quartic"]["ta"]
    ld = hy.taylor_adaptive(_oscillators(hy, True), np.array(OSC0, dtype=np.longdouble), fp_type=np.longdouble)
    a = two_trajectory.two_trajectory(ta, OSC0, d0=1e-8, tau=1.0, T=50.0, seed=1)
    b = two_trajectory.two_trajectory(ld, OSC0, d0=1e-8, tau=1.0, T=50.0, seed=1)
    assert b["final_state"].dtype == np.longdouble and a["final_state"].dtype == np.float64
    # the same orbit and partner, to double's rounding amplified over T = 50
    np.testing.assert_allclose(np.asarray(b["final_state"], float), a["final_state"], rtol=0, atol=1e-9)
    assert b["rate"] == pytest.approx(a["rate"], abs=1e-6)


@pytest.mark.parametrize("rates, stderrs, want, says", [
    ([1.0e-3, 1.02e-3, 0.99e-3], [1e-5, 1e-5, 1e-5], True, "independent of d0"),
    ([1.2e-2, 8.9e-3, 6.8e-3], [3e-4, 3e-4, 3e-4], False, "depends on d0"),  # the sleigh's main state
    ([1.0e-3, np.nan, 1.0e-3], [1e-5, 1e-5, 1e-5], False, "not finite"),
])
def test_d0_independence_of_the_two_trajectory_rate(rates, stderrs, want, says):
    ok, why = two_trajectory.d0_independent([1e-11, 1e-9, 1e-7], rates, stderrs, sigma=3.0)
    assert ok is want and says in why


def test_d0_independence_needs_two_separations():
    ok, why = two_trajectory.d0_independent([1e-9], [1e-3], [1e-5])
    assert ok is False and "not checked" in why
    with pytest.raises(ValueError):
        two_trajectory.d0_independent([1e-9, 1e-7], [1e-3], [1e-5])


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


# ----------------------------------------------------------------------------- callbacks, failures

class _Counter:
    def __init__(self):
        self.n = 0

    def __call__(self, ta):
        self.n += 1
        return True


def test_callbacks_reach_every_propagation_and_angle_reduction_works(hy):
    """Two uncoupled rotating pendula (a sheared torus with unbounded angles): with
    heyoka's angle_reducer and a wrapped difference all indicators stay regular."""
    a, b, pa, pb = hy.make_vars("a", "b", "pa", "pb")
    sys = [(a, pa), (b, pb), (pa, -hy.sin(a)), (pb, -math.sqrt(2.0) * hy.sin(b))]
    y0 = [0.0, 0.0, 2.5, 3.0]  # energies above the separatrix: rotation

    def wrap(u, v):
        d = np.asarray(u, float) - np.asarray(v, float)
        d[:2] = (d[:2] + math.pi) % (2.0 * math.pi) - math.pi
        return d

    ta = hy.taylor_adaptive(sys, y0, compact_mode=True)
    red = hy.callback.angle_reducer([a, b])
    r = two_trajectory.two_trajectory(ta, y0, d0=1e-8, tau=1.0, T=3000.0, callback=red, difference=wrap)
    assert np.all(np.abs(r["final_state"][:2]) <= 2 * math.pi)
    assert _two_verdict(r) == REGULAR
    L = loschmidt.loschmidt(ta, y0, np.geomspace(10, 3000, 8), _flip_momenta, callback=red, difference=wrap)
    assert np.max(L["error"]) < 1e-9
    tm, n = integrators.megno_integrator(sys)
    m = megno.megno(tm, n, y0, T=3000.0, n_samples=60, callback=hy.callback.angle_reducer([a, b]))
    assert abs(m["final"] - 2.0) < 0.1 and np.all(np.abs(m["final_state"][:2]) <= 2 * math.pi)
    # a counting callback is called by every engine
    c = _Counter()
    two_trajectory.two_trajectory(ta, y0, d0=1e-8, tau=1.0, T=20.0, callback=c, n_blocks=2)
    n1 = c.n
    assert n1 >= 40  # at least one step per leg, 2 legs per interval
    loschmidt.loschmidt(ta, y0, [5.0], _flip_momenta, callback=c)
    assert c.n > n1
    n2 = c.n
    megno.megno(tm, n, y0, T=20.0, n_samples=4, tau=1.0, callback=c)
    assert c.n >= n2 + 20


def test_failed_integration_raises_runtime_error_naming_the_time(hy):
    x, y = hy.make_vars("x", "y")
    sys = [(x, x * x), (y, -y)]  # x blows up at t = 1 / x0
    ta = hy.taylor_adaptive(sys, [1.0, 1.0], compact_mode=True)
    with pytest.raises(RuntimeError, match="t = "):
        two_trajectory.two_trajectory(ta, [0.2, 1.0], d0=1e-8, tau=1.0, T=20.0, n_blocks=2)
    with pytest.raises(RuntimeError, match="t = "):
        loschmidt.loschmidt(ta, [0.2, 1.0], [10.0], lambda s: s)
    tm, n = integrators.megno_integrator(sys)
    with pytest.raises(RuntimeError, match="t = "):
        megno.megno(tm, n, [0.2, 1.0], T=20.0, n_samples=4, tau=1.0)


# ----------------------------------------------------------------------------- judges (synthetic)

TWO_CHAOS = {"rate": 0.9, "stderr": 0.01, "T": 1000.0, "tau": 0.1, "running_slope": 0.0, "running_slope_err": 0.01}
TWO_REG = {"rate": 8e-4, "stderr": 5e-4, "T": 1e4, "tau": 1.0, "running_slope": -0.85, "running_slope_err": 0.01}


def test_judge_two_trajectory_branches():
    v, reason = two_trajectory.judge_two_trajectory(**TWO_CHAOS)
    assert v == CHAOTIC and "0.9" in reason
    assert two_trajectory.judge_two_trajectory(**TWO_REG)[0] == REGULAR
    # positive rate but still decaying (e.g. an orbit sticking to islands): undecided
    assert two_trajectory.judge_two_trajectory(**{**TWO_CHAOS, "running_slope": -0.5})[0] == UNDECIDED
    # steady but not above what polynomial growth gives over T: undecided
    assert two_trajectory.judge_two_trajectory(**{**TWO_CHAOS, "rate": 0.05, "T": 100.0, "tau": 1e-3})[0] == UNDECIDED
    _nan_each(two_trajectory.judge_two_trajectory, TWO_CHAOS, TWO_CHAOS.keys())
    _nan_each(two_trajectory.judge_two_trajectory, TWO_REG, TWO_REG.keys())
    s = _monotone_in_errors(two_trajectory.judge_two_trajectory, TWO_CHAOS, ["stderr", "running_slope_err"])
    assert s[0] == CHAOTIC and s[-1] == UNDECIDED
    s = _monotone_in_errors(two_trajectory.judge_two_trajectory, TWO_REG, ["stderr", "running_slope_err"])
    assert s[0] == REGULAR and s[-1] == UNDECIDED
    with pytest.raises(ValueError, match="stderr"):
        two_trajectory.judge_two_trajectory(**{**TWO_CHAOS, "stderr": -0.1})


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


# ----------------------------------------------------------------------------- the sleigh's Loschmidt indicator: double and long double

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


def _tt(d0, rate, stderr=1e-5, T=1e5):
    return {"d0": d0, "rate": rate, "stderr": stderr, "T": T, "running_slope": 0.0, "running_slope_err": 1e-12}


def test_two_trajectory_indicator_judges_the_middle_run_and_needs_d0_independence():
    d0s = (1e-11, 1e-9, 1e-7)
    same = two_trajectory.two_trajectory_indicator([_tt(d, 1e-2) for d in d0s], d0s, tau=1.0, sigma=3.0)
    assert same["value"] == 1e-2 and same["error"] == 1e-5 and same["verdict"][0] == CHAOTIC
    follows = two_trajectory.two_trajectory_indicator([_tt(d, r) for d, r in zip(d0s, (1e-2, 5e-3, 2e-3))], d0s,
                                              tau=1.0, sigma=3.0)
    assert follows["value"] == 5e-3 and follows["verdict"][0] == UNDECIDED
    assert "at d0 = 1e-09 alone: chaotic" in follows["verdict"][1]
