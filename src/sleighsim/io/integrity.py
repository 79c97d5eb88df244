"""Products that are not valid netCDF are set aside before the workflow plans its jobs, so that a
real run rebuilds them instead of failing on them (a truncated file from a killed copy or a full
disk: the workflow's own writes are atomic and never leave one); leftover temporary files of killed
writes are swept.

Only the products a run declares are looked at, and only a file that is not netCDF/HDF5 (no
signature, or one netCDF4 cannot open for a format reason) is moved. A product that cannot be judged
(permission denied, held by another process's lock, an I/O error) stops the run with the reason
(:class:`ProductError`): moving it would hide the fault.
"""

from __future__ import annotations

import errno
import fcntl
import os
from pathlib import Path

import netCDF4

#: Where products that are not valid netCDF go, under the results directory, keeping their
#: relative paths (a later copy of the same product gets a numbered name: fig4.1.nc, fig4.2.nc, ...).
SET_ASIDE = "unreadable"
#: The first bytes of a netCDF-4 (HDF5) file and of the classic netCDF formats (CDF-1, -2, -5).
SIGNATURES = (b"\x89HDF\r\n\x1a\n", b"CDF\x01", b"CDF\x02", b"CDF\x05")
#: errno values that mean "cannot judge this file" rather than "this file is not netCDF".
STOPPING = {errno.EACCES: "permission denied", errno.EPERM: "operation not permitted",
            errno.EIO: "input/output error", errno.EAGAIN: "locked by another process"}  # EAGAIN = EWOULDBLOCK


class ProductError(OSError):
    """A product that can neither be trusted nor set aside: the run stops with the reason."""


def _stop(path, err: OSError) -> ProductError:
    reason = STOPPING.get(err.errno, err.strerror or str(err))
    return ProductError(err.errno, f"{path}: {reason}; the run stops rather than set it aside (fix or remove it)")


def _signed(path) -> bool:
    """Whether ``path`` starts with a netCDF/HDF5 signature; raises :class:`ProductError` when it
    cannot be opened, is locked by a writer (HDF5 takes an exclusive flock) or cannot be read."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError as err:
        raise _stop(path, err) from None
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        head = os.pread(fd, 8, 0)
    except OSError as err:
        raise _stop(path, err) from None
    finally:
        os.close(fd)  # closing releases the shared lock
    return any(head.startswith(s) for s in SIGNATURES)


def valid(path) -> bool:
    """Whether ``path`` is a netCDF file netCDF4 opens (False when it has no signature or is
    truncated or damaged); raises :class:`ProductError` for a permission, lock or I/O error."""
    if not _signed(path):
        return False
    try:
        netCDF4.Dataset(path).close()
    except OSError as err:
        if err.errno in STOPPING:
            raise _stop(path, err) from None
        return False  # a netCDF library error (a negative code): not a readable netCDF file
    return True


def _free_name(dst: Path) -> Path:
    """Reserve (create empty) the first of ``dst``, ``<stem>.1<suffix>``, ... that does not exist."""
    dst.parent.mkdir(parents=True, exist_ok=True)
    k = 0
    while True:
        candidate = dst if k == 0 else dst.with_name(f"{dst.stem}.{k}{dst.suffix}")
        try:
            os.close(os.open(candidate, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
            return candidate
        except FileExistsError:
            k += 1


def set_aside(results, products) -> list[tuple[Path, Path]]:
    """Move each of ``products`` (paths under ``results``) that exists and is not valid netCDF to
    ``results/unreadable/<its relative path>``, never over an earlier copy, so that a run that needs
    it builds it again. Returns [(product, where it went)]; raises :class:`ProductError` first for a
    product that cannot be judged (nothing is moved then)."""
    results = Path(results)
    bad = [Path(p) for p in products if os.path.lexists(p) and not valid(p)]
    moves = []
    for src in bad:
        dst = _free_name(results / SET_ASIDE / src.relative_to(results))
        os.replace(src, dst)
        moves.append((src, dst))
    return moves


def _own_temps(results: Path, dirs):
    """The files named as :func:`sleighsim.io.netcdf.atomic_path` names its temporaries
    (:data:`sleighsim.io.netcdf.TEMP_NAME`) directly in ``results`` and anywhere under its
    subdirectories ``dirs`` (None: all), symbolic links not followed, hidden directories (.git,
    .snakemake) not entered."""
    from sleighsim.io.netcdf import TEMP_NAME

    tops = [results] + [results / d for d in (dirs if dirs is not None else _subdirs(results))]
    for i, top in enumerate(tops):
        if i and (top.is_symlink() or not top.is_dir()):
            continue
        for here, subdirs, files in os.walk(top):
            subdirs[:] = [] if i == 0 else [d for d in subdirs if not d.startswith(".")]
            yield from (Path(here) / f for f in files if TEMP_NAME.fullmatch(f))


def _subdirs(results: Path) -> list[str]:
    try:
        return [e.name for e in os.scandir(results) if not e.name.startswith(".") and e.is_dir(follow_symlinks=False)]
    except OSError:
        return []


def stale_temps(results, before: float, dirs=None) -> list[Path]:
    """The workflow's temporary files (:func:`_own_temps`: only its own names, only in ``results``
    itself and its subdirectories ``dirs``, the ones the workflow writes) last modified before
    ``before`` (a time.time()) and open in no process this user can see."""
    old = []
    for p in _own_temps(Path(results), dirs):
        try:
            if not p.is_symlink() and p.stat().st_mtime < before:
                old.append(p)
        except OSError:
            continue  # gone meanwhile
    held = _open_files() if old else set()
    return [p for p in old if os.path.realpath(p) not in held]


def _open_files() -> set[str]:
    """Real paths of the files the visible processes hold open (Linux /proc; empty elsewhere)."""
    held = set()
    for fd_dir in Path("/proc").glob("[0-9]*/fd"):
        try:
            entries = list(fd_dir.iterdir())
        except OSError:
            continue
        for entry in entries:
            try:
                held.add(os.readlink(entry))
            except OSError:
                continue
    return held


def sweep_stale_temps(results, before: float, dirs=None) -> list[Path]:
    """Remove :func:`stale_temps` (left by killed writes); returns what was removed."""
    gone = stale_temps(results, before, dirs)
    for p in gone:
        p.unlink(missing_ok=True)
    return gone
