"""What a finished workflow run cost: :func:`summarize` reads the run's Snakemake benchmark files
(one TSV per job, columns ``s`` for wall seconds and ``cpu_time`` for CPU seconds) and the run's job
graph (:mod:`sleighsim.ops.jobgraph`), and returns the cost summary that ``benchmarks/full_run.py``
writes.

Summary schema (``schema: sleighsim.costs/1``; seconds throughout; lists sorted largest first)::

    schema, date (UTC), git_commit ("-dirty" when tracked files differ from it)
    config: {label, files (merged in this order, as Snakemake does), values (the merged config)}
    machine: {nproc, cpu_count, cpu_model, memory_gb, platform, python, snakemake}
    run: {...}                  added by benchmarks/full_run.py: command, cores, workdir, wall_source
    wall_s                      the whole snakemake command
    cpu_s                       sum of the jobs' cpu_s (jobs whose CPU was not sampled count 0)
    jobs_total, cpu_not_sampled (jobs whose benchmark has cpu_time NA)
    rules: {rule: {jobs, cpu_s, wall_s}}
    jobs: [{job, rule, scene, wildcards, cpu_s, wall_s, in_dag}]  job = benchmark path below
                                                                  results/benchmarks, without .tsv
    scenes: {scene: {kind, jobs, cpu_s, wall_s}}                  scene, chunk and gather jobs
    critical_path: {wall_s, jobs: [{job, rule, wall_s}], dag_jobs, predicted_wall_s: {cores: s}} or null
                                without a job graph (predicted: jobgraph.predicted_wall, measured job walls)
    row_verdicts: {scene: {cost_per_cycle_step_s, steps_per_cycle_law, rows}}  each Lyapunov grid's measured
                                row verdicts, what the estimate prices other grids' rows by (ops.rowprices)
    notes: [...]

``cpu_time`` is sampled by Snakemake (every 0.5 s for the first 15 s of a job, then every 30 s),
so a long job's CPU seconds miss up to its last 30 s, and a job shorter than the first sample
reports NA.
"""

from __future__ import annotations

import datetime as _dt
import os
from pathlib import Path

import yaml

from sleighsim.io.benchmark_files import read_benchmark, rule_from_path
from sleighsim.io.netcdf import atomic_path
from sleighsim.ops import rowprices
from sleighsim.ops.config import BASE_CONFIG, merged_config
from sleighsim.ops.facts import git_commit, machine_facts
from sleighsim.ops.jobgraph import COSTS_DIR, DAG_FILE, DRYRUN_FILE, critical_path, job_graph, predicted_wall

#: Core counts the summary predicts the wall for (list scheduling of the measured jobs).
PREDICTED_CORES = (2, 4, 8, 16)

#: The summary's format (a data format id, kept across code moves).
SCHEMA = "sleighsim.costs/1"


def _r(x):
    return None if x is None else round(float(x), 3)


def _cpu(j) -> float:
    return j["cpu_s"] or 0.0


def _config_of(config_label, config):
    """(files merged, merged values or None, notes) of the run's config (see :func:`summarize`)."""
    notes, files = [], [str(BASE_CONFIG)]
    if config is None:
        if config_label in (None, "default", str(BASE_CONFIG)):
            config = merged_config()
        elif Path(config_label).is_file():
            files.append(str(Path(config_label).resolve()))
            config = merged_config([config_label])
        else:
            files = []
            notes.append(f"config {config_label!r} is not a file: its values are not recorded")
    elif config_label not in (None, "default") and Path(str(config_label)).is_file():
        files.append(str(Path(config_label).resolve()))
    return files, config, notes


def _text(x, workdir: Path, name: str):
    """The text of x: a path, or text itself; None: the run's own file, if any."""
    if x is None:
        x = workdir / COSTS_DIR / name
        return x.read_text() if x.exists() else None
    if isinstance(x, Path) or ("\n" not in x and os.path.isfile(x)):
        return Path(x).read_text()
    return x


def _run_graph(workdir: Path, dag, dryrun) -> tuple[dict, list[str]]:
    """The run's job graph and notes on it; an empty graph without its two dry-run texts."""
    dot_text, dry_text = _text(dag, workdir, DAG_FILE), _text(dryrun, workdir, DRYRUN_FILE)
    if dot_text and dry_text:
        return job_graph(dot_text, dry_text)
    return {}, [("no job graph (costs/dag.dot and costs/dryrun.txt): no critical path; rules named "
                 "by the benchmark directory")]


def _measured_jobs(tsvs: list, bench_root: Path, workdir: Path, graph: dict):
    """Every benchmark file as a job of the summary, in file order; its wall seconds per DAG node,
    and the job of each DAG node that has a benchmark file."""
    node_of = {}
    for n, g in graph.items():
        if g["benchmark"]:
            node_of[(workdir / g["benchmark"]).resolve()] = n
    jobs, weight, job_of_node = [], {}, {}
    for path in tsvs:
        rel = path.relative_to(bench_root).with_suffix("")
        b = read_benchmark(path)
        n = node_of.get(path.resolve())
        if n is not None:
            rule, wildcards = graph[n]["rule"], graph[n]["wildcards"]
            weight[n] = b["wall_s"]
        else:
            rule = rule_from_path(rel.parts)
            wildcards = {"scene": rel.parts[1]} if rule in ("scene", "gather", "chunk") and len(rel.parts) > 1 else {}
            if rule == "chunk" and len(rel.parts) > 2:
                wildcards["chunk"] = rel.parts[2]
        jobs.append({"job": rel.as_posix(), "rule": rule, "scene": wildcards.get("scene"),
                     "wildcards": dict(wildcards), "cpu_s": _r(b["cpu_s"]), "wall_s": _r(b["wall_s"]),
                     "in_dag": n is not None})
        if n is not None:
            job_of_node[n] = jobs[-1]
    return jobs, weight, job_of_node


def _coverage_notes(graph: dict, jobs: list, workdir: Path) -> list[str]:
    """Notes on benchmark files outside the DAG and DAG jobs without one."""
    if not graph:
        return []
    notes = []
    outside = [j["job"] for j in jobs if not j["in_dag"]]
    if outside:
        notes.append(f"{len(outside)} benchmark files belong to no job of this config's DAG (older or "
                     f"on-request jobs); counted in the sums: {', '.join(outside)}")
    missing = [g["benchmark"] for g in graph.values() if g["benchmark"] and
               not (workdir / g["benchmark"]).exists()]
    if missing:
        notes.append(f"{len(missing)} jobs of the DAG have no benchmark file: {', '.join(missing)}")
    return notes


def _ordered(d: dict) -> dict:
    """Rounded sums, largest CPU first (then wall, then name)."""
    return dict(sorted(((k, {**v, "cpu_s": _r(v["cpu_s"]), "wall_s": _r(v["wall_s"])}) for k, v in d.items()),
                       key=lambda kv: (-kv[1]["cpu_s"], -kv[1]["wall_s"], kv[0])))


def _per_rule_and_scene(jobs: list, kinds: dict) -> tuple[dict, dict]:
    """Jobs, CPU and wall seconds summed per rule and per scene, largest first."""
    rules, scenes = {}, {}
    for j in jobs:
        r = rules.setdefault(j["rule"], {"jobs": 0, "cpu_s": 0.0, "wall_s": 0.0})
        r["jobs"] += 1
        r["cpu_s"] += _cpu(j)
        r["wall_s"] += j["wall_s"]
        if j["scene"]:
            s = scenes.setdefault(j["scene"], {"kind": kinds.get(j["scene"]), "jobs": 0, "cpu_s": 0.0, "wall_s": 0.0})
            s["jobs"] += 1
            s["cpu_s"] += _cpu(j)
            s["wall_s"] += j["wall_s"]
    return _ordered(rules), _ordered(scenes)


def _critical(graph: dict, weight: dict, job_of_node: dict):
    """The summary's critical path, None without a job graph."""
    if not graph:
        return None
    total, chain = critical_path(graph, weight)
    # jobs without a benchmark (the target rule `all`) weigh nothing and are not listed
    return {"wall_s": _r(total), "dag_jobs": len(graph),
            "jobs": [{k: job_of_node[n][k] for k in ("job", "rule", "wall_s")} for n in chain if n in job_of_node],
            "predicted_wall_s": {c: _r(predicted_wall(graph, weight, c)) for c in PREDICTED_CORES}}


def summarize(workdir, wall_s: float, config_label, *, config: dict | None = None, results: str | None = None,
              dag=None, dryrun=None) -> dict:
    """The cost summary of the finished run in ``workdir`` (schema in the module docstring):
    every benchmark TSV under ``<results>/benchmarks`` summed per rule, per scene and per job, and
    the critical path through the job graph (``dag``/``dryrun``: texts or paths, by default
    ``<workdir>/costs/dag.dot`` and ``dryrun.txt``; without them no critical path).

    ``config_label`` names the config the run used: a configfile merged onto config/config.yaml, or
    None / "default" for config/config.yaml alone; ``config`` gives the merged values directly."""
    workdir = Path(workdir)
    files, config, notes = _config_of(config_label, config)
    results = results or (config or {}).get("results", "results")
    bench_root = workdir / results / "benchmarks"
    tsvs = sorted(bench_root.rglob("*.tsv"))
    if not tsvs:
        raise FileNotFoundError(f"no benchmark files under {bench_root}")
    graph, graph_notes = _run_graph(workdir, dag, dryrun)
    notes += graph_notes
    jobs, weight, job_of_node = _measured_jobs(tsvs, bench_root, workdir, graph)
    notes += _coverage_notes(graph, jobs, workdir)
    jobs.sort(key=lambda j: (-_cpu(j), -j["wall_s"], j["job"]))
    kinds = {name: block.get("kind") for name, block in (config or {}).get("scenes", {}).items()}
    rules, scenes = _per_rule_and_scene(jobs, kinds)
    crit = _critical(graph, weight, job_of_node)
    notes.append("cpu_time is sampled by Snakemake (0.5 s, after 15 s every 30 s): long jobs miss up to their "
                 "last 30 s of CPU; jobs shorter than the first sample have none (cpu_not_sampled, counted 0)")
    return {
        "schema": SCHEMA,
        "date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "git_commit": git_commit(),
        "config": {"label": None if config_label is None else str(config_label), "files": files, "values": config},
        "machine": machine_facts(),
        "workdir": str(workdir.resolve()),
        "wall_s": _r(wall_s),
        "cpu_s": _r(sum(_cpu(j) for j in jobs)),
        "jobs_total": len(jobs),
        "cpu_not_sampled": [j["job"] for j in jobs if j["cpu_s"] is None],
        "rules": rules,
        "jobs": jobs,
        "scenes": scenes,
        "critical_path": crit,
        rowprices.SECTION: rowprices.measured(workdir / results, config),
        "notes": notes,
    }


def history_entry(summary: dict) -> dict:
    """One line of the history of full runs: date, commit, machine, config label, wall and CPU seconds,
    jobs, the summed job wall seconds, the longest job and the critical path's wall seconds."""
    jobs = summary.get("jobs", [])
    longest = max(jobs, key=lambda j: j["wall_s"]) if jobs else {"job": None, "wall_s": None}
    return {"date": summary.get("date"), "git_commit": summary.get("git_commit"),
            "machine": (summary.get("machine") or {}).get("cpu_model"),
            "config": (summary.get("config") or {}).get("label"), "wall_s": summary.get("wall_s"),
            "cpu_s": summary.get("cpu_s"), "jobs_total": summary.get("jobs_total"),
            "job_wall_sum_s": (summary.get("run") or {}).get("job_wall_sum_s"),
            "longest_job": longest["job"], "longest_job_wall_s": longest["wall_s"],
            "critical_path_wall_s": (summary.get("critical_path") or {}).get("wall_s")}


def with_history(summary: dict, previous: dict | None) -> dict:
    """The summary with ``history``: the previous summary's history, then the previous run itself
    (``history_entry``), oldest first; so rewriting the file keeps every earlier run's totals."""
    if previous is None:
        return {**summary, "history": list(summary.get("history", []))}
    earlier = list(previous.get("history", []))
    return {**summary, "history": earlier + [history_entry(previous)]}


def write_summary(summary: dict, path) -> Path:
    """Write the summary as YAML, atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(yaml.safe_dump(summary, sort_keys=False, default_flow_style=False, width=120))
    return Path(path)


def read_summary(path) -> dict:
    """The cost summary stored at ``path`` (YAML, as :func:`write_summary` writes it)."""
    return yaml.safe_load(Path(path).read_text())
