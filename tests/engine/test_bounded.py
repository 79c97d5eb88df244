"""Every integration keeps its state bounded by exact symmetries (sleighsim.engine.integrators): delta
reduced by whole turns after every step, theta and the path re-originated between chunks.
These are the accuracy properties that every long-horizon number depends on."""

import math

import numpy as np
import pytest

from sleighsim.chaos import benettin
from sleighsim.engine import integrators
from sleighsim.engine.integrate import bound, final_state, integrate, sample_grid
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE

P = Params.paper(eps=0.1)
EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def settled():
    """A state on the main attractor (t = 1e4 from the reference state)."""
    return final_state(integrate(P, REFERENCE_STATE, [0.0, 1e4]))


def _states(ds):
    return np.stack([ds[v].values for v in equations.STATE_NAMES], axis=-1)


def test_a_state_with_delta_near_1e6_integrates_exactly_as_the_same_state_reduced():
    turns = 159155  # delta = 0.7 + 2 pi turns, about 1e6
    big = [0.03, 0.05, 1.2, 0.7 + 2 * math.pi * turns]
    reduced = bound(big, kinematics=False)[0]  # the engine's own reduction of the same state
    grid = sample_grid(0.0, 2000.0, 1.0)
    a, b = integrate(P, big, grid), integrate(P, reduced, grid)
    for v in equations.STATE_NAMES:
        assert np.array_equal(a[v].values, b[v].values), v
    # and to rounding of the large number itself, the state with delta = 0.7
    c = integrate(P, [0.03, 0.05, 1.2, 0.7], grid[:11])
    assert np.max(np.abs(equations.state_difference(_states(a)[:11], _states(c)))) < 1e-9
    assert a.attrs["energy_max_rel_drift"] < 1e-13


def test_delta_is_reported_reduced_and_the_path_unwrapped_and_absolute():
    ds = integrate(P, REFERENCE_STATE, sample_grid(0.0, 3000.0, 0.5), kinematics=True)
    assert np.all((ds.delta.values >= 0) & (ds.delta.values < 2 * math.pi))
    # theta is the integral of Omega (no jumps of 2 pi); the path is continuous and leaves the origin
    t, Om, th = ds.time.values, ds.Omega.values, ds.theta.values
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (Om[1:] + Om[:-1]) * np.diff(t))])
    assert np.max(np.abs(th - integral)) < 1e-2 and np.max(np.abs(np.diff(th))) < 0.5  # no jumps of 2 pi
    steps = np.hypot(np.diff(ds.x.values), np.diff(ds.y.values))
    assert steps.max() < 0.5 * 1.0 and np.hypot(ds.x.values[-1], ds.y.values[-1]) > 5.0


def test_the_path_does_not_set_the_error_scale_of_the_dynamics():
    """With the path (x, y reaching tens of units) or without it, the dynamics are the same to rounding."""
    grid = sample_grid(0.0, 3000.0, 1.0)
    with_path, without = integrate(P, REFERENCE_STATE, grid, kinematics=True), integrate(P, REFERENCE_STATE, grid)
    assert np.hypot(with_path.x.values, with_path.y.values).max() > 5.0
    gap = np.max(np.abs(equations.state_difference(_states(with_path), _states(without))))
    assert gap < 1e-10, gap


def test_bound_is_an_exact_symmetry_and_keeps_the_shift():
    y = np.array([0.1, 0.2, 1.0, 13.0, -7.5, 40.0, -12.0])
    reduced, shift = bound(y, kinematics=True)
    assert -math.pi <= reduced[3] < math.pi and 0 <= reduced[4] < 2 * math.pi and np.all(reduced[5:] == 0)
    assert np.allclose(equations.state_difference(reduced + shift, y), 0.0, atol=1e-14)
    assert np.allclose(equations.full_rhs(reduced, P)[:4], equations.full_rhs(y, P)[:4], rtol=1e-13, atol=1e-15)
    assert np.allclose(equations.kinematics_rhs(reduced, P), equations.kinematics_rhs(y, P), rtol=1e-13, atol=1e-15)


def test_integrators_store_delta_shifted_and_convert_back(settled):
    """The sleigh's compiled integrators hold delta + pi in [0, 2 pi): delta itself in [-pi, pi)."""
    ta, _ = integrators.flow(False, 2.0**-52)
    integrators.set_pars(ta, P)
    ta.time = 0.0
    integrators.load(ta, settled)
    assert ta.state[3] == pytest.approx(settled[3] + integrators.DELTA_SHIFT)
    assert np.allclose(integrators.read(ta, 4), settled, rtol=0, atol=1e-15)
    ta.propagate_until(50.0, callback=integrators.bounded(ta))
    assert 0 <= ta.state[3] < 2 * math.pi + 1.0  # reduced after every step (within one step's motion)
    ours = final_state(integrate(P, settled, [0.0, 50.0]))
    assert np.max(np.abs(equations.state_difference(integrators.read(ta, 4), ours))) < 1e-12


def test_two_chunkings_agree_to_rounding_times_the_measured_growth(settled):
    """Different chunk boundaries change the step sequence only; the runs then differ by rounding,
    amplified at most by the largest growth of the tangent map along the orbit (one-vector
    Benettin run from the same state)."""
    T = 600.0
    grid = sample_grid(0.0, T, 1.0)
    a = _states(integrate(P, settled, grid, progress=1))
    b = _states(integrate(P, settled, grid, progress=int(T)))
    gap = np.max(np.abs(equations.state_difference(a, b)), axis=1)
    ta, _ = integrators.sleigh_tangent(1, 2.0**-52, True)
    integrators.set_pars(ta, P)
    r = benettin.benettin(ta, 4, 1, settled, t_align=0.0, T=T, tau=1.0)
    log_growth = np.concatenate([[0.0], np.cumsum(r["log_growth"][:, 0])])  # ln |v(t)|, t = 0, 1, ..., T
    worst = np.exp(log_growth - np.minimum.accumulate(log_growth))  # max over s <= t of the growth s -> t
    steps_per_unit = 4.0
    bound_t = 10 * EPS * np.max(np.abs(a), axis=1) * steps_per_unit * grid * worst
    assert np.all(gap[1:] <= bound_t[1:]), (gap[-1], bound_t[-1])
    assert gap[-1] > 0  # the step sequences did differ


def test_benettin_sums_do_not_depend_on_the_renormalisation_interval(settled):
    """In exact arithmetic the R factors of successive QR steps multiply: the accumulated sums, and so
    the exponents, are the same for every tau. Over a window where the step sequences' rounding has
    not grown (the runs' end states agree to 1e-7; 600 time units from this state), all four agree
    to far better than 0.5%."""
    T = 600.0
    grid = [0.0, T]
    ends = [final_state(integrate(P, settled, grid, progress=p)) for p in (1, 100)]
    assert np.max(np.abs(equations.state_difference(*ends))) < 1e-7
    ta, _ = integrators.sleigh_tangent(4, 2.0**-52, True)
    integrators.set_pars(ta, P)
    lam = {tau: benettin.benettin(ta, 4, 4, settled, t_align=0.0, T=T, tau=tau)["exponents"]
           for tau in (10.0, 1.0, 0.1)}
    for tau in (1.0, 0.1):
        assert np.all(np.abs(lam[tau] / lam[10.0] - 1) < 5e-3), (tau, lam[tau], lam[10.0])


def test_energy_drift_stays_below_1e_12_over_1e6_time_units():
    """The reference state at eps = 0.1, tol 2.2e-16 (about 7.6 million steps, half a minute)."""
    ds = integrate(P, REFERENCE_STATE, sample_grid(0.0, 1e6, 100.0), progress=4)
    assert ds.attrs["energy_max_rel_drift"] <= 1e-12, ds.attrs["energy_max_rel_drift"]


def test_scipy_keeps_delta_bounded_too_and_agrees_with_heyoka():
    grid = sample_grid(0.0, 300.0, 0.5)
    hy = integrate(P, REFERENCE_STATE, grid, kinematics=True)
    sp = integrate(P, REFERENCE_STATE, grid, kinematics=True, backend="scipy", rtol=1e-13, atol=1e-15)
    assert np.all((sp.delta.values >= 0) & (sp.delta.values < 2 * math.pi))
    for v in ("u", "Omega", "omega", "theta", "x", "y"):
        assert np.max(np.abs(hy[v].values - sp[v].values)) < 1e-7, v
    assert np.max(np.abs(equations.state_difference(_states(hy), _states(sp)))) < 1e-7


def test_state_difference_wraps_angles_and_keeps_long_double():
    a = np.array([0.5, 0.0, 0.0, 2 * np.pi - 1e-3])
    b = np.array([0.25, 0.0, 0.0, 1e-3])
    assert np.allclose(equations.state_difference(a, b), [0.25, 0.0, 0.0, -2e-3])
    ld = a.astype(np.longdouble)
    ld[0] += np.longdouble(1e-18)  # below double's resolution at 0.5
    d = equations.state_difference(ld, a)
    assert d.dtype == np.longdouble and 0.5e-18 < d[0] < 1.5e-18
    assert equations.state_difference([1, 2, 3, 0], [0, 0, 0, 0]).dtype == float
