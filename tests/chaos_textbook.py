"""Textbook systems with known answers for the chaos-indicator tests (test_chaos_*.py,
test_frequencies.py), the runs of the indicators on them, shared by the test modules (computed once
per process), and the checks every judge must pass on synthetic inputs.

Systems and reference values:
* Regular tori: two uncoupled oscillators with frequency ratio sqrt(2) (integrable, so every
  orbit lies on a 2-torus). Quartic (Duffing) oscillators, q'' = -w^2 q - q^3: the frequency
  depends on the amplitude (shear), so MEGNO <Y> -> 2; linear oscillators are isochronous
  (no shear), so <Y> -> 0 (Cincotta & Simo 2000, A&AS 147, 205; Cincotta, Giordano & Simo
  2003, Physica D 182, 151). Rotating pendula: a torus with shear and unbounded angles,
  exercising heyoka's angle_reducer callback.
* Henon-Heiles, H = (px^2+py^2)/2 + (x^2+y^2)/2 + x^2 y - y^3/3 (Henon & Heiles 1964,
  AJ 69, 73). E = 1/12: the x = 0 surface of section is filled by invariant curves; we use
  (x, y, px) = (0, -0.1, 0.1) with py from the energy (MEGNO -> 2 confirms the torus).
  E = 1/6: mostly chaotic; (x, y, px) = (0, -0.016, 0.49974) is orbit C of Skokos 2010
  (Lect. Notes Phys. 790, 63; there at E = 1/8), here with py from E = 1/6. Its largest
  exponent measured here is about 0.11-0.135 (three orbits at T = 1e5 gave 0.113, 0.119,
  0.125); the often-quoted 0.04-0.05 is the E = 1/8 chaotic sea (orbit C at E = 1/8 gives
  0.048 at T = 1e5 here), so only loose bounds 0.07-0.2 are asserted. (At E = 1/8 orbit C
  sticks to islands for thousands of time units in some realisations: not a robust test.)
* Lorenz (sigma 10, rho 28, beta 8/3): lambda_1 = 0.9056 (Sprott 2003, Chaos and
  Time-Series Analysis, table of Lyapunov exponents); dissipative, not reversible, so no
  Loschmidt test.
"""

import functools

import numpy as np

from sleighsim.chaos import known_orbits, megno, tangent, two_trajectory
from sleighsim.chaos.verdicts import UNDECIDED
from sleighsim.engine import integrators

# the systems live in sleighsim.chaos.known_orbits (the judge-power audit runs them too); their names here
# are the ones the test modules import
_hh_sys, _hh_V, _hh_y0, _hh_energy = known_orbits.hh_sys, known_orbits.hh_V, known_orbits.hh_y0, known_orbits.hh_energy
_hh_project, _flip_momenta = known_orbits.hh_project, known_orbits.flip_momenta
_oscillators, _lorenz_sys = known_orbits.oscillators, known_orbits.lorenz_sys
LORENZ_LAMBDA, HH_CHAOS, HH_REG = known_orbits.LORENZ_LAMBDA, known_orbits.HH_CHAOS, known_orbits.HH_REG
OSC0, LORENZ0 = known_orbits.OSC0, known_orbits.LORENZ0
T_HAM, TAU_HAM = 1.0e4, 1.0  # Hamiltonian cases
T_LOR, TAU_LOR = 1.0e3, 0.1  # Lorenz


@functools.cache
def textbook_runs(hy):
    """Each textbook orbit once: MEGNO (which also yields the one-vector Benettin series)
    and the two-trajectory estimate."""
    cases = {
        "hh_chaos": (_hh_sys(hy), HH_CHAOS, T_HAM, TAU_HAM),
        "hh_regular": (_hh_sys(hy), HH_REG, T_HAM, TAU_HAM),
        "quartic": (_oscillators(hy, True), OSC0, T_HAM, TAU_HAM),
        "linear": (_oscillators(hy, False), OSC0, T_HAM, TAU_HAM),
        "lorenz": (_lorenz_sys(hy), LORENZ0, T_LOR, TAU_LOR),
    }
    out = {}
    for name, (sys, y0, T, tau) in cases.items():
        tm, n = integrators.megno_integrator(sys)
        ta = hy.taylor_adaptive(sys, y0, compact_mode=True)
        m = megno.megno(tm, n, y0, T=T, n_samples=100, tau=tau)
        f = tangent.finite_time_exponents(m["log_growth"], tau, tau * np.array([10, 20, 40, 80, 160, 320]),
                                          t_skip=T / 2)
        two = two_trajectory.two_trajectory(ta, y0, d0=1e-8, tau=tau, T=T)
        out[name] = {"ta": ta, "megno": m, "ftle": f, "two": two, "T": T, "tau": tau, "y0": y0}
    return out


# ----------------------------------------------------------------------------- judges (synthetic)

def _monotone_in_errors(judge, base, err_keys, scales=(1.0, 2.0, 5.0, 20.0, 1e3, 1e6)):
    """Scaling the uncertainties up may only keep the verdict or turn it to undecided."""
    first = judge(**base)[0]
    seen = []
    for s in scales:
        kw = dict(base)
        for k in err_keys:
            kw[k] = base[k] * s
        v = judge(**kw)[0]
        assert v in (first, UNDECIDED), (kw, v)
        seen.append(v)
    # once undecided, stays undecided
    if UNDECIDED in seen:
        assert all(v == UNDECIDED for v in seen[seen.index(UNDECIDED):])
    return seen


def _nan_each(judge, base, keys):
    for k in keys:
        v, reason = judge(**{**base, k: float("nan")})
        assert v == UNDECIDED and k in reason, k
