"""Failure behaviour of the workflow: interruption, partial reruns, what a change reruns."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import yaml
from conftest import ROOT, SMOKE, SMOKE_RESULTS, smoke_config, snakemake

from sleighsim.io.netcdf import read_dataset

GRID = f"{SMOKE_RESULTS}/data/fig11_grid.nc"


def _cmd(workdir, configfile, *args):
    return [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflow" / "Snakefile"), "-d", str(workdir),
            "--configfile", str(configfile), *args]


@pytest.mark.workflow
def test_sigterm_during_the_grid_keeps_finished_chunks_and_reruns_the_rest(smoke_run, tmp_path):
    """The smoke grid has one eps row per chunk; the reference is the shared smoke run."""
    run = tmp_path / "interrupted"
    chunks = run / SMOKE_RESULTS / "chunks" / "fig11_grid"
    proc = subprocess.Popen(_cmd(run, SMOKE, "-c1", GRID), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            start_new_session=True)
    deadline = time.time() + 300

    def chunks_finished():  # Snakemake's own record that a chunk job completed
        logs = list((run / ".snakemake" / "log").glob("*.snakemake.log"))
        return sum(line.startswith("Finished jobid") and "Rule: chunk" in line
                   for f in logs for line in f.read_text().splitlines())

    while time.time() < deadline and chunks_finished() < 1:
        time.sleep(0.05)
    finished = sorted(chunks.glob("*.nc"))
    os.killpg(proc.pid, signal.SIGTERM)
    assert finished, "no chunk finished before the deadline"
    stamps = {p.name: p.stat().st_mtime_ns for p in finished}
    try:
        proc.wait(timeout=60)
        graceful = True
    except subprocess.TimeoutExpired:  # a job spawned just after the signal: stop hard, as a killed node would
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=60)
        graceful = False
    assert not (run / GRID).exists()
    if graceful:
        assert not list(chunks.glob(".*.tmp"))  # SIGTERM lets the job delete its temporary file
    else:  # a hard kill leaves Snakemake's lock, which the user removes as Snakemake says
        unlock = subprocess.run(_cmd(run, SMOKE, "--unlock"), capture_output=True, text=True, timeout=120)
        assert unlock.returncode == 0, unlock.stderr[-2000:]

    again = subprocess.run(_cmd(run, SMOKE, "-c1", "--rerun-incomplete", GRID), capture_output=True, text=True,
                           timeout=600)
    assert again.returncode == 0, again.stderr[-2000:]
    for name, stamp in stamps.items():
        assert (chunks / name).stat().st_mtime_ns == stamp, f"{name} was recomputed"
    a, b = read_dataset(smoke_run / GRID), read_dataset(run / GRID)
    for name in ("lambda_1", "stderr", "flagged"):
        assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name


@pytest.mark.workflow
def test_changing_one_scene_reruns_only_what_depends_on_it(smoke_run, tmp_path):
    target = [f"{SMOKE_RESULTS}/figures/{f}.png" for f in ("fig3", "fig7", "fig2")]
    cfg = smoke_config()
    cfg["scenes"]["fig3"]["t_end"] = 250.0
    changed = tmp_path / "changed.yaml"
    changed.write_text(yaml.safe_dump(cfg, sort_keys=True))  # reordered keys must not count as a change
    dry = snakemake(smoke_run, changed, "-n", *target, timeout=120)
    out = dry.stdout + dry.stderr
    assert dry.returncode == 0, out[-2000:]
    assert "wildcards: scene=fig3" in out and "wildcards: fig=fig3" in out
    assert "scene=fig7" not in out and "scene=fig2" not in out and "fig=fig7" not in out


@pytest.mark.workflow
def test_changing_the_grid_runtime_resource_reruns_nothing(smoke_run, tmp_path):
    """chunk_runtime_min schedules the chunk jobs and runtime_min a scene's job; neither is part of
    what they compute."""
    cfg = smoke_config()
    cfg["scenes"]["fig11_grid"]["chunk_runtime_min"] += 60
    cfg["scenes"]["formal_exponents"]["runtime_min"] = 500
    changed = tmp_path / "changed.yaml"
    changed.write_text(yaml.safe_dump(cfg))
    dry = snakemake(smoke_run, changed, "-n", GRID, f"{SMOKE_RESULTS}/data/formal_exponents.nc", timeout=120)
    assert dry.returncode == 0 and "Nothing to be done" in dry.stdout + dry.stderr, (dry.stdout + dry.stderr)[-2000:]
    forced = snakemake(smoke_run, changed, "-n", "--forcerun", "scene_first", "--",
                       f"{SMOKE_RESULTS}/data/formal_exponents.nc", timeout=120)
    assert "runtime=500" in forced.stdout + forced.stderr, (forced.stdout + forced.stderr)[-2000:]
    cfg["scenes"]["fig11_grid"]["T_round"] *= 2  # what the grid computes does force a rerun
    changed.write_text(yaml.safe_dump(cfg))
    dry = snakemake(smoke_run, changed, "-n", GRID, timeout=120)
    assert "rule chunk:" in dry.stdout + dry.stderr


@pytest.mark.workflow
def test_a_deleted_or_truncated_dataset_is_rebuilt_by_the_default_target(smoke_run, tmp_path):
    """Snakemake alone would not rebuild a missing intermediate file whose products are up to date,
    and would fail on a truncated one at every run: rule all declares every dataset, and an
    unreadable product is set aside (results/unreadable/, by the real run) before the jobs are
    planned; a dry run moves nothing."""
    import shutil

    run = tmp_path / "run"
    shutil.copytree(smoke_run / SMOKE_RESULTS, run / SMOKE_RESULTS)
    shutil.copytree(smoke_run / ".snakemake" / "metadata", run / ".snakemake" / "metadata")
    (run / SMOKE_RESULTS / "data" / "fig2.nc").unlink()
    cut = run / SMOKE_RESULTS / "data" / "fig4.nc"
    cut.write_bytes(cut.read_bytes()[:4000])
    dry = subprocess.run(_cmd(run, SMOKE, "-n"), capture_output=True, text=True, timeout=300)
    out = dry.stdout + dry.stderr
    assert dry.returncode == 0 and "unreadable:" not in out and cut.stat().st_size == 4000, out[-3000:]
    res = subprocess.run(_cmd(run, SMOKE, "-c2"), capture_output=True, text=True, timeout=600)
    out = res.stdout + res.stderr
    assert res.returncode == 0, out[-3000:]
    assert f"{SMOKE_RESULTS}/data/fig4.nc -> " in out and f"{SMOKE_RESULTS}/unreadable/data/fig4.nc" in out, out[-3000:]
    assert "wildcards: scene=fig2" in out and "wildcards: scene=fig4" in out and "scene=fig7" not in out
    assert (run / SMOKE_RESULTS / "unreadable" / "data" / "fig4.nc").stat().st_size == 4000
    for name in ("fig2", "fig4"):
        new = read_dataset(run / SMOKE_RESULTS / "data" / f"{name}.nc")
        old = read_dataset(smoke_run / SMOKE_RESULTS / "data" / f"{name}.nc")
        assert all(np.array_equal(new[v].values, old[v].values, equal_nan=True)
                   for v in old.data_vars if old[v].dtype.kind == "f")
