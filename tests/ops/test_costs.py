"""Run costs (the cost modules of sleighsim.ops, benchmarks/full_run.py) on synthetic benchmark
trees and configs: per-rule sums, the critical path through a hand-made DAG, the cost figure, the
estimator's scaling and chunk-runtime warning, and the refusals. No Snakemake run."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from sleighsim.io.benchmark_files import read_benchmark
from sleighsim.ops import costs, jobgraph, walltime, workmodel
from sleighsim.ops.estimate import estimate
from sleighsim.ops.summary import SCHEMA, summarize
from sleighsim.report.figures import costs as plots
from sleighsim.report.figures.common import legibility
from sleighsim.scenes import catalog

ROOT = Path(__file__).resolve().parents[2]
HEADER = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"

# job (benchmark path below results/benchmarks) -> (wall s, cpu s or "NA")
TIMES = {
    "scene/a": (10.0, 9.0),
    "scene/b": (33.0, 30.0),  # the longest job, yet not on the critical path
    "chunk/g/0": (30.0, 28.0),
    "chunk/g/1": (5.0, "NA"),  # shorter than Snakemake's first CPU sample
    "gather/g": (2.0, 1.5),
    "figure/f": (3.0, 2.5),
    "report/claims": (1.0, 0.5),
    "report/report": (4.0, 3.5),
}

# snakemake --forceall -n --dag: node ids unlike the dry run's jobids; gather's label hides its
# wildcard (shared with the chunk jobs it reads), as Snakemake does
DOT = r"""Building DAG of jobs...
digraph snakemake_dag {
    graph[bgcolor=white, margin=0];
	10[label = "all", color = "0.00 0.6 0.85", style="rounded"];
	11[label = "figure\nfig: f", color = "0.38 0.6 0.85", style="rounded"];
	12[label = "scene\nscene: a", color = "0.61 0.6 0.85", style="rounded"];
	13[label = "scene_first\nscene: b", color = "0.62 0.6 0.85", style="rounded"];
	14[label = "gather", color = "0.39 0.6 0.85", style="rounded"];
	15[label = "chunk\nchunk: 0\nscene: g", color = "0.06 0.6 0.85", style="rounded"];
	16[label = "chunk\nchunk: 1\nscene: g", color = "0.06 0.6 0.85", style="rounded"];
	17[label = "claims", color = "0.08 0.6 0.85", style="rounded"];
	18[label = "report", color = "0.59 0.6 0.85", style="rounded"];
	12 -> 11
	14 -> 11
	15 -> 14
	16 -> 14
	13 -> 17
	11 -> 17
	12 -> 17
	17 -> 18
	11 -> 18
	18 -> 10
	11 -> 10
}
"""


def _job(rule, jobid, output, benchmark=None, wildcards="", inputs=()):
    lines = ["[Mon Nov 23 00:44:37 2026]", f"rule {rule}:"]
    if inputs:
        lines.append(f"    input: {', '.join(inputs)}")
    lines += [f"    output: {output}", f"    jobid: {jobid}"]
    if benchmark:
        lines.append(f"    benchmark: results/benchmarks/{benchmark}.tsv")
    lines.append("    reason: Forced execution")
    if wildcards:
        lines.append(f"    wildcards: {wildcards}")
    lines.append("    resources: tmpdir=/tmp")
    return "\n".join(lines)


# snakemake --forceall -n, jobs in another order than the dot file's nodes
DRYRUN = "\n".join([
    "Building DAG of jobs...", "Job stats:", "job      count", "-----  -------", "chunk        2", "",
    _job("report", 3, "results/report/index.html", "report/report",
         inputs=("results/claims.nc", "results/figures/f.png")),
    _job("chunk", 7, "results/chunks/g/1.nc", "chunk/g/1", "scene=g, chunk=1"),
    _job("gather", 5, "results/data/g.nc", "gather/g", "scene=g",
         inputs=("results/chunks/g/0.nc", "results/chunks/g/1.nc")),
    _job("scene", 2, "results/data/a.nc", "scene/a", "scene=a"),
    _job("chunk", 6, "results/chunks/g/0.nc", "chunk/g/0", "scene=g, chunk=0"),
    _job("scene_first", 8, "results/data/b.nc", "scene/b", "scene=b"),
    _job("figure", 1, "results/figures/f.png, results/figures/f.pdf", "figure/f", "fig=f",
         inputs=("results/data/a.nc", "results/data/g.nc")),
    _job("claims", 4, "results/claims.nc", "report/claims",
         inputs=("results/data/a.nc", "results/data/b.nc", "results/figures/f.png")),
    _job("all", 0, "", inputs=("results/figures/f.png", "results/report/index.html")),
    "Job stats:", "This was a dry-run (flag -n). The order of jobs does not reflect the order of execution.",
])

SYNTH_CONFIG = {"results": "results", "scenes": {"a": {"kind": "trajectory"}, "b": {"kind": "lyapunov_spectrum"},
                                                 "g": {"kind": "lyapunov_grid"}}}


def fake_run(tmp_path, times=TIMES, graph=True):
    """A finished run's directory: its benchmark files and (``graph``) its saved job graph."""
    bench = tmp_path / "results" / "benchmarks"
    for job, (wall, cpu) in times.items():
        path = bench / f"{job}.tsv"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(HEADER + f"{wall}\t0:00:{int(wall):02d}\t100\t200\t90\t95\t0.1\t0.1\t80.0\t{cpu}\n")
    if graph:
        (tmp_path / "costs").mkdir()
        (tmp_path / "costs" / "dag.dot").write_text(DOT)
        (tmp_path / "costs" / "dryrun.txt").write_text(DRYRUN)
    return tmp_path


def test_summary_sums_per_rule_and_job(tmp_path):
    s = summarize(fake_run(tmp_path), 61.5, "synthetic", config=SYNTH_CONFIG)
    assert s["schema"] == SCHEMA and s["wall_s"] == 61.5
    assert s["cpu_s"] == pytest.approx(9 + 30 + 28 + 1.5 + 2.5 + 0.5 + 3.5)
    assert s["jobs_total"] == 8 and s["cpu_not_sampled"] == ["chunk/g/1"]
    assert s["rules"]["chunk"] == {"jobs": 2, "cpu_s": 28.0, "wall_s": 35.0}
    # rule names from the job graph: scene_first and claims/report, not the benchmark directories
    assert s["rules"]["scene_first"] == {"jobs": 1, "cpu_s": 30.0, "wall_s": 33.0}
    assert s["rules"]["scene"]["jobs"] == 1 and s["rules"]["claims"]["cpu_s"] == 0.5
    assert list(s["rules"])[:3] == ["scene_first", "chunk", "scene"]  # largest CPU first
    assert [j["job"] for j in s["jobs"]][:3] == ["scene/b", "chunk/g/0", "scene/a"]
    cpus = [j["cpu_s"] or 0.0 for j in s["jobs"]]
    assert cpus == sorted(cpus, reverse=True)
    assert s["scenes"]["g"] == {"kind": "lyapunov_grid", "jobs": 3, "cpu_s": 29.5, "wall_s": 37.0}
    assert all(j["in_dag"] for j in s["jobs"])
    assert s["machine"]["nproc"] >= 1 and s["machine"]["python"] and s["git_commit"]
    assert s["config"]["label"] == "synthetic" and s["config"]["values"] == SYNTH_CONFIG


def test_critical_path_follows_the_dag_not_the_longest_job(tmp_path):
    s = summarize(fake_run(tmp_path), 61.5, "synthetic", config=SYNTH_CONFIG)
    crit = s["critical_path"]
    # chunk 0 -> gather -> figure -> claims -> report: 30 + 2 + 3 + 1 + 4 = 40 > scene b's 33 + 1 + 4 = 38
    assert [j["job"] for j in crit["jobs"]] == ["chunk/g/0", "gather/g", "figure/f", "report/claims", "report/report"]
    assert crit["wall_s"] == pytest.approx(40.0)
    assert crit["dag_jobs"] == 9
    # make scene b 3 s longer: the path moves to it
    times = dict(TIMES, **{"scene/b": (36.0, 30.0)})
    s = summarize(fake_run(tmp_path / "other", times), 61.5, "synthetic", config=SYNTH_CONFIG)
    assert [j["job"] for j in s["critical_path"]["jobs"]] == ["scene/b", "report/claims", "report/report"]
    assert s["critical_path"]["wall_s"] == pytest.approx(41.0)


def test_predicted_wall_lies_between_the_critical_path_and_one_core_and_is_exact_on_small_graphs(tmp_path):
    s = summarize(fake_run(tmp_path), 61.5, "synthetic", config=SYNTH_CONFIG)
    pred, crit = s["critical_path"]["predicted_wall_s"], s["critical_path"]["wall_s"]
    total = sum(j["wall_s"] for j in s["jobs"])
    assert list(pred) == [2, 4, 8, 16]
    assert all(crit - 1e-9 <= pred[c] <= total + 1e-9 for c in pred) and pred[16] == pytest.approx(crit)
    assert pred[2] >= total / 2 - 1e-9 and pred[2] >= pred[4] >= pred[8]
    # a diamond a -> (b, c) -> d with b 5, c 3: two cores run b beside c (10 + 5 + 1), one core all (19)
    graph = {n: {"deps": deps} for n, deps in (("a", ()), ("b", ("a",)), ("c", ("a",)), ("d", ("b", "c")))}
    weight = {"a": 10.0, "b": 5.0, "c": 3.0, "d": 1.0}
    assert jobgraph.predicted_wall(graph, weight, 2) == 16.0 and jobgraph.predicted_wall(graph, weight, 1) == 19.0
    # three independent jobs 4, 3, 3 on two cores: the longest chain first gives 6 (not 7)
    graph = {n: {"deps": ()} for n in "xyz"}
    assert jobgraph.predicted_wall(graph, {"x": 3.0, "y": 4.0, "z": 3.0}, 2) == 6.0
    with pytest.raises(ValueError, match="cores"):
        jobgraph.predicted_wall(graph, {}, 0)


def test_job_graph_recovers_hidden_wildcards():
    graph, notes = jobgraph.job_graph(DOT, DRYRUN)
    assert not notes
    assert graph[14]["wildcards"] == {"scene": "g"} and graph[14]["benchmark"] == "results/benchmarks/gather/g.tsv"
    assert graph[16]["benchmark"].endswith("chunk/g/1.tsv") and graph[10]["benchmark"] is None


def test_summary_without_a_job_graph_and_with_a_stray_file(tmp_path):
    times = dict(TIMES, **{"scene/old": (7.0, 6.0)})
    s = summarize(fake_run(tmp_path, times, graph=False), 50.0, "synthetic", config=SYNTH_CONFIG)
    assert s["critical_path"] is None
    assert s["rules"]["scene"]["jobs"] == 3  # scene_first is named by its benchmark directory here
    assert s["rules"]["claims"]["jobs"] == 1 and s["rules"]["report"]["jobs"] == 1
    s = summarize(fake_run(tmp_path / "g", times), 50.0, "synthetic", config=SYNTH_CONFIG)
    stray = next(j for j in s["jobs"] if j["job"] == "scene/old")
    assert stray["in_dag"] is False and any("scene/old" in n for n in s["notes"])
    assert s["critical_path"]["wall_s"] == pytest.approx(40.0)


def test_read_benchmark_sums_repeats_and_reads_na(tmp_path):
    p = tmp_path / "x.tsv"
    p.write_text(HEADER + "1.5\t0:00:01\t1\t1\t1\t1\t0\t0\t50\t1.25\n2.5\t0:00:02\t1\t1\t1\t1\t0\t0\t50\t2.0\n")
    assert read_benchmark(p) == {"wall_s": 4.0, "cpu_s": 3.25}
    p.write_text(HEADER + "0.2\t0:00:00\tNA\tNA\tNA\tNA\tNA\tNA\tNA\tNA\n")
    assert read_benchmark(p) == {"wall_s": 0.2, "cpu_s": None}


def test_plot_costs_writes_png_and_pdf(tmp_path):
    s = summarize(fake_run(tmp_path), 61.5, "synthetic", config=SYNTH_CONFIG)
    png, pdf = tmp_path / "out" / "costs.png", tmp_path / "out" / "costs.pdf"
    plots.plot_costs(s, png, pdf)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 5000
    assert pdf.read_bytes()[:5] == b"%PDF-" and pdf.stat().st_size > 1000
    assert sorted(p.name for p in png.parent.iterdir()) == ["costs.pdf", "costs.png"]  # no temporary left
    assert legibility(plots.costs_figure(s)) == []


def test_job_costs_from_the_reports_benchmark_files_and_their_figure(tmp_path):
    bench = fake_run(tmp_path, graph=False) / "results" / "benchmarks"
    files = {"data/a": [bench / "scene" / "a.tsv"],
             "data/g": [bench / "gather" / "g.tsv", bench / "chunk" / "g" / "0.tsv", bench / "chunk" / "g" / "1.tsv"],
             "figure/f": [bench / "figure" / "f.tsv"], "data/again": [bench / "scene" / "a.tsv"]}
    jobs = plots.job_costs(files)
    assert [j["job"] for j in jobs] == ["chunk/g/0", "scene/a", "chunk/g/1", "figure/f", "gather/g"]  # once each
    assert [j["rule"] for j in jobs] == ["chunk", "scene", "chunk", "figure", "gather"]
    assert jobs[0]["wall_s"] == 30.0 and jobs[2]["cpu_s"] is None
    png, pdf = tmp_path / "out" / "c.png", tmp_path / "out" / "c.pdf"
    png.parent.mkdir()
    plots.plot_job_costs(jobs, png, pdf, top=3)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and pdf.read_bytes()[:5] == b"%PDF-"
    assert legibility(plots.job_costs_figure(jobs, top=3)) == []
    plots.plot_job_costs(jobs, png.with_name("beside.png"))  # as the report calls it: the PDF beside the PNG
    assert png.with_name("beside.pdf").read_bytes()[:5] == b"%PDF-"
    with pytest.raises(ValueError, match="no benchmark"):
        plots.plot_job_costs([], png, pdf)


# ---------------------------------------------------------------------------------------------
# The estimator on a synthetic pair of configs

GRID = {"kind": "lyapunov_grid", "eps_range": [0.1, 0.1], "n_eps": 2, "b_range": [0.5, 2.0], "n_b": 2,
        "n_chunks": 2, "chunk_runtime_min": 5, "energy_label": 0.1127, "y0": [0.0, 0.1, 1.0, 0.0],
        "reference_eps": 0.1, "t_pre": 100.0, "t_pre_min": 100.0, "replicas": 2, "replica_spacing": 10.0,
        "tau": 10.0, "t_align": 0.0, "T_round": 50.0, "max_rounds": 2, "target_rel": 0.3, "poincare_span": 0.0,
        "b_check": [], "transient": {"dt": 1.0, "window": 10.0, "rtol": 0.02, "spike_factor": 1.8, "t_min": 5.0}}
BASE = {"results": "results", "defaults": {"tol": 1e-12},
        "scenes": {"gr": GRID, "tr": {"kind": "trajectory", "t_end": 100.0, "dt": 0.5},
                   "same": {"kind": "trajectory", "t_end": 50.0, "dt": 0.5}}}
# every eps is reference_eps (slow time 1, pre-run t_pre): a row is t_pre + replicas x spacing +
# t_align + T_round x max_rounds = 100 + 20 + 0 + 100 = 220 measured, 100 + 20 + 0 + 400 = 520 target
OVERLAY = {"scenes": {"gr": {"n_eps": 4, "n_chunks": 4, "n_b": 40, "T_round": 100.0, "max_rounds": 4},
                      "tr": {"t_end": 300.0}}}


def measured_summary():
    jobs = [
        {"job": "chunk/gr/0", "rule": "chunk", "scene": "gr", "wildcards": {"scene": "gr", "chunk": "0"},
         "cpu_s": 50.0, "wall_s": 55.0},
        {"job": "chunk/gr/1", "rule": "chunk", "scene": "gr", "wildcards": {"scene": "gr", "chunk": "1"},
         "cpu_s": 60.0, "wall_s": 62.0},
        {"job": "gather/gr", "rule": "gather", "scene": "gr", "wildcards": {"scene": "gr"}, "cpu_s": 2.0,
         "wall_s": 2.0},
        {"job": "scene/tr", "rule": "scene", "scene": "tr", "wildcards": {"scene": "tr"}, "cpu_s": 10.0,
         "wall_s": 11.0},
        {"job": "scene/same", "rule": "scene", "scene": "same", "wildcards": {"scene": "same"}, "cpu_s": 7.0,
         "wall_s": 7.5},
        # a job that does nothing: the startup cost is zero here, so scaling is by the plain work ratio
        {"job": "report/report", "rule": "report", "scene": None, "wildcards": {}, "cpu_s": 0.0, "wall_s": 0.1},
    ]
    return {"schema": SCHEMA, "date": "2026-01-01T00:00:00+00:00", "git_commit": "abc",
            "config": {"label": None, "files": [], "values": BASE}, "machine": {"nproc": 2, "cpu_model": "test"},
            "wall_s": 140.0, "cpu_s": 129.0, "jobs_total": len(jobs), "cpu_not_sampled": [], "jobs": jobs}


def target(overlay=OVERLAY):
    from snakemake.utils import update_config

    cfg = yaml.safe_load(yaml.safe_dump(BASE))
    update_config(cfg, yaml.safe_load(yaml.safe_dump(overlay)))
    return cfg


def test_estimator_scales_the_grid_by_its_work_ratio():
    assert workmodel.work("lyapunov_grid", catalog.scene_config(BASE, "gr")) == pytest.approx(2 * 220)
    est = estimate(target(), measured_summary())
    ratio = (4 * 520) / (2 * 220)
    scaled = {s["scene"]: s for s in est["scaled"]}
    assert scaled["gr"]["ratio"] == pytest.approx(ratio)
    assert scaled["tr"]["ratio"] == pytest.approx(3.0)
    assert "same" not in scaled and est["startup_s"] == 0.0
    chunks = [j for j in est["jobs"] if j["rule"] == "chunk"]
    assert len(chunks) == 4  # re-cut to the target's n_chunks
    assert sum(j["cpu_s"] for j in chunks) == pytest.approx((50 + 60) * ratio)
    assert all(j["cpu_s"] == pytest.approx(110 / 440 * 520) for j in chunks)  # one row of 520 units each
    by_job = {j["job"]: j["cpu_s"] for j in est["jobs"]}
    assert by_job["scene/tr"] == pytest.approx(30.0) and by_job["scene/same"] == pytest.approx(7.0)
    assert by_job["gather/gr"] == pytest.approx(2.0)
    assert est["rules"]["chunk"]["jobs"] == 4
    assert est["kinds"]["lyapunov_grid"]["cpu_s"] == pytest.approx(110 * ratio + 2.0)
    assert est["total_cpu_s"] == pytest.approx(110 * ratio + 2.0 + 30.0 + 7.0 + 0.0)
    # n_b is free (b is a symmetry): it is reported as changed but outside the model
    assert any(k.startswith("n_b:") for k in scaled["gr"]["not_modelled"])


def test_estimator_keeps_a_fixed_startup_unscaled():
    summary = measured_summary()
    summary["jobs"][-1]["cpu_s"] = 1.0  # every job pays 1 s that does not grow with the work
    est = estimate(target(), summary)
    by_job = {j["job"]: j["cpu_s"] for j in est["jobs"]}
    assert by_job["scene/tr"] == pytest.approx(1.0 + 9.0 * 3)
    assert by_job["chunk/gr/0"] == pytest.approx(1.0 + (49 + 59) / 440 * 520)


def test_estimator_warns_when_a_chunk_would_exceed_its_runtime(tmp_path, capsys):
    # largest chunk: 110 / 440 x 520 = 130 s = 2.17 min
    est = estimate(target(), measured_summary())
    assert est["chunks"][0]["largest_s"] == pytest.approx(130.0)
    assert not est["chunks"][0]["exceeds"] and not any("chunk_runtime_min" in w for w in est["warnings"])
    overlay = yaml.safe_load(yaml.safe_dump(OVERLAY))
    overlay["scenes"]["gr"]["chunk_runtime_min"] = 2
    est = estimate(target(overlay), measured_summary())
    assert est["chunks"][0]["exceeds"] and est["chunks"][0]["limit_s"] == 120
    assert any("chunk_runtime_min = 2 min" in w for w in est["warnings"])
    # the command line, with files
    base, over, measured = tmp_path / "base.yaml", tmp_path / "over.yaml", tmp_path / "measured.yaml"
    base.write_text(yaml.safe_dump(BASE))
    over.write_text(yaml.safe_dump(overlay))
    measured.write_text(yaml.safe_dump(measured_summary()))
    assert costs.main(["estimate", "--base", str(base), "--configfile", str(over), "--measured", str(measured),
                       "--no-schedule"]) == 0
    out = capsys.readouterr().out
    assert "linear work model" in out and "ESTIMATES" in out
    assert "WARNING" in out and "EXCEEDS" in out and "chunk_runtime_min 2 min" in out
    assert "gr (lyapunov_grid): x4.727" in out and "tr (trajectory): x3" in out
    total_h = (110 * 2080 / 440 + 2.0 + 30.0 + 7.0) / 3600
    assert f"{total_h:.4g}" in out.split("total", 1)[1].splitlines()[0]
    assert "differs from" not in out and "Wall time" not in out  # measured with the base config itself


def test_estimate_without_a_measured_summary_exits_nonzero(tmp_path):
    missing = tmp_path / "full_run.yaml"
    res = subprocess.run([sys.executable, "-m", "sleighsim.ops.costs", "estimate", "--configfile",
                          str(ROOT / "config" / "cluster.yaml"), "--measured", str(missing)],
                         capture_output=True, text=True, timeout=60, check=False)
    assert res.returncode != 0
    assert "no measured summary" in res.stderr and str(missing) in res.stderr and "full_run.py" in res.stderr
    assert res.stdout == ""


# ---------------------------------------------------------------------------------------------
# benchmarks/full_run.py without Snakemake


def full_run_module():
    spec = importlib.util.spec_from_file_location("full_run", ROOT / "benchmarks" / "full_run.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_full_run_reports_a_failed_workflow(tmp_path):
    mod = full_run_module()
    with pytest.raises(SystemExit) as exc:
        mod.run_workflow([sys.executable, "-c", "import sys; sys.exit(3)"], tmp_path)
    assert "workflow failed" in str(exc.value.code) and "exit code 3" in str(exc.value.code)
    wall = mod.run_workflow([sys.executable, "-c", "import time; time.sleep(0.3)"], tmp_path)
    assert 0.3 <= wall < 30


def test_full_run_reuse_writes_the_summary(tmp_path):
    run = fake_run(tmp_path / "run")
    (run / "costs" / "run.yaml").write_text(yaml.safe_dump({"wall_s": 61.5, "command": "snakemake ...",
                                                            "configfiles": [], "cores": 2,
                                                            "load_average": [6.9, 7.1]}))
    out = tmp_path / "summary.yaml"
    assert full_run_module().main(["--reuse", str(run), "--out", str(out)]) == 0
    s = yaml.safe_load(out.read_text())
    assert s["wall_s"] == 61.5 and s["run"]["wall_source"] == "measured by full_run.py"
    assert s["run"]["load_average"] == [6.9, 7.1]  # the machine's other work, recorded with the time
    assert s["critical_path"]["wall_s"] == pytest.approx(40.0)
    assert s["run"]["lower_bound_s"] == pytest.approx(max(40.0, sum(w for w, _ in TIMES.values()) / 2))
    assert s["config"]["values"]["scenes"] and s["config"]["files"][0].endswith("config/config.yaml")


def test_wall_from_the_snakemake_log(tmp_path):
    log = tmp_path / ".snakemake" / "log" / "2026-11-23T004522.260483.snakemake.log"
    log.parent.mkdir(parents=True)
    log.write_text("Building DAG of jobs...\n[Mon Nov 23 00:45:30 2026]\nrule scene:\n"
                   "[Mon Nov 23 00:46:46 2026]\nFinished jobid: 0 (Rule: all)\n")
    assert full_run_module().wall_from_log(tmp_path) == pytest.approx(83.74, abs=0.01)


def test_estimate_of_the_cluster_config_from_the_committed_measurement():
    """The committed full-run summary may predate a scene's current form (the chaos verdict measured
    as one job, before its realizations): the estimate still runs and names what it has no
    measurement for, instead of failing."""
    res = subprocess.run([sys.executable, "-m", "sleighsim.ops.costs", "estimate", "--configfile",
                          "config/cluster.yaml"], capture_output=True, text=True, timeout=600, check=False,
                         cwd=ROOT)  # as the README writes it: a path relative to the repository
    assert res.returncode == 0, res.stderr[-2000:]
    assert "core-hours (estimate)" in res.stdout
    wall = res.stdout.split("Wall time on N cores", 1)[1]
    per_unit = {"h": 1.0, "min": 1 / 60, "s": 1 / 3600}
    hours = [float(line.split()[2]) * per_unit[line.split()[-1]] for line in wall.splitlines()[1:5]
             if line.split()[-1] in per_unit]
    assert len(hours) == 4 and hours == sorted(hours, reverse=True), wall  # more cores, never longer
    assert "Longest job: " in wall and "critical path" in wall and "no job graph" not in res.stdout


def test_jobs_the_measured_run_did_not_have_are_estimated_from_their_scene_or_named_unmeasured():
    import copy

    import yaml

    from sleighsim.ops import estimate as est_mod

    target = copy.deepcopy(yaml.safe_load((ROOT / "config" / "config.yaml").read_text()))
    target["scenes"]["lyap_energy"].update(realizations=4)
    target["scenes"]["fig9_ref"]["precisions"] = ["double", "long double", "quad"]
    target["scenes"]["fig9_highE"]["precisions"] = ["double", "long double", "quad"]
    target["scenes"]["lyap_energy"]["precisions"] = ["double", "long double", "quad"]
    target["scenes"]["fig9_eps001"]["precisions"] = ["double", "double-double", "quad"]
    mjobs = [{"job": "scene/lyap_energy", "cpu_s": 10.0, "wall_s": 11.0},
             {"job": "scene/fig9_eps001", "cpu_s": 15.0, "wall_s": 16.0},
             {"job": "scene/realization/1/lyap_energy", "cpu_s": 10.5, "wall_s": 11.0},
             {"job": "scene/precision/long_double/fig9_ref", "cpu_s": 4.0, "wall_s": 4.5},
             *({"job": f"chunk/precision/long_double/lyap_energy/{k}", "cpu_s": 3.0, "wall_s": 3.5} for k in range(2)),
             {"job": "gather/precision/long_double/lyap_energy", "cpu_s": 1.0, "wall_s": 1.5}]
    est = {"jobs": [], "unmeasured": []}
    est_mod._new_jobs(target, mjobs, est)
    jobs = {j["job"]: j for j in est["jobs"]}
    # realizations 2 and 3 cost what the scene's own job cost; realization 1 was measured
    assert jobs["scene/realization/2/lyap_energy"]["cpu_s"] == 10.0 and "scene/realization/1/lyap_energy" not in jobs
    cost = est_mod._precision_cost()
    quad = jobs["scene/precision/quad/fig9_ref"]
    assert quad["cpu_s"] == pytest.approx(4.0 * cost["quad"] / cost["long double"]) and quad["cpu_s"] > 100 * 4.0
    # a long-double variant run as chunks: measured by its chunks and their gather, scaled from their sum
    assert jobs["scene/precision/quad/lyap_energy"]["cpu_s"] == pytest.approx(7.0 * cost["quad"] / cost["long double"])
    assert "scene/precision/long_double/lyap_energy" not in est["unmeasured"] + list(jobs)
    # no long-double measurement to scale from: named, not guessed
    assert ("scene/precision/quad/fig9_highE" in est["unmeasured"]
            and "scene/precision/long_double/fig9_highE" in est["unmeasured"])
    # no long double but the scene's own job in double: scaled from it; double-double has no cost per time unit
    assert jobs["scene/precision/quad/fig9_eps001"]["cpu_s"] == pytest.approx(15.0 * cost["quad"] / cost["double"])
    assert "scene/precision/double_double/fig9_eps001" in est["unmeasured"]


def test_a_rewritten_full_run_summary_keeps_the_earlier_runs_in_its_history(tmp_path):
    """with_history: the first summary has an empty history; rewriting the file appends the run it
    replaces (date, commit, wall, CPU, jobs, longest job, critical path), oldest first."""
    from sleighsim.ops.summary import read_summary, with_history, write_summary

    def run(day, wall, longest):
        return {"date": f"2026-11-{day}", "git_commit": f"c{day}", "machine": {"cpu_model": "cpu"},
                "config": {"label": None}, "wall_s": wall, "cpu_s": 2 * wall, "jobs_total": 3,
                "run": {"job_wall_sum_s": 2 * wall}, "critical_path": {"wall_s": wall / 2},
                "jobs": [{"job": "a", "wall_s": 1.0}, {"job": longest, "wall_s": wall / 3}]}

    path = tmp_path / "full_run.yaml"
    write_summary(with_history(run(24, 900.0, "x"), None), path)
    assert read_summary(path)["history"] == []
    write_summary(with_history(run(25, 600.0, "y"), read_summary(path)), path)
    write_summary(with_history(run(26, 500.0, "z"), read_summary(path)), path)
    history = read_summary(path)["history"]
    assert [h["git_commit"] for h in history] == ["c24", "c25"]
    assert history[0]["wall_s"] == 900.0 and history[0]["longest_job"] == "x"
    assert history[0]["longest_job_wall_s"] == 300.0
    assert history[1]["critical_path_wall_s"] == 300.0 and history[1]["job_wall_sum_s"] == 1200.0
    assert read_summary(path)["wall_s"] == 500.0


def _saved_graph(tmp_path) -> Path:
    (tmp_path / "dag.dot").write_text(DOT)
    (tmp_path / "dryrun.txt").write_text(DRYRUN)
    return tmp_path


def test_the_estimated_jobs_are_scheduled_on_the_configs_job_graph(tmp_path):
    """A job's wall is its estimated CPU times the measured wall per CPU second; a variant estimated as
    one job spreads over its chunks; a graph job without an estimate is named, not guessed."""
    graph, _ = walltime.dry_run_graph([], saved=_saved_graph(tmp_path))
    summary = {"jobs": [{"cpu_s": 10.0, "wall_s": 15.0}, {"cpu_s": None, "wall_s": 2.0},
                        {"cpu_s": 30.0, "wall_s": 45.0}]}
    assert walltime.wall_per_cpu(summary) == 1.5  # the unsampled job counts in neither sum
    est = {"jobs": [{"job": "scene/a", "cpu_s": 10.0}, {"job": "scene/b", "cpu_s": 40.0},
                    {"job": "scene/g", "cpu_s": 20.0}, {"job": "figure/f", "cpu_s": 2.0},
                    {"job": "report/claims", "cpu_s": 1.0}]}
    sched = walltime.schedule(est, graph, "results", summary, cores=(1, 2, 8))
    assert sched["unestimated"] == ["gather/g", "report/report"]
    assert sched["wall_s"][1] == pytest.approx(1.5 * 73.0)  # one core: the sum
    assert sched["longest"] == {"job": "scene/b", "wall_s": 60.0}
    # the chain b -> claims -> report outweighs a chunk of g (20 / 2 chunks) -> gather -> figure -> claims
    assert sched["critical_path"]["jobs"][0] == "scene/b" and sched["critical_path"]["wall_s"] == 61.5
    assert sched["wall_s"][8] == pytest.approx(61.5) and sched["wall_s"][2] >= sched["wall_s"][8]
    text = "\n".join(walltime.format_schedule(sched))
    assert "1 cores" in text and "Longest job: scene/b, 60 s" in text and "gather/g, report/report" in text


def test_chunk_jobs_are_named_as_one_entry_and_durations_read_as_planned():
    assert walltime.grouped(["chunk/x/0", "chunk/x/1", "gather/x"]) == "chunk/x/* (2 jobs), gather/x"
    assert [walltime.duration(s) for s in (45, 147, 720, 12240)] == ["45 s", "2.5 min", "12 min", "3.4 h"]


def test_the_estimate_writes_its_record_with_the_schedule(tmp_path, capsys):
    base, measured, out = tmp_path / "base.yaml", tmp_path / "measured.yaml", tmp_path / "est.yaml"
    base.write_text(yaml.safe_dump(BASE))
    measured.write_text(yaml.safe_dump(measured_summary()))
    assert costs.main(["estimate", "--base", str(base), "--measured", str(measured), "--graph",
                       str(_saved_graph(tmp_path)), "--cores", "1", "4", "--out", str(out)]) == 0
    record = yaml.safe_load(out.read_text())
    assert record["schema"] == costs.RECORD_SCHEMA and record["config"]["files"] == [str(base)]
    assert set(record["schedule"]["wall_s"]) == {1, 4} and record["measured"]["file"] == str(measured)
    assert "Wall time on N cores" in capsys.readouterr().out


def test_the_chunks_of_a_scene_scheduled_first_are_chunk_jobs_to_the_estimate():
    """A chunk job run by the chunk_first rule (the paper config's chaos_verdict, schedule_first) is rated like
    any chunk job, at its CPU seconds above the startup; a gather job is not rated."""
    import yaml

    from sleighsim.ops import estimate as est_mod
    from sleighsim.ops.config import BASE_CONFIG
    from sleighsim.scenes import catalog

    config = yaml.safe_load(BASE_CONFIG.read_text())
    assert config["scenes"]["chaos_verdict"]["schedule_first"] is True
    cfg = catalog.scene_config(config, "chaos_verdict")
    have = [{"job": "chunk/chaos_verdict/0", "rule": "chunk_first", "wildcards": {"chunk": "0"}, "cpu_s": 12.0},
            {"job": "gather/chaos_verdict", "rule": "gather", "wildcards": {}, "cpu_s": 3.0}]
    assert est_mod._chunk_rates(have, cfg, 2.0) == [(10.0, est_mod.chunk_work(cfg)[0])]
