import fcntl
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from sleighsim.ops.config import merged_config

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "config" / "config.yaml"
SMOKE = ROOT / "config" / "smoke.yaml"  # an overlay: pass it to Snakemake, or read it with smoke_config()


def smoke_config() -> dict:
    """The smoke config as a run sees it: config/smoke.yaml merged onto config/config.yaml the way
    Snakemake merges ``--configfile`` (a fresh copy each call, so a test may change it)."""
    return merged_config([SMOKE], base=PAPER)


def snakemake(workdir, configfile, *args, timeout=900, cores=2):
    """Run the workflow in ``workdir`` with ``configfile`` merged onto the paper config."""
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflow" / "Snakefile"), "-d", str(workdir),
           "--configfile", str(configfile), f"-c{cores}", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture
def rng():
    return np.random.default_rng(20261121)


#: Where a smoke run writes (its own results directory, never a paper run's results/).
SMOKE_RESULTS = smoke_config()["results"]


def pytest_collection_modifyitems(config, items):
    """Every test that reads the smoke run joins one xdist group (``--dist loadgroup``, pyproject.toml), so one
    worker runs the smoke workflow and its readers while the other runs everything else instead of waiting on
    the run's lock (in CI the wait was about 250 s of one of two workers)."""
    for item in items:
        if "smoke_run" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.xdist_group("smoke"))


@pytest.fixture(scope="session")
def smoke_run(tmp_path_factory, worker_id):
    """The smoke workflow, run once per test session and shared, read-only, by every test that reads
    it or dry-runs against it. Under pytest-xdist its readers share one worker (their xdist group); the
    lock keeps a second worker from running it again where they do not (another --dist mode)."""
    base = tmp_path_factory.getbasetemp()
    base = base.parent if worker_id != "master" else base
    workdir = base / "smoke_shared"
    with open(base / "smoke_shared.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (workdir / SMOKE_RESULTS / "report" / "index.html").exists():
            res = snakemake(workdir, SMOKE)
            assert res.returncode == 0, res.stderr[-3000:]
    return workdir


@pytest.fixture(scope="session")
def hy():
    """heyoka (the tests that need it skip without it)."""
    return pytest.importorskip("heyoka")


@pytest.fixture(scope="session")
def runs(hy):
    """Each textbook orbit's indicator runs once (``chaos_textbook.textbook_runs``), for the chaos tests."""
    from chaos_textbook import textbook_runs

    return textbook_runs(hy)


def write_fixture(ds, path):
    """Write a fixture dataset (write_dataset); one under precision/<tag>/ as computed in that
    precision: the tests lay out the tree, so they know it."""
    from sleighsim.io.netcdf import write_dataset
    from sleighsim.precision import Precision

    parts = Path(path).parts
    tag = parts[parts.index("precision") + 1] if "precision" in parts else "double"
    write_dataset(ds, path, precision={p.tag: p.value for p in Precision}[tag])
