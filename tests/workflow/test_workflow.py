"""The Snakemake workflow end to end: the smoke run, what it builds (derived from the registry),
config refusal before any job, and what reruns after a change."""

import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import ROOT, SMOKE, SMOKE_RESULTS, smoke_config, snakemake

from sleighsim.io import layout
from sleighsim.io.netcdf import read_dataset
from sleighsim.report import sections
from sleighsim.report.figures import catalog as figure_catalog
from sleighsim.scenes import catalog

SMOKE_CFG = smoke_config()  # config/smoke.yaml is an overlay (tests/test_config.py checks it)
PAPER_CFG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


def test_scene_names_appear_only_in_the_config_and_the_registry():
    """The list of scenes is written once: the workflow, the library and the outputs derive it. (A scene
    named like its figure or its kind, fig3 or bench, shares that name with a plot function or module.)"""
    names = [n for n in PAPER_CFG["scenes"] if n not in figure_catalog.FIGURES and n not in catalog.KINDS]
    assert len(names) >= 10
    places = [ROOT / "workflow" / "Snakefile", *sorted((ROOT / "workflow").rglob("*.smk")),
              *sorted((ROOT / "workflow").rglob("*.py")), *sorted((ROOT / "src").rglob("*.py"))]
    # figures' declarations
    declared = {sys.modules[f.plot.__module__].__file__ for f in figure_catalog.FIGURES.values()}
    allowed = {ROOT / "src" / "sleighsim" / p
               for p in ("claims/evidence.py", "report/tables.py")}
    allowed |= {ROOT / "src" / "sleighsim" / "report" / "figures" / Path(f).name for f in declared}
    found = [(p.relative_to(ROOT), n) for p in places if p not in allowed for n in names
             if re.search(rf"\b{n}\b", p.read_text())]
    assert not found, found


@pytest.mark.workflow
def test_smoke_workflow_builds_every_figure_and_dataset(smoke_run):
    results = smoke_run / SMOKE_RESULTS
    for fig in figure_catalog.figures_built(SMOKE_CFG):
        for ext in ("png", "pdf"):
            f = results / "figures" / f"{fig}.{ext}"
            assert f.stat().st_size > 1000, f
        assert (results / "benchmarks" / "figure" / f"{fig}.tsv").exists()
    for scene in catalog.datasets(SMOKE_CFG):
        path = results / "data" / f"{scene}.nc"
        ds = read_dataset(path)
        assert ds.attrs["git_commit"] and ds.attrs["version_heyoka"], scene
        if "energy_max_rel_drift" in ds.attrs:  # scenes that run loose tolerances on purpose say so in tol_max
            bound = 100 * ds.attrs["tol_max"] if "tol_max" in ds.attrs else 1e-8
            assert ds.attrs["energy_max_rel_drift"] < bound, scene
        assert oct(path.stat().st_mode & 0o777) == oct(0o666 & ~_umask()), scene
    for scene in catalog.datasets(SMOKE_CFG, on_request=True):
        if SMOKE_CFG["scenes"][scene].get("on_request"):
            assert not (results / "data" / f"{scene}.nc").exists(), f"{scene} is on request"
    for scene in ("fig9_ref", "fig9_highE", "fig9_eps001"):
        ds = read_dataset(results / "data" / f"{scene}.nc")
        assert ds.attrs["max_crossing_residual"] < 1e-12
        assert ds.attrs["n_p2pi"] >= 10 and set(ds.ppi2_class.values) == {0, 1, 2, 3}
        assert ds.sizes["nret"] == ds.attrs["n_p2pi"] - 1
    fig6 = read_dataset(results / "data" / "fig6.nc")
    assert fig6.attrs["order1_max_abs"] == 0.0 and np.isfinite(fig6.attrs["T1_Omega2"])
    fig4 = read_dataset(results / "data" / "fig4.nc")
    assert fig4.attrs["n_reached"] >= 1 and fig4.sizes["run"] == 3
    scaling = read_dataset(results / "data" / "fig9_scaling.nc")
    assert scaling.attrs["distance_scaled_median"] < scaling.attrs["distance_unscaled_median"]
    psd = read_dataset(results / "data" / "psd_eps01.nc")
    assert psd.attrs["Omega_band_low"] <= psd.attrs["Omega_band_peak"] <= psd.attrs["Omega_band_high"]
    fig3 = read_dataset(results / "data" / "fig3.nc")
    assert set(fig3.data_vars) == {"u", "Omega", "omega", "theta"}
    assert fig3.attrs["energy_label"] == pytest.approx(0.1127)
    assert read_dataset(results / "data" / "fig2.nc").attrs["closed_form_max_abs_error"] < 1e-10
    from sleighsim.claims.rules import VERDICTS
    from sleighsim.io.claims_table import parse_claims

    n_ids = len(parse_claims(ROOT / "paper" / "CLAIMS.md"))
    ledger = read_dataset(results / "claims.nc")
    assert ledger.sizes["id"] == n_ids and set(ledger.verdict.values) <= set(VERDICTS)
    assert (results / "claims.csv").read_text().count("\n") == n_ids + 1
    html = (results / "report" / "index.html").read_text()
    assert all(f'id="{i}"' in html for i in ledger.id.values)
    assert '<img src="costs.png"' in html and (results / "report" / "costs.png").stat().st_size > 5000
    # Nothing left to do on a second run: outputs are complete and up to date.
    dry = snakemake(smoke_run, SMOKE, "-n")
    assert "Nothing to be done" in dry.stdout + dry.stderr


def _umask():
    current = os.umask(0)
    os.umask(current)
    return current


@pytest.mark.workflow
def test_snakemakes_own_report_holds_every_figure_under_its_paper_section(smoke_run, tmp_path):
    report = tmp_path / "report.zip"
    res = snakemake(smoke_run, SMOKE, "--report", str(report))
    assert res.returncode == 0, res.stderr[-2000:]
    with zipfile.ZipFile(report) as z:
        files = {Path(n).name: n for n in z.namelist()}
        page = z.read(files["report.html"]).decode()
        standalone = z.read(files["standalone.html"]).decode()
    built = figure_catalog.figures_built(SMOKE_CFG)
    assert {f"{fig}.png" for fig in built} | {"claims.csv"} <= set(files)
    entries = sections.figure_entries(ROOT / "paper" / "fedonyuk-tallapragada-sleigh-rotor.tex",
                                      ROOT / "paper" / "CLAIMS.md")
    categories = json.loads(re.search(r"var categories = (\{.*?\});\n", page)[1])
    for fig in built:
        e = entries[fig]
        assert f"{SMOKE_RESULTS}/figures/{fig}.png" in categories[e["category"]][e["subcategory"]], fig
    ledger = {f for files in categories[sections.LEDGER].values() for f in files}
    assert ledger == {f"{SMOKE_RESULTS}/claims.csv", f"{SMOKE_RESULTS}/report/standalone.html"}
    # the project's own report, linked as one file: every figure inlined, none left to fetch
    assert standalone.count('<img src="data:image/png;base64,') >= len(built)
    assert not re.search(r'<img [^>]*src="(?!data:)', standalone)


def _mutate(cfg, path, value):
    node = cfg
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value


# One case per kind of check; test_config.py covers every key without Snakemake.
BAD = [
    (("scenes", "fig3", "params", "eps"), 1.5, r"eps"),
    (("scenes", "fig3", "tol"), 0.0, r"scenes\.fig3\.tol: 0\.0 is less than the minimum"),
    (("scenes", "fig3", "colour"), "red", r"colour"),
    (("scenes", "fig8", "t_end"), float("nan"), r"scenes.fig8.t_end = nan is not a finite number"),
    (("scenes", "fig7", "t_sample_start"), 20000.0, r"scenes.fig7.t_sample_start = 20000.0 must lie in"),
    (("scenes", "fig3", "t_end"), 1e12, r"scenes.fig3: .* would need about .* GiB in memory"),
]


@pytest.mark.parametrize("path, value, message", BAD, ids=[".".join(b[0][1:]) + f"={b[1]}" for b in BAD])
def test_invalid_config_stops_before_any_job_naming_the_key(tmp_path, path, value, message):
    cfg = smoke_config()
    _mutate(cfg, path, value)
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(cfg))
    sentinel = tmp_path / SMOKE_RESULTS / "data" / "fig3.nc"
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
    n_chunks = PAPER_CFG["scenes"]["fig11_grid"]["n_chunks"]
    res = snakemake(tmp_path, ROOT / "config" / "config.yaml", "-n", "results/data/fig11_grid.nc", timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    out = res.stdout + res.stderr
    counts = dict(re.findall(r"^(chunk|gather)\s+(\d+)\s*$", out, flags=re.M))
    assert int(counts["chunk"]) == n_chunks and int(counts["gather"]) == 1
    assert int(re.search(r"^total\s+(\d+)", out, flags=re.M).group(1)) == n_chunks + 1


def test_dry_run_of_the_paper_config_chunks_the_long_double_sweep_and_runs_f9s_double_double_in_one_job(tmp_path):
    """The long-double energy sweep in precision_chunks jobs (its labels), gathered; F9's eps = 0.01 maps in
    double-double in one job (maps and attractor stretch from one integration); their double runs one job each."""
    scenes = PAPER_CFG["scenes"]
    n = {s: catalog.chunk_count(scenes[s]) for s in ("lyap_energy", "fig9_eps001")}
    assert n == {"lyap_energy": scenes["lyap_energy"]["precision_chunks"], "fig9_eps001": 1}
    res = snakemake(tmp_path, ROOT / "config" / "config.yaml", "-n", "results/data/lyap_energy.nc",
                    "results/data/fig9_eps001.nc", f"results/data/{layout.variant('lyap_energy', 'long double')}.nc",
                    f"results/data/{layout.variant('fig9_eps001', 'double-double')}.nc", timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    counts = dict(re.findall(r"^(\w+)\s+(\d+)\s*$", res.stdout + res.stderr, flags=re.M))
    assert {k: int(v) for k, v in counts.items()} == {
        "chunk_in_precision": n["lyap_energy"], "gather_in_precision": 1, "scene": 2, "scene_in_precision": 1,
        "total": n["lyap_energy"] + 4}


def test_atlas_builds_the_regime_diagram_and_the_basin_fractions(tmp_path):
    """`snakemake atlas` (on request): every atlas figure, and a basins dataset that accounts for
    every sample once."""
    res = snakemake(tmp_path, SMOKE, "atlas", timeout=600)
    assert res.returncode == 0, res.stderr[-3000:]
    for fig in figure_catalog.ATLAS:
        assert (tmp_path / SMOKE_RESULTS / "figures" / f"{fig}.png").stat().st_size > 0
    ds = read_dataset(tmp_path / SMOKE_RESULTS / "data" / "basins.nc")
    n = SMOKE_CFG["scenes"]["basins"]["n_samples"]
    assert ds.sizes["sample"] == n and int(ds["count"].sum()) == n
    assert np.isclose(float(ds.fraction.sum()), 1.0)
    assert ((ds.ci_low <= ds.fraction) & (ds.fraction <= ds.ci_high)).all()


def test_commands_without_a_core_count_parse_the_workflow(tmp_path):
    """`snakemake --unlock` (after a killed run) takes no --cores: no rule may need workflow.cores."""
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflow" / "Snakefile"), "-d", str(tmp_path),
           "--configfile", str(SMOKE), "--unlock"]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    assert "Unlocked working directory" in res.stdout + res.stderr


def test_on_request_scenes_join_the_run_and_the_report_when_switched_on(tmp_path):
    """bench and hardcases run on request; switched on, the report declares (and so waits for) them."""
    cfg = smoke_config()
    res = snakemake(tmp_path, SMOKE, "-n", "--forceall", f"{SMOKE_RESULTS}/report/index.html", timeout=120)
    assert "data/hardcases.nc" not in res.stdout and "figures/bench.png" not in res.stdout
    for name in ("hardcases", "bench"):
        cfg["scenes"][name]["on_request"] = False
    on = tmp_path / "on.yaml"
    on.write_text(yaml.safe_dump(cfg))
    res = snakemake(tmp_path, on, "-n", "--forceall", f"{SMOKE_RESULTS}/report/index.html", timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    report_job = res.stdout[res.stdout.index("rule report:"):]
    report_inputs = report_job[: report_job.index("output:")]
    assert f"{SMOKE_RESULTS}/data/hardcases.nc" in report_inputs
    assert f"{SMOKE_RESULTS}/figures/bench.png" in report_inputs
    assert f"{SMOKE_RESULTS}/benchmarks/scene/bench.tsv" in report_inputs


@pytest.mark.workflow
def test_changing_a_file_only_the_report_reads_reruns_the_report(smoke_run, tmp_path):
    """The report declares every file it reads, the run-time records (benchmark files) included:
    a new one reruns the report and nothing else (on a copy of the shared run)."""
    import shutil
    import time

    run = tmp_path / "run"
    shutil.copytree(smoke_run, run, symlinks=True)
    record = run / SMOKE_RESULTS / "benchmarks" / "scene" / "fig9_scaling.tsv"
    time.sleep(1.1)  # a newer file, with new content
    record.write_text(record.read_text().replace("\t", "\t ", 1))
    dry = snakemake(run, SMOKE, "-n", f"{SMOKE_RESULTS}/report/index.html")
    assert "rule report:" in dry.stdout and "benchmarks/scene/fig9_scaling.tsv" in dry.stdout, dry.stdout[-2000:]
    assert "rule claims:" not in dry.stdout and "rule scene:" not in dry.stdout


@pytest.mark.workflow
def test_smoke_grid_through_a_cluster_executor_equals_the_local_run(smoke_run, tmp_path):
    pytest.importorskip("snakemake_executor_plugin_cluster_generic")
    target = f"{SMOKE_RESULTS}/data/fig11_grid.nc"
    res = snakemake(tmp_path, SMOKE, target, "--executor", "cluster-generic",
                    "--cluster-generic-submit-cmd", str(ROOT / "tests" / "workflow" / "local_submit.sh"), "--jobs", "2",
                    "--latency-wait", "10")
    assert res.returncode == 0, res.stderr[-3000:]
    a, b = read_dataset(smoke_run / target), read_dataset(tmp_path / target)
    for name in ("lambda_1", "stderr", "flagged"):
        assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name


@pytest.mark.workflow
def test_the_smoke_ledger_judges_what_the_smoke_config_declares(smoke_run):
    """The claims rule passes the run's config to the ledger: C16 (fig9_ref, laddered in smoke.yaml)
    is judged in double-double, C18 (lyap_spectrum, realized) on every realization; re-judging the
    tree from the command line's merged config gives the same rows."""
    from sleighsim.claims import ledger as claims
    from sleighsim.ops.config import merged_config

    assert "double-double" in catalog.laddered(SMOKE_CFG)["fig9_ref"] and "lyap_spectrum" in catalog.realized(SMOKE_CFG)
    results = smoke_run / SMOKE_RESULTS
    rows = {r.id: r for r in claims.read(results / "claims.nc")}
    assert rows["C16"].precision.startswith("double-double") and rows["C18"].realizations
    again = claims.ledger(ROOT / "paper" / "CLAIMS.md", results / "data", results / "figures", merged_config([SMOKE]),
                           figure_catalog.FIGURES)
    assert [(r.id, r.verdict, r.precision, r.realizations) for r in again] == \
        [(r.id, r.verdict, r.precision, r.realizations) for r in rows.values()]


@pytest.mark.workflow
def test_every_laddered_scene_of_the_smoke_run_has_its_ladder_from_one_settled_state(smoke_run):
    """Every scene smoke.yaml ladders (a chunked grid among them: chunk_in_precision, gather_in_precision)
    has its variant, run in that arithmetic after the double pre-run, and a ladder naming a converged
    precision or "not converged"; F3, F8, F10 and F11 are drawn beside it."""
    data = smoke_run / SMOKE_RESULTS / "data"
    ladders = catalog.laddered(SMOKE_CFG)
    assert {"fig3", "fig8", "lyap_energy", "lyap_protocol", "fig11_grid"} <= set(ladders)
    for scene, precisions in ladders.items():
        ds = read_dataset(data / f"{layout.ladder(scene)}.nc")
        assert ds.attrs["converged_precision"] in (*precisions[:-1], "not converged"), scene
        assert list(ds.precision.values) == precisions and ds.sizes["observable"] >= 1, scene
        finer = read_dataset(data / f"{layout.variant(scene, precisions[-1])}.nc")
        assert finer.attrs["precision"] == precisions[-1]
        assert finer.attrs["transient_precision"] in ("double", precisions[-1])
    assert all(figure_catalog.FIGURES[f].beside for f in ("fig3", "fig8", "fig10", "fig11"))


def test_every_smoke_dataset_names_the_runs_configuration(smoke_run):
    """Issue 53: the datasets, like the ledger, record which configuration wrote them (label and SHA-256)."""
    import netCDF4

    ledger = read_dataset(smoke_run / SMOKE_RESULTS / "claims.nc")
    paths = sorted((smoke_run / SMOKE_RESULTS / "data").rglob("*.nc"))
    assert paths
    for path in paths:
        with netCDF4.Dataset(path) as nc:
            assert nc.getncattr("config_label") == "smoke", path
            assert nc.getncattr("config_sha256") == ledger.attrs["config_sha256"], path


@pytest.mark.parametrize("name, text, flag", [("chaos_verdict", "verdict", "verdict_flag"),
                                              ("chaos_verdict", "realization_verdict", "realization_verdict_flag"),
                                              ("fig11_grid", "row_verdict", "row_verdict_flag")])
def test_the_verdicts_are_also_cf_flags_that_decode_to_their_texts(smoke_run, name, text, flag):
    ds = read_dataset(smoke_run / SMOKE_RESULTS / "data" / f"{name}.nc")
    meanings = ds[flag].attrs["flag_meanings"].split()
    decoded = np.vectorize(lambda k: meanings[k].replace("_", " "))(ds[flag].values)
    assert decoded.tolist() == ds[text].values.tolist()
