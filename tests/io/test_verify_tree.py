"""Issue 55: ``sleighsim verify`` fails on anything it cannot read or follow (before: an unreadable
tree or root passed with 0 checked, symlinked directories were skipped, an empty directory passed, a
FIFO named *.nc hung it, and it loaded matplotlib and heyoka, which want a writable HOME)."""

import os
import subprocess
import sys
import textwrap

import netCDF4
import numpy as np
import xarray as xr

from sleighsim import cli
from sleighsim.io.netcdf import write_dataset


def _tree(root):
    write_dataset(xr.Dataset({"u": ("t", np.arange(3.0))}), root / "data" / "fig3.nc")
    return root


def test_a_directory_that_cannot_be_listed_fails_naming_it(tmp_path, capsys, monkeypatch):
    results = _tree(tmp_path / "results")
    locked = results / "data" / "ladder"
    write_dataset(xr.Dataset({"u": ("t", np.arange(3.0))}), locked / "fig3.nc")
    real = os.scandir

    def denied(path="."):  # what mode 000 does to a user other than root (the tests run as root)
        if os.fspath(path) in (str(locked), str(tmp_path / "other")):
            raise PermissionError(13, "Permission denied", os.fspath(path))
        return real(path)

    monkeypatch.setattr(os, "scandir", denied)
    assert cli.main(["verify", str(results)]) == 1
    assert f"FAILED {locked}: cannot be listed (Permission denied)" in capsys.readouterr().out
    (tmp_path / "other").mkdir()
    assert cli.main(["verify", str(tmp_path / "other")]) == 1  # an unreadable root: nothing checked is a failure


def test_symlinked_directories_are_followed_once(tmp_path, capsys):
    results = _tree(tmp_path / "results")
    elsewhere = tmp_path / "elsewhere"
    bad = write_dataset(xr.Dataset({"u": ("t", np.arange(3.0))}), elsewhere / "data" / "fig4.nc")
    with netCDF4.Dataset(bad, "a") as nc:
        nc.setncattr("n_loops", 3)
    (results / "more").symlink_to(elsewhere)
    (elsewhere / "loop").symlink_to(elsewhere)  # a loop ends
    assert cli.main(["verify", str(results)]) == 1
    out = capsys.readouterr().out
    assert f"FAILED {results / 'more' / 'data' / 'fig4.nc'}" in out and "2 datasets checked" in out


def test_an_empty_directory_fails(tmp_path, capsys):
    assert cli.main(["verify", str(tmp_path)]) == 1
    assert "holds no dataset" in capsys.readouterr().out


def test_a_fifo_named_nc_fails_without_blocking(tmp_path):
    results = _tree(tmp_path / "results")
    os.mkfifo(results / "data" / "pipe.nc")
    res = subprocess.run([sys.executable, "-m", "sleighsim.cli", "verify", str(results)], capture_output=True,
                         text=True, timeout=60)
    assert res.returncode == 1 and f"FAILED {results / 'data' / 'pipe.nc'}: not a regular file" in res.stdout


def test_verify_needs_no_home_directory(tmp_path):
    """Without HOME and with no passwd entry for the user, verify loads nothing that wants a home."""
    results = _tree(tmp_path / "results")
    code = textwrap.dedent(f"""
        import pwd, sys
        def nobody(uid):
            raise KeyError(uid)
        pwd.getpwuid = nobody
        from sleighsim import cli
        status = cli.main(["verify", {str(results)!r}])
        loaded = sorted(m for m in ("matplotlib", "heyoka", "sympy") if m in sys.modules)
        print("loaded:", loaded)
        sys.exit(status)
    """)
    env = {k: v for k, v in os.environ.items() if k not in ("HOME", "MPLCONFIGDIR")}
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=env)
    assert res.returncode == 0 and "loaded: []" in res.stdout, res.stdout + res.stderr[-2000:]
