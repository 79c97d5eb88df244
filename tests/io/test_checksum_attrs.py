"""Issues 49 (item 6) and 55: the checksum covers attributes (global and per variable), dimension
names and the dataset's identity, so an edited attribute, an added scale_factor, add_offset,
missing_value or time units, swapped dimension names or another scene's dataset copied in place are
caught by every read and by ``sleighsim verify``; a read opens the file once."""

import shutil

import netCDF4
import numpy as np
import pytest
import xarray as xr

from sleighsim import cli
from sleighsim.io.checksum import ChecksumError, verify
from sleighsim.io.netcdf import read_dataset, write_dataset


def scene(name: str) -> xr.Dataset:
    return xr.Dataset({"u": (("time", "loop"), np.arange(12.0).reshape(4, 3)), "verdict": ("loop", ["a", "b", "c"]),
                       "w": (("k", "loop"), np.arange(9.0).reshape(3, 3))},
                      coords={"time": np.arange(4.0)}, attrs={"scene": name, "n_loops": 4})


def _edit(path, change):
    with netCDF4.Dataset(path, "a") as nc:
        change(nc)


def _swap_dims(nc):  # w(k, loop) read as w(loop, k): transposed
    nc.renameDimension("k", "tmp")
    nc.renameDimension("loop", "k")
    nc.renameDimension("tmp", "loop")


EDITS = {
    "a global attribute (n_loops 4 to 3)": lambda nc: nc.setncattr("n_loops", 3),
    "a variable's long_name": lambda nc: nc["verdict"].setncattr("long_name", "the reason, reworded"),
    "scale_factor added": lambda nc: nc["u"].setncattr("scale_factor", 10.0),
    "add_offset added": lambda nc: nc["u"].setncattr("add_offset", 1.0),
    "missing_value added": lambda nc: nc["u"].setncattr("missing_value", 4.0),
    "time units added": lambda nc: nc["time"].setncattr("units", "days since 2000-01-01"),
    "an attribute deleted": lambda nc: nc.delncattr("scene"),
    "dimension names swapped": _swap_dims,
}


@pytest.mark.parametrize("edit", EDITS, ids=list(EDITS))
def test_an_edited_attribute_or_dimension_is_caught_by_read_and_verify(tmp_path, capsys, edit):
    path = write_dataset(scene("fig9_ref"), tmp_path / "results" / "data" / "fig9_ref.nc")
    _edit(path, EDITS[edit])
    with pytest.raises(ChecksumError, match=rf"^{path}: its data do not match the checksum"):
        read_dataset(path)
    assert cli.main(["verify", str(tmp_path / "results")]) == 1
    assert "1 datasets checked" in capsys.readouterr().out


def test_another_scenes_dataset_copied_in_place_is_caught(tmp_path, capsys):
    data = tmp_path / "results" / "data"
    write_dataset(scene("fig9_ref"), data / "fig9_ref.nc")
    write_dataset(scene("fig9_eps001"), data / "fig9_eps001.nc")
    write_dataset(scene("fig9_ref"), data / "precision" / "long_double" / "fig9_ref.nc", precision="long double")
    shutil.copy(data / "fig9_eps001.nc", data / "fig9_ref.nc")
    with pytest.raises(ChecksumError, match=r"fig9_ref.nc: written as data/fig9_eps001.nc, read as data/fig9_ref.nc"):
        read_dataset(data / "fig9_ref.nc")
    shutil.copy(data / "precision" / "long_double" / "fig9_ref.nc", data / "fig9_ref.nc")  # another precision
    with pytest.raises(ChecksumError, match="written as data/precision/long_double/fig9_ref.nc"):
        verify(data / "fig9_ref.nc")
    assert cli.main(["verify", str(tmp_path / "results")]) == 1
    assert "3 datasets checked" in capsys.readouterr().out


def test_a_moved_results_tree_still_verifies(tmp_path):
    write_dataset(scene("fig3"), tmp_path / "results" / "data" / "realization" / "1" / "fig3.nc")
    write_dataset(scene("claims"), tmp_path / "results" / "claims.nc")
    shutil.move(tmp_path / "results", tmp_path / "old_results")
    assert verify(tmp_path / "old_results" / "data" / "realization" / "1" / "fig3.nc")
    assert verify(tmp_path / "old_results" / "claims.nc")
    from sleighsim.io.checksum import identity

    assert identity("/x/results/chunks/precision/quad/fig11_grid/3.nc") == "chunks/precision/quad/fig11_grid/3.nc"


def test_a_read_opens_the_file_once_and_returns_what_xarray_decodes(tmp_path, monkeypatch):
    path = write_dataset(scene("fig9_ref").assign(t=("time", np.arange(4.0), {"units": "days since 2000-01-01"})),
                         tmp_path / "data" / "fig9_ref.nc")
    with xr.open_dataset(path) as plain:
        expected = plain.load()
    opened, real = [], netCDF4.Dataset

    class Like(type):  # isinstance(x, Counting) as isinstance(x, netCDF4.Dataset): xarray asks
        def __instancecheck__(cls, obj):
            return isinstance(obj, real)

    class Counting(metaclass=Like):
        def __new__(cls, *args, **kwargs):
            opened.append(args[0])
            return real(*args, **kwargs)

    monkeypatch.setattr(netCDF4, "Dataset", Counting)
    ds = read_dataset(path)
    assert len(opened) == 1, opened
    assert ds.t.dtype.kind == "M"  # decoded as open_dataset decodes
    expected.attrs = {k: v for k, v in expected.attrs.items() if not k.startswith("sleighsim_")}
    assert ds.identical(expected)
