"""The Snakemake workflow: the smoke run end to end, config validation, clean failure."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from sleighsim.io import read_dataset

ROOT = Path(__file__).resolve().parents[1]
SMOKE = ROOT / "config" / "smoke.yaml"
FIGURES = ["fig1", "fig2", "fig3", "fig4", "fig5", "fig6", "transients", "perturbation", "fig7", "fig8", "fig9", "fig10", "fig11", "fig12", "fig13", "fig14", "lyapunov",
           "audit"]
DATASETS = ["fig2", "fig3", "fig4", "fig5", "fig6", "pert_audit", "transients", "fig7", "fig8", "fig9_ref", "fig9_highE", "fig9_eps001", "psd_eps01", "psd_eps001",
            "lyap_spectrum", "lyap_protocol", "lyap_energy", "lyap_feasibility", "audit"]


def snakemake(workdir, configfile, *args, timeout=600):
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(workdir),
           "--configfile", str(configfile), "-c2", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


def key_paths(d, prefix=""):
    out = set()
    for k, v in d.items():
        out.add(prefix + k)
        if isinstance(v, dict):
            out |= key_paths(v, prefix + k + ".")
    return out


def test_smoke_config_has_the_same_keys_as_the_paper_config():
    """Snakemake merges --configfile into config/config.yaml, so smoke must set every key."""
    full = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    smoke = yaml.safe_load(SMOKE.read_text())
    assert key_paths(full) == key_paths(smoke)


@pytest.mark.workflow
def test_smoke_workflow_builds_every_figure(tmp_path):
    res = snakemake(tmp_path, SMOKE)
    assert res.returncode == 0, res.stderr[-3000:]
    for fig in FIGURES:
        for ext in ("png", "pdf"):
            f = tmp_path / "results" / "figures" / f"{fig}.{ext}"
            assert f.stat().st_size > 1000, f
        assert (tmp_path / "results" / "benchmarks" / "figure" / f"{fig}.tsv").exists()
    for scene in DATASETS:
        ds = read_dataset(tmp_path / "results" / "data" / f"{scene}.nc")
        assert ds.attrs["git_commit"] and ds.attrs["version_heyoka"], scene
        if "energy_max_rel_drift" in ds.attrs:
            assert ds.attrs["energy_max_rel_drift"] < 1e-8, scene
        log = (tmp_path / "results" / "logs" / "scene" / f"{scene}.log").read_text()
        assert "done in" in log, scene
    for scene in ("fig9_ref", "fig9_highE", "fig9_eps001"):
        ds = read_dataset(tmp_path / "results" / "data" / f"{scene}.nc")
        assert ds.attrs["max_crossing_residual"] < 1e-12
        assert ds.attrs["n_p2pi"] >= 10 and set(ds.ppi2_class.values) == {0, 1, 2, 3}
        assert ds.sizes["nret"] == ds.attrs["n_p2pi"] - 1
    fig6 = read_dataset(tmp_path / "results" / "data" / "fig6.nc")
    assert fig6.attrs["order1_max_abs"] == 0.0 and np.isfinite(fig6.attrs["T1_Omega2"])
    fig4 = read_dataset(tmp_path / "results" / "data" / "fig4.nc")
    assert fig4.attrs["n_reached"] >= 1 and fig4.sizes["run"] == 3
    scaling = read_dataset(tmp_path / "results" / "data" / "fig9_scaling.nc")
    assert scaling.attrs["distance_scaled_median"] < scaling.attrs["distance_unscaled_median"]
    psd = read_dataset(tmp_path / "results" / "data" / "psd_eps01.nc")
    assert psd.attrs["Omega_band_low"] <= psd.attrs["Omega_band_peak"] <= psd.attrs["Omega_band_high"]
    fig3 = read_dataset(tmp_path / "results" / "data" / "fig3.nc")
    assert set(fig3.data_vars) == {"u", "Omega", "omega", "theta"}
    assert fig3.attrs["energy_label"] == pytest.approx(0.1127)
    assert read_dataset(tmp_path / "results" / "data" / "fig2.nc").attrs["closed_form_max_abs_error"] < 1e-10
    from sleighsim.claims import VERDICTS, parse_claims

    n_ids = len(parse_claims(ROOT / "paper" / "CLAIMS.md"))
    ledger = read_dataset(tmp_path / "results" / "claims.nc")
    assert ledger.sizes["id"] == n_ids and set(ledger.verdict.values) <= set(VERDICTS)
    assert (tmp_path / "results" / "claims.csv").read_text().count("\n") == n_ids + 1
    html = (tmp_path / "results" / "report" / "index.html").read_text()
    assert all(f"id='{i}'" in html for i in ledger.id.values)
    # Snakemake's own report from the run's metadata.
    sm_report = tmp_path / "results" / "snakemake_report.html"
    res = snakemake(tmp_path, SMOKE, "--report", str(sm_report))
    assert res.returncode == 0 and sm_report.stat().st_size > 100000, res.stderr[-2000:]
    # Nothing left to do on a second run: outputs are complete and up to date.
    dry = snakemake(tmp_path, SMOKE, "-n")
    assert "Nothing to be done" in dry.stdout + dry.stderr


def _mutate(cfg, path, value):
    node = cfg
    for k in path[:-1]:
        node = node[k]
    if value is KeyError:
        node.pop(path[-1])
    else:
        node[path[-1]] = value


BAD = [
    (("scenes", "fig3", "params", "eps"), 1.5, r"eps"),
    (("scenes", "fig3", "params", "b"), -1.0, r"\['b'\]"),
    (("scenes", "fig7", "params", "K2"), 0.9, r"K2"),
    (("scenes", "fig3", "tol"), 0.0, r"\['tol'\]"),
    (("scenes", "fig8", "t_end"), -5.0, r"\['t_end'\]"),
    (("scenes", "fig3", "dt"), "fast", r"'fast' is not of type 'number'"),
    (("scenes", "fig3", "colour"), "red", r"colour"),
    (("scenes", "fig9"), {"y0": [0, 0, 0, 0]}, r"fig9"),
    (("scenes", "fig7", "t_sample_start"), 20000.0, r"scenes.fig7.t_sample_start = 20000.0 must lie in"),
    (("scenes", "fig3", "params", "eps"), KeyError, r"params"),
    (("scenes", "fig6", "fit_window"), [50.0, 500.0], r"scenes.fig6.fit_window = \[50.0, 500.0\] must be increasing"),
    (("scenes", "fig4", "compare_window"), 1e9, r"scenes.fig4.compare_window = 1000000000.0 must lie in"),
    (("scenes", "fig5", "order"), 7, r"\['order'\]"),
    (("scenes", "transients", "eps"), [0.1, 1.5], r"eps"),
    (("scenes", "psd_eps01", "dt"), 0.05, r"\['dt'\]"),
    (("scenes", "psd_eps01", "check_duration"), 1e6, r"scenes.psd_eps01.check_duration = 1000000.0 must lie in"),
    (("scenes", "fig9_ref", "params", "eps"), 20.0, r"eps"),
    (("lyap_grid", "n_chunks"), 9, r"lyap_grid.n_chunks = 9 must lie in \[1, n_eps = 3\]"),
    (("lyap_grid", "reference_eps"), 0.1, r"lyap_grid.reference_eps = 0.1 must lie in eps_range"),
]


@pytest.mark.parametrize("path, value, message", BAD, ids=[".".join(b[0][1:]) + f"={b[1]}" for b in BAD])
def test_invalid_config_stops_before_any_job_naming_the_key(tmp_path, path, value, message):
    import re

    cfg = yaml.safe_load(SMOKE.read_text())
    _mutate(cfg, path, value)
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(cfg))
    sentinel = tmp_path / "results" / "data" / "fig3.nc"
    sentinel.parent.mkdir(parents=True)
    sentinel.write_bytes(b"earlier result")
    stamp = sentinel.stat().st_mtime_ns
    res = snakemake(tmp_path, bad, timeout=120)
    out = res.stdout + res.stderr
    assert res.returncode != 0
    assert re.search(message, out), out[-2000:]
    assert "Select jobs to execute" not in out and "rule scene" not in out
    assert sentinel.read_bytes() == b"earlier result" and sentinel.stat().st_mtime_ns == stamp
    assert sorted(os.listdir(sentinel.parent)) == ["fig3.nc"]


def test_dry_run_of_the_paper_config_fans_the_grid_out(tmp_path):
    """One job per chunk plus one gather: the grid scales out to a cluster."""
    import re

    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    res = snakemake(tmp_path, ROOT / "config" / "config.yaml", "-n", "results/data/fig11_grid.nc", timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    out = res.stdout + res.stderr
    counts = dict(re.findall(r"^(lyap_grid\w*)\s+(\d+)\s*$", out, flags=re.M))
    assert int(counts["lyap_grid_chunk"]) == cfg["lyap_grid"]["n_chunks"]
    assert int(counts["lyap_grid"]) == 1
    total = int(re.search(r"^total\s+(\d+)", out, flags=re.M).group(1))
    assert total == cfg["lyap_grid"]["n_chunks"] + 1


@pytest.mark.workflow
def test_smoke_grid_through_a_cluster_executor_equals_the_local_run(tmp_path):
    pytest.importorskip("snakemake_executor_plugin_cluster_generic")
    target = "results/data/fig11_grid.nc"
    local, remote = tmp_path / "local", tmp_path / "cluster"
    res = snakemake(local, SMOKE, target)
    assert res.returncode == 0, res.stderr[-2000:]
    res = snakemake(remote, SMOKE, target, "--executor", "cluster-generic",
                    "--cluster-generic-submit-cmd", str(ROOT / "tests" / "local_submit.sh"), "--jobs", "2",
                    "--latency-wait", "10")
    assert res.returncode == 0, res.stderr[-3000:]
    a, b = read_dataset(local / target), read_dataset(remote / target)
    for name in ("lambda_1", "stderr", "flagged"):
        assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name
