"""The precision ladder (sleighsim.scenes.ladder): its agreement and convergence rules on each
branch, and a run in three precisions on a state whose orbit every arithmetic follows."""

import math

import numpy as np
import pytest

from sleighsim.precision import parsed
from sleighsim.scenes import ladder


def _train(mean, sd, n=10):
    return {"interval_mean": mean, "interval_sd": sd, "n_intervals": n}


def test_agrees_on_each_branch():
    assert ladder.agrees(_train(2330.0, 8.0), _train(2334.0, 5.0), 1.0)      # within the smaller sd
    assert not ladder.agrees(_train(2330.0, 8.0), _train(2336.0, 5.0), 1.0)  # 6 apart, smaller sd 5
    assert not ladder.agrees(_train(2311.5, 14.0), _train(2338.5, 7.6), 1.0)  # 27 apart
    assert not ladder.agrees(_train(2901.9, 2421.6), _train(2337.8, 7.6), 1.0)  # a wild train is not regular
    assert ladder.agrees(_train(1326.0, 0.0), _train(1326.5, 0.0), 1.0)      # periodic: sd floored at dt
    assert not ladder.agrees(_train(2330.0, 8.0), _train(2330.0, math.nan, n=1), 1.0)  # one interval: no train


@pytest.mark.parametrize("trains, want", [
    ([_train(1326.2, 5.1), _train(1326.2, 5.1), _train(1326.3, 5.0)], "double"),
    ([_train(2311.5, 14.0), _train(2338.5, 7.6), _train(2340.0, 5.0)], "long double"),
    ([_train(2311.5, 14.0), _train(2338.5, 1.0), _train(2680.0, 0.1)], "not converged"),
    ([_train(2311.5, 14.0), _train(2338.5, 7.6)], "not converged"),
    ([_train(2330.0, 3.0), _train(2332.0, 3.0), _train(2334.5, 3.0)], "long double"),  # double agrees with one, not all
    ([_train(2901.9, 2421.6), _train(2337.8, 7.6)], "not converged"),
])
def test_converged_precision_is_the_lowest_that_agrees_with_every_finer_one(trains, want):
    assert ladder.converged_precision(trains, ["double", "long double", "quad"][:len(trains)], 1.0) == want


def test_separation_is_relative_to_the_finer_runs_largest_velocity():
    fine = {"velocities": np.array([[1.0, 0.0, 2.0], [0.0, 1.0, 4.0]])}
    coarse = {"velocities": np.array([[1.0, 0.0, 2.0], [0.0, 1.0, 3.0]])}
    assert ladder.separation(coarse, fine).tolist() == [0.0, 0.25]


def test_a_rotor_start_converges_in_double(hy):
    """The rotor start (sleigh at rest, rotor spinning) follows one orbit in double and long double
    (G x rounding is small there): the same spike train in both, the runs never separate. (Quad runs
    in the smoke workflow: 9e-3 s per time unit is too slow for the horizon this needs.)"""
    cfg = {"params": {"eps": 0.1, "b": 1.0, "K2": 1.1}, "energy_label": 0.1127,
           "states": {"rotor_a": [0.0, 0.0, 1.0, 0.3]}, "t_transient": 6000.0,
           "transient": {"dt": 3.0, "window": 750.0, "rtol": 0.02, "spike_factor": 1.8, "t_min": 200.0},
           "T": 6000.0, "dt": 1.0, "separation_every": 10.0, "precisions": ["double", "long double"]}
    ds = ladder.precision_ladder(parsed(cfg), "test")
    assert ds.converged_precision.values.tolist() == ["double"]
    assert np.all(ds.interval_mean.values > 1000) and np.all(np.isnan(ds.t_separated.values))
    assert ds.separation.values.max() < 1e-6 and list(ds.pair.values) == ["double / long double"]
    assert ds.run_energy_max_rel_drift.values.max() < 1e-12


def test_the_findings_are_composed_from_the_datasets(tmp_path):
    import xarray as xr

    from sleighsim.claims.ledger import Row
    from sleighsim.io.netcdf import write_dataset
    from sleighsim.report.findings import precision_findings

    lad = xr.Dataset({"interval_mean": (("state", "precision"), [[2311.5, 2338.5], [math.nan, math.nan]]),
                      "interval_sd": (("state", "precision"), [[14.0, 7.6], [math.nan, math.nan]]),
                      "t_separated": (("state", "pair"), [[2062.0], [math.nan]]),
                      "converged_precision": ("state", np.array(["not converged", "not converged"], dtype=object)),
                      "start": (("state", "component"), [[0.0, 0.1, 1.0, 0.0], [0.0, 0.0, 1.0, 0.3]])},
                     coords={"state": ["main", "rotor_a"], "precision": ["double", "long double"],
                             "pair": ["double / long double"]}, attrs={"T": 3e4})
    ver = xr.Dataset({"ln_gain_max": ("state", [36.3]), "verdict": ("state", np.array(["undecided"], dtype=object)),
                      "reason": ("state", np.array(["all 3 realizations agree; realization 0: x"], dtype=object)),
                      "log10_gain_rounding": (("state", "arithmetic"), [[-0.2, -3.5, -18.3]]),
                      "follows_orbit": (("state", "arithmetic"),
                                        np.array([["does not follow", "follows", "follows"]], dtype=object))},
                     coords={"state": ["main"], "arithmetic": ["double", "long double", "quad"]})
    write_dataset(lad, tmp_path / "l.nc")
    write_dataset(ver, tmp_path / "v.nc")
    rows = [Row("C05", "spike interval", "about 2200")]
    found = precision_findings(rows, {"ladder": tmp_path / "l.nc", "verdict": tmp_path / "v.nc"},
                               {"ladder": "precision_ladder", "verdict": "chaos_verdict"})
    (st0, main), (st1, rotor) = [(st, " ".join(s)) for st, s in found["states"]]
    assert (st0, st1) == ("main", "rotor_a") and not found["missing"] and found["ladders"] is None
    assert "double 2311.5 +- 14.0; long double 2338.5 +- 7.6 (the paper: about 2200 (C05))" in main
    assert "separate (0.001) at t = 2062" in main and "e^36.3; double does not follow (G x rounding 10^-0.2)" in main
    assert "Chaos verdict: undecided (all 3 realizations agree)" in main
    assert "no spike train within the run" in rotor and "(the paper: no value for this state)" in rotor
    assert "stay within 0.001" in rotor and "Mechanism" not in rotor
    assert precision_findings(rows, {}, {}) == {"states": [], "missing": True, "ladders": None, "setup": ""}
