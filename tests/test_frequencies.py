"""Frequency analysis (sleighsim.frequencies), its engine and judge (indicators.frequency_drift,
judge_frequency, frequency_log_ratio) and the chaos verdict's use of it, on synthetic signals,
on the textbook orbits of test_indicators and on every branch of the judge.

Measured with splits (2, 4, 8, 16), double / long double (heyoka, compact mode), x(t) sampled
every 0.25 (Lorenz 0.02): Henon-Heiles E = 1/12 slope -3.2 (T = 1e4) and -4.0 (T = 2e4), quartic
oscillators at the refinement's precision (-inf); Henon-Heiles E = 1/6 slope 0.0 to 0.25, Lorenz
(T = 4e3) -0.2 to -0.6, with drift ratios double / long double of 1.0 to 1.3. The sleigh's main
state (eps = 0.1, label 0.1127, T = 2e5, the paper config's chaos_verdict): slope about 0 in both
precisions, drift ratio 300 (ln 5.70 +- 0.38) against the rounding ratio 2048; rotor start a:
slope -4.43 +- 0.35 in double.
"""

import math

import numpy as np
import pytest

from sleighsim import frequencies as fq
from sleighsim import indicators as ind
from sleighsim.indicators import REGULAR, UNDECIDED

G, U = REGULAR, UNDECIDED
ROUNDING = 2.220446049250313e-16 / 1.0842021724855044e-19  # 2048


def _torus(T, dt):
    """Three lines at 0.1, 0.1 sqrt(2) and their sum: a 2-torus."""
    f1, f2 = 0.1, 0.1 * math.sqrt(2)
    t = np.arange(0.0, T, dt)
    return np.cos(2 * math.pi * f1 * t) + 0.4 * np.cos(2 * math.pi * f2 * t + 0.3) + 0.1 * np.cos(2 * math.pi * (f1 + f2) * t)


def test_leading_frequency_recovers_a_quasi_periodic_line_and_follows_the_band():
    x = _torus(4000.0, 0.25)
    assert fq.leading_frequency(x, 0.25) == pytest.approx(0.1, rel=1e-9)
    assert fq.leading_frequency(x, 0.25, band=(0.12, 0.2)) == pytest.approx(0.1 * math.sqrt(2), rel=1e-8)
    # a band that holds only the flank of a line: no local maximum inside, no frequency
    assert math.isnan(fq.leading_frequency(x, 0.25, band=(0.101, 0.12)))
    with pytest.raises(ValueError, match="no DFT bin"):
        fq.leading_frequency(x, 0.25, band=(0.1001, 0.10011))
    # a line below the first bin is not resolved from zero frequency
    t = np.arange(4000) * 0.25
    assert math.isnan(fq.leading_frequency(np.cos(2 * math.pi * 0.3 / 1000.0 * t), 0.25))
    with pytest.raises(ValueError, match="non-finite"):
        fq.leading_frequency(np.r_[x[:100], np.nan], 0.25)
    with pytest.raises(ValueError, match="dt"):
        fq.leading_frequency(x, 0.0)
    for bad in (0, 2.5):
        with pytest.raises(ValueError, match="n_windows"):
            fq.window_frequencies(x, 0.25, bad)


def test_refined_frequency_reaches_the_stated_precision():
    f = 0.1 * math.sqrt(2)
    for T in (2000.0, 32000.0):
        t = np.arange(0.0, T, 0.25)
        assert abs(fq.leading_frequency(np.cos(2 * math.pi * f * t + 0.3), 0.25) / f - 1) < fq.PRECISION


def test_drift_converges_on_a_torus_and_not_on_a_wandering_frequency():
    rng = np.random.default_rng(3)
    torus = fq.drift(_torus(16000.0, 0.25), 0.25)
    assert list(torus["splits"]) == [2, 4, 8, 16] and torus["slope"] == -math.inf
    assert torus["f_ref"] == pytest.approx(0.1, rel=1e-6)
    # a phase diffusing like a random walk: the window frequency scatters like W^-1/2
    dt, T = 0.25, 16000.0
    n = int(T / dt)
    phase = 2 * math.pi * 0.1 * dt * np.arange(n) + np.cumsum(rng.normal(scale=0.02, size=n))
    wander = fq.drift(np.cos(phase), dt)
    assert wander["slope"] + 3 * wander["slope_err"] > -1.0
    assert -1.2 < wander["slope"] < 0.2
    # windows shorter than min_cycles periods are left out
    few = fq.drift(_torus(1000.0, 0.25), 0.25, min_cycles=15.0)
    assert list(few["splits"]) == [2, 4] and few["W"][-1] == pytest.approx(250.0)
    none = fq.drift(_torus(1000.0, 0.25), 0.25, min_cycles=60.0)
    assert none["splits"].size == 0 and math.isnan(none["slope"]) and math.isnan(none["f"])
    with pytest.raises(ValueError, match="splits"):
        fq.drift(_torus(1000.0, 0.25), 0.25, splits=(1, 4))
    with pytest.raises(ValueError, match="splits"):
        fq.drift(_torus(1000.0, 0.25), 0.25, splits=())
    with pytest.raises(ValueError, match="min_cycles"):
        fq.drift(_torus(1000.0, 0.25), 0.25, min_cycles=0.0)


def test_drift_leaves_out_a_split_with_a_window_without_the_line():
    # the line at 0.1 stops half way (0.3 from then on, outside the band around f_ref = 0.1): the
    # split into 2 has a window without it; the finer splits' first halves hold it, their second
    # halves not, so only splits whose every window has the line remain
    t = np.arange(0.0, 8000.0, 0.25)
    x = np.where(t < 4000.0, np.cos(2 * math.pi * 0.1 * t), 0.0) + 0.01 * np.cos(2 * math.pi * 0.3 * t)
    d = fq.drift(x, 0.25, splits=(2, 4, 8, 16))
    assert d["splits"].size == 0 and math.isnan(d["slope"])
    # no line anywhere (white noise has no stable leading line, but f_ref exists): spreads are large
    noise = np.random.default_rng(0).normal(size=t.size)
    dn = fq.drift(noise, 0.25, splits=(2, 4, 8, 16), min_cycles=1.0)
    assert np.all(dn["D"] > 1e-3)


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
    v, reason = ind.judge_frequency(runs)
    assert v == want and says in reason, reason
    if want == U:
        assert ("integration error" in reason) == ("exact dynamics" in says)


def test_judge_frequency_rejects_bad_input():
    with pytest.raises(ValueError, match="slope_err"):
        ind.judge_frequency([_run("double", -3.0, -0.1)])
    with pytest.raises(ValueError, match="log_ratio_err"):
        ind.judge_frequency([_run("double", 0.0), _run("long double", 0.0, log_ratio=1.0, log_ratio_err=-1.0)])
    with pytest.raises(ValueError, match="sigma"):
        ind.judge_frequency([_run("double", -3.0)], sigma=-1.0)
    with pytest.raises(ValueError, match="empty"):
        ind.judge_frequency([])


def test_frequency_log_ratio_uses_the_shared_splits_and_a_correlated_error():
    a = {"splits": np.array([2, 4, 8]), "D": np.array([1e-2, 1e-2, 1e-2])}
    b = {"splits": np.array([2, 4]), "D": np.array([1e-4, 1e-3])}
    lr, err = ind.frequency_log_ratio(a, b)
    assert lr == pytest.approx((1 * math.log(100) + 3 * math.log(10)) / 4)
    assert err == pytest.approx((1 + math.sqrt(3)) / 4)  # fully correlated splits: no averaging down
    assert all(map(math.isnan, ind.frequency_log_ratio(a, {"splits": np.array([16]), "D": np.array([1.0])})))
    # a spread below the refinement's precision counts as that precision
    zero = ind.frequency_log_ratio(a, {"splits": np.array([2]), "D": np.array([0.0])})
    assert zero[0] == pytest.approx(math.log(1e-2 / fq.PRECISION)) and zero[1] == pytest.approx(1.0)


# ----------------------------------------------------------------------------- textbook orbits

@pytest.fixture(scope="module")
def textbook():
    """Double and long-double frequency_drift of x(t) on the textbook orbits."""
    hy = pytest.importorskip("heyoka")
    from test_indicators import (
        HH_CHAOS,
        HH_REG,
        LORENZ0,
        OSC0,
        _hh_sys,
        _lorenz_sys,
        _oscillators,
    )

    cases = {"hh_chaos": (_hh_sys(hy), HH_CHAOS, 0.25, 1e4), "hh_regular": (_hh_sys(hy), HH_REG, 0.25, 1e4),
             "quartic": (_oscillators(hy, True), OSC0, 0.25, 1e4), "lorenz": (_lorenz_sys(hy), LORENZ0, 0.02, 4e3)}
    out = {}
    for name, (sys, y0, dt, T) in cases.items():
        runs = []
        for fp in (float, np.longdouble):
            ta = hy.taylor_adaptive(sys, np.array(y0, dtype=fp), fp_type=fp, compact_mode=True)
            runs.append(ind.frequency_drift(ta, np.array(y0, dtype=fp), T=T, dt=dt, component=0))
        out[name] = runs
    return out


def _judge(runs):
    d, ld = runs
    lr, lr_err = ind.frequency_log_ratio(d, ld)
    return ind.judge_frequency([_run("double", d["slope"], d["slope_err"], d["D"][0]),
                                _run("long double", ld["slope"], ld["slope_err"], ld["D"][0], log_ratio=lr,
                                     log_ratio_err=lr_err, rounding_ratio=ROUNDING)])


@pytest.mark.parametrize("name, want", [("hh_regular", G), ("quartic", G), ("hh_chaos", U), ("lorenz", U)])
def test_frequency_indicator_on_textbook_orbits(textbook, name, want):
    d, ld = textbook[name]
    v, reason = _judge(textbook[name])
    assert v == want, reason
    if want == G:
        assert d["slope"] < -2.5 and ind.judge_frequency([_run("double", d["slope"], d["slope_err"])])[0] == G
    else:  # chaos: the frequency wanders by as much at the smaller rounding, and does not converge
        assert d["slope"] > -1.0 and ld["slope"] > -1.0
        assert abs(ind.frequency_log_ratio(d, ld)[0]) < 1.0


def test_frequency_drift_checks_its_arguments(textbook):
    import heyoka as hy
    from test_indicators import OSC0, _oscillators

    ta = hy.taylor_adaptive(_oscillators(hy, True), OSC0, compact_mode=True)
    with pytest.raises(ValueError, match="component"):
        ind.frequency_drift(ta, OSC0, T=100.0, dt=0.25, component=4)
    with pytest.raises(ValueError, match="too few"):
        ind.frequency_drift(ta, OSC0, T=10.0, dt=0.25, component=0)
    out = ind.frequency_drift(ta, OSC0, T=200.0, dt=0.25, component=1, splits=(2, 4), min_cycles=4.0)
    assert out["T"] == 200.0 and out["f_ref"] == pytest.approx(math.sqrt(2) / (2 * math.pi), rel=0.05)


# ----------------------------------------------------------------------------- the chaos verdict's use

# (slope, usable splits, D) of the double, long-double and quad runs; None: that run must not be made
_RUNS = {
    "converged in double": ([(-3.5, 3, 1e-9), None, None], G),
    "converged in long double": ([(0.0, 3, 1e-2), (-3.5, 3, 1e-9), None], G),
    # the main state: the long-double drift is 300 times smaller, then quad converges
    "converged in quad": ([(0.0, 3, 1e-2), (0.05, 3, 4e-5), (-6.5, 2, 9e-8)], G),
    "converged in none": ([(0.0, 3, 1e-2), (0.05, 3, 4e-5), (0.1, 2, 4e-5)], U),
    "too few windows in double": ([(math.nan, 1, 1e-2), None, None], U),
    "no window at all": ([(math.nan, 0, 1e-2), None, None], U),
}


@pytest.mark.parametrize("case", list(_RUNS))
@pytest.mark.parametrize("quad_T", [0.0, 1e5])
def test_frequency_indicator_runs_each_precision_only_when_needed(monkeypatch, case, quad_T):
    from sleighsim.params import Params
    from sleighsim.scenes import verdict

    specs, want = _RUNS[case]
    names = ("double", "long double", "quad")

    def run(params, y, cfg, precision="double"):
        calls.append(precision)
        slope, n, D = specs[names.index(precision)]
        splits = np.array([2, 4, 8][:n])
        return dict(splits=splits, D=np.full(n, D), W=2e5 / splits, D_log_err=1 / np.sqrt(2 * (splits - 1.0)),
                    slope=slope, slope_err=0.55 if n > 2 else 1.18, T=2e5, f=4e-4)

    calls = []
    monkeypatch.setattr(verdict, "frequency_run", run)
    cfg = dict(tol=2.220446049250313e-16, tol_long_double=1.0842021724855044e-19,
               frequency={"quad_T": quad_T, "tol_quad": 1.925929944387235853e-34})
    out = verdict.frequency_indicator(Params.paper(eps=0.1), [0.0, 0.1, 1.0, 0.0], cfg, 3.0)
    expected = [p for p, spec in zip(names, specs) if spec is not None and (p != "quad" or quad_T > 0)]
    assert calls == expected and list(out["runs"]) == expected
    assert out["verdict"][0] == (want if "quad" in expected or case != "converged in quad" else U), out["verdict"][1]
    not_made = "quad run not made" in out["verdict"][1]
    assert not_made == (quad_T == 0 and "long double" in expected and out["verdict"][0] == U
                        and out["runs"]["long double"]["splits"].size >= 2)
    last = out["runs"][expected[-1]]
    if last["D"].size:
        assert out["value"] == pytest.approx(last["D"][0] / last["W"][0])
        assert out["error"] == pytest.approx(out["value"] / math.sqrt(2))
    else:
        assert math.isnan(out["value"]) and math.isnan(out["error"])
    table = verdict.frequency_table([out], [2, 4, 8, 16])
    made = np.isfinite(table["slope"][0]) | np.isinf(table["slope"][0])
    assert [p for p, m in zip(names, made) if m] == [p for p in expected if not math.isnan(specs[names.index(p)][0])]


def test_the_sleighs_flow_runs_in_quad_precision():
    pytest.importorskip("heyoka")
    from sleighsim import integrators
    from sleighsim.params import Params
    from sleighsim.scenes import verdict

    cfg = dict(tol=2.220446049250313e-16, tol_long_double=1.0842021724855044e-19,
               frequency={"T": 200.0, "quad_T": 200.0, "dt": 0.5, "component": "u", "splits": [2, 4],
                          "min_cycles": 4.0, "tol_quad": 1.925929944387235853e-34})
    y = np.array([0.05, 0.02, 0.8, 0.4])
    runs = {p: verdict.frequency_run(Params.paper(eps=0.1), y, cfg, p) for p in ("double", "long double", "quad")}
    flow, _ = integrators.flow(False, 1.925929944387235853e-34, quad=True)
    assert "real128" in str(flow.state.dtype)
    # the same orbit (end states agree to 1e-13 here): window frequencies agree to the refinement's
    # precision, which for windows of only 100 (13 periods, bins of 0.01) is about 1e-9 relative
    for p in ("long double", "quad"):
        np.testing.assert_allclose(runs[p]["frequencies"][0], runs["double"]["frequencies"][0], rtol=5e-9)
    with pytest.raises(ValueError, match="exclude"):
        integrators.flow(False, 1e-20, long_double=True, quad=True)
