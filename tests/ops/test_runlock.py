"""The results directory's lock across clones, and which Snakemake commands count as real runs."""

import json
import os
import socket
import subprocess
import sys

import pytest

from sleighsim.ops import runlock
from sleighsim.ops.runlock import LOCK_NAME, LockError, acquire, real_run, release


def _held_by(results, **over):
    record = {**runlock.holder(), **over}
    results.mkdir(parents=True, exist_ok=True)
    (results / LOCK_NAME).write_text(json.dumps(record))
    return record


def test_a_lock_names_its_holder_and_is_released_by_it(tmp_path):
    results = tmp_path / "results"
    me = acquire(results)
    on_disk = json.loads((results / LOCK_NAME).read_text())
    assert on_disk == me and on_disk["pid"] == os.getpid() and {"host", "user", "checkout", "started"} <= set(me)
    assert release(results) and not (results / LOCK_NAME).exists()
    assert not release(results)


def test_a_live_holder_refuses_another_run_naming_the_holder(tmp_path):
    results = tmp_path / "results"
    _held_by(results, pid=os.getppid(), checkout="/elsewhere/clone")
    with pytest.raises(LockError, match=rf"in use by pid {os.getppid()} .* \(checkout /elsewhere/clone"):
        acquire(results)
    assert not release(results)  # not ours: left alone
    assert (results / LOCK_NAME).exists()


def test_a_holder_on_another_host_is_never_taken_over(tmp_path):
    results = tmp_path / "results"
    _held_by(results, host="another-" + socket.gethostname(), pid=999999)
    with pytest.raises(LockError, match=r"on another-"):
        acquire(results)


def test_a_stale_lock_of_a_dead_process_is_taken_over_with_a_warning(tmp_path, capsys):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    results = tmp_path / "results"
    _held_by(results, pid=dead.pid)
    assert acquire(results)["pid"] == os.getpid()
    assert f"taking over the stale lock {results / LOCK_NAME} of pid {dead.pid}" in capsys.readouterr().err


def test_a_lock_file_that_names_no_pid_is_refused_not_signalled(tmp_path):
    results = tmp_path / "results"
    _held_by(results, pid=0)
    with pytest.raises(LockError, match="a lock file naming no valid process"):
        acquire(results)
    (results / LOCK_NAME).write_text("{not json")
    with pytest.raises(LockError, match="a lock file that cannot be read"):
        acquire(results)


class _Workflow:
    """What real_run reads of a Snakemake Workflow."""

    def __init__(self, executor=True, dryrun=False, touch=False, main=True):
        self.executor_plugin, self.dryrun, self.touch, self.is_main_process = (object() if executor else None), \
            dryrun, touch, main


@pytest.mark.parametrize("workflow, real", [
    (_Workflow(), True), (_Workflow(dryrun=True), False), (_Workflow(touch=True), False),
    (_Workflow(executor=False), False), (_Workflow(main=False), False)],
    ids=["executing", "dry run", "touch", "no executor (a listing, --summary, --lint)", "a job's process"])
def test_real_runs_are_told_from_dry_runs_and_other_commands(workflow, real):
    assert real_run(workflow) is real
