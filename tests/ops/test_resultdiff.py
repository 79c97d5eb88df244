"""The result-tree comparison (sleighsim.ops.resultdiff): bit-for-bit values, volatile attributes
ignored, subfolders of data/ compared, and --module-paths for a restructure that moves modules."""

import numpy as np
import xarray as xr

from sleighsim.io.netcdf import write_dataset
from sleighsim.ops import resultdiff


def _tree(root, value, note, sub="precision/long_double"):
    for rel in ("data/a.nc", f"data/{sub}/a.nc"):
        ds = xr.Dataset({"x": ("t", np.array([1.0, value]))},
                        attrs={"rule": note, "created_utc": str(root)})
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        write_dataset(ds, root / rel, precision="long double" if "precision/" in rel else "double")
    return root


def test_identical_trees_compare_equal_in_every_subfolder(tmp_path):
    old = _tree(tmp_path / "old", 2.0, "sleighsim.transient.phases")
    new = _tree(tmp_path / "new", 2.0, "sleighsim.transient.phases")
    diffs = resultdiff.compare_trees(old, new)
    assert set(diffs) == {"data/a.nc", "data/precision/long_double/a.nc"}
    assert not any(diffs.values())


def test_a_value_that_moves_by_one_bit_differs_in_a_subfolder(tmp_path):
    old = _tree(tmp_path / "old", 2.0, "r")
    new = _tree(tmp_path / "new", np.nextafter(2.0, 3.0), "r")
    assert resultdiff.compare_trees(old, new)["data/precision/long_double/a.nc"] == ["variable x differs"]
    assert resultdiff.main([str(old), str(new)]) == 1


def test_module_paths_compare_by_last_name_only_with_the_flag(tmp_path, capsys):
    old = _tree(tmp_path / "old", 2.0, "spikes by sleighsim.transient.phases")
    moved = _tree(tmp_path / "moved", 2.0, "spikes by sleighsim.engine.transient.phases")
    assert resultdiff.main([str(old), str(moved)]) == 1
    assert resultdiff.main(["--module-paths", str(old), str(moved)]) == 0
    other = _tree(tmp_path / "other", 2.0, "spikes by sleighsim.engine.transient.settle")
    assert resultdiff.main(["--module-paths", str(old), str(other)]) == 1
    assert "attribute rule differs" in capsys.readouterr().out


def test_module_paths_in_double_backquotes_compare_by_last_name_only(tmp_path):
    old = _tree(tmp_path / "old", 2.0, "the gate (``chaos.orbits.LOSCHMIDT_MAX``)")
    moved = _tree(tmp_path / "moved", 2.0, "the gate (``chaos.loschmidt.LOSCHMIDT_MAX``)")
    other = _tree(tmp_path / "other", 2.0, "the gate (``chaos.loschmidt.OTHER_MAX``)")
    assert resultdiff.main(["--module-paths", str(old), str(moved)]) == 0
    assert resultdiff.main(["--module-paths", str(old), str(other)]) == 1


def test_nan_in_a_column_of_text_and_numbers_equals_nan():
    mixed = np.array(["a", float("nan"), 1.5], dtype=object)
    assert resultdiff._equal(mixed, mixed.copy())
    assert not resultdiff._equal(mixed, np.array(["a", float("nan"), 2.5], dtype=object))
    assert not resultdiff._equal(mixed, np.array(["a", "b", 1.5], dtype=object))
