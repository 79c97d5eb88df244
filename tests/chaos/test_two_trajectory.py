"""Two nearby trajectories (sleighsim.chaos.two_trajectory), a chaos indicator without tangent
dynamics: on textbook systems with known answers (chaos_textbook), the d0-independence check, every
branch of its judge on synthetic inputs and the sleigh's two-trajectory indicator."""


import numpy as np
import pytest
from chaos_textbook import (
    HH_CHAOS,
    LORENZ_LAMBDA,
    OSC0,
    T_HAM,
    TAU_HAM,
    _hh_project,
    _monotone_in_errors,
    _nan_each,
    _oscillators,
)

from sleighsim.chaos import two_trajectory
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED

C, G, U = CHAOTIC, REGULAR, UNDECIDED


def _two_verdict(r):
    return two_trajectory.judge_two_trajectory(r["rate"], r["stderr"], r["T"], r["tau"], r["running_slope"],
                                               r["running_slope_err"])[0]


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


# ----------------------------------------------------------------------------- judge (synthetic)

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


# ----------------------------------------------------------------------------- the sleigh's two-trajectory indicator

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
