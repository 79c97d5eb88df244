"""Systems of known class for auditing the chaos judges (``chaos.power``): textbook systems, sticky
chaotic orbits beside islands, slow-fast tori and tori and chaos with rare spikes of e^30 per cycle,
each with a heyoka builder. Their realizations (independent starts, confirmed) are drawn in
``chaos.audit_orbits``.

Systems (builders take the heyoka module and return its list of (variable, expression)):

* Henon-Heiles, H = (px^2+py^2)/2 + (x^2+y^2)/2 + x^2 y - y^3/3 (Henon & Heiles 1964, AJ 69, 73),
  state (x, y, px, py). E = 1/6 from (0, -0.016, 0.49974) (orbit C of Skokos 2010, Lect. Notes Phys.
  790, 63) is chaotic; E = 1/8 from the same start is chaotic and sticks to the island chains of the
  x = 0 section for thousands of time units at a time; E = 1/12: mostly invariant curves (tori), with
  thin chaotic layers (so each torus start is confirmed).
* Lorenz (sigma 10, rho 28, beta 8/3): chaotic, dissipative, not reversible.
* Uncoupled quartic (Duffing) / linear oscillators with frequency ratio sqrt(2): every orbit a torus.
* Nose-Hoover oscillator (Sprott 1994 case A, Phys. Rev. E 50, R647): x' = y, y' = -x + y z, z' = 1 - y^2,
  reversible under (x, -y, -z), a chaotic sea through (0, 5, 0) around nested tori it sticks to.
* A forced pendulum q'' = -sin q + 0.2 cos(1.5 t), the forcing's phase carried by the unit
  oscillator (c, s): state (q, p, c, s); reversible under (q, -p, c, -s); a chaotic layer around the
  separatrix that sticks to its islands (a third of 20 / lambda windows nearly regular), and tori
  around the bottom.
* The x^2 y^2 potential with quartic walls, H = (px^2+py^2)/2 + x^2 y^2 / 2 + 0.25 (x^4 + y^4) / 4 on
  E = 1/2: about half the level chaotic (lambda 0.01 to 0.07), half tori.
* Slow-fast tori: H = p1^2/2 + W1^2 (1 - cos q1) + p2^2/2 + q2^2/2, a pendulum of frequency W1 = 1e-3
  near its separatrix beside a unit oscillator: separable, every orbit a torus, p1 spiking once per
  half period.
* Spiked systems (:func:`spiked`): a system x' = f(x) seen through the time-periodic change of
  coordinates y_i = w x_i, y_j = x_j / w, with w = exp(c g), g = exp(kappa (cos phi - 1)) and the
  phase phi carried by a unit oscillator (cos phi, sin phi) of frequency nu = 2 pi / P. Once per P the
  coordinates swing by w^2 = e^(2c) (w spikes from 1 to e^c): the tangent map's largest singular value
  over a cycle is about e^(2c) times the base flow's, while Lyapunov exponents and tori are those of
  the base (the change of coordinates is bounded and periodic): the sleigh's case of rare spikes
  with e^30 or more per cycle that does not compound on a torus. Spiked quartic oscillators: tori;
  spiked Henon-Heiles E = 1/8: sticky chaos.

A :class:`System` knows its class, builder, involution (reversible systems), the component the
frequency judge and the section follow, its characteristic period P (the analogue of the sleigh's
spike period), its angles, the arithmetic the audit follows it in and how its starts are drawn.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

CHAOTIC_ORBITS, TORI = "chaotic", "tori"
W1 = 1.0e-3  # the slow-fast torus' pendulum frequency (small oscillations)
LORENZ_LAMBDA = 0.9056  # Sprott 2003, Chaos and Time-Series Analysis, table of Lyapunov exponents
FORCING = (0.2, 1.5)  # the forced pendulum's amplitude and frequency
X2Y2_B, X2Y2_E = 0.25, 0.5  # the x^2 y^2 potential's quartic walls and energy
#: The spiked systems: kappa (spike width about P / (2 pi sqrt(kappa))), the spike period P and c (a swing of
#: e^(2c) per cycle), chosen so that ln G per cycle reaches about 30 (measured by the audit's gauge on every
#: realization) while long double still follows most orbits by the gauge's count (G x steps x rounding < 1e-3:
#: a short cycle of about 100 to 160 steps).
SPIKE_KAPPA, SPIKE_PERIOD, SPIKE_C = 20.0, 20.0, 15.0


# ----------------------------------------------------------------------------- builders

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


def flip_forced(s):
    """Time-reversal involution (q, p, c, s) -> (q, -p, c, -s) of the forced pendulum (dtype kept)."""
    s = np.array(s, dtype=np.result_type(np.asarray(s).dtype, float))
    s[[1, 3]] *= -1.0
    return s


def oscillators(hy, quartic):
    """Two uncoupled oscillators, frequencies 1 and sqrt(2), with (quartic) or without a cubic force
    (written as products: heyoka's pow differentiates badly at 0)."""
    q1, q2, p1, p2 = hy.make_vars("q1", "q2", "p1", "p2")
    c = 1.0 if quartic else 0.0
    return [(q1, p1), (q2, p2), (p1, -q1 - c * q1 * q1 * q1), (p2, -2.0 * q2 - c * q2 * q2 * q2)]


def lorenz_sys(hy):
    """Lorenz (10, 28, 8/3), state (x, y, z)."""
    x, y, z = hy.make_vars("x", "y", "z")
    return [(x, 10.0 * (y - x)), (y, x * (28.0 - z) - y), (z, x * y - 8.0 / 3.0 * z)]


def nose_hoover_sys(hy):
    """Nose-Hoover oscillator (Sprott A), state (x, y, z)."""
    x, y, z = hy.make_vars("x", "y", "z")
    return [(x, y), (y, -x + y * z), (z, 1.0 - y * y)]


def forced_sys(hy):
    """The forced pendulum, state (q, p, c, s): (c, s) = (cos, sin) of the forcing's phase."""
    q, p, c, s = hy.make_vars("q", "p", "c", "s")
    a, nu = FORCING
    return [(q, p), (p, -hy.sin(q) + a * c), (c, -nu * s), (s, nu * c)]


def x2y2_sys(hy):
    """The x^2 y^2 potential with quartic walls, state (x, y, px, py)."""
    x, y, px, py = hy.make_vars("x", "y", "px", "py")
    b = X2Y2_B
    return [(x, px), (y, py), (px, -x * y * y - b * x * x * x), (py, -x * x * y - b * y * y * y)]


def slow_fast_sys(hy):
    """Pendulum (frequency W1) beside a unit oscillator, state (q1, q2, p1, p2)."""
    q1, q2, p1, p2 = hy.make_vars("q1", "q2", "p1", "p2")
    return [(q1, p1), (q2, p2), (p1, -(W1**2) * hy.sin(q1)), (p2, -q2)]


def slow_period(kc: float) -> float:
    """The slow-fast pendulum's period 4 K(k) / W1 at complementary modulus kc = sqrt(1 - k^2)."""
    from scipy.special import ellipk

    return 4.0 * float(ellipk(1.0 - kc * kc)) / W1


def spiked(hy, base, i: int, j: int, c: float = SPIKE_C, kappa: float = SPIKE_KAPPA, period: float = SPIKE_PERIOD):
    """``base`` (a builder) seen through y_i = w x_i, y_j = x_j / w (module docstring): state (y, cos phi,
    sin phi, w), with w'/w = c g'(phi) nu, so that w = exp(c g(phi)) along every orbit."""
    eqs = base(hy)
    xs = [v for v, _ in eqs]
    ys = hy.make_vars(*[f"y{k}" for k in range(len(xs))])
    cp, sp, w = hy.make_vars("cphi", "sphi", "w")
    nu = 2.0 * math.pi / period
    rate = -c * kappa * nu * sp * hy.exp(kappa * (cp - 1.0))  # w' / w
    sub = {str(v): ys[k] for k, v in enumerate(xs)}
    sub[str(xs[i])], sub[str(xs[j])] = ys[i] / w, ys[j] * w
    out = []
    for k, (_, f) in enumerate(eqs):
        f = hy.subs(f, sub)
        out.append((ys[k], rate * ys[k] + w * f if k == i else -rate * ys[k] + f / w if k == j else f))
    return out + [(cp, -nu * sp), (sp, nu * cp), (w, rate * w)]


def spiked_state(x, phase: float, c: float = SPIKE_C, i: int = 0, j: int = 2, kappa: float = SPIKE_KAPPA):
    """The spiked system's state for the base state x at the phase ``phase`` (radians)."""
    w = math.exp(c * math.exp(kappa * (math.cos(phase) - 1.0)))
    y = np.array(x, float)
    y[i], y[j] = y[i] * w, y[j] / w
    return np.concatenate([y, [math.cos(phase), math.sin(phase), w]])


def unspiked(y, i: int = 0, j: int = 2) -> np.ndarray:
    """The base state x of a spiked state y (its last three components the phase pair and w)."""
    y = np.asarray(y, float)
    x = y[:-3].copy()
    x[i], x[j] = x[i] / y[-1], x[j] * y[-1]
    return x


def spiked_perturb(base, rng):
    """A spiked Henon-Heiles base state with its base part perturbed on its level (``perturbed``), the phase
    and w kept on their invariant (w = exp(c g(phase)))."""
    y = np.asarray(base, float)
    x = unspiked(y)
    x = hh_on_level(perturbed(x, rng), hh_energy(x))
    return spiked_state(x, math.atan2(y[-2], y[-3]))


def spiked_flip(s):
    """Time reversal of a spiked natural system: the base's momenta and the phase's sine flip (dtype kept)."""
    s = np.array(s, dtype=np.result_type(np.asarray(s).dtype, float))
    s[2:4] *= -1.0
    s[-2] *= -1.0
    return s


# ----------------------------------------------------------------------------- starts

HH_CHAOS = hh_y0(0.0, -0.016, 0.49974, 1.0 / 6.0)
HH_STICKY = hh_y0(0.0, -0.016, 0.49974, 1.0 / 8.0)
HH_REG = hh_y0(0.0, -0.1, 0.1, 1.0 / 12.0)  # a torus of E = 1/12 (the textbook tests' regular orbit)
OSC0 = [1.0, 0.5, 0.0, 0.0]
LORENZ0 = [1.0, 1.0, 20.0]
NH0 = [0.0, 5.0, 0.0]
FORCED0 = [math.pi - 0.05, 0.0, 1.0, 0.0]
X2Y2_0 = [1e-3, 1.2, 0.4, math.sqrt(2 * (X2Y2_E - X2Y2_B * 1.2**4 / 4 - 0.5e-6 * 1.44) - 0.16)]
SLOW_FAST_KC = (1e-4, 1e-2)  # the draws' complementary moduli kc (log-uniform): 1 - k^2 from 1e-8 to 1e-4


def hh_section(E, rng):
    """A uniform start on the x = 0 section of Henon-Heiles at energy E (px >= 0): (y, py) uniform in
    the region the level allows."""
    while True:
        y, py = rng.uniform(-0.5, 1.0), rng.uniform(-0.6, 0.6)
        left = 2.0 * (E - hh_V(0.0, y)) - py * py
        if left > 0:
            return np.array([0.0, y, math.sqrt(left), py])


def x2y2_start(rng):
    """A start on the x^2 y^2 level E = 1/2 at x = 1e-3 (y uniform where the level allows, the momentum's
    direction uniform)."""
    y = rng.uniform(0.1, 0.95 * (4.0 * X2Y2_E / X2Y2_B) ** 0.25)
    p = math.sqrt(2.0 * (X2Y2_E - X2Y2_B * (y**4 + 1e-12) / 4.0 - 0.5e-6 * y * y))
    a = rng.uniform(0.0, 2.0 * math.pi)
    return np.array([1e-3, y, p * math.cos(a), p * math.sin(a)])


def forced_torus(rng):
    """A forced-pendulum start near the bottom: q uniform in [-1, 1], p in [-0.3, 0.3], the forcing's phase
    uniform."""
    a = rng.uniform(0.0, 2.0 * math.pi)
    return np.array([rng.uniform(-1.0, 1.0), rng.uniform(-0.3, 0.3), math.cos(a), math.sin(a)])


def oscillator_box(rng):
    """A random torus of the uncoupled oscillators (q1, q2, p1, p2 uniform in a box)."""
    return np.array([rng.uniform(0.5, 1.5), rng.uniform(0.25, 0.75), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)])


def slow_fast_torus(rng):
    """A random slow-fast torus: pendulum energy 2 W1^2 k^2 with kc = sqrt(1 - k^2) log-uniform in
    SLOW_FAST_KC, its angle uniform within 0.9 of its amplitude, either direction; the oscillator's
    amplitude uniform in [0.5, 1.5] at a uniform phase."""
    kc = math.exp(rng.uniform(*np.log(SLOW_FAST_KC)))
    h = 2.0 * W1**2 * (1.0 - kc * kc)
    q1 = 0.9 * rng.uniform(-1.0, 1.0) * 2.0 * math.asin(math.sqrt(1.0 - kc * kc))
    p1 = rng.choice([-1.0, 1.0]) * math.sqrt(max(2.0 * (h - W1**2 * (1.0 - math.cos(q1))), 0.0))
    a, phase = rng.uniform(0.5, 1.5), rng.uniform(0.0, 2.0 * math.pi)
    return np.array([q1, a * math.cos(phase), p1, -a * math.sin(phase)])


def spiked_torus(rng):
    """A spiked quartic-oscillator torus: an ``oscillator_box`` start at a uniform phase of the spike cycle."""
    return spiked_state(oscillator_box(rng), rng.uniform(0.0, 2.0 * math.pi), SPIKE_C)


def perturbed(base, rng, rel: float = 1e-6):
    """The base state perturbed by ``rel`` of its largest component (the chaotic base orbits' starts;
    their burn-in spreads them apart)."""
    base = np.asarray(base, float)
    return base + rel * np.max(np.abs(base)) * rng.normal(size=base.size)


def on_level(energy: Callable, project: Callable):
    """A perturbation of a Hamiltonian system's base state put back on its level."""
    return lambda base, rng: project(perturbed(base, rng), energy(base))


def hh_on_level(y, E):
    """The Henon-Heiles state y with py reset to put it on energy E."""
    return np.array(hh_y0(y[0], y[1], y[2], E))


# ----------------------------------------------------------------------------- the audit set

@dataclass(frozen=True)
class System:
    """An audit system: ``name``, orbit class (CHAOTIC_ORBITS or TORI), ``build(hy)``, ``period`` P (its
    characteristic period, time units), ``component`` (the frequency judge's and the section's),
    ``involution`` (None: not reversible), ``angles`` (components that are angles), ``arithmetic`` (the
    heyoka arithmetic the audit follows it in: long double for the spiked systems and the slow-fast tori,
    whose swings over cycles of many steps double does not follow by the gauge's count), ``integrable``
    (every orbit a torus: no confirmation needed) and the starts: ``draw(rng)`` (tori: independent starts)
    or ``base`` and ``perturb(base, rng)`` (chaotic: the base orbits' starts)."""

    name: str
    cls: str
    build: Callable
    period: float
    component: int
    involution: Callable | None = None
    angles: tuple = ()
    arithmetic: str = "double"
    integrable: bool = False
    draw: Callable | None = None
    base: tuple = ()
    perturb: Callable | None = None


def _chaotic(name, build, base, period, component, involution=None, perturb=perturbed, **kw):
    return System(name, CHAOTIC_ORBITS, build, period, component, involution, base=tuple(base), perturb=perturb,
                  **kw)


def _tori(name, build, period, component, involution, draw, **kw):
    return System(name, TORI, build, period, component, involution, draw=draw, **kw)


def _spiked_hh(hy):
    return spiked(hy, hh_sys, 0, 2, SPIKE_C)


def _spiked_osc(hy):
    return spiked(hy, lambda h: oscillators(h, True), 0, 2, SPIKE_C)


_SPIKE = 6  # the spiked systems' w: after the base's 4 components and the phase's (cos, sin)

#: The audit set. Periods: the component's leading line (tests/chaos/test_judge_power.py measures them).
SYSTEMS: dict[str, System] = {s.name: s for s in (
    _chaotic("henon-heiles E=1/6", hh_sys, HH_CHAOS, 6.8, 0, flip_momenta,
             perturb=on_level(hh_energy, hh_on_level)),
    _chaotic("henon-heiles E=1/8 sticky", hh_sys, HH_STICKY, 6.6, 0, flip_momenta,
             perturb=on_level(hh_energy, hh_on_level)),
    _chaotic("lorenz", lorenz_sys, LORENZ0, 0.75, 2),
    _chaotic("nose-hoover sticky", nose_hoover_sys, NH0, 8.6, 0, flip_nose_hoover),
    _chaotic("forced pendulum sticky", forced_sys, FORCED0, 20.0, 1, flip_forced, angles=(0,)),
    _chaotic("x2y2 sticky", x2y2_sys, X2Y2_0, 7.5, 1, flip_momenta),
    _chaotic("spiked henon-heiles E=1/8", _spiked_hh, spiked_state(HH_STICKY, math.pi, SPIKE_C), SPIKE_PERIOD, _SPIKE,
             spiked_flip, perturb=spiked_perturb, arithmetic="long double"),
    _tori("henon-heiles E=1/12", hh_sys, 6.5, 0, flip_momenta, lambda rng: hh_section(1.0 / 12.0, rng)),
    _tori("quartic oscillators", lambda hy: oscillators(hy, True), 4.5, 0, flip_momenta, oscillator_box,
          integrable=True),
    _tori("linear oscillators", lambda hy: oscillators(hy, False), 2 * math.pi, 0, flip_momenta, oscillator_box,
          integrable=True),
    _tori("slow-fast", slow_fast_sys, slow_period(1e-3), 2, flip_momenta, slow_fast_torus, integrable=True,
          arithmetic="long double"),
    _tori("forced pendulum tori", forced_sys, 5.7, 1, flip_forced, forced_torus, angles=(0,)),
    _tori("x2y2 tori", x2y2_sys, 7.5, 1, flip_momenta, x2y2_start),
    _tori("spiked quartic oscillators", _spiked_osc, SPIKE_PERIOD, _SPIKE, spiked_flip, spiked_torus,
          arithmetic="long double", integrable=True),
)}


def rng_for(system: str, stream: int, index: int) -> np.random.Generator:
    """The generator of draw ``index`` of ``system`` in ``stream`` (independent streams)."""
    return np.random.default_rng([2026, list(SYSTEMS).index(system), stream, index])
