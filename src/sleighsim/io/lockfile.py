"""The lock files (requirements/py311.lock, py311-test.lock: pip-compile output with hashes) and
whether this environment was installed from one: then every dataset names the lock's hash.

An environment counts as installed from a lock when the file is a lock (UTF-8 text whose every pin
carries a hash, as pip-compile --generate-hashes writes, pinning every requirement of sleighsim) and
every package it pins is installed at exactly the pinned version (checked, not assumed); a file that
is not a lock (``SLEIGHSIM_LOCK`` naming a one-line file or a binary) is passed over with a warning.
The locks looked at are those of the running Python in this checkout's ``requirements/`` (the test
lock first: it pins more), or the file the environment variable ``SLEIGHSIM_LOCK`` names (for an
install outside a checkout)."""

from __future__ import annotations

import hashlib
import logging
import os
import re
import sys
from functools import cache
from importlib import metadata
from pathlib import Path

from packaging.requirements import InvalidRequirement, Requirement
from packaging.utils import canonicalize_name
from packaging.version import InvalidVersion, Version

log = logging.getLogger("sleighsim")

#: The checkout's folder of lock files (this file is src/sleighsim/io/lockfile.py).
REQUIREMENTS = Path(__file__).resolve().parents[3] / "requirements"
_PIN = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)==(\S+)")
#: sleighsim's core requirements, when its distribution's metadata cannot be read.
CORE = ("numpy", "scipy", "sympy", "heyoka", "xarray", "netcdf4", "matplotlib")


def lock_paths() -> list[Path]:
    """The lock files to try, in order: $SLEIGHSIM_LOCK alone when set, else this Python's test
    lock and its plain lock in the checkout (pyXY-test.lock, pyXY.lock)."""
    if os.environ.get("SLEIGHSIM_LOCK"):
        return [Path(os.environ["SLEIGHSIM_LOCK"])]
    py = f"py{sys.version_info.major}{sys.version_info.minor}"
    return [REQUIREMENTS / f"{py}-test.lock", REQUIREMENTS / f"{py}.lock"]


def pins(path) -> dict[str, str]:
    """{canonical name: version} of every ``name==version`` line of a lock file."""
    out = {}
    for line in Path(path).read_text().splitlines():
        if m := _PIN.match(line):
            out[canonicalize_name(m[1])] = m[2]
    return out


def installed() -> dict[str, str]:
    """{canonical name: version} of the distributions this Python sees."""
    return {canonicalize_name(d.metadata["Name"]): d.version for d in metadata.distributions()}


def required() -> set[str]:
    """Canonical names of sleighsim's unconditional requirements (its metadata; :data:`CORE` without it)."""
    try:
        reqs = metadata.requires("sleighsim") or []
    except metadata.PackageNotFoundError:
        return set(CORE)
    out = set()
    for line in reqs:
        try:
            req = Requirement(line)
        except InvalidRequirement:
            continue
        if req.marker is None or req.marker.evaluate({"extra": ""}):
            out.add(canonicalize_name(req.name))
    return out or set(CORE)


def _lock_pins(path: Path) -> tuple[dict[str, str], str]:
    """(:func:`pins` of ``path``, "") when it is a lock file, else ({}, why not)."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        return {}, f"cannot be read as text ({getattr(err, 'strerror', None) or err.__class__.__name__})"
    blocks = re.split(r"\n(?=[A-Za-z0-9])", text)
    unhashed = [b.split()[0] for b in blocks if _PIN.match(b) and "--hash=sha256:" not in b]
    if unhashed:
        return {}, f"pins without a hash ({', '.join(unhashed[:3])}): not pip-compile --generate-hashes output"
    pinned = pins(path)
    if missing := sorted(required() - set(pinned)):
        return {}, f"pins no version of {', '.join(missing[:5])}, which sleighsim requires"
    return pinned, ""


def _matches(pinned: dict[str, str], have: dict[str, str]) -> bool:
    try:
        return all(name in have and Version(have[name]) == Version(v) for name, v in pinned.items())
    except InvalidVersion:
        return False


@cache
def lock_attrs() -> dict[str, str]:
    """{"lock_file": its name, "lock_sha256": the SHA-256 of its bytes} of the first lock of
    :func:`lock_paths` that this environment matches pin for pin (versions equal as PEP 440 versions);
    {} when none exists or matches. A file ``SLEIGHSIM_LOCK`` names that is not a lock is logged."""
    have = installed()
    for path in lock_paths():
        if not path.is_file():
            continue
        pinned, why = _lock_pins(path)
        if why and os.environ.get("SLEIGHSIM_LOCK"):
            log.warning("SLEIGHSIM_LOCK %s: not a lock file: %s; datasets name no lock", path, why)
        if pinned and _matches(pinned, have):
            return {"lock_file": path.name, "lock_sha256": hashlib.sha256(path.read_bytes()).hexdigest()}
    return {}
