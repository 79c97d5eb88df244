"""The lock files (requirements/py311.lock, py311-test.lock: pip-compile output with hashes) and
whether this environment was installed from one: then every dataset names the lock's hash.

An environment counts as installed from a lock when every package the lock pins is installed at
exactly the pinned version (checked, not assumed). The locks looked at are those of the running
Python in this checkout's ``requirements/`` (the test lock first: it pins more), or the file the
environment variable ``SLEIGHSIM_LOCK`` names (for an install outside a checkout)."""

from __future__ import annotations

import hashlib
import os
import re
import sys
from functools import cache
from importlib import metadata
from pathlib import Path

from packaging.utils import canonicalize_name
from packaging.version import Version

#: The checkout's folder of lock files (this file is src/sleighsim/io/lockfile.py).
REQUIREMENTS = Path(__file__).resolve().parents[3] / "requirements"
_PIN = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)==(\S+)")


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


@cache
def lock_attrs() -> dict[str, str]:
    """{"lock_file": its name, "lock_sha256": the SHA-256 of its bytes} of the first lock of
    :func:`lock_paths` that this environment matches pin for pin (versions equal as PEP 440 versions);
    {} when none exists or matches."""
    have = installed()
    for path in lock_paths():
        pinned = pins(path) if path.is_file() else {}
        if pinned and all(name in have and Version(have[name]) == Version(v) for name, v in pinned.items()):
            return {"lock_file": path.name, "lock_sha256": hashlib.sha256(path.read_bytes()).hexdigest()}
    return {}
