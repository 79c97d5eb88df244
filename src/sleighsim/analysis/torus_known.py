"""Orbits of known class for the train test of sleighsim.analysis.torus: section data (times t_k, rows
X_k) of an orbit cut where a fast angle is 0 mod 2 pi, with the event that marks its cycles.

Each orbit is sampled at the fast angle's zeros t_k = k dt (an uncoupled oscillator or rotor of
period dt: its section is the stroboscopic one). The chaotic and Henon-Heiles orbits are integrated by
heyoka in double (sleighsim.engine.orbits.taylor); the pendulum is its exact solution (Jacobi elliptic
functions, scipy.special.ellipj), since heyoka in double does not follow a pendulum this close to its
separatrix to the train's resolution (its rounding moves the period). Families (the systems of
sleighsim.chaos.known_orbits):

* "slow-fast torus" (2-torus): the pendulum of small-oscillation frequency W1 = 1e-3 beside a unit
  oscillator (two uncoupled oscillators; near the separatrix p1 spikes once per half period), a start
  drawn by known_orbits (kc log-uniform); event: p1 crossing 0 downward (the turning point q1 > 0).
* "three-interval torus" (2-torus whose train repeats after 3 unequal intervals): the same orbits seen
  through s = cos(3 psi) + b cos(psi + beta), psi = atan2(p1 / (2 k W1), sin(q1 / 2) / k) the pendulum's
  angle (its Jacobi amplitude), b uniform in [0.2, 0.5], beta in [0, 2 pi); event: s crossing 0 downward.
* "henon-heiles E=1/6", "henon-heiles E=1/8 sticky" (chaotic: Skokos' orbit C drawn along itself, its
  base orbit at a uniform time in [0.1, 1] x ALONG_PERIODS periods, the sticky one spending thousands of
  time units near island chains), "lorenz" (chaotic, time slowed by 20, drawn alike), all sampled by a
  rotor of period dt; events: px crossing 0 downward (the maxima of x) and, for Lorenz, z crossing 25
  downward.
* "henon-heiles E=1/12" (the textbook 2-torus of Henon-Heiles perturbed by 1e-6 on its level; with the
  rotor a 3-torus: its train is quasi-periodic, not periodic; the test claims 2-tori only).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ellipj, ellipk, ellipkinc

from sleighsim.chaos import known_orbits as ko
from sleighsim.engine.orbits import grid_samples, taylor

LORENZ_SLOW = 20.0  # Lorenz's time stretched by this factor (one loop every 15 time units)
ALONG_PERIODS = 2000.0  # a chaotic start: its base orbit at a uniform time in [0.1, 1] x this many periods


@dataclass(frozen=True)
class Family:
    """A family of known orbits: ``system`` (known_orbits.SYSTEMS), ``torus`` (True: 2-tori), ``k`` (the
    number of repeating intervals of its train; 0: none), ``dt`` (section period), ``column``, ``level``,
    ``direction`` of its event, ``cycle`` (an upper bound of one event's cycle, time units)."""

    system: str
    torus: bool
    k: int
    dt: float
    column: int
    level: float
    direction: int
    cycle: float


FAMILIES = {
    "slow-fast torus": Family("slow-fast", True, 1, 2 * math.pi, 1, 0.0, -1, ko.slow_period(1e-4)),
    "three-interval torus": Family("slow-fast", True, 3, 2 * math.pi, 3, 0.0, -1, ko.slow_period(1e-4) / 2),
    "henon-heiles E=1/6": Family("henon-heiles E=1/6", False, 0, 0.1, 2, 0.0, -1, 40.0),
    "henon-heiles E=1/8 sticky": Family("henon-heiles E=1/8 sticky", False, 0, 0.1, 2, 0.0, -1, 40.0),
    "lorenz": Family("lorenz", False, 0, 0.2, 2, 25.0, -1, 60.0),
    "henon-heiles E=1/12": Family("henon-heiles E=1/12", False, 0, 0.1, 2, 0.0, -1, 40.0),
}
#: The chaotic families (the rest: 2-tori, and Henon-Heiles E = 1/12, a 3-torus with the rotor).
CHAOTIC = ("henon-heiles E=1/6", "henon-heiles E=1/8 sticky", "lorenz")


def _slowed_lorenz(hy):
    return [(v, e / LORENZ_SLOW) for v, e in ko.lorenz_sys(hy)]


def _three_intervals(Y: np.ndarray, rng) -> np.ndarray:
    """Columns (q1, p1, q2, s) of slow-fast samples Y, s the three-reversal observable of the module's
    docstring (b, beta drawn from rng)."""
    q1, p1 = Y[:, 0], Y[:, 2]
    k = math.sqrt((0.5 * p1[0] ** 2 + ko.W1**2 * (1 - math.cos(q1[0]))) / (2 * ko.W1**2))
    psi = np.arctan2(p1 / (2 * k * ko.W1), np.sin(q1 / 2) / k)
    b, beta = rng.uniform(0.2, 0.5), rng.uniform(0.0, 2 * math.pi)
    return np.c_[q1, p1, Y[:, 1], np.cos(3 * psi) + b * np.cos(psi + beta)]


def _start(fam: Family, rng, ta) -> np.ndarray:
    """A start of family ``fam`` (integrator ``ta``): the textbook Henon-Heiles torus perturbed on its level,
    a torus' own draw, or a chaotic system's base orbit at a uniform time (module docstring)."""
    sysd = ko.SYSTEMS[fam.system]
    if fam.system == "henon-heiles E=1/12":
        return np.array(ko.hh_y0(*ko.perturbed(ko.HH_REG, rng)[:3], 1.0 / 12.0))
    if sysd.draw is not None:
        return sysd.draw(rng)
    spread = ALONG_PERIODS * sysd.period
    ta.time, ta.state[:] = 0.0, sysd.base
    ta.propagate_until(rng.uniform(0.1 * spread, spread))
    return ta.state.copy()


def pendulum(y0, t) -> np.ndarray:
    """The slow-fast system's exact orbit from y0 = (q1, q2, p1, p2) (libration) at the times t: rows
    (q1, q2, p1, p2), q1 = 2 asin(k sn(W1 t + u0 | k^2)), p1 = 2 k W1 cn(W1 t + u0 | k^2), the unit
    oscillator rotating."""
    q1, q2, p1, p2 = (float(v) for v in y0)
    m = (0.5 * p1**2 + ko.W1**2 * (1 - math.cos(q1))) / (2 * ko.W1**2)
    k = math.sqrt(m)
    u0 = ellipkinc(math.atan2(math.sin(q1 / 2) / k, p1 / (2 * k * ko.W1)), m)
    u = np.fmod(np.longdouble(ko.W1) * np.asarray(t, np.longdouble) + np.longdouble(u0), 4 * np.longdouble(ellipk(m)))
    sn, cn, _, _ = ellipj(u.astype(float), m)  # the argument reduced in long double: no rounding of W1 t in it
    c, s = np.cos(t), np.sin(t)
    return np.c_[2 * np.arcsin(k * sn), q2 * c + p2 * s, 2 * k * ko.W1 * cn, p2 * c - q2 * s]


def section(name: str, rng: np.random.Generator, n_events: int) -> dict:
    """Section data of one orbit of family ``name`` drawn from ``rng``, long enough for n_events events
    (upper bound: n_events + 2 cycles): t (n,), X (n, columns) and the family."""
    fam = FAMILIES[name]
    sysd = ko.SYSTEMS[fam.system]
    build = _slowed_lorenz if fam.system == "lorenz" else sysd.build
    n = int((n_events + 2) * fam.cycle / fam.dt) + 1
    if fam.system == "slow-fast":
        Y = pendulum(sysd.draw(rng), fam.dt * np.arange(n))
    else:
        ta, _ = taylor(f"torus_known {fam.system}", build)
        y0 = _start(fam, rng, ta)
        ta.time, ta.state[:] = 0.0, y0
        Y, _ = grid_samples(ta, n, fam.dt)
    X = _three_intervals(Y, rng) if fam.k == 3 else Y if fam.system != "slow-fast" else Y[:, [0, 2, 1]]
    return {"t": fam.dt * np.arange(n), "X": X, "family": fam}
