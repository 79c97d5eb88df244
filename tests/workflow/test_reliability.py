"""Issue 40 through Snakemake: nothing written outside results/, nothing moved by a dry run, the
results lock, the stale-temp sweep (a real run of a target no rule makes: the plan fails, no job runs)."""

import json
import os
import time

import yaml
from conftest import SMOKE, SMOKE_RESULTS, snakemake

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
    stale = data / ".fig2.k3j4.nc.tmp"
    stale.write_bytes(b"killed")
    os.utime(stale, (time.time() - 3600,) * 2)
    res = snakemake(tmp_path, SMOKE, "-c1", "no_such_target", timeout=120)
    out = res.stdout + res.stderr
    assert f"{SMOKE_RESULTS}/data/fig4.nc -> {SMOKE_RESULTS}/unreadable/data/fig4.nc" in out, out[-2000:]
    assert f"removed a stale temporary file: {SMOKE_RESULTS}/data/.fig2.k3j4.nc.tmp" in out
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
