"""Products that cannot be read are set aside before the workflow plans its jobs, so that the run
rebuilds them instead of failing on them (a truncated netCDF file from a killed copy or a full
disk, for example: the workflow's own writes are atomic and never leave one)."""

from __future__ import annotations

import os
from pathlib import Path

import netCDF4

#: Where unreadable products go, under the results directory, keeping their relative paths.
SET_ASIDE = "unreadable"


def readable(path) -> bool:
    """Whether netCDF4 can open ``path`` (False when it is absent, empty or truncated)."""
    try:
        netCDF4.Dataset(path).close()
    except OSError:
        return False
    return True


def unreadable(results) -> list[Path]:
    """The netCDF files under ``results`` (outside ``SET_ASIDE``) that netCDF4 cannot open."""
    results = Path(results)
    return [p for p in sorted(results.rglob("*.nc"))
            if SET_ASIDE not in p.relative_to(results).parts[:1] and not readable(p)]


def set_aside(results) -> list[tuple[Path, Path]]:
    """Move every unreadable product to ``results/unreadable/<its relative path>`` (replacing an
    older unreadable copy there, the only file it removes), so that a run that needs it sees it
    missing and builds it again.
    Returns [(product, where it went)]."""
    results = Path(results)
    moves = [(p, results / SET_ASIDE / p.relative_to(results)) for p in unreadable(results)]
    for src, dst in moves:
        dst.parent.mkdir(parents=True, exist_ok=True)
        os.replace(src, dst)
    return moves
