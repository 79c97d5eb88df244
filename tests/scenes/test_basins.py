"""Basin fractions: the sample lies on the level, every grouping branch, the Wilson intervals, and
the gather of synthetic chunks."""

import numpy as np
import pytest
import xarray as xr

from sleighsim.io.netcdf import write_dataset
from sleighsim.model.params import Params
from sleighsim.model.symmetries import energy_label
from sleighsim.scenes import basins

P = Params.from_config({"eps": 0.1, "b": 1.0, "K2": 1.1})


def test_the_sample_lies_on_the_level_with_delta_uniform_and_is_reproducible():
    y = basins.sample_states(P, 0.1127, 400, seed=3)
    assert y.shape == (400, 4)
    assert np.allclose([energy_label(s, P) for s in y], 0.1127, rtol=1e-12)
    assert 0 <= y[:, 3].min() and y[:, 3].max() < 2 * np.pi
    assert abs(np.mean(y[:, 3] < np.pi) - 0.5) < 0.1  # uniform: half below pi within sampling noise
    assert np.array_equal(y, basins.sample_states(P, 0.1127, 400, seed=3))
    assert not np.array_equal(y, basins.sample_states(P, 0.1127, 400, seed=4))


def test_classify_names_every_branch():
    """Reference match, a second group of its own, no interval, unsettled; a reference without an
    interval names no group."""
    groups = basins.classify(["main", "rotor", "quiet"], [2300.0, 1330.0, np.nan], [True, True, False],
                             intervals=np.array([2350.0, 1300.0, 1800.0, 1810.0, np.nan, 2310.0]),
                             settled=np.array([1, 1, 1, 1, 1, 0], bool),
                             has_interval=np.array([1, 1, 1, 1, 0, 1], bool), rel_tol=0.04)
    assert groups.tolist() == ["main", "rotor", "other 1", "other 1", basins.NO_INTERVAL, basins.UNSETTLED]


def test_fractions_with_wilson_intervals_and_mirrored_share():
    groups = np.array(["main"] * 8 + ["rotor"] * 2 + [basins.UNSETTLED] * 0, dtype=object)
    f = basins.fractions(groups, omega_sign=np.array([1, -1] * 5), confidence=0.95)
    assert f["group"] == ["main", "rotor"]
    assert f["fraction"].tolist() == [0.8, 0.2] and f["count"].tolist() == [8, 2]
    # Wilson 95% for 8 of 10: [0.490, 0.943] (textbook value)
    assert f["ci_low"][0] == pytest.approx(0.4902, abs=1e-3) and f["ci_high"][0] == pytest.approx(0.9433, abs=1e-3)
    assert f["mirrored"].tolist() == [0.5, 0.5]


def test_a_reference_state_no_run_reached_is_listed_with_its_upper_bound():
    f = basins.fractions(np.array(["main"] * 200, dtype=object), np.ones(200), always=["main", "rotor_a"])
    assert f["group"] == ["main", "rotor_a"] and f["count"].tolist() == [200, 0]
    # Wilson 95% for 0 of 200: [0, 0.0188]
    assert f["ci_low"][1] == pytest.approx(0.0, abs=1e-12) and f["ci_high"][1] == pytest.approx(0.0188, abs=2e-4)
    assert np.isnan(f["mirrored"][1])


def test_unsettled_is_listed_last_whatever_its_count():
    f = basins.fractions(np.array([basins.UNSETTLED] * 5 + ["main"] * 2, dtype=object), np.ones(7))
    assert f["group"] == ["main", basins.UNSETTLED]


def _chunk(index, n_chunks, n, intervals, refs=None):
    ids = np.arange(n)[index::n_chunks]
    runs = {v: np.zeros(ids.size) for v in basins.RUN_VARIABLES}
    runs.update(settled=np.ones(ids.size), n_spikes=np.full(ids.size, 6.0), interval=np.asarray(intervals)[ids],
                omega_sign=np.ones(ids.size))
    ds = xr.Dataset({v: ("sample", runs[v]) for v in basins.RUN_VARIABLES}, coords={"sample": ids})
    ds["y0"] = (("sample", "component"), np.zeros((ids.size, 4)))
    if refs:
        ds = ds.assign_coords(reference=list(refs))
        for v in basins.RUN_VARIABLES:
            ds[f"reference_{v}"] = ("reference", np.zeros(len(refs)))
        ds["reference_settled"][:] = 1
        ds["reference_n_spikes"][:] = 6
        ds["reference_interval"][:] = list(refs.values())
    ds.attrs.update(chunk=index, n_chunks=n_chunks)
    return ds


CFG = {"params": {"eps": 0.1, "b": 1.0, "K2": 1.1}, "energy_label": 0.1127, "n_samples": 5, "seed": 1, "n_chunks": 2,
       "t_round": 1.0, "max_rounds": 1, "T_measure": 1.0, "dt_measure": 0.1, "min_spikes": 4, "group_rel_tol": 0.04,
       "confidence": 0.95, "tol": 1e-15}


def test_gather_puts_chunks_in_sample_order_and_counts_every_sample(tmp_path):
    intervals = [2300.0, 1330.0, 2290.0, 2310.0, 1500.0]
    paths = []
    for k, refs in ((1, None), (0, {"main": 2300.0, "rotor": 1330.0})):
        paths.append(tmp_path / f"{k}.nc")
        write_dataset(_chunk(k, 2, 5, intervals, refs), paths[-1])
    ds = basins.gather(paths, CFG, scene="b")
    assert ds.sample.values.tolist() == [0, 1, 2, 3, 4]
    assert ds.group_of.values.tolist() == ["main", "rotor", "main", "main", "other 1"]
    assert ds.group.values.tolist() == ["main", "other 1", "rotor"]
    assert ds["count"].values.tolist() == [3, 1, 1] and ds.fraction.values.sum() == pytest.approx(1.0)


def test_gather_refuses_a_missing_chunk(tmp_path):
    path = tmp_path / "0.nc"
    write_dataset(_chunk(0, 2, 5, [1.0] * 5, {"main": 1.0}), path)
    with pytest.raises(ValueError, match="expected 0 ... 4"):
        basins.gather([path], CFG)
