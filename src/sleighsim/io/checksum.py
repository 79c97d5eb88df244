"""Content checksums of datasets: every dataset sleighsim writes records a SHA-256 of its contents in
the global attribute :data:`ATTR`, and every read checks it, so a flipped byte in any variable's data
(a coordinate's included), a changed attribute (a verdict's reason, a unit, an added scale_factor),
swapped dimension names or a dataset of another scene copied in its place are caught instead of drawn.

The checksum covers the file as stored (read with no decoding, so no masking, scaling, time units or
text joining can hide a change): the global attributes but :data:`ATTR`, the dimensions (name, size),
and for each variable, in name order, its name, dtype, dimension names, shape, attributes and raw
values (little-endian; a variable-length text as its UTF-8 strings), every part preceded by its
length. The file's identity (:func:`identity`: ``data/<scene>.nc``, ``chunks/<scene>/<k>.nc``, ...)
is recorded in :data:`FILE_ATTR` and checked against the path it is read from.
"""

from __future__ import annotations

import hashlib
import os
import stat
from pathlib import Path

import numpy as np
import xarray as xr

#: The global attribute holding a dataset's checksum: "sha256:" and 64 hex digits.
ATTR = "sleighsim_checksum"
#: The global attribute naming the file a dataset was written as (:func:`identity`).
FILE_ATTR = "sleighsim_file"
#: Top-level directories of a results tree an identity starts at (the last one in a path).
ANCHORS = ("data", "chunks")
#: Errors of reading a file that is not a readable netCDF file.
READ_ERRORS = (OSError, RuntimeError, ValueError, IndexError, KeyError, TypeError)


class ChecksumError(ValueError):
    """A dataset whose contents do not match its recorded checksum, or that records none."""


def identity(path) -> str:
    """The name a dataset is known by in a results tree: its path from the last ``data`` or
    ``chunks`` directory on (``data/precision/long_double/<scene>.nc``), else its file name; moving
    a whole results tree keeps it."""
    parts = Path(path).parts
    anchors = [i for i, p in enumerate(parts[:-1]) if p in ANCHORS]
    return "/".join(parts[anchors[-1]:]) if anchors else parts[-1]


def _raw(values) -> bytes:
    """The bytes of raw values: little-endian numbers, or length-prefixed UTF-8 texts."""
    array = np.asarray(values)
    if array.dtype.kind == "O":
        return b"".join(_framed(str(v).encode()) for v in array.ravel())
    if array.dtype.byteorder == ">":
        array = array.astype(array.dtype.newbyteorder("<"))
    return np.ascontiguousarray(array).tobytes()


def _framed(part: bytes) -> bytes:
    return len(part).to_bytes(8, "little") + part


def _dtype(array) -> str:
    return "str" if array.dtype.kind == "O" else array.dtype.str.lstrip("<>=|")


def _value(value) -> list[bytes]:
    """An attribute value as typed parts: a text, bytes, or a number or array (dtype, shape, bytes)."""
    if isinstance(value, str):
        return [b"str", value.encode()]
    if isinstance(value, bytes):
        return [b"bytes", value]
    array = np.asarray(value)
    return [_dtype(array).encode(), repr(array.shape).encode(), _raw(array)]


def _attrs(attrs: dict) -> list[bytes]:
    """The parts of an attribute mapping, in name order, :data:`ATTR` left out."""
    names = sorted(k for k in attrs if k != ATTR)
    out = [str(len(names)).encode()]
    for name in names:
        out += [name.encode(), *_value(attrs[name])]
    return out


def checksum(raw: xr.Dataset) -> str:
    """SHA-256 of a dataset as stored (:func:`load_raw`; see the module's docstring)."""
    parts = [b"sleighsim-checksum-2", *_attrs(raw.attrs), str(len(raw.sizes)).encode()]
    for dim in sorted(raw.sizes):
        parts += [str(dim).encode(), str(raw.sizes[dim]).encode()]
    for name in sorted(raw.variables, key=str):
        var = raw.variables[name]
        parts += [b"variable", str(name).encode(), _dtype(var).encode(), _framed_all(var.dims),
                  repr(tuple(var.shape)).encode(), *_attrs(var.attrs), _raw(var.values)]
    digest = hashlib.sha256()
    for part in parts:
        digest.update(_framed(part))
    return "sha256:" + digest.hexdigest()


def _framed_all(names) -> bytes:
    return b"".join(_framed(str(n).encode()) for n in names)


def load_raw(path) -> xr.Dataset:
    """The netCDF file ``path`` loaded into memory as stored (no decoding), the file opened and read
    once; :class:`ChecksumError` naming it when it is not a regular file (a FIFO would block) or
    cannot be read."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise ChecksumError(f"{path}: not a regular file; a dataset is a netCDF file")
        with xr.open_dataset(path, engine="netcdf4", decode_cf=False) as ds:
            return ds.load()
    except READ_ERRORS as err:
        if isinstance(err, ChecksumError):
            raise
        raise ChecksumError(f"{path}: cannot be read to check its checksum ({err})") from err


def stamp(path, as_path=None) -> str:
    """Record in the netCDF file ``path`` its identity (:data:`FILE_ATTR`, that of ``as_path``, the
    name it will have, default ``path``) and then its checksum (:data:`ATTR`); returns the checksum."""
    import netCDF4

    with netCDF4.Dataset(path, "a") as nc:
        nc.setncattr(FILE_ATTR, identity(as_path or path))
    value = checksum(load_raw(path))
    with netCDF4.Dataset(path, "a") as nc:
        nc.setncattr(ATTR, value)
    return value


def check(raw: xr.Dataset, path) -> str:
    """The checksum ``raw`` (the file ``path`` as :func:`load_raw` read it) records, after checking
    it against its contents and its identity against ``path``; :class:`ChecksumError` naming the file."""
    stored, written_as = raw.attrs.get(ATTR), raw.attrs.get(FILE_ATTR)
    if stored is None or written_as is None:
        raise ChecksumError(f"{path}: records no checksum ({ATTR}) or no identity ({FILE_ATTR}): written by another "
                            "program, or by a sleighsim whose checksum did not cover attributes; delete it so that "
                            "the workflow builds it again")
    actual = checksum(raw)
    if stored != actual:
        raise ChecksumError(f"{path}: its data do not match the checksum recorded when it was written ({stored}, now "
                            f"{actual}; it covers values, attributes and dimensions): the file was corrupted or "
                            "altered since; delete it so that the workflow builds it again")
    if written_as != identity(path):
        raise ChecksumError(f"{path}: written as {written_as}, read as {identity(path)}: another dataset put in its "
                            "place; delete it so that the workflow builds it again")
    return stored


def verify(path) -> str:
    """The checksum recorded in the netCDF file ``path``, after checking it (:func:`check`)."""
    return check(load_raw(path), path)


def _datasets(root):
    """(path, "") of every ``*.nc`` under ``root``, symlinked directories followed (each directory
    once, so a link loop ends), and (directory, why) for each directory that cannot be listed."""
    seen, stack = set(), [Path(root)]
    while stack:
        directory = stack.pop()
        try:
            st = os.stat(directory)
            if (st.st_dev, st.st_ino) in seen:
                continue
            seen.add((st.st_dev, st.st_ino))
            with os.scandir(directory) as it:
                entries = list(it)
        except OSError as err:
            yield directory, f"{directory}: cannot be listed ({err.strerror or err}); its datasets cannot be checked"
            continue
        for entry in entries:
            try:
                is_dir = entry.is_dir()  # through a symlink too
            except OSError:
                is_dir = False
            if is_dir:
                stack.append(Path(entry.path))
            elif entry.name.endswith(".nc"):
                yield Path(entry.path), ""


def verify_tree(root) -> dict[Path, str]:
    """{path: why it fails :func:`verify`, "" when it passes} for every netCDF file under ``root``
    (its subdirectories and symlinked directories included), and {directory: why} for each directory
    that cannot be listed, in path order."""
    out = {}
    for path, problem in _datasets(root):
        if not problem:
            try:
                verify(path)
            except ChecksumError as err:
                problem = str(err)
        out[path] = problem
    return dict(sorted(out.items()))
