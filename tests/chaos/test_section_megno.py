"""The return map's MEGNO (sleighsim.chaos.section_megno): the section's crossings, the map's MEGNO on
log-norm laws whose MEGNO is known, the judge on each branch, and the engine on orbits of known class
(a torus with shear, an isochronous one, a chaotic orbit). Its power and false rates on the audit set
are measured by the judge-power audit (sleighsim.chaos.power)."""

import math

import numpy as np
import pytest

from sleighsim.chaos import section_megno as sm
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED


def test_the_section_is_one_maximum_per_period_refined_between_samples():
    t = np.arange(0.0, 100.0, 0.1)
    x = np.cos(2 * np.pi * (t - 0.03) / 5.0) + 0.2 * np.cos(2 * np.pi * t / 0.7)  # a small fast ripple
    ts = sm.section_times(t, np.cos(2 * np.pi * (t - 0.03) / 5.0))
    assert ts.size == 19 and np.allclose(ts, 0.03 + 5.0 * np.arange(1, 20), atol=2e-3)  # t = 0.03: at the edge
    assert sm.section_times(t, x).size >= 19  # maxima above the mean only: the ripple's below-mean ones drop
    with pytest.raises(ValueError, match="increasing"):
        sm.section_times(t[::-1], x)


def _crossings(n):
    return np.arange(n + 1, dtype=float)  # return time 1


@pytest.mark.parametrize("law, want", [
    (lambda k: 0.5 * k, lambda N: 0.5 * N / 2),  # exponential growth, 0.5 per return: <Y> ~ lambda N / 2
    (lambda k: np.log1p(k), lambda N: 2.0),  # a torus with shear: l_k ~ ln k, <Y> -> 2
    (lambda k: np.sin(0.7 * k), lambda N: 0.0),  # isochronous: bounded l, <Y> -> 0
])
def test_the_maps_megno_on_known_laws(law, want):
    N = 4000
    k = _crossings(N)
    m = sm.section_megno(k, law(k), k)
    assert m["final"] == pytest.approx(want(N), abs=0.02 * max(1.0, want(N)) + 0.01)


def test_the_maps_megno_needs_enough_returns():
    with pytest.raises(ValueError, match="at least"):
        sm.section_megno(_crossings(5), np.zeros(6), _crossings(5))


@pytest.mark.parametrize("law, want", [(lambda k: 0.5 * k, CHAOTIC), (lambda k: np.log1p(k), REGULAR),
                                       (lambda k: 1.5 * np.log1p(k), UNDECIDED)])  # degree 1.5: <Y> -> 3
def test_the_judge_on_each_branch(law, want):
    k = _crossings(200)
    assert sm.judge_section_megno(sm.section_megno(k, law(k), k), 3.0)[0] == want


def test_the_judge_refuses_too_few_returns():
    m = {"n": np.arange(1, 5), "final": 2.0, "resid": 0.0, "slope": 0.0, "slope_err": 0.0}
    v, reason = sm.judge_section_megno(m, 3.0)
    assert v == UNDECIDED and "only 4 returns" in reason


def test_the_implied_rate_is_per_unit_time():
    k = _crossings(400)
    m = sm.section_megno(2.5 * k, 0.5 * k, 2.5 * k)  # 0.5 per return of 2.5 time units: 0.2 per time unit
    rate, err = sm.section_rate(m, 2.5 * k)
    assert rate == pytest.approx(0.2, rel=0.01) and err >= 0


def _orbit_verdict(build, y0, period, component, returns=60):
    hy = pytest.importorskip("heyoka")
    from sleighsim.engine import integrators

    ta, n = integrators.megno_integrator(build(hy))
    r = sm.log_norm_series(ta, n, y0, T=(returns + 2) * period, dt=period / 50)
    ts = sm.section_times(r["t"], r["X"][:, component])
    return sm.judge_section_megno(sm.section_megno(r["t"], r["log_norm"], ts), 3.0)[0]


def test_the_engine_on_orbits_of_known_class():
    """Henon-Heiles E = 1/12 (a torus), the quartic oscillators (a torus with shear), E = 1/6 orbit C
    (chaotic) and Lorenz (chaotic), 60 returns each to the maxima of x (z for Lorenz)."""
    from chaos_textbook import HH_CHAOS, HH_REG, LORENZ0, _hh_sys, _lorenz_sys, _oscillators

    assert _orbit_verdict(_hh_sys, HH_REG, 6.5, 0) == REGULAR
    assert _orbit_verdict(lambda hy: _oscillators(hy, True), [1.0, 0.5, 0.1, -0.2], 4.5, 0) == REGULAR
    assert _orbit_verdict(_hh_sys, HH_CHAOS, 6.8, 0) == CHAOTIC
    assert _orbit_verdict(_lorenz_sys, LORENZ0, 0.75, 2) == CHAOTIC
    assert math.isfinite(sm.section_rate({"slope": 0.1, "slope_err": 0.0}, [0.0, 1.0, 2.0])[0])
