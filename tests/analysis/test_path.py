"""The sleigh's path from samples of its reduced state (sleighsim.analysis.path) on motions whose paths are known,
and the path's shape on bounded, straight and periodic paths."""

import math

import numpy as np
import pytest

from sleighsim.analysis.path import path, shape

T = np.arange(0.0, 2000.0 + 0.25, 0.5)


def state(u, Om, du=0.0, dOm=0.0):
    """Samples (n, 4) of constant u and Omega (omega, delta unused) with their derivatives."""
    Y = np.zeros((T.size, 4))
    Y[:, 0], Y[:, 1] = u, Om
    dY = np.zeros_like(Y)
    dY[:, 0], dY[:, 1] = du, dOm
    return Y, dY, np.zeros_like(Y)


def test_a_steady_turn_is_a_circle_and_a_straight_run_a_line():
    """u = 1, Omega = 0.01: the runner's point circles at radius sqrt(u^2 + (b Omega)^2) / Omega about a fixed
    centre; u = 1, Omega = 0: a straight line x = t."""
    b, u, Om = 1.0, 1.0, 0.01
    theta, x, y = path(T, *state(u, Om), b)
    assert theta == pytest.approx(Om * T, abs=1e-11)  # summation over 4000 intervals
    exact_x = (u * np.sin(Om * T) + b * Om * np.cos(Om * T) - b * Om) / Om
    exact_y = (-u * np.cos(Om * T) + b * Om * np.sin(Om * T) + u) / Om
    assert np.max(np.hypot(x - exact_x, y - exact_y)) < 1e-9
    _, x, y = path(T, *state(1.0, 0.0), b)
    assert x == pytest.approx(T, abs=1e-12) and np.max(np.abs(y)) == 0.0


def test_a_turning_rate_that_varies_is_integrated_to_the_quadrature_order():
    """Omega = 0.3 sin(0.7 t): theta = 0.3 (1 - cos(0.7 t)) / 0.7, to far better than the samples' spacing
    would give by the trapezoid rule."""
    Y, dY, d2Y = state(1.0, 0.0)
    Y[:, 1], dY[:, 1], d2Y[:, 1] = 0.3 * np.sin(0.7 * T), 0.21 * np.cos(0.7 * T), -0.147 * np.sin(0.7 * T)
    theta, _, _ = path(T, Y, dY, d2Y, 1.0)
    exact = 0.3 * (1 - np.cos(0.7 * T)) / 0.7
    trapezoid = np.concatenate([[0.0], np.cumsum((Y[1:, 1] + Y[:-1, 1]) / 2 * 0.5)])
    assert np.max(np.abs(theta - exact)) < 1e-7 < 1e-4 < np.max(np.abs(trapezoid - exact))  # measured 1.6e-8


def test_the_shape_tells_a_bounded_path_a_straight_one_and_a_periodic_one():
    t = np.arange(0.0, 1e4, 1.0)
    rng = np.random.default_rng(0)
    wobble = 0.05 * rng.standard_normal(t.size)
    circle = shape(t, np.cos(t / 37.0) + np.cos(t / (37.0 * math.sqrt(2))) + wobble, np.sin(t / 37.0) + wobble)
    assert circle["growth"] < 1.2 and circle["recurrence"] > 0.01
    line = shape(t, t, 0 * t)
    assert line["growth"] == pytest.approx(2.0, rel=1e-3) and line["reach"] == pytest.approx(t[-1])
    ring = shape(t, np.cos(2 * math.pi * t / 100.0), np.sin(2 * math.pi * t / 100.0))
    assert ring["growth"] == pytest.approx(1.0) and ring["recurrence"] < 1e-9


def test_a_path_too_short_for_any_lag_has_no_recurrence():
    t = np.arange(0.0, 100.0, 1.0)
    assert math.isnan(shape(t, np.cos(t), np.sin(t))["recurrence"])
