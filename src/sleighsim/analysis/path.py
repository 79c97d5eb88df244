"""The sleigh's path in the plane from an orbit of its reduced state, and the path's shape (bounded? periodic?).

The path obeys theta' = Omega, x' = u cos theta - b Omega sin theta, y' = u sin theta + b Omega cos theta
(``model.equations.kinematics_rhs``), so it follows from samples of (u, Omega) and their time derivatives alone:
theta by the quintic Hermite rule of ``analysis.volume`` on Omega, then x and y by the same rule on the state
(u, Omega, theta), whose first and second derivatives the flow gives. The path starts at (0, 0) heading
theta = 0. Lengths in the model's unit (the runner distance b = 1 in the paper's form), times in its time unit.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.analysis.volume import cumulative, hermite_integrals


def path(t, Y, dY, d2Y, b: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(theta, x, y) at the samples ``t`` of an orbit ``Y`` (n, 4: u, Omega, omega, delta) with its first and
    second time derivatives ``dY``, ``d2Y``, for runner distance ``b``."""
    t = np.asarray(t, float)
    theta = cumulative(hermite_integrals(t, Y[:, 1:2], dY[:, 1:2], d2Y[:, 1:2], lambda s: s[..., 0],
                                         coarse=False)[0])
    Z = np.c_[Y[:, 0], Y[:, 1], theta]
    dZ = np.c_[dY[:, 0], dY[:, 1], Y[:, 1]]
    d2Z = np.c_[d2Y[:, 0], d2Y[:, 1], dY[:, 1]]

    def velocity(s):
        """(x', y') of the states s (u, Omega, theta), on a last axis."""
        u, Om, th = s[..., 0], s[..., 1], s[..., 2]
        c, sn = np.cos(th), np.sin(th)
        return np.stack([u * c - b * Om * sn, u * sn + b * Om * c], axis=-1)

    xy = cumulative(hermite_integrals(t, Z, dZ, d2Z, velocity, coarse=False)[0])
    return theta, xy[:, 0], xy[:, 1]


def shape(t, x, y, min_lag: float = 50.0) -> dict:
    """The path's shape: growth (the farthest distance from the start at the end over that at half the path:
    about 1 bounded, 1.41 diffusive, 2 straight), reach (that farthest distance), size (RMS distance from the
    path's centre, on at most about 5000 points) and recurrence (the smallest RMS distance between the path and
    its copy shifted by a lag from ``min_lag`` to a third of the path, over its size: 0 for a periodic path; NaN
    when the path is shorter than 3 min_lag)."""
    x, y, t = np.asarray(x, float), np.asarray(y, float), np.asarray(t, float)
    r = np.hypot(x - x[0], y - y[0])
    reach = np.maximum.accumulate(r)
    growth = float(reach[-1] / reach[reach.size // 2])
    step = max(1, x.size // 5000)
    X = np.c_[x[::step], y[::step]]
    size = float(np.sqrt(np.mean(np.sum((X - X.mean(0)) ** 2, axis=1))))
    lags = range(max(1, int(min_lag / (t[step] - t[0]))), X.shape[0] // 3)
    recurrence = min((float(np.sqrt(np.mean(np.sum((X[L:] - X[:-L]) ** 2, axis=1)))) for L in lags),
                     default=math.nan) / size
    return {"growth": growth, "reach": float(reach[-1]), "size": size, "recurrence": recurrence}
