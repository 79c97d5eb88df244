"""Orbits of known class for auditing the chaos judges (``chaos.power``): textbook systems, sticky
chaotic orbits and slow-fast tori, each with a heyoka builder and seeded independent realizations.

Systems (builders take the heyoka module and return its list of (variable, expression)):

* Henon-Heiles, H = (px^2+py^2)/2 + (x^2+y^2)/2 + x^2 y - y^3/3 (Henon & Heiles 1964, AJ 69, 73),
  state (x, y, px, py). E = 1/12: invariant curves fill the x = 0 section; (0, -0.1, 0.1) is a torus.
  E = 1/6: (0, -0.016, 0.49974), orbit C of Skokos 2010 (Lect. Notes Phys. 790, 63) there at E = 1/8,
  chaotic. E = 1/8: the same start is chaotic and sticks to the island chains of the x = 0 section
  for thousands of time units at a time (the sticky case).
* Lorenz (sigma 10, rho 28, beta 8/3): chaotic, dissipative, not reversible.
* Uncoupled quartic (Duffing) / linear oscillators with frequency ratio sqrt(2): every orbit a torus.
* Nose-Hoover oscillator (Sprott 1994 case A, Phys. Rev. E 50, R647; Hoover 1985, Phys. Rev. A 31,
  1695): x' = y, y' = -x + y z, z' = 1 - y^2, a 3-D flow that is not Hamiltonian (its divergence z is
  not zero) but reversible under (x, y, z, t) -> (x, -y, -z, -t), with mixed dynamics: a chaotic sea
  (through (0, 5, 0), lambda_1 about 0.014) around nested tori that its orbits stick to.
* Slow-fast tori: H = p1^2/2 + W1^2 (1 - cos q1) + p2^2/2 + q2^2/2, state (q1, q2, p1, p2), a pendulum
  of small-oscillation frequency W1 = 1e-3 beside a unit oscillator: separable, so every orbit is a
  torus. Near the pendulum's separatrix its period, 4 K(k) / W1 (k^2 = its energy / 2 W1^2), is
  thousands of fast periods, and p1 spikes once per half period, like the sleigh's spikes.

A :class:`System` knows its class, its builder, its involution (reversible systems), the component
the frequency judge follows, its characteristic period (that component's leading line, the
analogue of the sleigh's spike period) and how to draw realizations (:func:`draw`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

CHAOTIC_ORBITS, TORI = "chaotic", "tori"
W1 = 1.0e-3  # the slow-fast torus' pendulum frequency (small oscillations)
LORENZ_LAMBDA = 0.9056  # Sprott 2003, Chaos and Time-Series Analysis, table of Lyapunov exponents


# ----------------------------------------------------------------------------- systems

def hh_sys(hy):
    """Henon-Heiles, state (x, y, px, py)."""
    x, y, px, py = hy.make_vars("x", "y", "px", "py")
    return [(x, px), (y, py), (px, -x - 2.0 * x * y), (py, -y - x * x + y * y)]


def hh_V(x, y):
    """Henon-Heiles potential."""
    return 0.5 * (x * x + y * y) + x * x * y - y**3 / 3.0


def hh_y0(x, y, px, E):
    """The Henon-Heiles state (x, y, px, py) on energy E with py >= 0."""
    return [x, y, px, math.sqrt(2.0 * (E - hh_V(x, y)) - px * px)]


def hh_energy(s):
    """Henon-Heiles energy of state s."""
    return 0.5 * (s[2] ** 2 + s[3] ** 2) + hh_V(s[0], s[1])


def hh_project(ref, partner):
    """Rescale the partner's momenta onto the reference's energy surface."""
    p = partner.copy()
    p[2:] *= math.sqrt(2.0 * (hh_energy(ref) - hh_V(p[0], p[1])) / (p[2] ** 2 + p[3] ** 2))
    return p


def flip_momenta(s):
    """Time-reversal involution R(q, p) = (q, -p) of a natural Hamiltonian system (dtype kept)."""
    s = np.array(s, dtype=np.result_type(np.asarray(s).dtype, float))  # long double stays long double
    s[len(s) // 2:] *= -1.0
    return s


def flip_nose_hoover(s):
    """Time-reversal involution (x, y, z) -> (x, -y, -z) of the Nose-Hoover oscillator (dtype kept)."""
    s = np.array(s, dtype=np.result_type(np.asarray(s).dtype, float))
    s[1:] *= -1.0
    return s


def oscillators(hy, quartic):
    """Two uncoupled oscillators, frequencies 1 and sqrt(2), with (quartic) or without a cubic force."""
    q1, q2, p1, p2 = hy.make_vars("q1", "q2", "p1", "p2")
    w2 = math.sqrt(2.0)
    c = 1.0 if quartic else 0.0
    return [(q1, p1), (q2, p2), (p1, -q1 - c * q1**3), (p2, -(w2**2) * q2 - c * q2**3)]


def lorenz_sys(hy):
    """Lorenz (10, 28, 8/3), state (x, y, z)."""
    x, y, z = hy.make_vars("x", "y", "z")
    return [(x, 10.0 * (y - x)), (y, x * (28.0 - z) - y), (z, x * y - 8.0 / 3.0 * z)]


def nose_hoover_sys(hy):
    """Nose-Hoover oscillator (Sprott A), state (x, y, z)."""
    x, y, z = hy.make_vars("x", "y", "z")
    return [(x, y), (y, -x + y * z), (z, 1.0 - y * y)]


def slow_fast_sys(hy):
    """Pendulum (frequency W1) beside a unit oscillator, state (q1, q2, p1, p2)."""
    q1, q2, p1, p2 = hy.make_vars("q1", "q2", "p1", "p2")
    return [(q1, p1), (q2, p2), (p1, -(W1**2) * hy.sin(q1)), (p2, -q2)]


def slow_period(kc: float) -> float:
    """The slow-fast pendulum's period 4 K(k) / W1 at complementary modulus kc = sqrt(1 - k^2)."""
    from scipy.special import ellipk

    return 4.0 * float(ellipk(1.0 - kc * kc)) / W1


HH_CHAOS = hh_y0(0.0, -0.016, 0.49974, 1.0 / 6.0)
HH_STICKY = hh_y0(0.0, -0.016, 0.49974, 1.0 / 8.0)
HH_REG = hh_y0(0.0, -0.1, 0.1, 1.0 / 12.0)
OSC0 = [1.0, 0.5, 0.0, 0.0]
LORENZ0 = [1.0, 1.0, 20.0]
NH0 = [0.0, 5.0, 0.0]
SLOW_FAST_KC = (1e-4, 1e-2)  # the draws' complementary moduli kc (log-uniform): 1 - k^2 from 1e-8 to 1e-4


# ----------------------------------------------------------------------------- realizations

def _perturbed(base, energy, rng):
    """The base state perturbed by 1e-6 of its largest component (Henon-Heiles: on its level)."""
    base = np.asarray(base, float)
    y = base + 1e-6 * np.max(np.abs(base)) * rng.normal(size=base.size)
    return np.array(hh_y0(y[0], y[1], y[2], energy)) if energy is not None else y


def _oscillator_box(rng):
    """A random torus of the uncoupled oscillators (q1, q2, p1, p2 uniform in a box)."""
    return np.array([rng.uniform(0.5, 1.5), rng.uniform(0.25, 0.75), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)])


def _slow_fast_torus(rng):
    """A random slow-fast torus: pendulum energy 2 W1^2 k^2 with kc = sqrt(1 - k^2) log-uniform in
    SLOW_FAST_KC, its angle uniform within 0.9 of its amplitude, either direction; the oscillator's
    amplitude uniform in [0.5, 1.5] at a uniform phase."""
    kc = math.exp(rng.uniform(*np.log(SLOW_FAST_KC)))
    h = 2.0 * W1**2 * (1.0 - kc * kc)
    q1 = 0.9 * rng.uniform(-1.0, 1.0) * 2.0 * math.asin(math.sqrt(1.0 - kc * kc))
    p1 = rng.choice([-1.0, 1.0]) * math.sqrt(max(2.0 * (h - W1**2 * (1.0 - math.cos(q1))), 0.0))
    a, phase = rng.uniform(0.5, 1.5), rng.uniform(0.0, 2.0 * math.pi)
    return np.array([q1, a * math.cos(phase), p1, -a * math.sin(phase)])


@dataclass(frozen=True)
class System:
    """An audit system: ``name``, orbit class (CHAOTIC_ORBITS or TORI), ``build(hy)``, ``period``
    (its characteristic period: that of the frequency judge's ``component``'s leading line, in its
    time unit), ``involution`` (None: not reversible), ``draw`` (rng -> a start) and, for a chaotic
    orbit drawn along itself, ``base`` and ``spread``: a realization is the orbit from ``base`` at a
    seeded uniform time in [spread / 10, spread] (time units)."""

    name: str
    cls: str
    build: Callable
    period: float
    component: int
    involution: Callable | None = None
    draw: Callable | None = None
    base: tuple = ()
    spread: float = 0.0


def _along(name, build, base, period, component, involution=None, spread_periods=2000.0):
    return System(name, CHAOTIC_ORBITS, build, period, component, involution, base=tuple(base),
                  spread=spread_periods * period)


def _tori(name, build, period, component, involution, draw):
    return System(name, TORI, build, period, component, involution, draw)


#: The audit set. Periods: the leading line of the component, measured by
#: ``frequency.leading_frequency`` over 200 periods (scripts in docs/methods.md, "Judges' power").
SYSTEMS: dict[str, System] = {s.name: s for s in (
    _along("henon-heiles E=1/6", hh_sys, HH_CHAOS, 6.8, 0, flip_momenta),
    _along("henon-heiles E=1/8 sticky", hh_sys, HH_STICKY, 6.6, 0, flip_momenta),
    _along("lorenz", lorenz_sys, LORENZ0, 0.75, 2),
    _along("nose-hoover sticky", nose_hoover_sys, NH0, 8.6, 0, flip_nose_hoover),
    _tori("henon-heiles E=1/12", hh_sys, 6.5, 0, flip_momenta, lambda rng: _perturbed(HH_REG, 1.0 / 12.0, rng)),
    _tori("quartic oscillators", lambda hy: oscillators(hy, True), 4.5, 0, flip_momenta, _oscillator_box),
    _tori("linear oscillators", lambda hy: oscillators(hy, False), 2 * math.pi, 0, flip_momenta, _oscillator_box),
    _tori("slow-fast", slow_fast_sys, slow_period(1e-3), 2, flip_momenta, _slow_fast_torus),
)}


def rng_for(system: str, stream: int, index: int) -> np.random.Generator:
    """The generator of realization ``index`` of ``system`` in ``stream`` (independent streams)."""
    return np.random.default_rng([2026, list(SYSTEMS).index(system), stream, index])


def draw(system: System, rng: np.random.Generator, flow=None) -> np.ndarray:
    """One realization's start: ``system.draw(rng)``, or for an orbit drawn along itself the state at a
    uniform time in [spread / 10, spread] of the orbit from ``base`` (``flow``: a heyoka integrator of
    the system in double)."""
    if system.draw is not None:
        return system.draw(rng)
    t = rng.uniform(0.1 * system.spread, system.spread)
    flow.time = 0.0
    flow.state[:] = system.base
    flow.propagate_until(t)
    return flow.state.copy()
