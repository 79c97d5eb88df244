"""Issue 55: the results lock under races and hostile contents. One process takes over a stale lock
(before: two did in 10 of 40 races); a run whose jobs outlived it is not taken over; a lock appears
whole (before: one mid-creation was "unreadable", a full disk left a 0-byte lock blocking every later
run); odd contents are refused with a message (before: tracebacks); the lock names the Snakefile's
checkout (before: the installed package's)."""

import errno
import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from sleighsim.ops import runlock
from sleighsim.ops.runlock import LOCK_NAME, LockError, acquire


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def _stale(results):
    results.mkdir(parents=True, exist_ok=True)
    (results / LOCK_NAME).write_text(json.dumps({**runlock.holder(), "pid": _dead_pid()}))


RACER = textwrap.dedent("""
    import sys, time
    from sleighsim.ops import runlock
    from sleighsim.ops.runlock import LockError, acquire
    alive = runlock._alive
    def slow(pid):  # a slow machine: every racer reads the stale lock before any replaces it
        time.sleep(0.3)
        return alive(pid)
    runlock._alive = slow
    start = float(sys.argv[2])
    while time.time() < start:
        pass
    try:
        acquire(sys.argv[1])
        print("took", flush=True)
    except LockError:
        print("refused", flush=True)
    time.sleep(3)  # hold it while the others try
""")


def test_one_process_alone_takes_over_a_stale_lock(tmp_path):
    for trial in range(3):
        results = tmp_path / f"r{trial}"
        _stale(results)
        start = str(time.time() + 1.5)
        racers = [subprocess.Popen([sys.executable, "-c", RACER, str(results), start], stdout=subprocess.PIPE,
                                   text=True) for _ in range(6)]
        outcomes = sorted(p.communicate(timeout=60)[0].strip() for p in racers)
        assert outcomes == ["refused"] * 5 + ["took"], (trial, outcomes)


def test_a_run_whose_jobs_outlived_it_is_not_taken_over(tmp_path):
    results = tmp_path / "results"
    run = textwrap.dedent(f"""
        import subprocess, sys
        from sleighsim.ops.runlock import acquire
        acquire({str(results)!r})
        job = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
        print(job.pid, flush=True)
        import time; time.sleep(60)
    """)
    proc = subprocess.Popen([sys.executable, "-c", run], stdout=subprocess.PIPE, text=True)
    job = int(proc.stdout.readline())
    try:
        proc.send_signal(signal.SIGKILL)  # the run is killed; its job keeps writing
        proc.wait(timeout=30)
        with pytest.raises(LockError, match=rf"is dead but its processes \[{job}\] still run"):
            acquire(results)
    finally:
        os.kill(job, signal.SIGKILL)
    time.sleep(0.5)
    assert acquire(results)["pid"] == os.getpid()  # the job gone, the stale lock is taken over


def test_a_lock_being_written_is_never_seen_half_written(tmp_path):
    results = tmp_path / "results"
    slow = textwrap.dedent(f"""
        import json, time
        from sleighsim.ops import runlock
        real = json.dump
        def dump(obj, f):
            print("writing", flush=True)
            time.sleep(3)
            real(obj, f)
        runlock.json.dump = dump
        try:
            runlock.acquire({str(results)!r})
            print("took", flush=True)
        except runlock.LockError as err:
            print("refused", err, flush=True)
    """)
    proc = subprocess.Popen([sys.executable, "-c", slow], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "writing"
    try:
        mine = acquire(results)  # the other's lock is not in place yet: this run takes it
    except LockError as err:
        assert "in use by" in str(err), err  # or the other's, whole; never "cannot be read"
        mine = None
    out = proc.communicate(timeout=30)[0]
    assert (mine is None and "took" in out) or (mine is not None and "refused" in out and "in use by pid" in out), out


def test_a_full_disk_leaves_no_lock_behind(tmp_path, monkeypatch):
    results = tmp_path / "results"

    def full(obj, f):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(runlock.json, "dump", full)
    with pytest.raises((LockError, OSError), match="No space left"):
        acquire(results)
    assert list(results.iterdir()) == []
    monkeypatch.undo()
    assert acquire(results)["pid"] == os.getpid()


@pytest.mark.parametrize("contents", ["[1]", "null", '"text"', json.dumps({"pid": 2**64, "host": "h"}),
                                      json.dumps({"pid": -1}), json.dumps({"pid": True}), ""],
                         ids=["a list", "null", "a string", "pid 2**64", "pid -1", "pid true", "empty"])
def test_a_lock_with_odd_contents_is_refused_with_a_message(tmp_path, contents):
    results = tmp_path / "results"
    results.mkdir()
    (results / LOCK_NAME).write_text(contents)
    with pytest.raises(LockError, match=rf"{LOCK_NAME}: a lock file (naming no valid process|that cannot be read)"):
        acquire(results)
    assert (results / LOCK_NAME).read_text() == contents and not runlock.release(results)


def test_the_lock_names_the_checkout_whose_snakefile_runs(tmp_path):
    assert acquire(tmp_path / "results", checkout="/clones/other")["checkout"] == "/clones/other"
    assert json.loads((tmp_path / "results" / LOCK_NAME).read_text())["checkout"] == "/clones/other"
