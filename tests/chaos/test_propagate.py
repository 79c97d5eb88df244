"""The engines' shared propagation conventions (sleighsim.chaos.propagate) in the indicators on
pairs of orbits and MEGNO: callbacks reach every propagation, angle reduction works, and a failed
integration raises naming the time."""

import math

import numpy as np
import pytest
from chaos_textbook import (
    _flip_momenta,
)

from sleighsim.chaos import loschmidt, megno, two_trajectory
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED
from sleighsim.engine import integrators

C, G, U = CHAOTIC, REGULAR, UNDECIDED


# ----------------------------------------------------------------------------- callbacks, failures

class _Counter:
    def __init__(self):
        self.n = 0

    def __call__(self, ta):
        self.n += 1
        return True


def test_callbacks_reach_every_propagation_and_angle_reduction_works(hy):
    """Two uncoupled rotating pendula (a sheared torus with unbounded angles): with
    heyoka's angle_reducer and a wrapped difference all indicators stay regular."""
    a, b, pa, pb = hy.make_vars("a", "b", "pa", "pb")
    sys = [(a, pa), (b, pb), (pa, -hy.sin(a)), (pb, -math.sqrt(2.0) * hy.sin(b))]
    y0 = [0.0, 0.0, 2.5, 3.0]  # energies above the separatrix: rotation

    def wrap(u, v):
        d = np.asarray(u, float) - np.asarray(v, float)
        d[:2] = (d[:2] + math.pi) % (2.0 * math.pi) - math.pi
        return d

    ta = hy.taylor_adaptive(sys, y0, compact_mode=True)
    red = hy.callback.angle_reducer([a, b])
    r = two_trajectory.two_trajectory(ta, y0, d0=1e-8, tau=1.0, T=3000.0, callback=red, difference=wrap)
    assert np.all(np.abs(r["final_state"][:2]) <= 2 * math.pi)
    assert two_trajectory.judge_two_trajectory(r["rate"], r["stderr"], r["T"], r["tau"], r["running_slope"],
                                               r["running_slope_err"])[0] == REGULAR
    L = loschmidt.loschmidt(ta, y0, np.geomspace(10, 3000, 8), _flip_momenta, callback=red, difference=wrap)
    assert np.max(L["error"]) < 1e-9
    tm, n = integrators.megno_integrator(sys)
    m = megno.megno(tm, n, y0, T=3000.0, n_samples=60, callback=hy.callback.angle_reducer([a, b]))
    assert abs(m["final"] - 2.0) < 0.1 and np.all(np.abs(m["final_state"][:2]) <= 2 * math.pi)
    # a counting callback is called by every engine
    c = _Counter()
    two_trajectory.two_trajectory(ta, y0, d0=1e-8, tau=1.0, T=20.0, callback=c, n_blocks=2)
    n1 = c.n
    assert n1 >= 40  # at least one step per leg, 2 legs per interval
    loschmidt.loschmidt(ta, y0, [5.0], _flip_momenta, callback=c)
    assert c.n > n1
    n2 = c.n
    megno.megno(tm, n, y0, T=20.0, n_samples=4, tau=1.0, callback=c)
    assert c.n >= n2 + 20


def test_failed_integration_raises_runtime_error_naming_the_time(hy):
    x, y = hy.make_vars("x", "y")
    sys = [(x, x * x), (y, -y)]  # x blows up at t = 1 / x0
    ta = hy.taylor_adaptive(sys, [1.0, 1.0], compact_mode=True)
    with pytest.raises(RuntimeError, match="t = "):
        two_trajectory.two_trajectory(ta, [0.2, 1.0], d0=1e-8, tau=1.0, T=20.0, n_blocks=2)
    with pytest.raises(RuntimeError, match="t = "):
        loschmidt.loschmidt(ta, [0.2, 1.0], [10.0], lambda s: s)
    tm, n = integrators.megno_integrator(sys)
    with pytest.raises(RuntimeError, match="t = "):
        megno.megno(tm, n, [0.2, 1.0], T=20.0, n_samples=4, tau=1.0)
