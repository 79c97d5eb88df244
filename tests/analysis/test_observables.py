"""A scene's ladder (sleighsim.analysis.observables): the agreement and convergence rules on each branch,
the uncertainty each observable states, the same-start check, and a Poincare scene run in double
and long double from one settled point on a short horizon that both arithmetics follow."""

import math

import numpy as np
import pytest
import xarray as xr

from sleighsim.analysis import observables
from sleighsim.precision import parsed
from sleighsim.scenes import catalog
from sleighsim.scenes.steady_state import poincare_maps


def test_agrees_on_each_branch():
    agrees = observables.agrees
    assert agrees((1.0, 0.1), (1.2, 0.1), count=False)            # 0.2 <= 2 sqrt(0.02) = 0.28
    assert not agrees((1.0, 0.1), (1.3, 0.1), count=False)        # 0.3 > 0.28
    assert not agrees((1.0, 0.0), (1.0 + 1e-6, 0.0), count=False)  # zero uncertainty floored at 1e-9 |value|
    assert agrees((1.0, 0.0), (1.0 + 1e-9, 0.0), count=False)
    assert agrees((4.0, 0.0), (4.0, 0.0), count=True) and not agrees((4.0, 0.0), (5.0, 0.0), count=True)
    assert not agrees((math.nan, 0.1), (1.0, 0.1), count=False)
    assert not agrees((1.0, math.nan), (1.0, 0.1), count=False)


@pytest.mark.parametrize("pairs, want", [
    ({(0, 1): True, (0, 2): True, (1, 2): True}, "double"),
    ({(0, 1): True, (0, 2): False, (1, 2): True}, "long double"),  # double agrees with one finer, not all
    ({(0, 1): False, (0, 2): False, (1, 2): False}, "not converged"),
])
def test_converged_is_the_lowest_precision_agreeing_with_every_finer_one(pairs, want):
    agree = np.eye(3, dtype=bool)
    for (i, j), v in pairs.items():
        agree[i, j] = agree[j, i] = v
    assert observables.converged(agree, ["double", "long double", "quad"]) == want


def test_a_single_precision_is_never_converged():
    assert observables.converged(np.ones((1, 1), bool), ["double"]) == "not converged"


def _poincare(rot, halves, rt, loops=4, start=(0.1, 0.2, 1.0, 0.0), precision="double", tol=2.0**-52):
    return xr.Dataset({"return_time": ("nret", np.asarray(rt, float)),
                       "attractor_u": ("natt", [0.1, 0.2]), "attractor_Omega": ("natt", [0.0, 0.1]),
                       "attractor_omega": ("natt", [1.0, 1.0])},
                      attrs=dict(rotation_number=rot, rotation_number_first_half=halves[0],
                                 rotation_number_second_half=halves[1], n_loops=loops, settled_state=np.array(start),
                                 return_time_mean=float(np.mean(rt)),
                                 precision=precision, tol=tol, attractor_dt=0.5, param_eps=0.1))


def test_each_observable_states_its_uncertainty():
    ds = _poincare(0.25, (0.24, 0.27), [1.0, 1.0, 2.0, 2.0])
    assert observables.observable(ds, "rotation_number") == (0.25, pytest.approx(0.03))
    assert observables.observable(ds, "return_time_mean") == (1.5, 1.0)  # halves 1.0 and 2.0
    assert observables.observable(ds, "n_loops") == (4.0, 0.0)
    psd = xr.Dataset(attrs={"Omega_band_low": 0.5, "psd_segment": 2e4, "Omega_n_peaks_near_zero": 3})
    assert observables.observable(psd, "Omega_band_low") == (0.5, 5e-5)
    assert observables.observable(psd, "Omega_n_peaks_near_zero") == (3.0, 0.0)
    ds.attrs["p2pi_curve_thickness"] = 0.01
    with pytest.raises(KeyError, match="no rule"):
        observables.observable(ds, "p2pi_curve_thickness")


def test_every_declared_observable_has_an_uncertainty_rule():
    for kind, declared in catalog.KINDS.items():
        for name in declared.observables:
            try:
                observables.observable(xr.Dataset(), name)
            except (KeyError, AttributeError) as err:  # the empty dataset lacks the value, not the rule
                assert "no rule" not in str(err), f"{kind}.{name}"


def test_ladder_of_synthetic_runs():
    double = _poincare(0.25, (0.24, 0.26), [1.0, 1.0, 1.0, 1.0])
    ld = _poincare(0.30, (0.299, 0.301), [1.0, 1.0, 1.0, 1.0], precision="long double", tol=2.0**-63)
    ds = observables.ladder("poincare", catalog.KINDS["poincare"].observables, [double, ld], ["double", "long double"],
                            scene="x")
    assert list(ds.converged_precision_of.values) == ["not converged", "double", "double"]
    assert ds.attrs["converged_precision"] == "not converged"
    assert ds.value.sel(precision="long double", observable="rotation_number") == 0.30
    assert ds.tol.values.tolist() == [2.0**-52, 2.0**-63]
    assert ds.separation.values.tolist() == [[0.0, 0.0]] and math.isnan(ds.t_separated.values[0])


def test_ladder_refuses_runs_from_different_settled_states():
    with pytest.raises(ValueError, match="different settled states"):
        observables.ladder("poincare", catalog.KINDS["poincare"].observables, [_poincare(0.25, (0.25, 0.25), [1.0]),
                                        _poincare(0.25, (0.25, 0.25), [1.0], start=(0.1, 0.2, 1.0, 1e-15))],
                           ["double", "long double"])


def test_poincare_scene_in_double_and_long_double_from_one_settled_point():
    """The reference state over a short map: both arithmetics follow the orbit (separation ~1e-13),
    so every observable agrees and the ladder converges in double."""
    cfg = dict(params={"eps": 0.1, "b": 1.0, "K2": 1.1}, y0=[0.0, 0.1, 1.0, 0.0], energy_label=0.1127,
               t_settle=300.0, t_map=150.0, attractor_span=20.0, attractor_dt=0.1, max_stored_pi2=1000,
               loop_knn=10, return_time_tie_tol=1e-7, tol=2.0**-52,
               transient=dict(dt=0.5, window=100.0, rtol=0.02, spike_factor=1.8, t_min=50.0))
    runs = [poincare_maps(parsed({**cfg, "precision": p}), scene="t") for p in ("double", "long double")]
    assert [r.attrs["precision"] for r in runs] == ["double", "long double"]
    assert runs[1].attrs["tol"] == 2.0**-63 and runs[1].attrs["transient_tol"] == 2.0**-52
    ds = observables.ladder("poincare", catalog.KINDS["poincare"].observables, runs, ["double", "long double"],
                            scene="t")
    assert ds.attrs["converged_precision"] == "double"
    assert 0 < ds.separation.max() < 1e-9


def test_the_gauge_says_unknown_without_a_complete_cycle_and_is_stored_per_precision():
    """Over 300 time units from the reference state there is no complete spike cycle: the gauge
    must not call any arithmetic faithful."""
    g = observables.gauge({"eps": 0.1, "b": 1.0, "K2": 1.1}, [0.0, 0.1, 1.0, 0.0], T=300.0, tau=2.0,
                          spike_factor=1.8, tol=2.0**-52)
    assert math.isnan(g["ln_gain_max"]) and set(g["follows"].values()) == {"unknown"}
    ds = observables._with_gauge(xr.Dataset(coords={"precision": ["double", "long double"]}), g,
                                 ["double", "long double"], 300.0)
    assert list(ds.follows_orbit.values) == ["unknown", "unknown"] and ds.attrs["T_gain"] == 300.0


def _record(t, Omega, x=None):
    data = {"Omega": ("time", Omega), "u": ("time", np.ones_like(t)), "omega": ("time", np.ones_like(t))}
    if x is not None:
        data.update(x=("time", x), y=("time", np.zeros_like(t)))
    return xr.Dataset(data, coords={"time": t})


def test_trajectory_observables_on_each_branch():
    """Spikes every 100 time units in a window after a pre-run: count, first spike, mean interval with
    the halves' difference; too few intervals leave the mean out; a path states its reach and the
    difference of its halves' farthest distances."""
    from sleighsim.scenes.trajectories import observed

    t = np.arange(0.0, 10000.0, 0.5)
    spikes = [1005.0, 2005.0, 3005.0, 4005.0, 5105.0, 6205.0]  # intervals 1000, 1000, 1000, 1100, 1100
    Omega = 0.01 * np.sin(t) + sum(np.exp(-((t - s) / 2.0) ** 2) for s in spikes)
    x = np.minimum(t, 3000.0) / 100.0  # reach 30, attained in the first half
    out = observed(_record(t, Omega, x), pre_run=True, spike_factor=1.8)
    assert out["n_spikes"] == 6 and out["first_spike_time"] == 1005.0 and out["first_spike_time_uncertainty"] == 0.5
    assert out["spike_interval_mean"] == pytest.approx(1040.0)
    # halves [1000, 1000], [1000, 1100, 1100]
    assert out["spike_interval_mean_uncertainty"] == pytest.approx(3200.0 / 3 - 1000.0)
    assert out["path_reach"] == pytest.approx(30.0) and out["path_reach_uncertainty"] == pytest.approx(0.0, abs=0.1)
    few = observed(_record(t, 0.01 * np.sin(t) + np.exp(-((t - 3000.0) / 2.0) ** 2)), pre_run=True, spike_factor=1.8)
    assert few["n_spikes"] == 1 and "spike_interval_mean" not in few and "path_reach" not in few
    none = observed(_record(t, 0.01 * np.sin(t)), pre_run=True, spike_factor=1.8)
    assert none["n_spikes"] == 0 and "first_spike_time" not in none


def test_a_stated_uncertainty_is_used_and_a_missing_observable_never_agrees():
    a = xr.Dataset(attrs={"spike_interval_mean": 2300.0, "spike_interval_mean_uncertainty": 30.0, "n_spikes": 7,
                          "settled_state": np.zeros(4), "tol": 1e-16, "precision": "double"})
    b = xr.Dataset(attrs={"n_spikes": 7, "settled_state": np.zeros(4), "tol": 1e-19, "precision": "long double"})
    assert observables.observable(a, "spike_interval_mean") == (2300.0, 30.0)
    assert all(math.isnan(v) for v in observables.observable(b, "spike_interval_mean"))
    ds = observables.ladder("trajectory", catalog.KINDS["trajectory"].observables, [a, b], ["double", "long double"],
                            scene="x")
    assert list(ds.observable.values) == ["n_spikes", "spike_interval_mean"]  # stated by no run: left out
    assert list(ds.converged_precision_of.values) == ["double", "not converged"]


def test_trajectory_scene_in_double_and_long_double_from_one_settled_point():
    """A window after a checked pre-run: the long double run starts from the double pre-run's state,
    says so, and over a short window both arithmetics give the same path reach."""
    from sleighsim.scenes.trajectories import trajectory

    cfg = dict(params={"eps": 0.1, "b": 1.0, "K2": 1.1}, y0=[0.0, 0.1, 1.0, 0.0], t_sample_start=200.0, t_end=300.0,
               dt=0.1, keep=["u", "Omega", "x", "y"], tol=2.0**-52,
               transient=dict(dt=0.5, window=50.0, rtol=0.05, spike_factor=1.8, t_min=50.0))
    runs = [trajectory(parsed({**cfg, "precision": p}), scene="t") for p in ("double", "long double")]
    assert [(r.attrs["precision"], r.attrs["transient_precision"]) for r in runs] == [("double", "double"),
                                                                                   ("long double", "double")]
    assert runs[1].attrs["tol"] == 2.0**-63
    ds = observables.ladder("trajectory", catalog.KINDS["trajectory"].observables, runs, ["double", "long double"],
                            scene="t")
    assert "path_reach" in ds.observable.values and ds.attrs["converged_precision"] == "double"
