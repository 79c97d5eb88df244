"""The torus-stability rule (sleighsim.analysis.torus): spike refinement, the spike-section curve and its
floor, and the classification on each branch, on synthetic data and on systems whose tori are known:
two uncoupled Duffing oscillators (integrable: every perturbation gives a neighbouring torus), and a
Stuart-Landau oscillator beside a linear one (the cycle r = 1 times a rotation is a torus that attracts
for lam > 0, so a perturbed orbit comes back, and repels for lam < 0, so it leaves)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from sleighsim.analysis import torus

RULE = dict(min_spikes=5, leave=0.1, change=2.0, same=3.0, sigma=3.0, period_floor=1e-9)
W2 = math.sqrt(2.0)


def test_spike_peaks_find_the_envelope_peak_and_the_state_there(rng):
    """A Gaussian envelope (width 25) sampled once per 'fast turn' (irregular steps near 1.9), beside a
    linear coordinate: the fitted peak lies within 1e-3 of the true one (far closer than the nearest
    sample) and the coordinate is interpolated to it; a spike whose window runs past the record's
    start is dropped."""
    t = np.cumsum(1.9 + 0.05 * rng.standard_normal(3000))
    peaks = np.array([500.3, 2400.7, 4100.1])
    X = np.c_[0.01 * t, sum(np.exp(-((t - p) / 25.0) ** 2) for p in peaks)]
    times, points = torus.spike_peaks(t, X, peaks + 20.0, 50.0)
    assert np.max(np.abs(times - peaks)) < 1e-3
    assert np.max(np.abs(times - peaks)) < 0.01 * np.max(np.abs(t[np.searchsorted(t, peaks)] - peaks))
    assert np.allclose(points[:, 0], 0.01 * times, rtol=0, atol=1e-9) and np.allclose(points[:, 1], 1.0, atol=1e-5)
    edge = torus.spike_peaks(t, np.c_[t, np.exp(-((t - t[1]) / 5.0) ** 2)], [t[1]], 50.0)
    assert edge[0].size == 0 and edge[1].shape == (0, 2)


def test_section_curve_recovers_a_fourier_curve_and_its_thickness(rng):
    """Points on x(phi) = (cos phi, 0.3 sin 2 phi, 1 + 0.1 cos 3 phi) plus noise of size s: the fitted
    curve's floor is of order s (leave-one-out), and points of the curve itself lie within a few s."""
    phi = rng.uniform(0, 2 * np.pi, 60)
    exact = np.c_[np.cos(phi), 0.3 * np.sin(2 * phi), 1 + 0.1 * np.cos(3 * phi)]
    s = 1e-6
    curve = torus.section_curve(phi, exact + s * rng.standard_normal(exact.shape), 4)
    assert curve["order"] == 4 and 0.5 * s < curve["floor"] < 5 * s
    other = rng.uniform(0, 2 * np.pi, 20)
    on = np.c_[np.cos(other), 0.3 * np.sin(2 * other), 1 + 0.1 * np.cos(3 * other)]
    assert np.max(torus.curve_distance(curve, other, on)) < 5 * s
    assert np.min(torus.curve_distance(curve, other, on + [1e-3, 0, 0])) > 0.9e-3
    with pytest.raises(ValueError, match="at least 3"):
        torus.section_curve(phi[:2], exact[:2], 4)


def test_section_curve_on_a_short_arc_is_the_points_mean(rng):
    """Points whose phases cover 0.2 rad (a near-resonant torus): no harmonic is resolved, order 0,
    the curve is their mean and the floor their scatter."""
    phi = 1.0 + 0.2 * rng.uniform(size=40)
    pts = np.array([0.3, -0.2, 3.1]) + 1e-7 * rng.standard_normal((40, 3))
    curve = torus.section_curve(phi, pts, 10)
    assert curve["order"] == 0 and 1e-7 < curve["floor"] < 5e-7
    assert torus.curve_distance(curve, [4.0], [[0.3, -0.2, 3.1 + 1e-3]])[0] == pytest.approx(1e-3, rel=1e-3)


def test_mean_interval_and_quarters():
    assert torus.mean_interval([0.0, 10.0, 21.0, 30.0]) == pytest.approx((10.0, 1.0 / math.sqrt(3)))
    assert torus.late_interval([0.0, 5.0, 10.0, 20.0, 30.0, 40.0]) == pytest.approx((10.0, 0.0))
    assert math.isnan(torus.mean_interval([0.0, 10.0])[1])
    assert torus.quarters([5.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 9.0]) == (3.0, 5.0)


@pytest.mark.parametrize("D, n, dT, err, want, why", [
    (np.full(20, 1e-3), 3, 0.0, 1.0, "leaves", "fewer than"),
    (np.r_[np.full(10, 1e-3), np.full(10, 0.2)], 20, 0.0, 1.0, "leaves", "D late >="),
    (np.geomspace(1e-6, 1e-4, 20), 20, 0.0, 1.0, "leaves", "grew"),
    (np.geomspace(1e-4, 1e-6, 20), 20, 0.5, 1.0, "same torus", "D decayed, same period"),
    (np.geomspace(1e-4, 1e-6, 20), 20, 50.0, 1.0, "neighbouring torus", "period differs"),
    (np.geomspace(3e-8, 5e-9, 20), 20, 0.5, 1.0, "same torus", "on the reference curve"),  # decay below 3 floors
    (np.full(20, 2e-8), 20, 0.5, 1.0, "same torus", "on the reference curve, same period"),
    (np.full(20, 2e-8), 20, 8.0, 1.0, "neighbouring torus", "period differs"),
    (np.full(20, 2e-8), 20, 1e-10, 0.0, "same torus", "same period"),  # strictly periodic: the period floor
    (np.full(20, 2e-8), 20, 1e-8, 0.0, "neighbouring torus", "period differs"),
    (np.full(20, 1e-3), 20, 0.0, 1.0, "neighbouring torus", "neither grows nor decays"),
])
def test_classify_on_each_branch(D, n, dT, err, want, why):
    """Each branch of the rule (floor 1e-8: the on-curve branch needs D late <= 3e-8)."""
    klass, reason = torus.classify(D, n, dT, err, 1e-8, **RULE)
    assert klass == want and why in reason


# ---------------------------------------------------------------- systems with known tori


def _duffing(t, y):
    q1, p1, q2, p2 = y
    return [p1, -q1 - q1**3, p2, -2.0 * q2 - q2**3]


def _landau(lam, c=0.5):
    def f(t, y):
        x, v, q2, p2 = y
        r2 = x * x + v * v
        nu = 1.0 + c * (r2 - 1.0)
        return [lam * x * (1 - r2) - nu * v, lam * v * (1 - r2) + nu * x, p2, -2.0 * q2]
    return f


def _spike_section(f, y0, T, fast_omega):
    """Spikes where the first oscillator's momentum-like coordinate y[1] falls through 0 with y[0] > 0
    (DOP853, rtol 1e-12); phase: the second oscillator's angle; point: (y[0], y[2], y[3])."""
    def event(t, y):
        return y[1]
    event.direction = -1.0 if f is _duffing else 1.0
    sol = solve_ivp(f, (0.0, T), y0, method="DOP853", rtol=1e-12, atol=1e-12, events=event)
    t, Y = sol.t_events[0], sol.y_events[0]
    keep = Y[:, 0] > 0
    t, Y = t[keep], Y[keep]
    return t, np.mod(np.arctan2(-Y[:, 3] / fast_omega, Y[:, 2]), 2 * np.pi), Y[:, [0, 2, 3]]


def _judge(f, y_ref, y_pert, T, fast_omega, T_ref=None):
    t0, ph0, x0 = _spike_section(f, y_ref, T_ref or T, fast_omega)
    curve = torus.section_curve(ph0, x0, 16)
    t, ph, x = _spike_section(f, y_pert, T, fast_omega)
    (m0, e0), (m, e) = torus.mean_interval(t0), torus.late_interval(t)
    D = torus.curve_distance(curve, ph, x)
    return torus.classify(D, t.size, m - m0, math.hypot(e, e0), curve["floor"], **RULE)


def _duffing_level(q1, H):
    """(q1, 0, q2, 0) with q2 > 0 from the total energy H = sum q'^2 / 2 + w^2 q^2 / 2 + q^4 / 4."""
    h2 = H - (q1**2 / 2 + q1**4 / 4)
    return [q1, 0.0, math.sqrt(-2.0 + math.sqrt(4.0 + 4.0 * h2)), 0.0]


@pytest.mark.parametrize("a", [1e-6, 1e-4, 1e-3])
def test_integrable_tori_are_neighbours(a):
    """Duffing pair, energy moved between the oscillators at fixed total energy: a neighbouring torus
    (measurably different period, offset that does not decay) at every size over 40 cycles."""
    y_ref = _duffing_level(1.0, 1.5)
    klass, why = _judge(_duffing, y_ref, _duffing_level(1.0 + a, 1.5), 200.0, W2, T_ref=400.0)
    assert klass == "neighbouring torus", why


def test_the_reference_against_itself_is_the_same_torus():
    """The rule's control: the reference orbit over half its horizon, judged against its own curve."""
    y_ref = _duffing_level(1.0, 1.5)
    klass, why = _judge(_duffing, y_ref, y_ref, 200.0, W2, T_ref=400.0)
    assert klass == "same torus", why


@pytest.mark.parametrize("a", [1e-6, 1e-3])
def test_neutral_cycles_are_neighbours(a):
    """Stuart-Landau at lam = 0 (every circle r = const is invariant, its frequency 1 + 0.5 (r^2 - 1)):
    the orbit started at r = 1 + a keeps its offset a and its shorter period."""
    klass, why = _judge(_landau(0.0), [1.0, 0.0, 0.7, 0.0], [1.0 + a, 0.0, 0.7, 0.0], 250.0, W2)
    assert klass == "neighbouring torus" and "neither grows nor decays" in why, why


@pytest.mark.parametrize("a", [1e-6, 1e-3])
def test_an_attracting_torus_is_found_again(a):
    """Stuart-Landau at lam = 0.05 (the cycle attracts at rate 2 lam): the perturbed orbit is back."""
    y = [1.0, 0.0, 0.7, 0.0]
    klass, why = _judge(_landau(0.05), y, [1.0 + a, 0.0, 0.7, 0.0], 250.0, W2)
    assert klass == "same torus", why


@pytest.mark.parametrize("a", [1e-6, 1e-3])
def test_a_repelling_torus_is_left(a):
    """Stuart-Landau at lam = -0.05 (the cycle repels at rate 0.1): the orbit started inside spirals away;
    over 150 (24 cycles) the reference's own integration error (1e-12) grows only to about 3e-6."""
    y = [1.0, 0.0, 0.7, 0.0]
    klass, why = _judge(_landau(-0.05), y, [1.0 - a, 0.0, 0.7, 0.0], 150.0, W2)
    assert klass == "leaves", why
