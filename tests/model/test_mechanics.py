"""The derivation against the matrix form of docs/equations.md and the paper's printed equations."""

import numpy as np
import pytest
import sympy as sp

from sleighsim.model import equations, printed
from sleighsim.model import mechanics as mech
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE


def test_derived_matrix_form_matches_lagrange_multiplier_form():
    d = mech.derive()
    m = mech.m_c + mech.m_r
    s, c = sp.sin(mech.delta), sp.cos(mech.delta)
    ma = mech.m_r * mech.a
    M = sp.Matrix([[m, 0, ma * s], [0, mech.I_c + m * mech.b**2, ma * mech.b * c],
                   [ma * s, ma * mech.b * c, mech.I_r + mech.m_r * mech.a**2]])
    u, Om, om = mech.u, mech.Omega, mech.omega
    f = sp.Matrix([m * mech.b * Om**2 + ma * om**2 * c,
                   -m * mech.b * u * Om - ma * mech.b * om**2 * s,
                   ma * Om * (mech.b * Om * s - u * c)])
    assert sp.expand(d.M - M) == sp.zeros(3, 3)
    assert sp.expand(d.f - f) == sp.zeros(3, 1)


def test_projected_equations_do_not_depend_on_heading(rng):
    """The theta = 0 evaluation is justified: the projection is rotation invariant."""
    th = sp.Symbol("th")
    general = mech.projected_equations(th)
    at_zero = mech.projected_equations(0)
    syms = sorted(general.free_symbols - {th}, key=str)
    f_gen = sp.lambdify([th, *syms], list(general))
    f_zero = sp.lambdify(syms, list(at_zero))
    for _ in range(20):
        vals = rng.uniform(0.1, 2.0, len(syms))
        assert np.allclose(f_gen(rng.uniform(-7, 7), *vals), f_zero(*vals), rtol=1e-12, atol=1e-12)


def test_printed_Omegadot_and_omegadot_equal_derived_udot_differs(rng):
    worst = {0: 0.0, 1: 0.0, 2: 0.0}
    for _ in range(200):
        eps = rng.uniform(0.01, 0.9)
        b = rng.uniform(0.2, 5.0)
        K2 = 1.0 + rng.uniform(0.01, 2.0)
        y = rng.uniform(-2, 2, 4)
        p = Params.paper(eps=eps, b=b, K2=K2)
        derived = equations.rhs(y, p)
        as_printed = printed.rhs(y, eps, b, K2)
        scale = np.abs(derived) + 1e-300
        for i in range(3):
            worst[i] = max(worst[i], abs(derived[i] - as_printed[i]) / max(scale[i], 1e-3))
        assert derived[3] == as_printed[3]
    assert worst[1] < 1e-12 and worst[2] < 1e-12, worst
    assert worst[0] > 1e-2, "the printed udot should differ from the mechanics"


def test_printed_udot_differs_by_the_omega_squared_term():
    """docs/equations.md: printed b w^2 eps (eps (K2-1) + K2) cos / D vs derived
    b w^2 eps^2 (K2^2 + eps (K2-1)) cos / D."""
    sub = mech.paper_substitution()
    derived = sp.together(mech.derive().rhs[0].subs(sub))
    udot_printed = printed.equations()[0]
    D = mech.eps * (mech.K2 - 1) * sp.cos(mech.delta) ** 2 + mech.K2**2
    bw2c = mech.b * mech.omega**2 * sp.cos(mech.delta) / D
    expected_gap = bw2c * (mech.eps * (mech.eps * (mech.K2 - 1) + mech.K2)
                           - mech.eps**2 * (mech.K2**2 + mech.eps * (mech.K2 - 1)))
    gap = sp.lambdify((*mech.STATE, mech.eps, mech.b, mech.K2), udot_printed - derived - expected_gap)
    rng = np.random.default_rng(1)
    for _ in range(50):
        args = (*rng.uniform(-2, 2, 4), rng.uniform(0.01, 0.9), rng.uniform(0.2, 3), 1 + rng.uniform(0.01, 2))
        assert abs(gap(*args)) < 1e-12


def test_paper_energy_formula_matches_mechanics(rng):
    eps, b, K2 = mech.eps, mech.b, mech.K2
    u, Om, om, de = mech.STATE
    science = (u**2 / 2 + K2 * b**2 * Om**2 / 2 + eps**2 * b * om * (u * sp.sin(de) + b * Om * sp.cos(de))
               + eps**3 * b**2 * (K2 + eps) * om**2 / 2)
    derived = mech.derive().energy.subs(mech.paper_substitution())
    f = sp.lambdify((*mech.STATE, eps, b, K2), derived - science)
    for _ in range(30):
        assert abs(f(*rng.uniform(-2, 2, 4), rng.uniform(0.01, 0.9), rng.uniform(0.2, 3), 1.5)) < 1e-12


def test_reference_state_energy_is_not_the_printed_label():
    E = float(equations.energy(REFERENCE_STATE, Params.paper(eps=0.1)))
    assert E == pytest.approx(0.0071, rel=1e-12)  # 0.0055 + 0.001 + 0.0006, not 0.1127


def test_b_is_a_length_scale_at_fixed_K2():
    """(u / b, Omega, omega, delta) obeys b-free equations: the grid's b axis is one system."""
    rhs, v = mech.b_free_form()
    assert all(mech.b not in e.free_symbols for e in rhs)
    assert any(mech.eps in e.free_symbols for e in rhs) and v in rhs[1].free_symbols


PARAM_SETS = [Params.paper(eps=0.1), Params.paper(eps=0.02, b=3.0, K2=1.3), Params.paper(eps=25.0, K2=1.1, formal=True),
              Params.physical(m_c=2.0, m_r=0.0, I_c=0.5, I_r=0.3, a=0.0, b=1.0)]


@pytest.mark.parametrize("params", PARAM_SETS)
def test_polynomial_form_is_the_derived_vector_field(params, rng):
    """N_i / D with S = sin delta, C = cos delta and K_j = its coefficients is the explicit rhs
    (random states; the paper's form, a formal eps >= 1 and a rotor without mass at the centre)."""
    args = (*mech.STATE, *mech.PHYSICAL)
    poly = sp.lambdify(args, mech.derive().polynomial.explicit())
    explicit = sp.lambdify(args, list(mech.derive().rhs[:3]))
    for y in rng.normal(size=(20, 4)):
        want = np.array(explicit(*y, *params.values), float)
        assert np.allclose(poly(*y, *params.values), want, rtol=1e-12, atol=1e-14 * np.abs(want).max())


def test_polynomial_form_names_each_parameter_coefficient_once_and_needs_a_common_denominator():
    D = 2 + mech.m_r * sp.sin(mech.delta) ** 2
    form = mech._polynomial_form((mech.m_c * mech.u / D, -mech.m_c * mech.Omega * sp.cos(mech.delta) ** 2 / D,
                                  3 * mech.omega / D))
    assert len(form.K) == 3  # m_c, -m_c (C^2 -> 1 - S^2 gives -m_c and +m_c S^2), m_r; the 3 stays a number
    assert set(form.coefficients) == {mech.m_c, -mech.m_c, mech.m_r}
    assert form.numerators[2] == 3 * mech.omega
    with pytest.raises(ValueError, match="denominators"):
        mech._polynomial_form((mech.u / D, mech.Omega / (1 + D)))
