"""The mean of an observable over whole spike cycles (sleighsim.analysis.volume) on observables whose integrals
are known: Hermite quadrature between samples of a fast rotation that the trapezoid rule aliases, the quoted
quadrature error above the true one, a periodic part that integrates away over whole cycles only, and the
windows' standard error seeing a drift."""

import math

import numpy as np
import pytest

from sleighsim.analysis.volume import cycle_mean, hermite_integrals

P, DT = 100.0, 0.5
T = np.arange(0.0, 4000.0 + DT / 2, DT)
SPIKES = np.arange(30.0, 4000.0, P)  # 40 spikes, 39 whole cycles, none at the ends of the orbit


def rotor(w=3.3, amp=0.5, slow=0.3):
    """An angle turning at w (1.65 rad per sample) with a modulation amp sin(slow t): its samples, first and
    second derivatives, each (n, 1)."""
    d = w * T + amp * np.sin(slow * T)
    d1 = w + amp * slow * np.cos(slow * T)
    d2 = -amp * slow**2 * np.sin(slow * T)
    return d[:, None], d1[:, None], d2[:, None]


def test_hermite_quadrature_resolves_a_rotation_the_trapezoid_rule_aliases():
    """cos(2 delta) of that angle over [0, 4000] (scipy's adaptive quadrature as the reference): the quintic rule
    on samples every 0.5 gets it to 1e-9, the trapezoid rule on the same samples misses by
    far more, and the quoted error (quintic against cubic) bounds the quintic's."""
    from scipy.integrate import quad

    Y, dY, d2Y = rotor()
    ref = quad(lambda t: math.cos(2 * (3.3 * t + 0.5 * math.sin(0.3 * t))), 0.0, 4000.0, limit=20000,
               epsabs=1e-11)[0]
    fine, coarse = hermite_integrals(T, Y, dY, d2Y, lambda y: np.cos(2 * y[..., 0]))
    trap = np.trapezoid(np.cos(2 * Y[:, 0]), T)
    assert abs(fine.sum() - ref) < 1e-9 and abs(trap - ref) > 0.1  # measured: 4e-11 and 0.16
    assert abs(fine.sum() - ref) <= abs(fine.sum() - coarse.sum())
    alone, none = hermite_integrals(T, Y, dY, d2Y, lambda y: np.cos(2 * y[..., 0]), coarse=False)
    assert none is None and np.array_equal(alone, fine)
    pair, _ = hermite_integrals(T, Y, dY, d2Y, lambda y: np.stack([np.cos(2 * y[..., 0]), np.sin(y[..., 0])], -1))
    assert pair.shape == (T.size - 1, 2) and np.array_equal(pair[:, 0], fine)


def test_a_periodic_part_integrates_away_over_whole_cycles_only():
    x = 1e-6 + 0.1 * np.sin(2 * math.pi * T / P)  # mean 1e-6 over a cycle
    integrals = (x[:-1] + x[1:]) / 2 * DT  # the trapezoid rule, exact enough for this slow observable
    out = cycle_mean(T, integrals, SPIKES, 8)
    assert out["mean"] == pytest.approx(1e-6, abs=1e-9) and out["cycles"] == 39
    assert out["stderr"] < 1e-9 and np.allclose(out["window_mean"], 1e-6, atol=1e-9)
    assert math.isnan(out["quadrature"])  # no coarser rule given
    part = T <= 3975.0  # 39.75 periods: not whole cycles
    assert abs(np.trapezoid(x[part], T[part]) / 3975.0 - 1e-6) > 1e-5


def test_the_quadrature_error_is_the_difference_of_the_two_rules_means():
    fine = np.full(T.size - 1, 2.0 * DT)
    out = cycle_mean(T, fine, SPIKES, 4, coarse=fine * (1 + 1e-6))
    assert out["mean"] == pytest.approx(2.0) and out["quadrature"] == pytest.approx(2e-6)


def test_the_windows_standard_error_sees_a_drift():
    x = 1e-3 * T / T[-1]
    out = cycle_mean(T, (x[:-1] + x[1:]) / 2 * DT, SPIKES, 4)
    assert out["stderr"] == pytest.approx(np.std(out["window_mean"], ddof=1) / 2) and out["stderr"] > 1e-4


def test_too_few_spikes_give_nan_and_bad_input_is_refused():
    ones = np.ones(T.size - 1)
    out = cycle_mean(T, ones, SPIKES[:1], 4)
    assert math.isnan(out["mean"]) and math.isnan(out["stderr"]) and out["cycles"] == 0
    with pytest.raises(ValueError, match="integrals"):
        cycle_mean(T, np.ones(T.size), SPIKES, 4)
    with pytest.raises(ValueError, match="integer >= 2"):
        cycle_mean(T, ones, SPIKES, 1)
    with pytest.raises(ValueError, match="within the samples"):
        cycle_mean(T, ones, [10.0, 5000.0], 4)
    with pytest.raises(ValueError, match="one n"):
        hermite_integrals(T, np.ones((T.size, 2)), np.ones((T.size, 2)), np.ones((T.size - 1, 2)), np.sum)
