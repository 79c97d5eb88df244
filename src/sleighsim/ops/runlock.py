"""One real run at a time on a results directory, across clones and working directories.

Snakemake locks a working directory (.snakemake/locks); two clones writing one results directory
are not stopped by it. A real run takes :data:`LOCK_NAME` under the results directory (created with
O_EXCL), naming its holder (host, pid, user, checkout, start time). Another run is refused with a
message naming the holder while the holder lives; a lock whose pid is dead on this host is taken
over with a warning; a lock held from another host is left to the user to remove. Dry runs and the
other commands that run no job (:func:`real_run`) take no lock.
"""

from __future__ import annotations

import getpass
import json
import os
import socket
import sys
import time
from pathlib import Path

from sleighsim.ops.config import REPO

#: The lock file, under the results directory.
LOCK_NAME = ".sleighsim.lock"
#: Snakemake options under which no job runs (sleighsim takes no lock and moves no file then).
NO_JOB_OPTIONS = ("dryrun", "touch", "unlock", "lint", "list_rules", "list_target_rules", "summary",
                  "detailed_summary", "dag", "rulegraph", "filegraph", "d3dag", "report", "cleanup_metadata",
                  "cleanup_shadow", "delete_all_output", "delete_temp_output", "list_changes", "list_untracked",
                  "print_compilation", "generate_unit_tests", "containerize", "export_cwl", "archive",
                  "list_conda_envs", "conda_cleanup_envs", "conda_create_envs_only", "container_cleanup_images")


class LockError(RuntimeError):
    """The results directory is locked by a live run."""


def real_run(argv) -> bool:
    """Whether the Snakemake command line ``argv`` (without the program name) runs jobs here, read
    with Snakemake's own parser (its profile included); False when it cannot be read as one."""
    from snakemake.cli import parse_args

    try:
        _, args = parse_args(list(argv))
    except SystemExit:
        return False
    return not any(getattr(args, name, None) for name in NO_JOB_OPTIONS)


def holder() -> dict:
    """This process as a lock holder."""
    return {"host": socket.gethostname(), "pid": os.getpid(), "user": getpass.getuser(), "checkout": str(REPO),
            "cwd": os.getcwd(), "started": time.strftime("%Y-%m-%dT%H:%M:%S%z")}


def describe(h: dict) -> str:
    """A holder record in words."""
    return (f"pid {h.get('pid')} of {h.get('user')} on {h.get('host')} (checkout {h.get('checkout')}, "
            f"working directory {h.get('cwd')}, since {h.get('started')})")


def _alive(pid) -> bool:
    """Whether process ``pid`` (a positive int; anything else counts as alive) exists on this host."""
    if not isinstance(pid, int) or isinstance(pid, bool) or pid <= 0:
        return True  # never signal 0 or a process group; a lock naming no pid is not taken over
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # another user's live process
    return True


def _read(path: Path) -> dict:
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        return {}
    except (OSError, ValueError) as err:
        raise LockError(f"{path}: a lock file that cannot be read ({err}); remove it if no run uses "
                        "this results directory") from None


def _create(path: Path, me: dict) -> bool:
    """Create the lock naming ``me``; False when it exists."""
    try:
        fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
    except FileExistsError:
        return False
    with os.fdopen(fd, "w") as f:
        json.dump(me, f)
    return True


def acquire(results) -> dict:
    """Take the lock of ``results`` (created if missing) for this process and return its holder
    record; a stale lock (dead pid on this host) is taken over with a warning on stderr. Raises
    :class:`LockError` naming the holder of a live lock."""
    path = Path(results) / LOCK_NAME
    path.parent.mkdir(parents=True, exist_ok=True)
    me = holder()
    for _ in range(3):
        if _create(path, me):
            return me
        other = _read(path)
        if not other:
            continue  # released meanwhile
        same_host = other.get("host") == me["host"]
        if same_host and other.get("pid") == me["pid"]:
            return other  # this process holds it already (the Snakefile parsed twice)
        if not same_host or _alive(other.get("pid")):
            raise LockError(f"{path}: results directory in use by {describe(other)}; wait for that run, "
                            "or remove the lock file if it is dead")
        print(f"warning: taking over the stale lock {path} of {describe(other)} (no such process)",
              file=sys.stderr)
        path.unlink(missing_ok=True)
    raise LockError(f"{path}: could not take the lock (other runs keep taking it)")


def release(results) -> bool:
    """Remove the lock of ``results`` if this process holds it; whether it did."""
    path = Path(results) / LOCK_NAME
    try:
        other = _read(path)
    except LockError:
        return False
    if other.get("pid") != os.getpid() or other.get("host") != socket.gethostname():
        return False
    path.unlink(missing_ok=True)
    return True
