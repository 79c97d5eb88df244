"""Issue 55: SLEIGHSIM_LOCK naming a file that is not a lock (a one-line file, a binary) neither
claims the environment was installed from it nor breaks a write (before: the one-line file was named
in every dataset's provenance; /bin/ls raised UnicodeDecodeError in every write)."""

import numpy as np
import pytest
import xarray as xr

from sleighsim.io import lockfile
from sleighsim.io.netcdf import read_dataset, write_dataset


@pytest.fixture
def lock_env(monkeypatch):
    def use(path):
        monkeypatch.setenv("SLEIGHSIM_LOCK", str(path))
        lockfile.lock_attrs.cache_clear()

    yield use
    lockfile.lock_attrs.cache_clear()


def test_a_one_line_file_is_not_a_lock(tmp_path, lock_env, caplog):
    one = tmp_path / "one.lock"
    one.write_text(f"numpy=={np.__version__}\n")
    lock_env(one)
    ds = read_dataset(write_dataset(xr.Dataset({"u": ("t", [1.0])}), tmp_path / "a.nc"))
    assert "lock_file" not in ds.attrs and "lock_sha256" not in ds.attrs
    assert "SLEIGHSIM_LOCK" in caplog.text and "pins without a hash (numpy" in caplog.text


def test_a_hashed_lock_missing_a_requirement_is_not_a_lock(tmp_path, lock_env):
    part = tmp_path / "part.lock"
    part.write_text(f"numpy=={np.__version__} \\\n    --hash=sha256:{'0' * 64}\n")
    lock_env(part)
    assert lockfile.lock_attrs() == {}


def test_a_binary_file_breaks_no_write(tmp_path, lock_env):
    lock_env("/bin/ls")
    assert read_dataset(write_dataset(xr.Dataset({"u": ("t", [1.0])}), tmp_path / "a.nc")).u.values.tolist() == [1.0]
