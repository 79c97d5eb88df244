"""The rotor-free sleigh (eps = 0): its vector field and closed-form solution, an exact oracle."""

from __future__ import annotations

import math

import numpy as np


def rhs(y, b, K2) -> np.ndarray:
    """y = (u, Omega): (b Omega^2, -u Omega / (b K2))."""
    y = np.asarray(y, dtype=float)
    u, Om = y[..., 0], y[..., 1]
    return np.stack([b * Om**2, -u * Om / (b * K2)], axis=-1)


def closed_form(t, u0, Omega0, b, K2):
    """Exact solution from (u0, Omega0) at t = 0.

    u = V tanh(s), Omega = sign(Omega0) V sech(s) / (K b), s = s0 + V t / (b K2),
    V^2 = u0^2 + K2 b^2 Omega0^2, tanh(s0) = u0 / V; heading
    theta - theta0 = sign(Omega0) K (gd(s) - gd(s0)), gd the Gudermannian.
    Returns (u, Omega, theta - theta0) as arrays over t.
    """
    t = np.asarray(t, dtype=float)
    K = math.sqrt(K2)
    V = math.sqrt(u0**2 + K2 * b**2 * Omega0**2)
    if V == 0 or Omega0 == 0:
        return np.full_like(t, u0), np.zeros_like(t), np.zeros_like(t)
    sgn = math.copysign(1.0, Omega0)
    s0 = math.atanh(u0 / V)
    s = s0 + V * t / (b * K2)

    def gd(z):
        return 2.0 * np.arctan(np.tanh(z / 2.0))

    return V * np.tanh(s), sgn * V / (K * b * np.cosh(s)), sgn * K * (gd(s) - gd(s0))
