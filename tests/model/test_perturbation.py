"""The perturbation hierarchy (derived, not transcribed), the fits and the transient-phase detector."""

import math

import numpy as np
import pytest
import sympy as sp

from sleighsim.analysis import fits
from sleighsim.engine import transient
from sleighsim.engine.hierarchy import integrate_hierarchy
from sleighsim.engine.transient import interval_groups
from sleighsim.model import equations, sleigh0
from sleighsim.model import mechanics as mech
from sleighsim.model import perturbation as pert
from sleighsim.model.params import Params
from sleighsim.scenes.hierarchy import convergence_study

REF = [0.0, 0.1, 1.0, 0.0]


def test_paper_form_equals_the_derived_system_when_kappa_is_K2_minus_1_over_eps():
    rng = np.random.default_rng(3)
    derived = [e.subs(mech.paper_substitution()) for e in mech.derive().rhs[:3]]
    for _ in range(5):
        u, Om, om, de = rng.uniform(-1, 1, 4)
        eps, K2, b = rng.uniform(0.05, 0.6), rng.uniform(1.01, 2.0), rng.uniform(0.3, 3)
        point = {mech.u: u, mech.Omega: Om, mech.omega: om, mech.delta: de, mech.eps: eps, mech.K2: K2, mech.b: b}
        for f, d in zip(pert.paper_form_rhs(), derived):
            got = float(f.subs(pert.kappa, (K2 - 1) / eps).subs(point))
            assert got == pytest.approx(float(d.subs(point)), rel=1e-12, abs=1e-14)


def test_order_zero_is_the_eps_zero_sleigh():
    h = pert.hierarchy(2)
    x = pert.symbols(2)
    u0, Om0 = x["u"][0], x["Omega"][0]
    assert sp.simplify(h["u"][0] - mech.b * Om0**2) == 0
    assert sp.simplify(h["Omega"][0] + u0 * Om0 / (mech.b * mech.K2)) == 0
    # and numerically against the closed form of the rotor-free sleigh
    t = np.linspace(0.0, 60.0, 301)
    ds = integrate_hierarchy(0, REF, t, K2=1.1)
    u_cf, Om_cf, _ = sleigh0.closed_form(t, 0.0, 0.1, 1.0, 1.1)
    assert np.max(np.abs(ds.u0.values - u_cf)) < 1e-13
    assert np.max(np.abs(ds.Omega0.values - Om_cf)) < 1e-13


def test_order_one_vanishes_for_the_papers_initial_data():
    # the order-1 equations are linear and homogeneous in the order-1 unknowns ...
    assert all(pert.forcing_terms(1, v) == [] for v in pert.VARS)
    # ... so zero initial data stay zero along the integration
    ds = integrate_hierarchy(2, REF, np.linspace(0.0, 50.0, 101))
    assert all(np.all(ds[f"{v}1"].values == 0.0) for v in pert.VARS)
    assert np.max(np.abs(ds.omega2.values)) > 0.1  # order 2 does not vanish


def test_order_three_forcing_vanishes_only_when_order_one_does():
    x = pert.symbols(3)
    zero1 = {x[v][1]: 0 for v in pert.VARS}
    forcing = {v: sp.sympify(sum(pert.forcing_terms(3, v))) for v in pert.VARS}
    assert any(f != 0 for f in forcing.values())
    assert all(f.subs(zero1) == 0 for f in forcing.values())


@pytest.mark.parametrize("order", [2, 4])
def test_truncated_series_converges_with_the_predicted_order(order):
    cfg = {"eps": [0.01, 0.02, 0.04, 0.08], "kappa": 1.0, "orders": [order], "y0": REF, "t_end": 10.0,
           "dt": 0.05, "tol": 2.0**-52}
    errs, slope, predicted = convergence_study(cfg)[order]
    assert predicted == order + 2  # odd orders vanish
    assert abs(slope - predicted) < 0.3, (slope, errs)
    assert np.all(np.diff(errs) > 0)


def test_printed_hierarchy_differs_only_where_the_mechanics_says():
    rows = pert.compare_printed()
    eqs = {r["equation"] for r in rows}
    # the printed Omega equations agree with the derivation term by term
    assert not any(e.startswith("dOmega") for e in eqs)
    # the omega^2 term of udot2 comes from the printed udot, which does not follow from the mechanics
    hit = [r for r in rows if r["equation"] == "du2/dt" and r["term"] == "omega0**2*cos(delta0)"]
    assert len(hit) == 1 and hit[0]["derived"] == "b" and hit[0]["printed"] == "K2*b"


def test_model_is_symmetric_under_the_mirror_map():
    p = Params.paper(eps=0.1)
    y = np.random.default_rng(0).uniform(-1, 1, (50, 4))
    mirror = np.array([1.0, -1.0, -1.0, -1.0])
    assert np.allclose(equations.rhs(y * mirror, p), equations.rhs(y, p) * mirror, atol=1e-15)


def test_line_plus_sinusoid_recovers_a_known_signal():
    t = np.linspace(10.0, 110.0, 5001)
    x = 0.3 + 0.04 * t + 0.25 * np.sin(2.1 * t + 0.7)
    f = fits.line_plus_sinusoid(t, x, 2.0)
    assert f["period"] == pytest.approx(2 * math.pi / 2.1, rel=1e-9)
    assert f["amplitude"] == pytest.approx(0.25, rel=1e-8)
    assert f["slope"] == pytest.approx(0.04, rel=1e-8)
    assert f["period_uncertainty"] < 1e-8


def test_phase_against_recovers_a_known_phase():
    angle = np.linspace(0.0, -60.0, 3001)
    x = -0.9 * np.sin(angle + 1.47)
    ph = fits.phase_against(x, angle)
    assert ph["amplitude"] == pytest.approx(0.9, rel=1e-12)
    assert ph["phase"] == pytest.approx(1.47, abs=1e-12)


def test_phase_detector_finds_known_change_points():
    dt = 0.25
    t = np.arange(0.0, 20000.0, dt)
    # sleigh-like rise of u to t = 300, then a slow decay; oscillations ride on top
    u = np.where(t < 300, t / 300, 1 - (t - 300) / 4e4) + 0.05 * np.sin(2 * t)
    spikes = [4000.0, 6000.0, 8000.0, 10000.0, 12000.0, 14000.0, 16000.0, 18000.0]
    Omega = 0.1 * np.sin(3 * t) + sum(2.0 * np.exp(-((t - s) / 5) ** 2) for s in spikes)
    omega = 3 + 0.1 * np.sin(t)
    ph = transient.phases(t, u, Omega, omega)
    assert ph["sleigh_phase_end"] == pytest.approx(0.99 * 300.0, abs=15.0)
    assert ph["first_spike"] == pytest.approx(4000.0, abs=1.0)
    assert ph["spike_interval_mean"] == pytest.approx(2000.0, abs=1.0)
    assert ph["n_spikes"] == len(spikes)


def test_interval_groups():
    intervals = np.array([2000.0, 2040.0, 1300.0, np.nan, 1310.0, 2090.0])
    assert interval_groups(intervals, 0.05).tolist() == [0, 0, 1, -1, 1, 0]
