"""The torus-stability rules (sleighsim.analysis.torus): event refinement on section data, the train test
on each branch, the identity on each branch, the family's laws; and the train test on orbits of known
class (sleighsim.analysis.torus_known: two uncoupled oscillators, the same seen through a three-reversal
observable, chaotic Henon-Heiles and Lorenz orbits through a fast rotor, a Henon-Heiles 3-torus). Its
power and false rates over 50 orbits per family: benchmarks/torus_power.py."""

import math

import numpy as np
import pytest

from sleighsim.analysis import torus, torus_known

RULE = dict(min_intervals=8, factor=10.0, max_intervals=4)


def _section(rng, P=500.0, n=4000):
    """Irregular section times (steps near 1.9) and rows (sin(2 pi t / P), cos, t / P)."""
    t = np.cumsum(1.9 + 0.05 * rng.standard_normal(n))
    return t, np.c_[np.sin(2 * np.pi * t / P), np.cos(2 * np.pi * t / P), t / P]


@pytest.mark.parametrize("direction, phase", [(-1, 0.5), (+1, 0.0)])
def test_crossings_refine_a_level_crossing_and_the_state_there(rng, direction, phase):
    """sin(2 pi t / P) crosses 0 downward at t = (k + 1/2) P and upward at k P: the refined times within
    1e-9 of the exact ones (the samples 1.9 apart), their error estimates positive and of that order at
    most, the third column interpolated to t / P there."""
    P = 500.0
    t, X = _section(rng, P)
    ev = torus.crossings(t, X, 0, 0.0, direction)
    exact = (np.round(ev["times"] / P - phase) + phase) * P
    assert ev["times"].size >= 10 and np.max(np.abs(ev["times"] - exact)) < 1e-9
    assert np.all(ev["time_err"] > 0) and np.max(ev["time_err"]) < 1e-8
    assert np.allclose(ev["points"][:, 2], ev["times"] / P, atol=1e-12)
    assert ev["point_err"].shape == (ev["times"].size, 3)


def test_crossings_drop_events_at_the_record_ends_and_refuse_a_bad_direction(rng):
    t, X = _section(rng)
    edge = torus.crossings(t[:5], X[:5] - X[2], 0, 0.0, -1)
    assert edge["times"].size == 0 and edge["points"].shape == (0, 3)
    with pytest.raises(ValueError, match="direction"):
        torus.crossings(t, X, 0, 0.0, 0)


def _train(rng, intervals, n, noise=1e-11):
    """n event times with the repeating intervals, plus noise, and their errors (the noise's size)."""
    d = np.resize(np.asarray(intervals, float), n - 1)
    return np.r_[0.0, np.cumsum(d)] + 1000.0 + noise * rng.standard_normal(n), np.full(n, noise)


def test_train_fit_recovers_the_period():
    P, R, c = torus.train_fit(100.0 + 7.0 * np.arange(12), 1)
    assert P == pytest.approx(7.0) and R < 1e-12 and c == pytest.approx(1 / math.sqrt(np.var(np.arange(12)) * 12))


@pytest.mark.parametrize("intervals, n, want, k, why", [
    ([2337.5], 8, torus.NOT_SHOWN, 0, "fewer than 8"),
    ([2337.5], 12, torus.PERIODIC, 1, "every interval"),
    ([2000.0, 2100.0, 2300.0], 12, torus.REPEATING, 3, "3 intervals repeating"),
    ([2000.0, 2100.0, 2200.0, 2300.0, 2400.0], 12, torus.NOT_SHOWN, 0, "no train of 1 .. 4"),  # k > max_intervals
])
def test_classify_on_each_branch(rng, intervals, n, want, k, why):
    t, e = _train(rng, intervals, n)
    c = torus.classify(t, e, **RULE)
    assert c["torus_class"] == want and c["train_intervals"] == k and why in c["class_reason"]
    if want != torus.NOT_SHOWN:
        assert c["period"] == pytest.approx(np.mean(intervals), abs=1e-9) and 0 < c["period_err"] < 1e-11


def test_classify_tries_only_the_k_whose_offsets_each_hold_three_events(rng):
    """Nine events of a 4-interval train: k = 4 would leave offsets with two events, so only 1 .. 3 are tried
    (and none fits)."""
    t, e = _train(rng, [2000.0, 2100.0, 2200.0, 2300.0], 9)
    c = torus.classify(t, e, min_intervals=8, factor=10.0, max_intervals=4)
    assert c["torus_class"] == torus.NOT_SHOWN and "no train of 1 .. 3 " in c["class_reason"]
    assert "R_3" in c["class_reason"] and "R_4" not in c["class_reason"]


def test_a_wandering_train_is_not_shown_to_be_a_torus(rng):
    """Intervals varying by 1e-6 of themselves (a chaotic train a million times more regular than the
    sticky Henon-Heiles ones) against a resolution of 1e-11: no k fits; its period is the k = 1 fit's."""
    t, e = _train(rng, 2337.5 * (1 + 1e-6 * rng.standard_normal(20)), 21)
    c = torus.classify(t, e, **RULE)
    assert c["torus_class"] == torus.NOT_SHOWN and "R_1" in c["class_reason"] and "R_4" in c["class_reason"]
    assert c["period"] == pytest.approx(2337.5, rel=1e-5) and c["period_err"] > 1e-5


@pytest.mark.parametrize("klass, dP, offset, want, why", [
    (torus.NOT_SHOWN, 0.0, 0.0, torus.UNDETERMINED, "not shown"),
    (torus.PERIODIC, 2e-13, 1e-10, torus.SAME, "both within"),
    (torus.PERIODIC, -26.3, 1e-10, torus.ANOTHER, "the period differs"),
    (torus.REPEATING, 2e-13, 2.7e-3, torus.ANOTHER, "the spike point differs"),
])
def test_identity_on_each_branch(klass, dP, offset, want, why):
    ident, reason = torus.identity(klass, dP, 1e-13, offset, 1e-10, 3.0)
    assert ident == want and why in reason


def test_family_law_from_independent_directions(rng):
    """Per direction y = s_k log10 a + b_k, s_k = -85 + 5 z_k (four directions): the law's slope is their
    mean, its error their spread over 2; a direction with one amplitude adds nothing; residual 0 on
    straight lines, the curvature's size on bent ones."""
    s = -85.0 + 5.0 * rng.standard_normal(4)
    x = np.tile(np.arange(-6.0, -2.0), 4)
    d = np.repeat(np.arange(4), 4)
    law = torus.family_law(np.r_[x, -6.0], np.r_[s[d] * x + d, 1.0], np.r_[d, 9])
    assert law["slope"] == pytest.approx(s.mean()) and law["slope_err"] == pytest.approx(s.std(ddof=1) / 2)
    assert law["K"] == 4 and law["residual"] < 1e-9 and set(law["per_direction"]) == {0, 1, 2, 3}
    bent = torus.family_law(x, s[d] * x + 2.0 * (x + 4.5) ** 2, d)
    assert 1.0 < bent["residual"] < 2.0
    one = torus.family_law([-6.0, -5.0], [1.0, 2.0], [0, 0])
    assert one["slope"] == pytest.approx(1.0) and math.isnan(one["slope_err"]) and one["K"] == 1


# ---------------------------------------------------------------- orbits of known class


@pytest.mark.parametrize("name", list(torus_known.FAMILIES))
def test_the_train_test_on_orbits_of_known_class(name):
    """Two orbits per family, 12 events each (the paper config's perturbed orbits have 11 or 12): the
    2-tori are tori with their own number of intervals, everything else is not shown to be one."""
    fam = torus_known.FAMILIES[name]
    for draw in range(2):
        d = torus_known.section(name, np.random.default_rng([52, draw]), 12)
        ev = torus.crossings(d["t"], d["X"], fam.column, fam.level, fam.direction)
        c = torus.classify(ev["times"][:12], ev["time_err"][:12], **RULE)
        assert ev["times"].size >= 12
        assert c["train_intervals"] == (fam.k if fam.torus else 0), c["class_reason"]
