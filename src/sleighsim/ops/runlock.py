"""One real run at a time on a results directory, across clones and working directories.

Snakemake locks a working directory (.snakemake/locks); two clones writing one results directory
are not stopped by it. A real run takes :data:`LOCK_NAME` under the results directory, naming its
holder (host, pid, user, the Snakefile's checkout, start time and a token its jobs inherit in the
environment variable :data:`RUN_ENV`). The lock appears whole or not at all (written aside, then
linked into place: a full disk leaves none). Another run is refused with a message naming the holder
while the holder lives, or while a process of its run (a job that outlived a killed run) still
does; a lock whose pid is dead on this host and whose jobs are gone is taken over with a warning, by
one process only (the stale file is locked and replaced atomically); a lock held from another host
is left to the user to remove. Only a run that executes jobs takes it (:func:`real_run`).
"""

from __future__ import annotations

import atexit
import contextlib
import fcntl
import getpass
import json
import os
import secrets
import socket
import sys
import time
from pathlib import Path

from sleighsim.ops.config import REPO

#: The lock file, under the results directory.
LOCK_NAME = ".sleighsim.lock"
#: The environment variable naming the run's token, inherited by every job the run starts.
RUN_ENV = "SLEIGHSIM_RUN"
#: Process ids are positive C ints (os.kill takes nothing larger).
MAX_PID = 2**31 - 1


class LockError(RuntimeError):
    """The results directory is locked by a live run, or its lock cannot be read or written."""


def real_run(workflow) -> bool:
    """Whether Snakemake ``workflow`` is about to execute jobs in this process: it runs (an executor
    is chosen: not --list-*, --summary, --lint, ...), and not as a dry run (-n, --executor dryrun,
    an API dry run) nor one that only touches files (--touch, --executor touch). Known only once
    the executor is chosen, i.e. when the job graph is about to be built, after the Snakefile is read."""
    return bool(workflow.is_main_process and workflow.executor_plugin is not None and not workflow.dryrun
                and not workflow.touch)


def holder(checkout=REPO) -> dict:
    """This process as a lock holder; ``checkout``: the clone whose Snakefile runs."""
    return {"host": socket.gethostname(), "pid": os.getpid(), "user": getpass.getuser(), "checkout": str(checkout),
            "cwd": os.getcwd(), "started": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "token": secrets.token_hex(8)}


def describe(h: dict) -> str:
    """A holder record in words."""
    return (f"pid {h.get('pid')} of {h.get('user')} on {h.get('host')} (checkout {h.get('checkout')}, "
            f"working directory {h.get('cwd')}, since {h.get('started')})")


def _alive(pid: int) -> bool:
    """Whether process ``pid`` (1 .. MAX_PID) exists on this host."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # another user's live process
    return True


def run_processes(token: str) -> list[int]:
    """Pids of the live processes (this user's, on this host; Linux /proc) started by the run of
    ``token``: they carry it in :data:`RUN_ENV`."""
    needle = f"{RUN_ENV}={token}".encode()
    pids = []
    for entry in Path("/proc").glob("[0-9]*"):
        try:
            env = (entry / "environ").read_bytes()
        except OSError:
            continue
        if needle in env.split(b"\0") and int(entry.name) != os.getpid():
            pids.append(int(entry.name))
    return sorted(pids)


def _read(path: Path) -> dict:
    """The holder record of the lock ``path``; {} when there is none; LockError when it is not one."""
    try:
        record = json.loads(path.read_text())
    except FileNotFoundError:
        return {}
    except (OSError, ValueError) as err:
        raise LockError(f"{path}: a lock file that cannot be read ({err}); remove it if no run uses "
                        "this results directory") from None
    pid = record.get("pid") if isinstance(record, dict) else None
    if not isinstance(pid, int) or isinstance(pid, bool) or not 0 < pid <= MAX_PID:
        raise LockError(f"{path}: a lock file naming no valid process ({str(record)[:200]}); remove it if no run "
                        "uses this results directory")
    return record


def _written_aside(path: Path, me: dict) -> Path:
    """A complete copy of the record ``me`` beside ``path`` (LockError, nothing left, when it cannot be written)."""
    tmp = path.with_name(f"{path.name}.{me['token']}")
    try:
        with open(tmp, "x") as f:
            json.dump(me, f)
            f.flush()
            os.fsync(f.fileno())
    except OSError as err:
        tmp.unlink(missing_ok=True)
        raise LockError(f"{path}: cannot write the lock ({err.strerror or err}); no run was started") from None
    return tmp


def _create(path: Path, me: dict) -> bool:
    """Put the lock naming ``me`` in place, whole; False when one exists."""
    tmp = _written_aside(path, me)
    try:
        os.link(tmp, path)
    except FileExistsError:
        return False
    finally:
        tmp.unlink(missing_ok=True)
    return True


def _take_over(path: Path, stale: dict, me: dict) -> bool:
    """Replace the stale lock ``path`` holding ``stale`` by ``me``, atomically: the stale file is
    locked (flock) and must still be the one at ``path`` holding ``stale``; False when another run
    took it over or released it meanwhile."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except FileNotFoundError:
        return False
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return False  # another run is taking it over
        with contextlib.suppress(FileNotFoundError):
            if os.stat(path).st_ino == os.fstat(fd).st_ino and _read(path) == stale:
                os.replace(_written_aside(path, me), path)
                return True
        return False
    finally:
        os.close(fd)


def _refuse_live(path: Path, other: dict, me: dict) -> None:
    """LockError when the holder ``other`` or a process of its run lives (or it is on another host)."""
    if other.get("host") != me["host"] or _alive(other["pid"]):
        raise LockError(f"{path}: results directory in use by {describe(other)}; wait for that run, "
                        "or remove the lock file if it is dead")
    if other.get("token") and (jobs := run_processes(str(other["token"]))):
        raise LockError(f"{path}: the run of {describe(other)} is dead but its processes {jobs} still run (jobs "
                        "that may still write results); wait for them or end them, then start again")


def acquire(results, checkout=REPO) -> dict:
    """Take the lock of ``results`` (created if missing) for this process and return its holder
    record (``checkout``: the clone whose Snakefile runs); a stale lock (dead pid on this host, no
    process of its run left) is taken over with a warning on stderr. Sets :data:`RUN_ENV` for the
    jobs. Raises :class:`LockError` naming the holder of a live lock."""
    path = Path(results) / LOCK_NAME
    path.parent.mkdir(parents=True, exist_ok=True)
    me = holder(checkout)
    for _ in range(20):
        if _create(path, me):
            break
        other = _read(path)
        if not other:
            continue  # released meanwhile
        if other.get("host") == me["host"] and other["pid"] == me["pid"]:
            return other  # this process holds it already (the Snakefile parsed twice)
        _refuse_live(path, other, me)
        if _take_over(path, other, me):
            print(f"warning: taking over the stale lock {path} of {describe(other)} (no such process)",
                  file=sys.stderr)
            break
        time.sleep(0.05)
    else:
        raise LockError(f"{path}: could not take the lock (other runs keep taking it)")
    os.environ[RUN_ENV] = me["token"]
    return me


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


def before_planning(workflow, action) -> None:
    """Call ``action()`` once, just before Snakemake ``workflow`` builds its job graph for a run
    that executes jobs (:func:`real_run`; the executor is not known while the Snakefile is read).
    Snakemake offers no hook there: its Workflow._build_dag is wrapped (a Snakemake without it is
    refused rather than run unlocked)."""
    build = getattr(workflow, "_build_dag", None)
    if not callable(build):
        raise LockError("this Snakemake has no Workflow._build_dag, where sleighsim takes the results lock before "
                        "a real run; use the Snakemake version of requirements/")
    done = []

    def planning(*args, **kwargs):
        if not done and real_run(workflow):
            done.append(True)
            action()
        return build(*args, **kwargs)

    workflow._build_dag = planning


def prepare_run(results, products, dirs, checkout) -> None:
    """What a run that executes jobs does before planning: take the lock of ``results`` (released
    when the process ends, also when the plan fails), remove the workflow's stale temporary files
    in ``results`` and its subdirectories ``dirs`` (sleighsim.io.integrity.sweep_stale_temps), and set
    aside the ``products`` that are not valid netCDF (sleighsim.io.integrity.set_aside); each said on
    stderr. ``checkout``: the clone whose Snakefile runs."""
    from sleighsim.io.integrity import set_aside, sweep_stale_temps

    started = time.time()
    acquire(results, checkout=checkout)
    atexit.register(release, Path(results).absolute())
    for gone in sweep_stale_temps(results, started, dirs):
        print(f"removed a stale temporary file: {gone}", file=sys.stderr)
    for bad, to in set_aside(results, products):
        print(f"unreadable: {bad} -> {to}; a run that needs it builds it again", file=sys.stderr)
