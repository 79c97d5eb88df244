"""The set-aside step and the stale-temp sweep (sleighsim.io.integrity)."""

import errno
import fcntl
import os
import time

import numpy as np
import pytest
import xarray as xr

from sleighsim.io import integrity
from sleighsim.io.integrity import ProductError, set_aside, sweep_stale_temps, valid
from sleighsim.io.netcdf import write_dataset


@pytest.fixture
def tree(tmp_path):
    """results/ with a good product, a truncated one, an empty one and an unrelated notes.nc."""
    results = tmp_path / "results"
    write_dataset(xr.Dataset({"u": ("t", [1.0, 2.0])}), results / "data" / "good.nc")
    cut = results / "data" / "ladder" / "cut.nc"
    write_dataset(xr.Dataset({"u": ("t", np.arange(1000.0))}), cut)
    cut.write_bytes(cut.read_bytes()[:3000])
    (results / "data" / "empty.nc").write_bytes(b"")
    (results / "data" / "notes.nc").write_text("my notes")
    return results


def test_only_declared_products_that_are_not_netcdf_are_set_aside(tree):
    d = tree / "data"
    declared = [d / "good.nc", d / "ladder" / "cut.nc", d / "empty.nc", d / "missing.nc"]
    to = tree / "unreadable" / "data"
    assert set_aside(tree, declared) == [(d / "ladder" / "cut.nc", to / "ladder" / "cut.nc"),
                                         (d / "empty.nc", to / "empty.nc")]
    assert (to / "ladder" / "cut.nc").stat().st_size == 3000 and (d / "good.nc").exists()
    assert (d / "notes.nc").read_text() == "my notes"  # not declared: never touched


def test_a_second_set_aside_copy_never_overwrites_the_first(tree):
    d, to = tree / "data", tree / "unreadable" / "data"
    set_aside(tree, [d / "empty.nc"])
    (d / "empty.nc").write_bytes(b"second")
    assert set_aside(tree, [d / "empty.nc"]) == [(d / "empty.nc", to / "empty.1.nc")]
    (d / "empty.nc").write_bytes(b"third")
    set_aside(tree, [d / "empty.nc"])
    assert [(to / n).read_bytes() for n in ("empty.nc", "empty.1.nc", "empty.2.nc")] == [b"", b"second", b"third"]


def test_a_product_locked_by_a_writer_stops_the_run_and_stays(tree):
    good = tree / "data" / "good.nc"
    with open(good, "rb") as writer:  # HDF5 takes this exclusive flock while a process writes the file
        fcntl.flock(writer, fcntl.LOCK_EX)
        with pytest.raises(ProductError, match=r"good.nc: locked by another process; the run stops"):
            set_aside(tree, [tree / "data" / "empty.nc", good])
    assert (tree / "data" / "empty.nc").exists() and good.exists()  # nothing moved


@pytest.mark.parametrize("code, reason", [(errno.EACCES, "permission denied"), (errno.EIO, "input/output error")])
def test_permission_and_io_errors_stop_the_run_with_the_reason(tree, monkeypatch, code, reason):
    real_open = os.open

    def failing(path, *args, **kw):
        if str(path).endswith("good.nc"):
            raise OSError(code, os.strerror(code), str(path))
        return real_open(path, *args, **kw)

    monkeypatch.setattr(integrity.os, "open", failing)
    with pytest.raises(ProductError, match=f"good.nc: {reason}"):
        set_aside(tree, [tree / "data" / "good.nc"])
    assert (tree / "data" / "good.nc").exists()


def test_valid_reads_the_signature_before_opening(tree):
    fake = tree / "data" / "fake.nc"
    fake.write_bytes(b"\x89HDF\r\n\x1a\n" + b"\0" * 100)  # an HDF5 signature, nothing behind it
    assert valid(tree / "data" / "good.nc") and not valid(fake) and not valid(tree / "data" / "notes.nc")


def test_stale_temps_older_than_the_run_and_not_open_are_swept(tree):
    d = tree / "data"
    old, held, fresh = d / ".fig4.a1a1a1a1.nc.tmp", d / ".fig2.b2b2b2b2.nc.tmp", d / ".fig3.c3c3c3c3.nc.tmp"
    for p in (old, held, fresh):
        p.write_bytes(b"partial")
    for p in (old, held):
        os.utime(p, (time.time() - 3600,) * 2)
    start = time.time() - 60
    with open(held, "rb"):
        assert sweep_stale_temps(tree, start) == [old]
    assert not old.exists() and held.exists() and fresh.exists()
    assert (d / "notes.nc").exists()


def test_the_sweep_removes_only_its_own_temporary_names_in_the_workflows_directories(tmp_path):
    """Issue 55: with results = ".", the sweep deleted .thesis.tmp and .git/.index.tmp; it now
    removes only atomic_path's names (.<stem>.<8 random><suffix>.tmp), in results itself and the
    directories the workflow writes, never in hidden directories or through links."""
    from sleighsim.io.netcdf import atomic_path

    project = tmp_path / "project"
    own = project / "data" / ".fig4.a1b2c3d4.nc.tmp"
    mine = [project / ".thesis.tmp", project / ".git" / ".index.tmp", project / ".git" / ".x.abcdefgh.nc.tmp",
            project / "docs" / ".notes.abcdefgh.md.tmp", project / "data" / "notes.tmp"]
    for p in [own, *mine]:
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(b"x")
        os.utime(p, (time.time() - 3600,) * 2)
    (project / "figures").symlink_to(project / "docs")
    assert sweep_stale_temps(project, time.time(), ["data", "figures"]) == [own]
    assert all(p.exists() for p in mine)
    assert sweep_stale_temps(project, time.time()) == [project / "docs" / ".notes.abcdefgh.md.tmp"]  # dirs not given
    assert (project / ".thesis.tmp").exists() and (project / ".git" / ".index.tmp").exists()
    with atomic_path(project / "data" / "fig3.nc") as tmp:  # the names atomic_path gives are the ones swept
        tmp.write_bytes(b"partial")
        os.utime(tmp, (time.time() - 3600,) * 2)
        assert integrity.stale_temps(project, time.time(), ["data"]) == [tmp]
