"""The energy sweep in a finer precision as chunk jobs of its labels: gathered, it is the sweep of
one job, number for number; the gather refuses chunks from different settled states or with labels
missing; at most one chunk per label."""

import pytest

from sleighsim.io.netcdf import read_dataset, write_dataset
from sleighsim.ops.resultdiff import compare_datasets
from sleighsim.precision import parsed
from sleighsim.scenes import energy_sweep as exponents

# three labels, a short pre-run and horizon: a second or two in long double
SWEEP = parsed({"kind": "lyapunov_energy", "params": {"eps": 0.1, "b": 1.0, "K2": 1.1}, "y0": [0.0, 0.1, 1.0, 0.0],
         "labels": [0.01, 0.1127, 10.0], "reference_label": 0.1127, "t_transient": 100.0,
         "transient": {"dt": 0.5, "window": 20.0, "rtol": 0.05, "spike_factor": 1.8, "t_min": 20.0},
         "t_align": 10.0, "T": 200.0, "tau": 10.0, "n_blocks": 4, "compact_mode": True, "precision_chunks": 2,
         "tol": 2.220446049250313e-16, "precision": "long double"})


def _chunk_files(cfg, tmp_path):
    paths = []
    for k in range(exponents.LYAPUNOV_ENERGY.chunk_count(cfg)):
        paths.append(write_dataset(exponents.energy_chunk(cfg, k, scene="sweep"), tmp_path / f"{k}.nc",
                                   precision=cfg["precision"]))
    return paths


def test_the_gathered_chunks_are_the_sweep_of_one_job(tmp_path, hy):
    one = read_dataset(write_dataset(exponents.energy_sweep(SWEEP, scene="sweep"), tmp_path / "one" / "sweep.nc",
                                     precision="long double"))
    gathered = read_dataset(write_dataset(exponents.energy_gather(_chunk_files(SWEEP, tmp_path), SWEEP, scene="sweep"),
                                          tmp_path / "gathered" / "sweep.nc", precision="long double"))
    assert list(gathered.data_vars) == list(one.data_vars) and gathered.label.values.tolist() == SWEEP["labels"]
    assert compare_datasets(one, gathered) == []  # every value and attribute but the run's wall and compile times
    assert all(gathered[v].attrs == one[v].attrs for v in one.variables)

def test_the_gather_refuses_chunks_from_different_settled_states_or_missing_labels(tmp_path, hy):
    paths = _chunk_files(SWEEP, tmp_path)
    with pytest.raises(ValueError, match="labels"):
        exponents.energy_gather(paths[:1], SWEEP, scene="sweep")
    moved = read_dataset(paths[1])
    moved.attrs["settled_state"] = moved.attrs["settled_state"] + 1e-15
    write_dataset(moved, paths[1], precision="long double")
    with pytest.raises(ValueError, match="settled states"):
        exponents.energy_gather(paths, SWEEP, scene="sweep")


@pytest.mark.parametrize(("precision_chunks", "jobs"), [(2, 2), (3, 3), (8, 3)])
def test_at_most_one_chunk_per_label(precision_chunks, jobs):
    assert exponents.LYAPUNOV_ENERGY.chunk_count(dict(SWEEP, precision_chunks=precision_chunks)) == jobs
