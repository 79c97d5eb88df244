"""Atomic writes leave neither a temporary file nor a truncated target on any failure: an exception,
a full disk (ENOSPC) midway, SIGTERM."""

import errno
import shutil
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import xarray as xr

from sleighsim.io import netcdf
from sleighsim.report import build


def full_disk(written: bytes):
    """A writer that puts ``written`` into its target, then fails as a full disk does."""
    def write(*args, **kwargs):
        target = args[1] if len(args) > 1 else args[0]
        with open(target, "wb") as fh:
            fh.write(written)
        raise OSError(errno.ENOSPC, "No space left on device")
    return write


def test_a_full_disk_while_writing_a_dataset_leaves_the_old_one_and_no_temporary(tmp_path, monkeypatch):
    ds = xr.Dataset({"u": ("time", np.arange(5.0))}, coords={"time": np.arange(5.0)})
    target = netcdf.write_dataset(ds, tmp_path / "d.nc")
    before = target.read_bytes()
    monkeypatch.setattr(xr.Dataset, "to_netcdf", lambda self, path, **kw: full_disk(b"CDF\x01 half")(self, path))
    with pytest.raises(OSError) as err:
        netcdf.write_dataset(ds, target)
    assert err.value.errno == errno.ENOSPC
    assert target.read_bytes() == before and [p.name for p in tmp_path.iterdir()] == ["d.nc"]


def test_a_full_disk_while_copying_a_figure_leaves_no_truncated_copy(tmp_path, monkeypatch):
    figures, report = tmp_path / "figures", tmp_path / "report"
    figures.mkdir()
    report.mkdir()
    png = figures / "fig7.png"
    old = b"\x89PNG" + bytes(range(256)) * 40
    png.write_bytes(old)
    assert build._copy_figure(png, report) == "fig7.png" and (report / "fig7.png").read_bytes() == old
    png.write_bytes(b"\x89PNG new figure" * 100)
    monkeypatch.setattr(shutil, "copy2", lambda src, dst: full_disk(png.read_bytes()[:50])(src, dst))
    with pytest.raises(OSError, match="No space left"):
        build._copy_figure(png, report)
    assert (report / "fig7.png").read_bytes() == old
    assert [p.name for p in report.iterdir()] == ["fig7.png"]  # the old complete copy, no temporary
    (report / "fig7.png").unlink()
    with pytest.raises(OSError, match="No space left"):
        build._copy_figure(png, report)
    assert list(report.iterdir()) == []


def test_sigterm_while_writing_removes_the_temporary_file(tmp_path):
    child = textwrap.dedent(f"""
        import os, signal, time
        from sleighsim.io.netcdf import atomic_path
        with atomic_path({str(tmp_path / "out.txt")!r}) as tmp:
            tmp.write_text("half written")
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(30)
    """)
    res = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=60)
    assert res.returncode == 128 + signal.SIGTERM, res.stderr
    assert list(tmp_path.iterdir()) == []


def test_sigterm_exits_only_while_writing_and_a_handler_of_the_program_is_kept(tmp_path):
    seen = []

    def own(*args):
        seen.append("own handler")

    old = signal.signal(signal.SIGTERM, signal.SIG_DFL)
    try:
        with netcdf.atomic_path(tmp_path / "y.txt") as tmp:
            assert signal.getsignal(signal.SIGTERM) is netcdf._exit_on_sigterm
            tmp.write_text("y")
        assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL
        signal.signal(signal.SIGTERM, own)
        with netcdf.atomic_path(tmp_path / "x.txt") as tmp:
            assert signal.getsignal(signal.SIGTERM) is own
            signal.raise_signal(signal.SIGTERM)
            tmp.write_text("done")
        assert seen == ["own handler"] and (tmp_path / "x.txt").read_text() == "done"
    finally:
        signal.signal(signal.SIGTERM, old)
