"""Content checksums of datasets: every dataset sleighsim writes records a SHA-256 of its values in
the global attribute :data:`ATTR`, and every read checks it, so a flipped byte in any variable's data
(a coordinate's included) is caught instead of drawn.

The checksum covers the file's variables as stored (netCDF4 with no masking, scaling or text
joining, so no decoding can hide a change): for each variable, in name order, its name, dtype, shape
and raw values (little-endian; a variable-length text as its UTF-8 strings, each preceded by its
length), each part preceded by its length. It is computed from the written file and then added to
it (an attribute cannot be part of its own checksum, so attributes are not covered).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import netCDF4
import numpy as np

#: The global attribute holding a dataset's checksum: "sha256:" and 64 hex digits.
ATTR = "sleighsim_checksum"


class ChecksumError(ValueError):
    """A dataset whose data do not match its recorded checksum, or that records none."""


def _raw(values) -> bytes:
    """The bytes of a variable's raw values: little-endian numbers, or length-prefixed UTF-8 texts."""
    array = np.asarray(values)
    if array.dtype.kind == "O":
        return b"".join(_framed(str(v).encode()) for v in array.ravel())
    if array.dtype.byteorder == ">":
        array = array.astype(array.dtype.newbyteorder("<"))
    return np.ascontiguousarray(array).tobytes()


def _framed(part: bytes) -> bytes:
    return len(part).to_bytes(8, "little") + part


def _checksum(nc: netCDF4.Dataset) -> str:
    """SHA-256 of the open file ``nc``'s variables as stored (see the module's docstring)."""
    nc.set_auto_maskandscale(False)
    nc.set_auto_chartostring(False)
    digest = hashlib.sha256()
    for name in sorted(nc.variables):
        var = nc.variables[name]
        dtype = "str" if var.dtype is str else np.dtype(var.dtype).str.lstrip("<>=|")
        for part in (name.encode(), dtype.encode(), repr(tuple(var.shape)).encode(), _raw(var[...])):
            digest.update(_framed(part))
    return "sha256:" + digest.hexdigest()


def stamp(path) -> str:
    """Compute the checksum of the netCDF file ``path`` and record it there (:data:`ATTR`)."""
    with netCDF4.Dataset(path, "a") as nc:
        value = _checksum(nc)
        nc.setncattr(ATTR, value)
    return value


def verify(path) -> str:
    """The checksum recorded in the netCDF file ``path``, after checking it against its data;
    :class:`ChecksumError` naming the file when it records none, its data differ from it, or it
    cannot be read."""
    try:
        with netCDF4.Dataset(path) as nc:
            stored = nc.getncattr(ATTR) if ATTR in nc.ncattrs() else None
            actual = _checksum(nc)
    except (OSError, RuntimeError, ValueError, IndexError) as err:
        raise ChecksumError(f"{path}: cannot be read to check its checksum ({err})") from err
    if stored is None:
        raise ChecksumError(f"{path}: records no checksum ({ATTR}): written by another program, or by sleighsim "
                            "before it recorded checksums; delete it so that the workflow builds it again")
    if stored != actual:
        raise ChecksumError(f"{path}: its data do not match the checksum recorded when it was written ({stored}, "
                            f"now {actual}): the file was corrupted or altered since; delete it so that the "
                            "workflow builds it again")
    return stored


def verify_tree(root) -> dict[Path, str]:
    """{path: why it fails :func:`verify`, "" when it passes} for every netCDF file under ``root``
    (its subdirectories included), in path order."""
    out = {}
    for path in sorted(Path(root).rglob("*.nc")):
        try:
            verify(path)
            out[path] = ""
        except ChecksumError as err:
            out[path] = str(err)
    return out
