"""The smoke workflow on a real single-node SLURM (cluster/slurm-test.sh): submitted through
snakemake-executor-plugin-slurm with profiles/slurm, every job COMPLETED in sacct, and results identical
to the local smoke run's (sleighsim.resultdiff).

Opt-in: the script starts SLURM's daemons, MariaDB and munge, and the run takes minutes on two cores, so
it runs only when asked for, with ``pytest -m slurm`` (or SLEIGHSIM_SLURM_TEST=1), as root, on a machine
with SLURM (sbatch and slurmctld; ``cluster/slurm-test.sh`` installs them on Debian). Otherwise it skips
and says why."""

import os
import re
import shutil
import signal
import subprocess

import pytest
from conftest import ROOT

SCRIPT = ROOT / "cluster" / "slurm-test.sh"
# slurmctld lives in /usr/sbin, which a user's PATH may lack.
SEARCH = os.pathsep.join([os.environ.get("PATH", ""), "/usr/sbin", "/usr/local/sbin"])


def _asked_for(config) -> bool:
    """True under ``-m slurm`` (an expression naming the marker, not negated) or SLEIGHSIM_SLURM_TEST=1."""
    expr = config.getoption("markexpr") or ""
    return os.environ.get("SLEIGHSIM_SLURM_TEST") == "1" or bool(re.search(r"(?<!not )\bslurm\b", expr))


def _why_not(config) -> str | None:
    if not _asked_for(config):
        return "the real-SLURM test runs only when asked for: pytest -m slurm (or SLEIGHSIM_SLURM_TEST=1)"
    missing = [cmd for cmd in ("sbatch", "slurmctld") if shutil.which(cmd, path=SEARCH) is None]
    if missing:
        return (f"SLURM is not installed here ({' and '.join(missing)} not found); "
                "cluster/slurm-test.sh installs it on Debian (as root)")
    if os.geteuid() != 0:
        return "cluster/slurm-test.sh needs root (it starts SLURM's daemons)"
    return None


@pytest.mark.slurm
def test_smoke_run_on_a_real_slurm_equals_the_local_run(request, tmp_path):
    why = _why_not(request.config)
    if why:
        pytest.skip(why)
    pytest.importorskip("snakemake_executor_plugin_slurm")
    # The session's local smoke run is the reference (the fixture runs it if no other test has).
    local = request.getfixturevalue("smoke_run")
    env = {**os.environ, "PATH": SEARCH}
    # A session of its own: on a timeout the whole group gets SIGTERM, so the script's trap stops the
    # daemons it started and Snakemake cancels its jobs.
    proc = subprocess.Popen(["bash", str(SCRIPT), "--local", str(local), "--workdir", str(tmp_path)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                            start_new_session=True)
    try:
        out, _ = proc.communicate(timeout=1800)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGTERM)
        out, _ = proc.communicate(timeout=120)
        pytest.fail("cluster/slurm-test.sh took over 30 minutes:\n" + out[-5000:])
    assert proc.returncode == 0, out[-5000:]
    assert "PASS: every job COMPLETED" in out and "0 differ" in out, out[-5000:]
