"""Lyapunov engine on textbook systems, the 0-1 test, and the sleigh's spectrum structure."""

import math

import numpy as np
import pytest

from sleighsim.analysis import fits
from sleighsim.chaos import benettin, zero_one
from sleighsim.engine import integrators
from sleighsim.engine.integrate import final_state, integrate
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE, b_image, state_at_label
from sleighsim.precision import Precision
from sleighsim.scenes import grid, verdict_tangent


def test_lorenz_spectrum_matches_published_values(hy):
    x, y, z = hy.make_vars("x", "y", "z")
    sys = [(x, 10.0 * (y - x)), (y, x * (28.0 - z) - y), (z, x * y - 8.0 / 3.0 * z)]
    ta, n, _ = integrators.tangent_integrator(sys, 3)
    r = benettin.benettin(ta, n, 3, [1.0, 1.0, 20.0], t_align=100.0, T=10000.0, tau=0.5)
    lam = r["exponents"]
    assert lam[0] == pytest.approx(0.906, rel=0.01)
    assert lam[2] == pytest.approx(-14.572, rel=0.01)
    assert abs(lam[1]) < 0.01
    assert lam.sum() == pytest.approx(-(10.0 + 1.0 + 8.0 / 3.0), rel=1e-6)  # constant divergence
    assert np.all(r["stderr"] > 0) and r["stderr"][0] < 0.02


def test_torus_flow_exponents_decay_like_one_over_T(hy):
    """theta_i' = w_i + a_i cos(theta_i): the tangent map is f(theta(T)) / f(theta(0)), so
    |lambda(T)| T is at most log(max f / min f) summed over both circles."""
    a, b = hy.make_vars("a", "b")
    sys = [(a, 1.0 + 0.5 * hy.cos(a)), (b, math.sqrt(2) + 0.3 * hy.cos(b))]
    ta, n, _ = integrators.tangent_integrator(sys, 2)
    r = benettin.benettin(ta, n, 2, [0.1, 0.2], t_align=0.0, T=1e5, tau=1.0)
    bound = math.log(1.5 / 0.5) + math.log((math.sqrt(2) + 0.3) / (math.sqrt(2) - 0.3))
    assert np.all(np.abs(r["running"]) * r["T_grid"][:, None] <= bound + 1e-9)
    assert np.all(np.abs(r["exponents"]) <= bound / 1e5)
    slope = np.polyfit(np.log(r["T_grid"][-20:]), np.log(np.abs(r["running"][-20:, 0]) + 1e-300), 1)[0]
    assert slope < -0.5


def test_alignment_and_renormalisation_interval_do_not_change_lorenz_lambda1(hy):
    x, y, z = hy.make_vars("x", "y", "z")
    sys = [(x, 10.0 * (y - x)), (y, x * (28.0 - z) - y), (z, x * y - 8.0 / 3.0 * z)]
    ta, n, _ = integrators.tangent_integrator(sys, 1)
    a = benettin.benettin(ta, n, 1, [1.0, 1.0, 20.0], t_align=50.0, T=5000.0, tau=0.1)["exponents"][0]
    b = benettin.benettin(ta, n, 1, [1.0, 1.0, 20.0], t_align=50.0, T=5000.0, tau=2.0)["exponents"][0]
    assert a == pytest.approx(0.906, rel=0.03) and b == pytest.approx(a, rel=0.03)


def test_benettin_rejects_bad_settings(hy):
    x = hy.make_vars("x")
    ta, n, _ = integrators.tangent_integrator([(x, -x)], 1)
    with pytest.raises(ValueError, match="tau"):
        benettin.benettin(ta, n, 1, [1.0], t_align=0.0, T=10.0, tau=0.0)
    with pytest.raises(ValueError, match="k = 2"):
        integrators.tangent_integrator([(x, -x)], 2)


def test_zero_one_test_separates_regular_from_chaotic():
    n = np.arange(3000)
    periodic = np.sin(0.7 * n)
    quasi = np.sin(0.7 * n) + 0.5 * np.sin(0.7 * math.sqrt(2) * n)
    x = np.empty(3000)
    x[0] = 0.3
    for i in range(2999):
        x[i + 1] = 3.97 * x[i] * (1 - x[i])  # chaotic logistic map
    assert zero_one.zero_one_test(periodic)["K"] < 0.1
    assert zero_one.zero_one_test(quasi)["K"] < 0.1
    assert zero_one.zero_one_test(x)["K"] > 0.9


def test_sleigh_exponents_sum_to_the_mean_divergence():
    """Sum of all exponents = (1/T) integral of trace J, exactly (det of the tangent map),
    computed here without tangent vectors; the near-zero pair needs the long run."""
    p = Params.paper(eps=0.1)
    y = REFERENCE_STATE
    ta, _ = integrators.sleigh_tangent(4, 1e-13, True)
    integrators.set_pars(ta, p)
    r = benettin.benettin(ta, 4, 4, y, t_align=0.0, T=2000.0, tau=5.0)
    lam = r["exponents"]
    div = benettin.mean_divergence(p, y, 2000.0, 1e-13)
    assert lam.sum() == pytest.approx(div, abs=1e-9)
    assert abs(div) > 1e-5  # the flow contracts phase-space volume (C18) although E is invariant


def test_grid_axes_are_log_spaced_and_cover_the_range():
    cfg = {"eps_range": [0.02, 0.5], "n_eps": 13, "b_range": [0.25, 4.0], "n_b": 12}
    eps, bs = grid.axes(cfg)
    assert eps.size == 13 and bs.size == 12 and eps[0] == 0.02 and bs[-1] == pytest.approx(4.0)
    assert np.allclose(np.diff(np.log(eps)), np.log(25) / 12)
    assert eps[6] == pytest.approx(0.1)  # an odd n_eps puts the reference eps on the grid


def test_grid_rows_left_to_another_config_are_stored_as_nan_with_status_elsewhere_and_cost_nothing():
    from pathlib import Path

    from sleighsim.scenes.grid import grid_rows

    cfg = {"eps_range": [0.02, 0.5], "n_eps": 13, "b_range": [0.25, 4.0], "n_b": 12, "n_chunks": 13,
           "reference_eps": 0.1, "elsewhere": {"eps": [0.02], "config": "config/cluster.yaml"},
           "verdict": {"eps_min": 0.2, "realizations": 3, "T": 5e5}}
    assert grid.elsewhere(cfg).tolist() == [True] + [False] * 12
    record = Path(__file__).resolve().parents[2] / "benchmarks" / "judge_power.yaml"
    ds = grid.chunk(cfg, 0, scene="g", inputs={"power": record})  # chunk 0 holds row 0 alone: nothing is integrated
    assert ds.eps.values.tolist() == [0.02] and np.isnan(ds.lambda_1.values[0])
    assert grid.STATUS[int(ds.status_code.values[0])] == "elsewhere" and ds.attrs["rule"] == ""
    assert ds.row_verdict.values[0] == "not judged" and "config/cluster.yaml" in ds.row_verdict_reason.values[0]
    work = dict(t_pre=2e4, t_pre_min=2e4, replicas=8, replica_spacing=2e4, t_align=1e3, T_round=2e4, max_rounds=10)
    rows = grid_rows({**cfg, **work})
    assert rows[0] == (0.02, 0.0) and all(w > 0 for _, w in rows[1:])
    with pytest.raises(ValueError, match="elsewhere.eps: 0.03 is not a row"):
        grid.elsewhere({**cfg, "elsewhere": {"eps": [0.03]}})
    with pytest.raises(ValueError, match="reference row"):
        grid.elsewhere({**cfg, "elsewhere": {"eps": [0.1]}})


def test_loglog_fit_recovers_a_power_law():
    x = np.geomspace(1e-3, 1e3, 7)
    slope, _, err = fits.loglog(x, 2e-4 * x**0.5, 1e-6 * x**0.5, min_points=3)
    assert slope == pytest.approx(0.5, abs=1e-9) and 0 < err < 1e-3


@pytest.mark.parametrize("k", [1, 4])
def test_batch_lanes_match_the_scalar_benettin_run(k):
    """Two systems (different params and renormalisation intervals) in SIMD lanes, k vectors each."""
    ps = [Params.paper(eps=0.1, b=1.0), Params.paper(eps=0.2, b=0.5)]
    ys = np.array([state_at_label([0.0, 0.1, 1.0, 0.0], p, 0.1127) for p in ps])
    taus = np.array([5.0, 3.0])
    ta, n, _ = integrators.tangent_integrator_batch(equations.heyoka_system(), 2, npars=equations.n_heyoka_pars(),
                                                    compact_mode=True, k=k)
    ta.pars[:] = np.array([equations.heyoka_pars(p) for p in ps]).T
    batch = benettin.batch_benettin(ta, n, k, ys, taus, t_align_steps=4, n_steps=40)
    lam = batch["log_growth"].sum(axis=0) / (40 * taus)  # (k, lanes)
    for j, p in enumerate(ps):
        ts, _, _ = integrators.tangent_integrator(equations.heyoka_system(), k, pars=equations.heyoka_pars(p),
                                                  compact_mode=True)
        one = benettin.benettin(ts, 4, k, ys[j], t_align=4 * taus[j], T=40 * taus[j], tau=taus[j], n_blocks=4)
        assert lam[:, j] == pytest.approx(one["exponents"], rel=1e-9, abs=1e-12)
        assert batch["log_growth"][:, :, j] == pytest.approx(one["log_growth"], rel=1e-9, abs=1e-12)
    with pytest.raises(ValueError):
        benettin.batch_benettin(ta, n, k, ys[:1], taus[:1], n_steps=10)


def _lorenz(hy):
    x, y, z = hy.make_vars("x", "y", "z")
    return [(x, 10.0 * (y - x)), (y, x * (28.0 - z) - y), (z, x * y - 8.0 / 3.0 * z)]


def test_replicas_resolve_lorenz_and_stop_as_converged(hy):
    ta, n, _ = integrators.tangent_integrator_batch(_lorenz(hy), 4, k=3)
    y0s = np.array([[1.0, 1.0, 20.0], [2.0, 1.0, 20.0], [1.0, 3.0, 20.0], [1.0, 1.0, 25.0]])
    r = benettin.replica_exponents(ta, n, 3, y0s, 0.5, T_round=500.0, max_rounds=6, target_rel=0.01, t_align=50.0,
                                   regular_floor=0.01)
    assert r["status"] == "converged" and r["stderr"][0] <= 0.01 * r["exponents"][0]
    assert r["exponents"][0] == pytest.approx(0.906, rel=0.02) and r["exponents"][2] == pytest.approx(-14.572, rel=0.01)
    assert r["per_replica"].shape == (4, 3) and r["log_growth"].shape == (r["T"] / 0.5, 3, 4)
    assert np.allclose(r["per_replica"].sum(axis=1), -(10 + 1 + 8 / 3), rtol=1e-6)  # constant divergence


def test_replicas_call_a_torus_regular_and_cap_an_unresolved_run(hy):
    a, b = hy.make_vars("a", "b")
    torus = [(a, 1.0 + 0.5 * hy.cos(a)), (b, math.sqrt(2) + 0.3 * hy.cos(b))]
    ta, n, _ = integrators.tangent_integrator_batch(torus, 4)
    starts = np.array([[0.1, 0.2], [1.0, 2.0], [2.0, 0.5], [3.0, 4.0]])
    r = benettin.replica_exponents(ta, n, 1, starts, 1.0, T_round=2000.0, max_rounds=5, target_rel=0.1,
                                   regular_floor=0.01)
    assert r["status"] == "regular" and r["T"] == 2000.0
    r = benettin.replica_exponents(ta, n, 1, starts, 1.0, T_round=2000.0, max_rounds=2, target_rel=0.1,
                                   regular_floor=1e-3)  # a finer floor needs a longer run than the cap
    assert r["status"] == "capped" and r["T"] == 4000.0
    ta, n, _ = integrators.tangent_integrator_batch(_lorenz(hy), 2)
    r = benettin.replica_exponents(ta, n, 1, np.array([[1.0, 1.0, 20.0], [2.0, 1.0, 20.0]]), 0.5, T_round=5.0,
                                   max_rounds=2, target_rel=1e-6, regular_floor=0.01)  # short: nothing is resolved
    assert r["status"] == "capped" and r["T"] == 10.0 and len(r["history"]) == 2
    with pytest.raises(ValueError, match="at least 2 lanes"):
        benettin.replica_exponents(integrators.tangent_integrator_batch(_lorenz(hy), 1)[0], 3, 1, np.ones((1, 3)), 0.5,
                                   T_round=5.0, max_rounds=1, target_rel=0.1, regular_floor=0.01)


def test_b_image_maps_a_trajectory_at_one_b_onto_the_trajectory_at_another():
    """The grid starts every b of a row from one settled state: exact only if the symmetry holds."""
    y0 = state_at_label([0.03, 0.1, 1.0, 0.4], Params.paper(eps=0.2, b=1.0), 0.1127)
    ends = {}
    for b in (1.0, 2.5):
        p = Params.paper(eps=0.2, b=b)
        ends[b] = final_state(integrate(p, b_image(y0, 1.0, b), [0.0, 60.0], tol=1e-15))
    assert np.allclose(b_image(ends[1.0], 1.0, 2.5), ends[2.5], rtol=1e-9, atol=1e-11)
    assert not np.allclose(ends[1.0], ends[2.5], rtol=1e-3)  # u itself differs: the map is not the identity


def test_grid_horizons_scale_with_the_slow_time_and_pre_runs_with_one_over_eps_squared():
    cfg = {"energy_label": 0.1127, "reference_eps": 0.1, "t_pre": 2e4, "t_pre_min": 5e3, "eps_range": [0.02, 0.5],
           "n_eps": 13, "b_range": [0.25, 4.0], "n_b": 12}
    assert grid.slow_time(cfg, 0.1) == pytest.approx(1.0) and grid.slow_time(cfg, 0.02) == pytest.approx(5.0)
    assert grid.pre_run(cfg, 0.02) == pytest.approx(5e5)
    assert grid.pre_run(cfg, 0.5) == 5e3  # the floor
    assert grid.axes(cfg)[0][grid.reference_row(cfg)] == pytest.approx(0.1)


def test_megno_in_long_double_matches_double_where_both_are_accurate():
    """Over a short horizon from the reference state (no spike yet) the long-double MEGNO run and
    the double one give the same log growth per interval and the same <Y>; the long-double one is
    what the chaos verdict's precision check runs."""

    p = Params.paper(eps=0.1)
    y0 = state_at_label([0.0, 0.1, 1.0, 0.0], p, 0.1127)
    cfg = dict(tol=2.220446049250313e-16, T_megno=200.0, T_long_double=200.0,
               megno_samples=20, tau=10.0, compact_mode=True)
    a = verdict_tangent.megno_run(p, y0, cfg, precision=Precision.LONG_DOUBLE)
    b = verdict_tangent.megno_run(p, y0, cfg)
    ta, _ = integrators.sleigh_megno(Precision.LONG_DOUBLE.epsilon, Precision.LONG_DOUBLE)
    assert ta.state.dtype == np.longdouble and a["log_growth"].dtype == float
    assert a["log_growth"] == pytest.approx(b["log_growth"], rel=1e-9, abs=1e-11)
    assert a["Y_mean"] == pytest.approx(b["Y_mean"], rel=1e-8)
    assert np.abs(a["log_growth"]).max() > 1e-3  # the vector does change length: the comparison is not vacuous

@pytest.mark.parametrize("precision", [Precision.LONG_DOUBLE, Precision.QUAD])
def test_lane_loop_runs_the_batch_method_in_extended_precision(precision):
    """sleigh_tangent_lanes in an extended precision (a LaneLoop over one scalar integrator) gives the
    SIMD batch's log growth on a short horizon (the orbits have not separated yet), keeps each lane's
    own state, and refuses a lane clock other than 0."""
    from sleighsim.engine import integrators

    p = Params.paper(eps=0.1, b=1.0)
    ys = np.array([state_at_label(y, p, 0.1127) for y in ([0.0, 0.1, 1.0, 0.0], [0.05, 0.1, 1.0, 1.0])])
    taus = np.array([5.0, 3.0])
    runs = {}
    for prec in (Precision.DOUBLE, precision):
        lanes, _ = benettin.sleigh_tangent_lanes(2, prec.epsilon, True, k=2, precision=prec)
        integrators.set_pars(lanes, p)
        runs[prec] = benettin.batch_benettin(lanes, 4, 2, ys, taus, t_align_steps=2, n_steps=8)
    assert isinstance(lanes, benettin.LaneLoop) and lanes.state.dtype != np.float64
    assert runs[precision]["log_growth"] == pytest.approx(runs["double"]["log_growth"], rel=1e-8, abs=1e-10)
    assert runs[precision]["final_state"] == pytest.approx(runs["double"]["final_state"], rel=1e-9, abs=1e-11)
    assert not np.allclose(runs[precision]["final_state"][0], runs[precision]["final_state"][1])
    with pytest.raises(ValueError, match="from t = 0"):
        lanes.set_time(np.ones(2))
