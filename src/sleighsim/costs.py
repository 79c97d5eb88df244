"""What a workflow run costs: measured after the fact, and estimated before a config is launched.

- :func:`summarize` reads a finished run's Snakemake benchmark files (one TSV per job, columns ``s``
  for wall seconds and ``cpu_time`` for CPU seconds) and the run's job graph, and returns the cost
  summary that ``benchmarks/full_run.py`` writes (schema below).
- :func:`plot_costs` draws CPU seconds per rule, each bar split into its jobs, with the critical path.
- :func:`estimate` (``python -m sleighsim.costs estimate --configfile config/cluster.yaml``) scales a
  measured full-run summary to the run another config would launch, with a linear work model per
  scene kind (:func:`work`), and checks the chunk jobs against their ``chunk_runtime_min``.

The job graph comes from two dry runs in the run's directory, saved by ``benchmarks/full_run.py``
under ``<workdir>/costs/``: ``snakemake --forceall -n --dag`` (``dag.dot``: the edges; its labels show
only the wildcards a job adds to its inputs' jobs) and ``snakemake --forceall -n`` (``dryrun.txt``:
every job's rule, wildcards, input and benchmark file). :func:`job_graph` matches the two.

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
    critical_path: {wall_s, jobs: [{job, rule, wall_s}], dag_jobs} or null without a job graph
    notes: [...]

``cpu_time`` is sampled by Snakemake (every 0.5 s for the first 15 s of a job, then every 30 s),
so a long job's CPU seconds miss up to its last 30 s, and a job shorter than the first sample
reports NA.
"""

from __future__ import annotations

import argparse
import csv
import datetime as _dt
import math
import os
import platform
import re
import subprocess
import sys
from collections import defaultdict
from importlib import metadata
from pathlib import Path

from . import registry
from .io import atomic_path

REPO = Path(__file__).resolve().parents[2]
BASE_CONFIG = REPO / "config" / "config.yaml"
DEFAULT_MEASURED = REPO / "benchmarks" / "full_run.yaml"
SCHEMA = "sleighsim.costs/1"
#: Where benchmarks/full_run.py keeps the dry-run outputs of a run, inside its workdir.
COSTS_DIR = "costs"
DAG_FILE = "dag.dot"
DRYRUN_FILE = "dryrun.txt"


# ----------------------------------------------------------------------------------------------
# Config and machine facts


def _plain(value):
    """Plain dicts and lists (Snakemake's loaders may return ordered or custom mappings)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def merged_config(configfiles=(), base=BASE_CONFIG) -> dict:
    """``base`` with each of ``configfiles`` merged onto it, the way Snakemake merges ``--configfile``
    onto the Snakefile's ``configfile:`` (snakemake.utils.update_config on load_configfile)."""
    from snakemake.common.configfile import load_configfile
    from snakemake.utils import update_config

    config = _plain(load_configfile(str(base)))
    for f in configfiles:
        update_config(config, _plain(load_configfile(str(f))))
    return _plain(config)


def git_commit(repo=REPO) -> str:
    """HEAD of ``repo``, with "-dirty" when tracked files differ (read-only git commands)."""
    try:
        head = subprocess.run(["git", "-C", str(repo), "rev-parse", "HEAD"], capture_output=True, text=True,
                              timeout=20, check=True).stdout.strip()
        dirty = subprocess.run(["git", "--no-optional-locks", "-C", str(repo), "status", "--porcelain",
                                "--untracked-files=no"], capture_output=True, text=True, timeout=20,
                               check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head + ("-dirty" if dirty else "")


def machine_facts() -> dict:
    """Cores usable here, CPU model, memory, platform, Python and Snakemake versions."""
    model, mem_gb = "unknown", None
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                mem_gb = round(int(line.split()[1]) / 1024**2, 2)
                break
    except (OSError, ValueError, IndexError):
        pass
    try:
        nproc = len(os.sched_getaffinity(0))
    except AttributeError:
        nproc = os.cpu_count()
    try:
        snakemake_version = metadata.version("snakemake")
    except metadata.PackageNotFoundError:
        snakemake_version = "not installed"
    return {"nproc": nproc, "cpu_count": os.cpu_count(), "cpu_model": model, "memory_gb": mem_gb,
            "platform": platform.platform(), "python": platform.python_version(), "snakemake": snakemake_version}


# ----------------------------------------------------------------------------------------------
# Reading a finished run


def read_benchmark(path) -> dict:
    """Wall and CPU seconds of one Snakemake benchmark TSV (summed over its rows when the rule
    repeats the measurement); ``cpu_s`` is None when no row has a sampled cpu_time."""
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh, delimiter="\t"))
    if not rows or "s" not in rows[0]:
        raise ValueError(f"{path}: not a Snakemake benchmark file (no 's' column)")
    wall = sum(float(r["s"]) for r in rows)
    cpus = [float(r["cpu_time"]) for r in rows if r.get("cpu_time") not in (None, "", "NA")]
    return {"wall_s": wall, "cpu_s": sum(cpus) if cpus else None}


_NODE = re.compile(r'^\s*(\d+)\s*\[\s*label\s*=\s*"((?:[^"\\]|\\.)*)"')
_EDGE = re.compile(r"^\s*(\d+)\s*->\s*(\d+)")


def parse_dot(text: str) -> tuple[dict, list]:
    """Nodes {id: (rule, {wildcard: value shown in the label})} and edges [(dependency, job)] of
    ``snakemake --dag`` output (lines before ``digraph`` are ignored)."""
    nodes, edges = {}, []
    for line in text.splitlines():
        if m := _NODE.match(line):
            parts = m.group(2).split("\\n")
            wildcards = dict(p.split(": ", 1) for p in parts[1:] if ": " in p)
            nodes[int(m.group(1))] = (parts[0], wildcards)
        elif m := _EDGE.match(line):
            edges.append((int(m.group(1)), int(m.group(2))))
    return nodes, edges


def parse_dryrun(text: str) -> list[dict]:
    """The jobs of ``snakemake -n`` output: [{rule, jobid, input, output, benchmark, wildcards}]."""
    jobs, job = [], None
    head = re.compile(r"^(?:local)?(?:rule|checkpoint)\s+(\S+):\s*$")
    field = re.compile(r"^\s+(\w+):(?:\s+(.*))?$")
    for line in text.splitlines():
        if m := head.match(line):
            job = {"rule": m.group(1), "jobid": None, "input": [], "output": [], "benchmark": None, "wildcards": {}}
            jobs.append(job)
        elif job is not None and (f := field.match(line)):
            key, value = f.group(1), f.group(2) or ""
            if key in ("input", "output"):
                job[key] = [v.strip() for v in value.split(", ") if v.strip()]
            elif key == "benchmark":
                job["benchmark"] = value.strip()
            elif key == "jobid" and value.strip().isdigit():
                job["jobid"] = int(value)
            elif key == "wildcards":
                job["wildcards"] = dict(w.split("=", 1) for w in value.split(", ") if "=" in w)
        elif not line.startswith("    "):
            job = None
    return jobs


def _topological(nodes, deps) -> list:
    """Node ids, every node after its dependencies (ties by id); raises on a cycle."""
    indegree = {n: len(deps[n]) for n in nodes}
    users = defaultdict(list)
    for n in nodes:
        for d in deps[n]:
            users[d].append(n)
    ready = sorted(n for n, k in indegree.items() if k == 0)
    order = []
    while ready:
        n = ready.pop(0)
        order.append(n)
        for u in sorted(users[n]):
            indegree[u] -= 1
            if indegree[u] == 0:
                ready.append(u)
        ready.sort()
    if len(order) != len(nodes):
        raise ValueError("the job graph has a cycle")
    return order


def job_graph(dot_text: str, dryrun_text: str) -> tuple[dict, list[str]]:
    """Every job of the DAG: {node id: {rule, wildcards, deps, benchmark, output}} with its full
    wildcards and benchmark file from the dry run, and notes on nodes that could not be matched.

    A dot label shows only the wildcards a job does not share with the jobs it depends on, so the
    others are taken from those jobs: going through the graph in dependency order, a node matches the
    dry-run job of its rule whose wildcards are the label's plus ones its dependencies carry (ties
    broken by the dependencies' outputs being its inputs)."""
    nodes, edges = parse_dot(dot_text)
    deps = {n: set() for n in nodes}
    for a, b in edges:
        if a in deps and b in deps:
            deps[b].add(a)
    by_rule = defaultdict(list)
    for j in parse_dryrun(dryrun_text):
        by_rule[j["rule"]].append(j)
    used, graph, notes = set(), {}, []
    for n in _topological(nodes, deps):
        rule, shown = nodes[n]
        inherited = set()
        for d in deps[n]:
            inherited |= set(graph[d]["wildcards"].items())
        candidates = [(i, j) for i, j in enumerate(by_rule[rule]) if (rule, i) not in used
                      and all(j["wildcards"].get(k) == v for k, v in shown.items())
                      and all(k in shown or (k, v) in inherited for k, v in j["wildcards"].items())]
        if len(candidates) > 1:
            made = {f for d in deps[n] for f in graph[d]["output"]}
            candidates = [(i, j) for i, j in candidates if made <= set(j["input"])] or candidates
        match = candidates[0][1] if len(candidates) == 1 else None
        if match is None:
            notes.append(f"DAG node {n} ({rule} {shown}) matched {len(candidates)} dry-run jobs: no benchmark taken")
        else:
            used.add((rule, candidates[0][0]))
        graph[n] = {"rule": rule, "deps": sorted(deps[n]),
                    "wildcards": dict(match["wildcards"]) if match else dict(shown),
                    "benchmark": match["benchmark"] if match else None,
                    "output": match["output"] if match else []}
    return graph, notes


def critical_path(graph: dict, weight: dict) -> tuple[float, list]:
    """The chain of jobs along the DAG with the largest summed weight: (total, [node ids in order])."""
    best, pred = {}, {}
    for n in _topological(graph, {k: v["deps"] for k, v in graph.items()}):
        prev = max(graph[n]["deps"], key=lambda d: (best[d], -d), default=None)
        best[n] = weight.get(n, 0.0) + (best[prev] if prev is not None else 0.0)
        pred[n] = prev
    if not best:
        return 0.0, []
    end = max(best, key=lambda n: (best[n], -n))
    chain = [end]
    while pred[chain[-1]] is not None:
        chain.append(pred[chain[-1]])
    return best[end], chain[::-1]


def _rule_from_path(parts: tuple[str, ...]) -> str:
    """Rule of a benchmark file that is in no job graph, by the workflow's layout
    (<rule>/<wildcards>.tsv, and report/<rule>.tsv for the final rules)."""
    return parts[-1] if parts[0] == "report" and len(parts) == 2 else parts[0]


def _r(x):
    return None if x is None else round(float(x), 3)


def summarize(workdir, wall_s: float, config_label, *, config: dict | None = None, results: str | None = None,
              dag=None, dryrun=None) -> dict:
    """The cost summary of the finished run in ``workdir`` (schema in the module docstring):
    every benchmark TSV under ``<results>/benchmarks`` summed per rule, per scene and per job, and
    the critical path through the job graph (``dag``/``dryrun``: texts or paths, by default
    ``<workdir>/costs/dag.dot`` and ``dryrun.txt``; without them no critical path).

    ``config_label`` names the config the run used: a configfile merged onto config/config.yaml, or
    None / "default" for config/config.yaml alone; ``config`` gives the merged values directly."""
    workdir = Path(workdir)
    notes = []
    files = [str(BASE_CONFIG)]
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
    results = results or (config or {}).get("results", "results")
    bench_root = workdir / results / "benchmarks"
    tsvs = sorted(bench_root.rglob("*.tsv"))
    if not tsvs:
        raise FileNotFoundError(f"no benchmark files under {bench_root}")

    def load(x, name):
        """The text of x: a path, or text itself; None: the run's own file, if any."""
        if x is None:
            x = workdir / COSTS_DIR / name
            return x.read_text() if x.exists() else None
        if isinstance(x, Path) or ("\n" not in x and os.path.isfile(x)):
            return Path(x).read_text()
        return x

    dot_text, dry_text = load(dag, DAG_FILE), load(dryrun, DRYRUN_FILE)
    graph = {}
    if dot_text and dry_text:
        graph, graph_notes = job_graph(dot_text, dry_text)
        notes += graph_notes
    else:
        notes.append("no job graph (costs/dag.dot and costs/dryrun.txt): no critical path; rules named "
                     "by the benchmark directory")
    node_of = {}
    for n, g in graph.items():
        if g["benchmark"]:
            node_of[(workdir / g["benchmark"]).resolve()] = n

    kinds = {name: block.get("kind") for name, block in (config or {}).get("scenes", {}).items()}
    jobs, weight, job_of_node = [], {}, {}
    for path in tsvs:
        rel = path.relative_to(bench_root).with_suffix("")
        b = read_benchmark(path)
        n = node_of.get(path.resolve())
        if n is not None:
            rule, wildcards = graph[n]["rule"], graph[n]["wildcards"]
            weight[n] = b["wall_s"]
        else:
            rule = _rule_from_path(rel.parts)
            wildcards = {"scene": rel.parts[1]} if rule in ("scene", "gather", "chunk") and len(rel.parts) > 1 else {}
            if rule == "chunk" and len(rel.parts) > 2:
                wildcards["chunk"] = rel.parts[2]
        jobs.append({"job": rel.as_posix(), "rule": rule, "scene": wildcards.get("scene"),
                     "wildcards": dict(wildcards), "cpu_s": _r(b["cpu_s"]), "wall_s": _r(b["wall_s"]),
                     "in_dag": n is not None})
        if n is not None:
            job_of_node[n] = jobs[-1]
    if graph:
        outside = [j["job"] for j in jobs if not j["in_dag"]]
        if outside:
            notes.append(f"{len(outside)} benchmark files belong to no job of this config's DAG (older or "
                         f"on-request jobs); counted in the sums: {', '.join(outside)}")
        missing = [g["benchmark"] for g in graph.values() if g["benchmark"] and
                   not (workdir / g["benchmark"]).exists()]
        if missing:
            notes.append(f"{len(missing)} jobs of the DAG have no benchmark file: {', '.join(missing)}")

    def cpu(j):
        return j["cpu_s"] or 0.0

    jobs.sort(key=lambda j: (-cpu(j), -j["wall_s"], j["job"]))
    rules, scenes = {}, {}
    for j in jobs:
        r = rules.setdefault(j["rule"], {"jobs": 0, "cpu_s": 0.0, "wall_s": 0.0})
        r["jobs"] += 1
        r["cpu_s"] += cpu(j)
        r["wall_s"] += j["wall_s"]
        if j["scene"]:
            s = scenes.setdefault(j["scene"], {"kind": kinds.get(j["scene"]), "jobs": 0, "cpu_s": 0.0, "wall_s": 0.0})
            s["jobs"] += 1
            s["cpu_s"] += cpu(j)
            s["wall_s"] += j["wall_s"]
    def order(d):
        return dict(sorted(((k, {**v, "cpu_s": _r(v["cpu_s"]), "wall_s": _r(v["wall_s"])}) for k, v in d.items()),
                           key=lambda kv: (-kv[1]["cpu_s"], -kv[1]["wall_s"], kv[0])))

    crit = None
    if graph:
        total, chain = critical_path(graph, weight)
        # jobs without a benchmark (the target rule `all`) weigh nothing and are not listed
        crit = {"wall_s": _r(total), "dag_jobs": len(graph),
                "jobs": [{k: job_of_node[n][k] for k in ("job", "rule", "wall_s")} for n in chain if n in job_of_node]}
    not_sampled = [j["job"] for j in jobs if j["cpu_s"] is None]
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
        "cpu_s": _r(sum(cpu(j) for j in jobs)),
        "jobs_total": len(jobs),
        "cpu_not_sampled": not_sampled,
        "rules": order(rules),
        "jobs": jobs,
        "scenes": order(scenes),
        "critical_path": crit,
        "notes": notes,
    }


def write_summary(summary: dict, path) -> Path:
    """Write the summary as YAML, atomically."""
    import yaml

    with atomic_path(path) as tmp:
        tmp.write_text(yaml.safe_dump(summary, sort_keys=False, default_flow_style=False, width=120))
    return Path(path)


def read_summary(path) -> dict:
    import yaml

    return yaml.safe_load(Path(path).read_text())


# ----------------------------------------------------------------------------------------------
# The cost figure


def plot_costs(summary: dict, png, pdf) -> None:
    """CPU seconds per rule (horizontal bars, largest on top), each bar split into its jobs (the
    chunk jobs show as separate segments; jobs on the critical path hatched and outlined in red),
    and the critical path beside it: its jobs' wall seconds in order, with its total."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    rules = list(summary["rules"])
    crit_jobs = [j["job"] for j in (summary.get("critical_path") or {}).get("jobs", [])]
    on_path = set(crit_jobs)
    by_rule = defaultdict(list)
    for j in summary["jobs"]:
        by_rule[j["rule"]].append(j)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, max(3.5, 0.45 * len(rules) + 1.5)),
                                  gridspec_kw={"width_ratios": [3, 2]})
    cmap = plt.get_cmap("tab10")
    ys = range(len(rules))[::-1]  # largest on top
    for y, rule in zip(ys, rules):
        left = 0.0
        jobs = sorted(by_rule[rule], key=lambda j: -(j["cpu_s"] or 0.0))
        for k, j in enumerate(jobs):
            c = j["cpu_s"] or 0.0
            crit = j["job"] in on_path
            ax.barh(y, c, left=left, height=0.7, color=cmap(k % 10) if rule == "chunk" else cmap(0),
                    alpha=0.85 if rule == "chunk" else 0.55 + 0.3 * (k % 2), edgecolor="red" if crit else "white",
                    linewidth=1.5 if crit else 0.6, hatch="//" if crit else None)
            if rule == "chunk" and "chunk" in (j.get("wildcards") or {}):
                ax.text(left + c / 2, y, j["wildcards"]["chunk"], ha="center", va="center", fontsize=6, clip_on=True)
            left += c
        ax.text(left, y, f" {left:.4g} s ({len(jobs)} job{'s' if len(jobs) != 1 else ''})", va="center", fontsize=8)
    ax.set_yticks(list(ys), rules)
    ax.set_xlabel("CPU seconds (segments: jobs)")
    ax.set_xlim(0, max((v["cpu_s"] or 0.0) for v in summary["rules"].values()) * 1.35 or 1.0)
    ax.set_title(f"CPU per rule: {summary['cpu_s']:.4g} s in {summary['jobs_total']} jobs, wall {summary['wall_s']:.4g} s")
    ax.legend(handles=[Patch(facecolor="white", edgecolor="red", hatch="//", label="on the critical path"),
                       Patch(facecolor=cmap(1), label="chunk jobs (one colour each, numbered)")],
              loc="lower right", fontsize=8)
    crit = summary.get("critical_path")
    if crit and crit["jobs"]:
        walls = [j["wall_s"] for j in crit["jobs"]]
        cy = range(len(walls))[::-1]
        ax2.barh(list(cy), walls, left=[sum(walls[:i]) for i in range(len(walls))], color="tab:red", alpha=0.7)
        ax2.set_yticks(list(cy), [j["job"] for j in crit["jobs"]], fontsize=8)
        ax2.set_xlabel("wall seconds along the path")
        ax2.set_title(f"Critical path: {crit['wall_s']:.4g} s of {summary['wall_s']:.4g} s wall")
    else:
        ax2.text(0.5, 0.5, "no job graph: no critical path", ha="center", va="center", transform=ax2.transAxes)
        ax2.set_axis_off()
    cfg = (summary.get("config") or {}).get("label") or "config/config.yaml"
    m = summary.get("machine") or {}
    fig.suptitle(f"Workflow cost ({cfg}; {m.get('nproc', '?')} cores, {m.get('cpu_model', '?')}; "
                 f"{str(summary.get('git_commit', ''))[:12]})", fontsize=9)
    fig.tight_layout()
    try:
        for path in (Path(png), Path(pdf)):
            with atomic_path(path) as tmp:
                fig.savefig(tmp, dpi=150, format=path.suffix[1:])
    finally:
        plt.close(fig)


def job_costs(benchmarks: dict) -> list[dict]:
    """Per job, from the report's benchmark files ({"data/<name>" or "figure/<name>": [TSV paths]}):
    job ("<rule>/<wildcards>"), rule, wall_s and cpu_s (None when never sampled), largest wall first."""
    jobs = {}
    for paths in benchmarks.values():
        for path in map(Path, paths):
            parts = path.with_suffix("").parts
            i = len(parts) - 1 - parts[::-1].index("benchmarks")
            rel = parts[i + 1:]
            jobs["/".join(rel)] = {"job": "/".join(rel), "rule": _rule_from_path(rel), **read_benchmark(path)}
    return sorted(jobs.values(), key=lambda j: -j["wall_s"])


def plot_job_costs(jobs: list[dict], png, pdf=None, top: int = 25) -> None:
    """Wall seconds per rule (left) and of the ``top`` costliest jobs (right), from
    :func:`job_costs`, as PNG (and PDF when given); the title gives the total and the lower bound
    it sets on 2 cores."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if not jobs:
        raise ValueError("no benchmark records to plot")
    per_rule = defaultdict(float)
    for j in jobs:
        per_rule[j["rule"]] += j["wall_s"]
    rules = sorted(per_rule, key=per_rule.get)
    colours = {r: plt.get_cmap("tab10")(k % 10) for k, r in enumerate(sorted(per_rule))}
    shown = jobs[:top][::-1]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, max(4.0, 0.28 * len(shown) + 1.5)),
                                 gridspec_kw={"width_ratios": [2, 3]})
    ax.barh(rules, [per_rule[r] for r in rules], color=[colours[r] for r in rules])
    for y, r in enumerate(rules):
        ax.text(per_rule[r], y, f" {per_rule[r]:.4g} s", va="center", fontsize=8)
    ax.set_xlabel("wall seconds, summed over the rule's jobs")
    ax.set_xlim(0, max(per_rule.values()) * 1.3)
    bx.barh([j["job"] for j in shown], [j["wall_s"] for j in shown], color=[colours[j["rule"]] for j in shown])
    bx.tick_params(axis="y", labelsize=7)
    bx.set_xlabel("wall seconds of the job")
    total = sum(per_rule.values())
    fig.suptitle(f"Run cost from the Snakemake benchmark files: {len(jobs)} jobs, {total:.4g} job-seconds "
                 f"(at least {total / 2:.4g} s of wall on 2 cores); the {len(shown)} costliest jobs on the right",
                 fontsize=9)
    fig.tight_layout()
    try:
        for path in [Path(png)] + ([Path(pdf)] if pdf else []):
            with atomic_path(path) as tmp:
                fig.savefig(tmp, dpi=120, format=path.suffix[1:])
    finally:
        plt.close(fig)


# ----------------------------------------------------------------------------------------------
# Work models and the estimate

#: Keys of a scene block (at any depth) that are integration horizons in time units; a list (of
#: horizons, one per case) counts as its sum. T_round counts T_round x max_rounds (the cap on rounds).
HORIZON_KEYS = ("T", "t_end", "t_map", "duration", "check_duration", "t_max", "t_settle", "t_transient",
                "t_pre", "t_scale", "t_half", "horizons", "T_long", "t_long", "t_short", "T_eps", "T_scaling",
                "T_lyapunov", "T_round", "max_rounds")

#: Keys the lyapunov_grid model reads (everything else of such a block is outside the model).
GRID_KEYS = ("eps_range", "n_eps", "n_chunks", "reference_eps", "t_pre", "t_pre_min", "replicas",
             "replica_spacing", "t_align", "T_round", "max_rounds", "poincare_span", "b_check")


def horizon_work(block: dict) -> float:
    """Work of a scene without a model of its own: the sum of its horizons (:data:`HORIZON_KEYS`, at
    any depth; T_round times max_rounds). A linear model: cost proportional to time integrated, with
    the number of cases (states, sweeps, lanes) and the step sizes taken as unchanged."""
    total = 0.0
    for key, value in block.items():
        if isinstance(value, dict):
            total += horizon_work(value)
        elif key == "T_round":
            total += float(value) * float(block.get("max_rounds", 1))
        elif key == "max_rounds":
            continue
        elif key in HORIZON_KEYS:
            if isinstance(value, (list, tuple)):
                total += sum(float(v) for v in value if isinstance(v, (int, float)))
            elif isinstance(value, (int, float)) and not isinstance(value, bool):
                total += float(value)
    return total


def grid_rows(cfg: dict) -> list[tuple[float, float]]:
    """(eps, work) of every row of a lyapunov_grid block, following sleighsim.scenes.grid.row, in time
    units integrated at slow time s = reference_eps / eps:

    - pre-run: max(t_pre_min, t_pre s^2) (one trajectory);
    - replica sampling: replicas x replica_spacing x s (one trajectory through the replicas' states);
    - tangent batch: (t_align + T_round x max_rounds) x s, counted once: the replicas are the SIMD
      lanes of one batch (the brief's n_b / batch_size), and max_rounds is the cap (rows that converge
      earlier cost less; target_rel is not modelled);
    - Poincare crossings: poincare_span x s;
    - the reference row also runs one round per b_check value: len(b_check) x (t_align + T_round) x s.

    n_b costs nothing: b is an exact symmetry and every row is computed once at b = 1."""
    from .scenes.grid import axes, pre_run, reference_row, slow_time

    eps_all, _ = axes(cfg)
    ref = reference_row(cfg)
    rows = []
    for i, eps in enumerate(eps_all):
        s = slow_time(cfg, eps)
        w = pre_run(cfg, eps) + cfg["replicas"] * cfg["replica_spacing"] * s
        w += (cfg["t_align"] + cfg["T_round"] * cfg["max_rounds"]) * s + cfg.get("poincare_span", 0.0) * s
        if i == ref:
            w += len(cfg.get("b_check") or ()) * (cfg["t_align"] + cfg["T_round"]) * s
        rows.append((float(eps), float(w)))
    return rows


def chunk_work(cfg: dict) -> list[float]:
    """Work of each chunk job of a lyapunov_grid block: chunk k computes rows k, k + n_chunks, ..."""
    rows = grid_rows(cfg)
    return [sum(w for _, w in rows[k::cfg["n_chunks"]]) for k in range(cfg["n_chunks"])]


def work(kind: str, cfg: dict) -> float:
    """The work measure of a scene block (as :func:`sleighsim.registry.scene_config` gives it)."""
    if kind == "lyapunov_grid":
        return sum(w for _, w in grid_rows(cfg))
    return horizon_work(cfg)


def _modelled(kind: str, key: str) -> bool:
    leaf = key.split(".")[-1]
    return leaf in GRID_KEYS if kind == "lyapunov_grid" else leaf in HORIZON_KEYS


def changed_keys(a, b, prefix="") -> list[str]:
    """Dotted paths of the values that differ between two blocks (added and removed keys included)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b), key=str):
            out += changed_keys(a.get(k), b.get(k), f"{prefix}{k}.")
        return out
    return [] if a == b else [prefix.rstrip(".")]


def _value(cfg, dotted, width: int = 40) -> str:
    """The value at a dotted path, its repr cut to ``width`` characters."""
    for k in dotted.split("."):
        cfg = cfg.get(k) if isinstance(cfg, dict) else None
    text = repr(cfg) if not isinstance(cfg, float) else f"{cfg:g}"
    return text if len(text) <= width else text[: width - 3] + "..."


def _job_cpu(j: dict) -> float:
    """CPU seconds of a measured job; its wall seconds where Snakemake sampled no CPU."""
    return j["cpu_s"] if j.get("cpu_s") is not None else j["wall_s"]


def startup_s(summary: dict) -> float:
    """The fixed CPU cost of a job (interpreter, imports): the smallest sampled CPU seconds of any
    measured job, i.e. of a job that does next to nothing. It does not scale with the work."""
    cpus = [j["cpu_s"] for j in summary["jobs"] if j.get("cpu_s") is not None]
    return min(cpus) if cpus else 0.0


def estimate(target: dict, summary: dict) -> dict:
    """Estimated CPU seconds of the full run ``target`` (a merged config) would launch, from the
    measured ``summary``. Linear work model: a job's CPU seconds are a fixed startup
    (:func:`startup_s`) plus a part proportional to its work, so each measured scene job becomes
    startup + (measured - startup) x work(target block) / work(measured block), the ratio 1 when no
    key of the work model changed; chunk jobs are re-cut to the target's chunks at the measured CPU
    seconds per unit of work of the scene's chunks; gather, figure, claims and report jobs stay as
    measured.

    Returns {jobs: [{job, rule, kind, scene, cpu_s, ratio}], rules, kinds: {name: {jobs, cpu_s}},
    total_cpu_s, startup_s, scaled: [{scene, kind, ratio, work_measured, work_target, modelled,
    not_modelled}], changed_not_scaled, unmeasured, chunks: [{scene, n_chunks, largest_s,
    largest_chunk, eps, limit_s, exceeds, rate_spread}], warnings}."""
    measured = summary["config"]["values"]
    if measured is None:
        raise ValueError("the measured summary records no config values: cannot compare configs")
    mjobs = summary["jobs"]
    base = startup_s(summary)

    def scale(cpu: float, ratio: float) -> float:
        fixed = min(base, cpu)
        return fixed + (cpu - fixed) * ratio
    by_scene = defaultdict(list)
    for j in mjobs:
        if j.get("scene"):
            by_scene[j["scene"]].append(j)
    jobs, scaled, changed_only, unmeasured, chunks, warnings = [], [], [], [], [], []
    for scene in registry.datasets(target):
        block = target["scenes"][scene]
        kind = block["kind"]
        tcfg = registry.scene_config(target, scene)
        have = by_scene.get(scene, [])
        if not have or scene not in measured.get("scenes", {}):
            unmeasured.append(scene)
            continue
        mcfg = registry.scene_config(measured, scene)
        changed = changed_keys(mcfg, tcfg)
        modelled = [k for k in changed if _modelled(kind, k)]
        not_modelled = [k for k in changed if not _modelled(kind, k)]
        ratio, w_m, w_t = 1.0, None, None
        if modelled:
            w_m, w_t = work(kind, mcfg), work(kind, tcfg)
            if w_m > 0 and w_t > 0:
                ratio = w_t / w_m
            else:
                warnings.append(f"{scene}: work measure is zero ({w_m} measured, {w_t} target): not scaled")
        if modelled and ratio != 1.0:
            scaled.append({"scene": scene, "kind": kind, "ratio": ratio, "work_measured": w_m, "work_target": w_t,
                           "modelled": [f"{k}: {_value(mcfg, k)} -> {_value(tcfg, k)}" for k in modelled],
                           "not_modelled": [f"{k}: {_value(mcfg, k)} -> {_value(tcfg, k)}" for k in not_modelled]})
        elif changed:
            changed_only.append({"scene": scene, "kind": kind, "changed": changed})
        if registry.KINDS[kind].chunked:
            mchunks = [j for j in have if j["rule"] == "chunk"]
            mwork = chunk_work(mcfg)
            rates = []
            for j in mchunks:
                k = int(j["wildcards"].get("chunk", j["job"].rsplit("/", 1)[-1]))
                if k < len(mwork) and mwork[k] > 0:
                    rates.append((max(_job_cpu(j) - base, 0.0), mwork[k]))
            if not rates:
                unmeasured.append(scene)
                continue
            rate = sum(c for c, _ in rates) / sum(w for _, w in rates)
            twork = chunk_work(tcfg)
            rows = grid_rows(tcfg)
            for k, w in enumerate(twork):
                jobs.append({"job": f"chunk/{scene}/{k}", "rule": "chunk", "kind": kind, "scene": scene,
                             "cpu_s": base + rate * w, "ratio": ratio})
            for j in have:
                if j["rule"] != "chunk":
                    jobs.append({"job": j["job"], "rule": j["rule"], "kind": kind, "scene": scene,
                                 "cpu_s": _job_cpu(j), "ratio": 1.0})
            k = max(range(len(twork)), key=lambda i: twork[i])
            limit = block.get("chunk_runtime_min")
            entry = {"scene": scene, "n_chunks": len(twork), "largest_s": base + rate * twork[k], "largest_chunk": k,
                     "eps": [e for e, _ in rows[k::tcfg["n_chunks"]]],
                     "limit_s": None if limit is None else 60.0 * limit,
                     "rate_spread": [min(c / w for c, w in rates), max(c / w for c, w in rates)]}
            entry["exceeds"] = limit is not None and entry["largest_s"] > entry["limit_s"]
            chunks.append(entry)
            if entry["exceeds"]:
                warnings.append(f"{scene}: chunk {k} is estimated at {entry['largest_s'] / 60:.4g} min, more than "
                                f"chunk_runtime_min = {limit} min: raise chunk_runtime_min or n_chunks, or lower the "
                                "horizons, before submitting")
        else:
            for j in have:
                jobs.append({"job": j["job"], "rule": j["rule"], "kind": kind, "scene": scene,
                             "cpu_s": scale(_job_cpu(j), ratio), "ratio": ratio})
    # jobs that are not scenes: figures, claims, report (as measured)
    figures = set(registry.figures_built(target))
    for j in mjobs:
        if j.get("scene"):
            continue
        parts = j["job"].split("/")
        if parts[0] == "figure" and parts[-1] not in figures:
            continue
        jobs.append({"job": j["job"], "rule": j["rule"], "kind": f"({j['rule']})", "scene": None,
                     "cpu_s": _job_cpu(j), "ratio": 1.0})
    measured_figs = {j["job"].split("/", 1)[1] for j in mjobs if j["job"].startswith("figure/")}
    unmeasured += [f"figure {f}" for f in figures if f not in measured_figs]
    if unmeasured:
        warnings.append(f"no measurement for {', '.join(unmeasured)}: left out of the estimate (it is low)")
    rules, kinds = {}, {}
    for j in jobs:
        for table, key in ((rules, j["rule"]), (kinds, j["kind"])):
            e = table.setdefault(key, {"jobs": 0, "cpu_s": 0.0})
            e["jobs"] += 1
            e["cpu_s"] += j["cpu_s"]
    def order(d):
        return dict(sorted(d.items(), key=lambda kv: (-kv[1]["cpu_s"], kv[0])))

    return {"jobs": sorted(jobs, key=lambda j: -j["cpu_s"]), "rules": order(rules), "kinds": order(kinds),
            "total_cpu_s": sum(j["cpu_s"] for j in jobs), "startup_s": base, "scaled": scaled, "changed_not_scaled": changed_only,
            "unmeasured": unmeasured, "chunks": chunks, "warnings": warnings}


def format_estimate(est: dict, target_label: str, summary: dict, measured_path, base=BASE_CONFIG) -> str:
    """The estimate as the text the CLI prints."""
    ch = 1 / 3600
    m = summary.get("machine") or {}
    base = Path(base).resolve()
    lines = [
        (f"Estimated cost of the full run of {target_label} (merged onto "
         f"{base.relative_to(REPO) if base.is_relative_to(REPO) else base})"),
        (f"measured: {measured_path} (config {summary['config'].get('label') or 'config/config.yaml'}, "
         f"{summary.get('date')}, commit {str(summary.get('git_commit'))[:12]}, {m.get('nproc')} cores "
         f"{m.get('cpu_model')}; {summary['cpu_s'] / 3600:.3g} core-h measured)"),
        "",
        ("ESTIMATES from a linear work model: a scene job's CPU seconds = startup + (measured - startup) x "
         "(its work in the target config / its work in the measured one),"),
        (f"startup = {est['startup_s']:.3g} s (the cheapest measured job); work = time units integrated "
         "(lyapunov_grid: per eps row pre-run + replica sampling + one tangent"),
        ("batch to the max_rounds cap; other kinds: the block's horizons). Gather, figure, claims and report "
         "jobs as measured; CPU seconds are Snakemake's sampled cpu_time."),
        "",
    ]
    if est["scaled"]:
        lines.append("Scaled scenes:")
        for s in est["scaled"]:
            lines.append(f"  {s['scene']} ({s['kind']}): x{s['ratio']:.4g}  [work {s['work_measured']:.4g} -> "
                         f"{s['work_target']:.4g}]")
            lines.append(f"      in the model: {'; '.join(s['modelled'])}")
            if s["not_modelled"]:
                lines.append(f"      changed, not in the model: {'; '.join(s['not_modelled'])}")
    else:
        lines.append("Scaled scenes: none (every scene's work is as measured)")
    for s in est["changed_not_scaled"]:
        lines.append(f"  {s['scene']} ({s['kind']}): changed but not scaled (no modelled key changed): "
                     f"{', '.join(s['changed'])}")
    n_same = len({j['scene'] for j in est['jobs'] if j['scene']}) - len(est["scaled"]) - len(est["changed_not_scaled"])
    lines.append(f"Unchanged scenes, as measured: {n_same}")
    lines += ["", f"{'per rule':<24}{'jobs':>6}{'core-h':>12}{'share':>8}"]
    total = est["total_cpu_s"] or 1.0
    for name, e in est["rules"].items():
        lines.append(f"  {name:<22}{e['jobs']:>6}{e['cpu_s'] * ch:>12.4g}{100 * e['cpu_s'] / total:>7.1f}%")
    lines += ["", f"{'per job kind':<24}{'jobs':>6}{'core-h':>12}{'share':>8}"]
    for name, e in est["kinds"].items():
        lines.append(f"  {name:<22}{e['jobs']:>6}{e['cpu_s'] * ch:>12.4g}{100 * e['cpu_s'] / total:>7.1f}%")
    n_jobs = sum(e["jobs"] for e in est["rules"].values())
    lines += ["", f"{'total':<24}{n_jobs:>6}{est['total_cpu_s'] * ch:>12.4g}  core-hours (estimate)", ""]
    for c in est["chunks"]:
        eps = ", ".join(f"{e:.4g}" for e in c["eps"])
        limit = "no chunk_runtime_min" if c["limit_s"] is None else f"chunk_runtime_min {c['limit_s'] / 60:g} min"
        lines.append(f"Chunk jobs of {c['scene']}: {c['n_chunks']} jobs; largest estimated runtime "
                     f"{c['largest_s'] / 60:.4g} min (chunk {c['largest_chunk']}, eps {eps}; one core) against "
                     f"{limit}: {'EXCEEDS' if c['exceeds'] else 'within'}")
        lo, hi = c["rate_spread"]
        lines.append(f"  measured CPU seconds per unit work across its chunks: {lo:.3g} to {hi:.3g} "
                     "(the linear model's spread)")
    for w in est["warnings"]:
        lines.append(f"WARNING: {w}")
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------------------------
# Command line


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sleighsim.costs", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("estimate", help="estimated core-hours of the full run a config would launch")
    p.add_argument("--configfile", nargs="*", default=[],
                   help="config file(s) merged onto config/config.yaml as Snakemake does (none: that file alone)")
    p.add_argument("--measured", default=str(DEFAULT_MEASURED),
                   help="full-run summary at paper fidelity (benchmarks/full_run.py; default %(default)s)")
    p.add_argument("--base", default=str(BASE_CONFIG),
                   help="the config the --configfile files are merged onto, as the Snakefile's configfile "
                        "(default %(default)s)")
    q = sub.add_parser("plot", help="the cost figure of a full-run summary")
    q.add_argument("summary")
    q.add_argument("png")
    q.add_argument("--pdf", help="default: the png path with .pdf")
    args = parser.parse_args(argv)
    if args.command == "plot":
        plot_costs(read_summary(args.summary), args.png, args.pdf or str(Path(args.png).with_suffix(".pdf")))
        return 0
    measured = Path(args.measured)
    if not measured.is_file():
        print(f"sleighsim.costs estimate: no measured summary at {measured}. Measure a full run at paper "
              "fidelity first: python benchmarks/full_run.py (writes benchmarks/full_run.yaml), or pass "
              "--measured FILE.", file=sys.stderr)
        return 2
    summary = read_summary(measured)
    if not isinstance(summary, dict) or summary.get("schema") != SCHEMA:
        print(f"sleighsim.costs estimate: {measured} is not a full-run summary ({SCHEMA})", file=sys.stderr)
        return 2
    for f in args.configfile:
        if not Path(f).is_file():
            print(f"sleighsim.costs estimate: no config file {f}", file=sys.stderr)
            return 2
    if not Path(args.base).is_file():
        print(f"sleighsim.costs estimate: no base config {args.base}", file=sys.stderr)
        return 2
    target = merged_config(args.configfile, base=args.base)
    label = " + ".join(args.configfile) or args.base
    est = estimate(target, summary)
    paper = merged_config(base=args.base)
    off = [n for n in paper["scenes"] if changed_keys(paper["scenes"][n], summary["config"]["values"]
                                                       .get("scenes", {}).get(n))]
    if off:
        est["warnings"].insert(0, f"the measured run was not at paper fidelity (config {summary['config']['label']}: "
                                  f"{len(off)} scenes differ from {args.base}): scaling across fidelity levels "
                                  "is rough")
    sys.stdout.write(format_estimate(est, label, summary, measured, base=args.base))
    if not math.isfinite(est["total_cpu_s"]):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
