"""Parameters, conservation, symmetries and the eps = 0 oracle."""

import math

import numpy as np
import pytest

from sleighsim.engine.integrate import DEFAULT_TOL, integrate, sample_grid
from sleighsim.model import equations, sleigh0
from sleighsim.model.params import PARAM_NAMES, Params, positive
from sleighsim.model.symmetries import REFERENCE_LABEL, REFERENCE_STATE, energy_label, state_at_label
from sleighsim.precision import Precision

REF = REFERENCE_STATE


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(eps=1.5), "eps"), (dict(eps=1.0), "eps"), (dict(eps=0.0), "eps"), (dict(eps=-0.1), "eps"),
        (dict(eps=float("nan")), "eps"), (dict(eps=0.1, b=0.0), "b"), (dict(eps=0.1, b=-1.0), "b"),
        (dict(eps=0.1, K2=1.0), "K2"), (dict(eps=0.1, K2=0.5), "K2"), (dict(eps=0.1, K2=float("inf")), "K2"),
    ],
)
def test_paper_params_reject_bad_values_naming_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=rf"^{name} = .*(admissible range|not a finite)"):
        Params.paper(**kwargs)


def test_physical_params_reject_singular_inertia_and_negative_values():
    with pytest.raises(ValueError, match="not positive definite"):
        Params.physical(m_c=1.0, m_r=0.1, I_c=0.1, I_r=0.0, a=0.0, b=1.0)
    with pytest.raises(ValueError, match=r"^m_c = .*admissible range \(0, inf\)"):
        Params.physical(m_c=0.0, m_r=0.1, I_c=0.1, I_r=0.1, a=0.1, b=1.0)
    with pytest.raises(ValueError, match=r"^I_r = .*admissible range \[0, inf\)"):
        Params.physical(m_c=1.0, m_r=0.1, I_c=0.1, I_r=-0.1, a=0.1, b=1.0)


def test_the_constructor_checks_as_the_physical_form_does_naming_the_argument():
    with pytest.raises(TypeError, match=r"^m_r = 'x' must be a real number"):
        Params(-1, "x", None, 0, 0, 0)
    with pytest.raises(ValueError, match=r"^m_c = -1.0 is outside the admissible range \(0, inf\)"):
        Params(-1.0, 0.1, 0.1, 0.1, 0.1, 1.0)
    with pytest.raises(ValueError, match=r"^b = 0.0 is outside"):
        Params(1.0, 0.1, 0.1, 0.1, 0.1, 0.0)
    with pytest.raises(ValueError, match="not positive definite"):
        Params(1.0, 0.1, 0.1, 0.0, 0.0, 1.0)
    assert Params(2, 0, 1, 1, 0, 1).m_c == 2.0 and isinstance(Params(2, 0, 1, 1, 0, 1).m_c, float)


def test_only_the_formal_system_admits_a_non_positive_sleigh_mass():
    formal = Params.paper(eps=2.0, formal=True)
    assert formal.m_c == -1.0 and Params(*formal.values, formal=True) == formal
    with pytest.raises(ValueError, match=r"^m_c = -1.0 is outside the admissible range \(0, inf\)"):
        Params(*formal.values)
    with pytest.raises(ValueError, match=r"^m_c = -3.0 .*the total mass m_c \+ m_r must be positive"):
        Params(-3.0, 2.0, 0.1, 8.0, 2.0, 1.0, formal=True)


@pytest.mark.parametrize("make, name", [
    (lambda: Params(1e308, 1.0, 1.0, 1.0, 0.1, 1.0), "m_c"),
    (lambda: Params.physical(m_c=1.0, m_r=1.0, I_c=1.0, I_r=1e308, a=0.1, b=1.0), "I_r"),
    (lambda: Params.physical(m_c=1.0, m_r=1e200, I_c=1.0, I_r=1.0, a=0.1, b=1.0), "m_r"),
    (lambda: Params.paper(eps=0.1, b=1e200), "b"),
    (lambda: Params.paper(eps=1e120, formal=True), "eps"),
])
def test_parameters_that_overflow_are_refused_naming_the_largest(make, name):
    with pytest.raises(ValueError, match=rf"^{name} = [0-9.e+]+ is too large: .* overflow"):
        make()


def test_integrate_refuses_a_negative_mass_system_naming_it():
    with pytest.raises(ValueError, match=r"^m_c = -1.0 is outside"):
        integrate(Params(-1.0, 0.1, 0.1, 0.1, 0.1, 1.0), REF, [0.0, 1.0])


def test_paper_form_round_trips_through_physical_parameters():
    p = Params.paper(eps=0.1, b=2.0, K2=1.3)
    assert p.is_paper_form
    assert (p.eps, p.b, p.K2) == pytest.approx((0.1, 2.0, 1.3), rel=1e-14)
    assert Params.paper(eps=0.1).K2 == pytest.approx(1.1)  # default K2 = 1 + eps
    q = Params.physical(**{k: getattr(p, k) for k in PARAM_NAMES})
    assert q == p and q.is_paper_form
    assert not Params.physical(m_c=2.0, m_r=0.1, I_c=0.3, I_r=0.01, a=0.2, b=1.0).is_paper_form


def test_rhs_is_vectorised(rng):
    p = Params.paper(eps=0.2)
    Y = rng.uniform(-1, 1, (5, 3, 4))
    out = equations.rhs(Y, p)
    assert out.shape == Y.shape
    assert np.allclose(out[2, 1], equations.rhs(Y[2, 1], p), rtol=0, atol=1e-15)
    assert equations.energy(Y, p).shape == (5, 3)
    assert equations.jacobian(Y, p).shape == (5, 3, 4, 4)


def test_jacobian_matches_finite_differences(rng):
    p = Params.paper(eps=0.3, b=1.5)
    y = rng.uniform(-1, 1, 4)
    J = equations.jacobian(y, p)
    h = 1e-6
    for j in range(4):
        e = np.zeros(4)
        e[j] = h
        fd = (equations.rhs(y + e, p) - equations.rhs(y - e, p)) / (2 * h)
        assert np.allclose(J[:, j], fd, rtol=1e-7, atol=1e-8)


def test_energy_is_a_first_integral_of_the_vector_field(rng):
    """dE/dt = grad E . f = 0 pointwise, independently of any integrator."""
    p = Params.paper(eps=0.4, b=0.7, K2=1.8)
    for y in rng.uniform(-2, 2, (20, 4)):
        h = 1e-6
        grad = np.array([(equations.energy(y + h * e, p) - equations.energy(y - h * e, p)) / (2 * h)
                         for e in np.eye(4)])
        assert abs(grad @ equations.rhs(y, p)) < 1e-8 * (1 + np.abs(equations.rhs(y, p)).sum())


def test_only_equilibria_have_zero_angular_velocities(rng):
    p = Params.paper(eps=0.1)
    for u, de in rng.uniform(-2, 2, (10, 2)):
        assert np.allclose(equations.rhs([u, 0.0, 0.0, de], p), 0.0, atol=1e-15)


@pytest.mark.parametrize("eps", [0.01, 0.1, 0.5])
def test_energy_drift_below_1e10_over_1e4_time_units(eps):
    p = Params.paper(eps=eps)
    ds = integrate(p, REF, sample_grid(0.0, 1e4, 1.0))
    assert ds.attrs["energy_max_rel_drift"] < 1e-10, ds.attrs["energy_max_rel_drift"]


def test_sleigh0_closed_form_matches_integration():
    b, K2 = 1.3, 1.2
    p = Params.sleigh0(b=b, K2=K2)
    for u0, Om0 in [(0.0, 1.0), (0.3, -0.4), (-0.5, 0.2)]:
        t = np.linspace(0, 30, 301)
        ds = integrate(p, [u0, Om0, 0.7, 0.0], t, kinematics=True)
        u_cf, Om_cf, th_cf = sleigh0.closed_form(t, u0, Om0, b, K2)
        assert np.max(np.abs(ds.u - u_cf)) < 1e-10
        assert np.max(np.abs(ds.Omega - Om_cf)) < 1e-10
        assert np.max(np.abs(ds.theta - th_cf)) < 1e-10
        assert np.allclose(ds.omega, 0.7, rtol=0, atol=1e-12)  # decoupled rotor


def test_sleigh0_closed_form_solves_its_ode():
    b, K2 = 0.8, 1.4
    t = np.linspace(-5, 5, 2001)
    u, Om, _ = sleigh0.closed_form(t, 0.2, 0.6, b, K2)
    du, dOm = np.gradient(u, t), np.gradient(Om, t)
    rhs = sleigh0.rhs(np.stack([u, Om], axis=-1), b, K2)
    assert np.max(np.abs(du - rhs[:, 0])[1:-1]) < 1e-4
    assert np.max(np.abs(dOm - rhs[:, 1])[1:-1]) < 1e-4
    V2 = 0.2**2 + K2 * b**2 * 0.6**2  # the closed form stays on its energy ellipse
    assert np.allclose(u**2 + K2 * b**2 * Om**2, V2, rtol=1e-13)


@pytest.mark.parametrize("c", [2.0, 0.5])
def test_time_scaling_symmetry(c):
    """(c u, c Omega, c omega, delta)(c t) is a solution: compare on a short horizon."""
    p = Params.paper(eps=0.1)
    y0 = np.array([0.05, 0.1, 1.0, 0.3])
    T = 50.0
    base = integrate(p, y0, np.linspace(0, T, 101))
    scaled = integrate(p, np.r_[c * y0[:3], y0[3]], np.linspace(0, T / c, 101))
    for i, name in enumerate(equations.STATE_NAMES):
        factor = c if i < 3 else 1.0
        assert np.max(np.abs(scaled[name].values - factor * base[name].values)) < 1e-9


def test_reversibility():
    """(-u, -Omega, -omega, delta)(-t) is a solution: run forward, flip, run forward again."""
    p = Params.paper(eps=0.1)
    y0 = np.array([0.05, 0.1, 1.0, 0.3])
    T = 50.0
    fwd = integrate(p, y0, [0.0, T])
    y1 = np.array([fwd[n].values[-1] for n in equations.STATE_NAMES])
    back = integrate(p, np.r_[-y1[:3], y1[3]], [0.0, T])
    y2 = np.array([back[n].values[-1] for n in equations.STATE_NAMES])
    assert np.max(np.abs(np.r_[-y2[:3], y2[3]] - y0)) < 1e-9


def test_energy_label_and_rescaling():
    p = Params.paper(eps=0.1)
    assert float(energy_label(REF, p)) == pytest.approx(REFERENCE_LABEL, rel=1e-14)
    y = state_at_label(REF, p, 0.8313)
    assert float(energy_label(y, p)) == pytest.approx(0.8313, rel=1e-12)
    assert y[3] == REF[3] and y[1] / REF[1] == pytest.approx(math.sqrt(0.8313 / 0.1127))
    with pytest.raises(ValueError, match="energy label"):
        state_at_label(REF, p, -1.0)


def test_default_tolerance_is_double_epsilon():
    assert DEFAULT_TOL == np.finfo(float).eps


def test_eps_above_one_is_refused_unless_formal():
    with pytest.raises(ValueError, match=r"^eps = 25.0 .*admissible range \(0, 1\).*formal=True"):
        Params.paper(eps=25.0)
    p = Params.paper(eps=25.0, formal=True)
    assert p.m_c < 0 and p.eps == pytest.approx(25.0)
    y = np.array([0.1, 0.2, 0.3, 0.4])
    assert float(equations.energy(y, p)) > 0  # the inertia stays positive definite


def test_sleigh0_field_is_the_derived_model_with_a_decoupled_rotor(rng):
    b, K2 = 1.3, 1.2
    p = Params.sleigh0(b=b, K2=K2)
    Y = np.c_[rng.uniform(-2, 2, (50, 2)), rng.uniform(-2, 2, 50), rng.uniform(-7, 7, 50)]
    assert np.allclose(sleigh0.rhs(Y[:, :2], b, K2), equations.rhs(Y, p)[:, :2], rtol=1e-13, atol=1e-14)


@pytest.mark.parametrize("params", [Params.paper(eps=0.1), Params.paper(eps=50.0, formal=True),
                                    Params.paper(eps=0.3, b=0.25, K2=1.5)])
def test_the_compiled_sleigh_is_the_lambdified_derivation(params, rng):
    """heyoka's system (polynomial form, coefficients as runtime parameters) against the explicit
    rhs lambdified by SymPy, to rounding relative to the field's size."""
    from sleighsim.engine import integrators

    f = integrators.rhs_function()
    Y = rng.normal(size=(4, 200))
    got = f(Y, pars=np.tile(equations.heyoka_pars(params)[:, None], (1, 200)))
    want = equations.rhs(Y.T, params).T
    assert np.max(np.abs(got - want)) <= 1e-13 * np.max(np.abs(want))


@pytest.mark.parametrize("kinematics, k", [(False, 0), (True, 0), (False, 2)])
def test_the_rhs_with_its_parameters_compiled_in_is_the_one_with_runtime_parameters(kinematics, k, rng):
    """SciPy's fast rhs (parameter values compiled in as numbers) against the runtime-parameter cfunc,
    and one compilation per parameter set."""
    from sleighsim.engine import integrators

    p = Params.paper(eps=0.3, b=0.25, K2=1.5)
    g = integrators.rhs_function(kinematics, k, params=p)
    n = 7 if kinematics else 4 + 4 * k
    Y = rng.normal(size=(n, 50))
    want = integrators.rhs_function(kinematics, k)(Y, pars=np.tile(equations.heyoka_pars(p)[:, None], (1, 50)))
    assert np.max(np.abs(g(Y) - want)) <= 1e-14 * np.max(np.abs(want))
    other = integrators.rhs_function(kinematics, k, params=Params.paper(eps=0.1))
    assert np.max(np.abs(other(Y) - want)) > 1e-3 * np.max(np.abs(want))
    assert integrators.rhs_function(kinematics, k, params=Params.paper(eps=0.3, b=0.25, K2=1.5)) is g


def test_set_pars_fills_every_lane_in_the_integrators_precision_and_a_stale_vector_is_refused():
    from sleighsim.engine import integrators

    p = Params.paper(eps=0.2, b=0.5)
    ta, _ = integrators.sleigh_tangent_batch(2, DEFAULT_TOL, True)
    integrators.set_pars(ta, p)
    assert ta.pars.shape == (equations.n_heyoka_pars(), 2)
    assert np.array_equal(ta.pars[:, 0], equations.heyoka_pars(p)) and np.array_equal(ta.pars[:, 1], ta.pars[:, 0])
    ld, _ = integrators.flow(False, 1e-19, Precision.LONG_DOUBLE)
    integrators.set_pars(ld, p)
    assert ld.pars.dtype == np.longdouble
    assert np.array_equal(ld.pars, equations.heyoka_pars(p, np.longdouble))
    assert not np.array_equal(ld.pars, equations.heyoka_pars(p).astype(np.longdouble))  # K computed in long double
    with pytest.raises(ValueError):  # the physical parameters alone would leave the coefficients stale
        ld.pars[:] = p.values


def test_heyoka_polynomial_writes_numbers_units_and_powers():
    """Every kind of term _heyoka_polynomial meets: a named coefficient, a plain number, a unit
    coefficient and a power (as repeated factors), checked by evaluating the compiled expression."""
    import heyoka as hy
    import sympy as sp

    from sleighsim.model import mechanics as mech

    k = sp.Symbol("K0")
    u, Om, om, de = hy.make_vars("u", "Omega", "omega", "delta")
    symbols = {mech.u: u, mech.Omega: Om, mech.omega: om, mech.S: hy.sin(de), mech.C: hy.cos(de), k: hy.par[0]}
    expr = equations._heyoka_polynomial(k * mech.Omega + 3 * mech.omega * mech.S**3 + mech.u, symbols)
    f = hy.cfunc([expr], vars=[u, Om, om, de])
    y, K0 = np.array([0.3, -1.2, 0.7, 0.9]), 2.5
    want = K0 * y[1] + 3 * y[2] * math.sin(y[3]) ** 3 + y[0]
    assert f(y, pars=[K0])[0] == pytest.approx(want, rel=1e-14)


@pytest.mark.parametrize("value", [0.0, -1.0, math.nan, math.inf, "x", None])
def test_positive_refuses_naming_the_argument(value):
    with pytest.raises(ValueError, match=r"^tau must be"):
        positive("tau", value)


def test_positive_returns_a_float():
    assert positive("tau", 2) == 2.0 and isinstance(positive("tau", 2), float)
