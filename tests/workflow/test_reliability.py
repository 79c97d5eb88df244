"""Issue 40 through Snakemake: nothing written outside results/, nothing moved by a dry run, the
results lock, the stale-temp sweep (a real run of a target no rule makes: the plan fails, no job runs)."""

import json
import os
import subprocess
import sys
import time

import pytest
import yaml
from conftest import ROOT, SMOKE, SMOKE_RESULTS, snakemake

from sleighsim.ops.runlock import LOCK_NAME, holder


def test_a_scene_name_climbing_out_of_results_is_refused_before_anything_is_written(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump({"scenes": {"../../../../tmp/x": {"kind": "sleigh0"}}}))
    run = tmp_path / "run"
    res = snakemake(run, bad, "-n", timeout=120)
    out = res.stdout + res.stderr
    assert res.returncode != 0 and "scenes.'../../../../tmp/x': a scene name must match" in out, out[-2000:]
    assert not (run / "results").exists()


def test_a_dry_run_moves_nothing_and_takes_no_lock(tmp_path):
    data = tmp_path / SMOKE_RESULTS / "data"
    data.mkdir(parents=True)
    (data / "fig4.nc").write_bytes(b"half a download")
    res = snakemake(tmp_path, SMOKE, "-n", f"{SMOKE_RESULTS}/data/fig4.nc", timeout=120)
    assert res.returncode == 0, (res.stdout + res.stderr)[-2000:]
    assert (data / "fig4.nc").read_bytes() == b"half a download"
    assert sorted(os.listdir(tmp_path / SMOKE_RESULTS)) == ["data"]


def test_a_real_run_sets_aside_declared_products_sweeps_stale_temps_and_releases_its_lock(tmp_path):
    data = tmp_path / SMOKE_RESULTS / "data"
    data.mkdir(parents=True)
    (data / "fig4.nc").write_bytes(b"half a download")
    (data / "notes.nc").write_text("not a product")
    stale = data / ".fig2.k3j4m5n6.nc.tmp"
    stale.write_bytes(b"killed")
    os.utime(stale, (time.time() - 3600,) * 2)
    res = snakemake(tmp_path, SMOKE, "-c1", "no_such_target", timeout=120)
    out = res.stdout + res.stderr
    assert f"{SMOKE_RESULTS}/data/fig4.nc -> {SMOKE_RESULTS}/unreadable/data/fig4.nc" in out, out[-2000:]
    assert f"removed a stale temporary file: {SMOKE_RESULTS}/data/.fig2.k3j4m5n6.nc.tmp" in out
    assert (tmp_path / SMOKE_RESULTS / "unreadable" / "data" / "fig4.nc").read_bytes() == b"half a download"
    assert (data / "notes.nc").exists() and not stale.exists()
    assert not (tmp_path / SMOKE_RESULTS / LOCK_NAME).exists()  # released when the process ends


def test_a_real_run_is_refused_while_another_live_run_holds_the_results(tmp_path):
    results = tmp_path / SMOKE_RESULTS
    results.mkdir()
    (results / LOCK_NAME).write_text(json.dumps({**holder(), "pid": os.getpid(), "checkout": "/other/clone"}))
    res = snakemake(tmp_path, SMOKE, "-c1", f"{SMOKE_RESULTS}/data/fig2.nc", timeout=120)
    out = res.stdout + res.stderr
    assert res.returncode != 0 and f"in use by pid {os.getpid()}" in out and "/other/clone" in out, out[-2000:]
    assert "rule scene" not in out and not (results / "data").exists()


# Issue 55: every mode that runs no job, however asked for, moves nothing, sweeps nothing and takes no lock.
API_DRY_RUN = """
import sys
from pathlib import Path
from snakemake.api import SnakemakeApi
from snakemake.settings.types import ConfigSettings, DAGSettings, OutputSettings, ResourceSettings
snakefile, workdir, smoke = map(Path, sys.argv[1:4])
target = sys.argv[4]
with SnakemakeApi(OutputSettings()) as api:
    wf = api.workflow(resource_settings=ResourceSettings(cores=1), config_settings=ConfigSettings(configfiles=[smoke]),
                      snakefile=snakefile, workdir=workdir)
    wf.dag(dag_settings=DAGSettings(targets={target})).execute_workflow(executor="dryrun")
"""


def _hostile_tree(tmp_path):
    data = tmp_path / SMOKE_RESULTS / "data"
    data.mkdir(parents=True)
    (data / "fig4.nc").write_bytes(b"half a download")
    stale = data / ".fig2.k3j4m5n6.nc.tmp"
    stale.write_bytes(b"killed")
    os.utime(stale, (time.time() - 3600,) * 2)
    return data, stale


@pytest.mark.parametrize("how", [["--executor", "dryrun"], ["--executor", "touch"], ["--list-input-changes"],
                                 ["--list-params-changes"], "api"], ids=lambda h: h if isinstance(h, str) else h[-1])
def test_no_mode_that_runs_no_job_moves_sweeps_or_locks(tmp_path, how):
    data, stale = _hostile_tree(tmp_path)
    if how == "api":
        res = subprocess.run([sys.executable, "-c", API_DRY_RUN, str(ROOT / "workflow" / "Snakefile"), str(tmp_path),
                              str(SMOKE), f"{SMOKE_RESULTS}/data/fig4.nc"], capture_output=True, text=True, timeout=300)
    else:
        res = snakemake(tmp_path, SMOKE, *how, f"{SMOKE_RESULTS}/data/fig4.nc", timeout=300)
    out = res.stdout + res.stderr
    assert (data / "fig4.nc").read_bytes() == b"half a download", out[-2000:]
    assert stale.exists() and sorted(os.listdir(tmp_path / SMOKE_RESULTS)) == ["data"], out[-2000:]


@pytest.mark.parametrize("results", ["/.", "/tmp/.."])
def test_a_results_directory_at_the_root_is_refused_naming_the_key(tmp_path, results):
    bad = tmp_path / "root.yaml"
    bad.write_text(yaml.safe_dump({"results": results}))
    res = snakemake(tmp_path, bad, "-n", timeout=120)
    out = res.stdout + res.stderr
    assert res.returncode != 0 and f"results = '{results}': resolves to the file-system root" in out, out[-2000:]


def _limited_memory():  # the old order expanded the bomb below: 6 GB
    import resource

    resource.setrlimit(resource.RLIMIT_DATA, (2 * 2**30, 2 * 2**30))


def test_an_alias_bomb_in_the_working_directorys_config_is_refused_before_snakemake_merges_it(tmp_path):
    """Issue 55: config/config.yaml of the working directory, which the Snakefile's configfile merges,
    is read strictly before that merge (a --configfile overlay Snakemake merges before the Snakefile runs)."""
    (tmp_path / "config").mkdir()
    bomb = "l0: &l0 {" + ", ".join(f"k{j}: lol" for j in range(9)) + "}\n" + "".join(
        f"l{i}: &l{i} {{" + ", ".join(f"k{j}: *l{i - 1}" for j in range(9)) + "}\n" for i in range(1, 9))
    (tmp_path / "config" / "config.yaml").write_text(bomb)  # 810 bytes, 9**9 mappings expanded
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflow" / "Snakefile"), "-d", str(tmp_path), "-n"]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=300, preexec_fn=_limited_memory)
    out = res.stdout + res.stderr
    assert res.returncode != 0 and "config.yaml: its aliases expand to more than" in out, out[-2000:]
