"""Frequency analysis as a chaos indicator (sleighsim.chaos.frequency): its engine and judge
(frequency_drift, judge_frequency, frequency_log_ratio) on every branch of the judge and on the textbook
orbits of chaos_textbook.

Measured with splits (2, 4, 8, 16), the slope between K = 4 and 16 (frequency.MIN_WINDOWS), double /
long double (heyoka, compact mode), x(t) sampled every 0.25 (Lorenz 0.02): Henon-Heiles E = 1/12 slope
-2.8 (T = 1e4) and -4.0 (T = 2e4), quartic oscillators at the refinement's precision (-inf) from T = 2e4
(-1.4 at T = 1e4, where D at K = 4 is just above that precision); Henon-Heiles E = 1/6 slope 0.0 to 0.25, Lorenz
(T = 4e3) -0.2 to -0.6, with drift ratios double / long double of 1.0 to 1.3. The sleigh's main
state (eps = 0.1, label 0.1127, T = 2e5, the paper config's chaos_verdict): slope about 0 in both
precisions, drift ratio 300 (ln 5.70 +- 0.38) against the rounding ratio 2048; rotor start a:
slope -4.43 +- 0.35 in double.
"""

import math

import numpy as np
import pytest

from sleighsim.chaos import frequency
from sleighsim.chaos.verdicts import REGULAR, UNDECIDED

G, U = REGULAR, UNDECIDED
ROUNDING = 2.220446049250313e-16 / 1.0842021724855044e-19  # 2048


# ----------------------------------------------------------------------------- judge

def _run(precision, slope, slope_err=0.55, D=1e-2, **ratio):
    return {"precision": precision, "slope": slope, "slope_err": slope_err, "D": D, **ratio}


_MAIN_LD = {"log_ratio": 5.70, "log_ratio_err": 0.38, "rounding_ratio": ROUNDING}  # the sleigh's main state


@pytest.mark.parametrize("runs, want, says", [
    ([_run("double", -3.5)], G, "converges faster than 1/W in double"),
    ([_run("double", -math.inf, math.nan)], G, "in double"),
    ([_run("double", -2.0)], U, "converges in no run"),  # -2 + 3 x 0.55 > -1: not resolved
    ([_run("double", 0.0), _run("long double", -3.5, 0.5, 1e-9, log_ratio=0.0, log_ratio_err=0.3,
                                rounding_ratio=ROUNDING)], G, "in long double"),
    ([_run("double", 0.0), _run("long double", -math.inf, math.nan, 1e-12)], G, "in long double"),
    # the main state: the double drift is integration error, the long-double one unexplained
    ([_run("double", 0.0), _run("long double", 0.05, 0.55, 4.4e-5, **_MAIN_LD)], U,
     "the double drift is integration error, the exact dynamics' below 4.4e-05"),
    # Henon-Heiles E = 1/6: the same drift in both precisions
    ([_run("double", 0.2, 0.35, 0.3), _run("long double", 0.1, 0.35, 0.3, log_ratio=0.2, log_ratio_err=0.26,
                                           rounding_ratio=ROUNDING)], U, "shrinks by 1.22"),
    ([_run("double", math.nan, math.nan), _run("long double", math.nan, math.nan, log_ratio=math.nan)], U,
     "converges in no run"),
])
def test_judge_frequency_on_each_branch(runs, want, says):
    v, reason = frequency.judge_frequency(runs)
    assert v == want and says in reason, reason
    if want == U:
        assert ("integration error" in reason) == ("exact dynamics" in says)


def test_judge_frequency_rejects_bad_input():
    with pytest.raises(ValueError, match="slope_err"):
        frequency.judge_frequency([_run("double", -3.0, -0.1)])
    with pytest.raises(ValueError, match="log_ratio_err"):
        frequency.judge_frequency([_run("double", 0.0), _run("long double", 0.0, log_ratio=1.0, log_ratio_err=-1.0)])
    with pytest.raises(ValueError, match="sigma"):
        frequency.judge_frequency([_run("double", -3.0)], sigma=-1.0)
    with pytest.raises(ValueError, match="empty"):
        frequency.judge_frequency([])


def test_frequency_log_ratio_uses_the_shared_splits_and_a_correlated_error():
    a = {"splits": np.array([2, 4, 8]), "D": np.array([1e-2, 1e-2, 1e-2])}
    b = {"splits": np.array([2, 4]), "D": np.array([1e-4, 1e-3])}
    lr, err = frequency.frequency_log_ratio(a, b)
    assert lr == pytest.approx((1 * math.log(100) + 3 * math.log(10)) / 4)
    assert err == pytest.approx((1 + math.sqrt(3)) / 4)  # fully correlated splits: no averaging down
    assert all(map(math.isnan, frequency.frequency_log_ratio(a, {"splits": np.array([16]), "D": np.array([1.0])})))
    # a spread below the refinement's precision counts as that precision
    zero = frequency.frequency_log_ratio(a, {"splits": np.array([2]), "D": np.array([0.0])})
    assert zero[0] == pytest.approx(math.log(1e-2 / frequency.PRECISION)) and zero[1] == pytest.approx(1.0)


# ----------------------------------------------------------------------------- textbook orbits

@pytest.fixture(scope="module")
def textbook():
    """Double and long-double frequency_drift of x(t) on the textbook orbits."""
    hy = pytest.importorskip("heyoka")
    from chaos_textbook import (
        HH_CHAOS,
        HH_REG,
        LORENZ0,
        OSC0,
        _hh_sys,
        _lorenz_sys,
        _oscillators,
    )

    cases = {"hh_chaos": (_hh_sys(hy), HH_CHAOS, 0.25, 1e4), "hh_regular": (_hh_sys(hy), HH_REG, 0.25, 1e4),
             "quartic": (_oscillators(hy, True), OSC0, 0.25, 2e4), "lorenz": (_lorenz_sys(hy), LORENZ0, 0.02, 4e3)}
    out = {}
    for name, (sys, y0, dt, T) in cases.items():
        runs = []
        for fp in (float, np.longdouble):
            ta = hy.taylor_adaptive(sys, np.array(y0, dtype=fp), fp_type=fp, compact_mode=True)
            runs.append(frequency.frequency_drift(ta, np.array(y0, dtype=fp), T=T, dt=dt, component=0))
        out[name] = runs
    return out


def _judge(runs):
    d, ld = runs
    lr, lr_err = frequency.frequency_log_ratio(d, ld)
    return frequency.judge_frequency([_run("double", d["slope"], d["slope_err"], d["D"][0]),
                                _run("long double", ld["slope"], ld["slope_err"], ld["D"][0], log_ratio=lr,
                                     log_ratio_err=lr_err, rounding_ratio=ROUNDING)])


@pytest.mark.parametrize("name, want", [("hh_regular", G), ("quartic", G), ("hh_chaos", U), ("lorenz", U)])
def test_frequency_indicator_on_textbook_orbits(textbook, name, want):
    d, ld = textbook[name]
    v, reason = _judge(textbook[name])
    assert v == want, reason
    if want == G:
        assert d["slope"] < -2.5 and frequency.judge_frequency([_run("double", d["slope"], d["slope_err"])])[0] == G
    else:  # chaos: the frequency wanders by as much at the smaller rounding, and does not converge
        assert d["slope"] > -1.0 and ld["slope"] > -1.0
        assert abs(frequency.frequency_log_ratio(d, ld)[0]) < 1.0


def test_frequency_drift_checks_its_arguments(textbook):
    import heyoka as hy
    from chaos_textbook import OSC0, _oscillators

    ta = hy.taylor_adaptive(_oscillators(hy, True), OSC0, compact_mode=True)
    with pytest.raises(ValueError, match="component"):
        frequency.frequency_drift(ta, OSC0, T=100.0, dt=0.25, component=4)
    with pytest.raises(ValueError, match="too few"):
        frequency.frequency_drift(ta, OSC0, T=10.0, dt=0.25, component=0)
    out = frequency.frequency_drift(ta, OSC0, T=200.0, dt=0.25, component=1, splits=(2, 4), min_cycles=4.0)
    assert out["T"] == 200.0 and out["f_ref"] == pytest.approx(math.sqrt(2) / (2 * math.pi), rel=0.05)


def _false_regular_runs(hy, n_seeds=50):
    """frequency_drift of x(t) on chaotic orbits: Henon-Heiles E = 1/6 (orbit C) and Lorenz, each start
    perturbed by 1e-8 (relative; the records decorrelate within a few hundred time units) for every
    seed, at three horizons each. Returns the runs with their system and horizon."""
    from chaos_textbook import HH_CHAOS, LORENZ0, _hh_sys, _hh_y0, _lorenz_sys

    rng = np.random.default_rng(2026)
    cases = (("henon-heiles", _hh_sys(hy), np.array(HH_CHAOS), 0.25, (2.5e3, 5e3, 1e4)),
             ("lorenz", _lorenz_sys(hy), np.array(LORENZ0, float), 0.02, (500.0, 1e3, 2e3)))
    out = []
    for name, sys, y0, dt, horizons in cases:
        ta = hy.taylor_adaptive(sys, y0, compact_mode=True)
        for T in horizons:
            for _ in range(n_seeds):
                y = y0 * (1 + 1e-8 * rng.normal(size=y0.size))
                if name == "henon-heiles":
                    y = np.array(_hh_y0(y[0], y[1], y[2], 1.0 / 6.0))  # back on the energy level
                out.append((name, T, frequency.frequency_drift(ta, y, T=T, dt=dt, component=0)))
    return out


def test_the_frequency_judge_calls_at_most_1_in_100_chaotic_orbits_regular(hy):
    """The audit of the judge's false-"regular" rate: 300 chaotic records (2 systems x 3 horizons x 50
    starts); the slope from splits of at least MIN_WINDOWS windows must say regular at most 3 times."""
    runs = _false_regular_runs(hy)
    verdicts = [frequency.judge_frequency([_run("double", d["slope"], d["slope_err"], d["D"][0])])[0]
                for _, _, d in runs]
    false = [(name, T, round(d["slope"], 2)) for (name, T, d), v in zip(runs, verdicts) if v == G]
    assert len(runs) == 300 and len(false) <= 3, false
    assert sum(math.isfinite(d["slope"]) for _, _, d in runs) >= 240  # the judge was exercised, not skipped
