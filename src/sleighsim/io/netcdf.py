"""Reading and writing results: atomic files with the umask's permissions, provenance and a checksum
of the values on every dataset (:mod:`sleighsim.io.checksum`), checked on every read."""

from __future__ import annotations

import contextlib
import datetime as _dt
import logging
import os
import platform
import signal
import subprocess
import tempfile
import threading
from functools import cache
from importlib import metadata
from pathlib import Path

import xarray as xr

from sleighsim.io import cf, lockfile
from sleighsim.io.checksum import ATTR as CHECKSUM_ATTR
from sleighsim.io.checksum import stamp, verify
from sleighsim.precision import Precision

log = logging.getLogger("sleighsim")

_PACKAGES = ("sleighsim", "numpy", "scipy", "sympy", "heyoka", "xarray", "netCDF4", "matplotlib")


@cache
def _git_commit() -> str:
    here = Path(__file__).resolve().parent
    try:
        commit = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=here, capture_output=True, text=True, timeout=10, check=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=here, capture_output=True, text=True, timeout=10, check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return commit + ("-dirty" if dirty else "")


def provenance_attrs() -> dict:
    """Package versions, Python version, git commit and creation time (UTC)."""
    out = {"python_version": platform.python_version(), "git_commit": _git_commit()}
    for pkg in _PACKAGES:
        try:
            out[f"version_{pkg}"] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[f"version_{pkg}"] = "not installed"
    out["created_utc"] = _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")
    out.update(lockfile.lock_attrs())
    return out


def _umask() -> int:
    current = os.umask(0)
    os.umask(current)
    return current


def _exit_on_sigterm(signum, frame):
    raise SystemExit(128 + signum)


@contextlib.contextmanager
def _sigterm_as_exit():
    """While the block runs, SIGTERM raises SystemExit (exit status 143) instead of ending the process
    on the spot, so that cleanup runs; only in the main thread and only when the program installed no
    SIGTERM handler of its own (which is then left as it is)."""
    if threading.current_thread() is not threading.main_thread() or signal.getsignal(signal.SIGTERM) != signal.SIG_DFL:
        yield
        return
    signal.signal(signal.SIGTERM, _exit_on_sigterm)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; on success rename it onto ``path`` with the
    permissions a plain ``open`` would give (0666 minus the umask), on any failure (an exception, a
    full disk, Ctrl-C, SIGTERM: :func:`_sigterm_as_exit`) delete it. An interrupted write therefore
    never leaves a partial file under the final name, nor a temporary one (SIGKILL aside)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with _sigterm_as_exit():
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f"{path.suffix}.tmp", dir=path.parent)
        os.close(fd)
        try:
            yield Path(tmp)
            os.chmod(tmp, 0o666 & ~_umask())
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise


def write_dataset(ds: xr.Dataset, path, precision=Precision.DOUBLE, what: str = cf.UNTOLD,
                  vocabulary: dict | None = None) -> Path:
    """Write ``ds`` to netCDF at ``path`` atomically, adding the provenance attributes
    (package versions, git commit, creation time) and the CF-1.11 attributes (:mod:`sleighsim.io.cf`:
    Conventions, title from ``what`` the dataset is, the path and ``precision`` (the arithmetic ``ds`` was
    computed in), history, source, references; long_name and units of every variable the writer's own
    ``vocabulary`` (a scene kind's) or the shared one knows; a variable still without them is logged, and
    the tests fail on it;
    no _FillValue on coordinate variables) and, computed from the written file, the checksum of its
    values (``sleighsim_checksum``, :mod:`sleighsim.io.checksum`).
    Text is written at its own width: a fixed text width kept in the encoding of a variable read from
    a file (or joined from such variables) would truncate longer texts put there since."""
    ds = cf.complete(ds, vocabulary)
    for name, v in ds.variables.items():
        if v.dtype.kind in "UO":
            v.encoding = {k: e for k, e in v.encoding.items() if k != "dtype"}
        if v.dims == (name,):  # a coordinate variable: CF 2.5.1 forbids it a _FillValue
            v.encoding = {**v.encoding, "_FillValue": None}
    provenance = provenance_attrs()
    ds.attrs.pop(CHECKSUM_ATTR, None)  # a stale one, of a file this dataset was read from
    ds.attrs.update(provenance)
    ds.attrs.update(cf.global_attrs(path, provenance, history=ds.attrs.get("history", ""), precision=precision,
                                    what=what))
    if lacking := cf.missing(ds):
        log.warning("%s: no CF attributes known for: %s", path, "; ".join(lacking))
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4")
        stamp(tmp)
    return Path(path)


def read_dataset(path, verified: bool = True) -> xr.Dataset:
    """Load a dataset fully into memory and close the file; first, when ``verified``, check its values
    against the checksum recorded when it was written (:func:`sleighsim.io.checksum.verify`:
    ChecksumError naming the file when they differ or it records none). The checksum attribute
    describes the file, so it is not among the returned dataset's attributes."""
    if verified:
        verify(path)
    with xr.open_dataset(path, engine="netcdf4") as ds:
        ds = ds.load()
    ds.attrs.pop(CHECKSUM_ATTR, None)
    return ds


def write_text(path, text: str) -> Path:
    """Write text atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text)
    return Path(path)
