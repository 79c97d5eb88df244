"""Cache directories no other user controls: heyoka's and numba's compiled code is read back from
them and run, so whoever can write there runs code in every job.

A cache directory is created with mode 0700 when missing. An existing one is used only when it is a
directory owned by the current user that no one else can write, and when each directory above it is
owned by the user or by root and, if someone else can write it, sticky (as /tmp is: no one else can
rename or replace what it holds). "Someone else" is others, and the group unless it is the user's
private group (named after the user, with no other members: umask 002 systems make directories
group-writable for it). The way there is checked too, before the cache is created or resolved: each
directory above the path as written, and each symbolic link on it, which must be the user's or
root's (a link inside a directory others can write would let them point the cache elsewhere).
Anything else is refused with the reason.
"""

from __future__ import annotations

import grp
import os
import pwd
import stat
from pathlib import Path


class UnsafeDirectory(RuntimeError):
    """A cache directory another user owns or can write, refused."""


def _private_group(gid: int) -> bool:
    """Whether ``gid`` is the user's private group: named after the user, no one else a member."""
    try:
        user, group = pwd.getpwuid(os.geteuid()).pw_name, grp.getgrgid(gid)
    except KeyError:
        return False
    return group.gr_name == user and set(group.gr_mem) <= {user}


def _problem(path: Path, leaf: bool) -> str:
    """Why another user controls the directory ``path`` ("" when no one else does); ``leaf``: the
    cache itself, which must be owned by the user and not sticky-shared."""
    st = os.stat(path)
    owners = (os.geteuid(),) if leaf else (os.geteuid(), 0)
    if not stat.S_ISDIR(st.st_mode):
        return f"{path} is not a directory"
    if st.st_uid not in owners:
        return f"{path} is owned by uid {st.st_uid}, not by you (uid {os.geteuid()})"
    shared = st.st_mode & 0o002 or (st.st_mode & 0o020 and not _private_group(st.st_gid))
    if shared and (leaf or not st.st_mode & stat.S_ISVTX):
        return f"{path} is writable by its group or by others (mode {stat.S_IMODE(st.st_mode):04o})"
    return ""


def _route_problem(path: Path) -> str:
    """Why another user controls the way to ``path`` as written ("" when no one does): an existing
    directory above it (:func:`_problem`) or a symbolic link on it owned by someone else."""
    absolute = Path(os.path.abspath(path))
    for p in (absolute, *absolute.parents):
        try:
            st = os.lstat(p)
        except FileNotFoundError:
            continue  # created below, 0700
        if stat.S_ISLNK(st.st_mode) and st.st_uid not in (os.geteuid(), 0):
            return f"{p} is a symbolic link owned by uid {st.st_uid}, not by you (uid {os.geteuid()}) or root"
        if p != absolute and not stat.S_ISLNK(st.st_mode) and (why := _problem(p, leaf=False)):
            return why
    return ""


def project_cache() -> tuple[Path, str]:
    """(the project's own cache directory, the setting that chose it): ``$SLEIGHSIM_CACHE``, else
    ``~/.cache/sleighsim``; not created or checked here (:func:`private_directory` does both)."""
    if os.environ.get("SLEIGHSIM_CACHE"):
        return Path(os.environ["SLEIGHSIM_CACHE"]), "SLEIGHSIM_CACHE"
    return Path.home() / ".cache" / "sleighsim", "~/.cache/sleighsim"


def private_directory(path, what: str) -> Path:
    """``path`` as a cache directory only the current user controls: created 0700 when missing;
    :class:`UnsafeDirectory` naming ``what`` (the setting that chose it) and the reason otherwise.
    OSError when it cannot be created."""
    path = Path(path)
    if why := _route_problem(path):
        raise _refused(what, path, why)
    os.makedirs(path, mode=0o700, exist_ok=True)
    real = path.resolve()
    for directory in (real, *real.parents):
        if why := _problem(directory, leaf=directory == real):
            raise _refused(what, path, why)
    return path


def _refused(what: str, path: Path, why: str) -> UnsafeDirectory:
    return UnsafeDirectory(f"{what} {path}: refused as a cache, since {why}; another user could put code there "
                           "that every job runs. Use a directory only you can write (e.g. under ~/.cache), or chmod "
                           "go-w it if it is yours")
