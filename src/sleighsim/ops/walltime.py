"""How long a config's run would take on N cores, before it is launched: the jobs
:func:`sleighsim.ops.estimate.estimate` prices, placed on the config's own job graph (two Snakemake dry
runs, :func:`dry_run_graph`) and list-scheduled (:func:`sleighsim.ops.jobgraph.predicted_wall`). Gives
the wall on each core count, the longest job and the critical path (no core count beats either).

A job's wall is its estimated CPU seconds times the measured run's job wall per CPU second
(:func:`wall_per_cpu`: startup Snakemake does not sample, input and output, a shared machine); one core
per job, no queueing: a cluster's queue adds its own wait. Seconds throughout."""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

from sleighsim.ops.config import BASE_CONFIG, REPO
from sleighsim.ops.jobgraph import DAG_FILE, DRYRUN_FILE, critical_path, job_graph, predicted_wall

#: Core counts the estimate gives the wall for.
CORES = (2, 8, 16, 64)


def dry_run_graph(configfiles: list, base=BASE_CONFIG, saved: Path | None = None) -> tuple[dict, list[str]]:
    """The job graph of the run ``configfiles`` merged onto ``base`` would launch, from Snakemake's
    ``--forceall -n --dag`` and ``--forceall -n`` in an empty directory, or from ``saved`` (a
    directory holding their outputs as ``dag.dot`` and ``dryrun.txt``, as benchmarks/full_run.py keeps
    them). Raises RuntimeError naming the command when a dry run fails."""
    if saved is not None:
        return job_graph((Path(saved) / DAG_FILE).read_text(), (Path(saved) / DRYRUN_FILE).read_text())
    texts = []
    with tempfile.TemporaryDirectory(prefix="sleighsim-dag-") as work:
        for extra in (["--dag"], []):
            cmd = [sys.executable, "-m", "snakemake", "-s", str(REPO / "workflow" / "Snakefile"), "-d", work,
                   "--configfile", *(str(Path(f).resolve()) for f in (base, *configfiles)), "--forceall", "-n", *extra]
            proc = subprocess.run(cmd, capture_output=True, text=True, check=False, cwd=work)
            if proc.returncode != 0:
                raise RuntimeError(f"`{' '.join(cmd)}` failed (exit {proc.returncode}): "
                                   f"{(proc.stdout + proc.stderr)[-800:]}")
            texts.append(proc.stdout + ("" if extra else proc.stderr))
    return job_graph(*texts)


def wall_per_cpu(summary: dict) -> float:
    """The measured run's wall seconds per CPU second over its jobs whose CPU Snakemake sampled."""
    jobs = [j for j in summary["jobs"] if j.get("cpu_s")]
    cpu = sum(j["cpu_s"] for j in jobs)
    return sum(j["wall_s"] for j in jobs) / cpu if cpu > 0 else 1.0


def _job_name(benchmark: str, results: str) -> str:
    """A job's name in a summary or an estimate: its benchmark path below <results>/benchmarks, no .tsv."""
    return benchmark.removeprefix(f"{results}/benchmarks/").removesuffix(".tsv")


def weights(est: dict, graph: dict, results: str, factor: float) -> tuple[dict, list[str]]:
    """Each graph node's estimated wall ({node: s}) and the names of the graph's jobs without an
    estimate (weight 0). An estimated ``scene/<variant>`` the graph runs as chunks is spread evenly
    over the variant's chunk jobs."""
    node_of = {_job_name(g["benchmark"], results): n for n, g in graph.items() if g["benchmark"]}
    weight = {}
    for j in est["jobs"]:
        name = j["job"]
        if name in node_of:
            weight[node_of[name]] = j["cpu_s"] * factor
            continue
        parts = [n for k, n in node_of.items() if k.startswith(f"chunk/{name.removeprefix('scene/')}/")]
        for n in parts:
            weight[n] = j["cpu_s"] * factor / len(parts)
    return weight, sorted(k for k, n in node_of.items() if n not in weight)


def schedule(est: dict, graph: dict, results: str, summary: dict, cores=CORES) -> dict:
    """The estimated run on each of ``cores``: {wall_per_cpu, wall_s: {cores: s}, longest: {job,
    wall_s}, critical_path: {wall_s, jobs}, jobs, unestimated: [job names]}."""
    factor = wall_per_cpu(summary)
    weight, unestimated = weights(est, graph, results, factor)
    names = {n: _job_name(g["benchmark"], results) for n, g in graph.items() if g["benchmark"]}
    longest = max(weight, key=weight.get) if weight else None
    total, chain = critical_path(graph, weight)
    return {"wall_per_cpu": round(factor, 4),
            "wall_s": {c: round(predicted_wall(graph, weight, c), 1) for c in cores},
            "longest": {"job": names.get(longest), "wall_s": round(weight.get(longest, 0.0), 1)},
            "critical_path": {"wall_s": round(total, 1), "jobs": [names[n] for n in chain if n in names]},
            "jobs": len(names), "unestimated": unestimated}


def duration(seconds: float) -> str:
    """Seconds as a reader plans by: '45 s', '2.5 min', '12 min', '3.4 h'."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 600:
        return f"{seconds / 60:.1f} min"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.2g} h"


def format_schedule(sched: dict) -> list[str]:
    """The schedule as the lines the estimate command prints."""
    lines = ["", (f"Wall time on N cores (ESTIMATE: the {sched['jobs']} jobs of this config's job graph, list-"
                  "scheduled one core each, no queue wait; a job's wall = its CPU seconds x "
                  f"{sched['wall_per_cpu']:.3g}, the measured run's wall per CPU second):")]
    lines += [f"  {c:>4} cores  {duration(s):>8}" for c, s in sched["wall_s"].items()]
    crit, longest = sched["critical_path"], sched["longest"]
    lines.append(f"Longest job: {longest['job']}, {duration(longest['wall_s'])}; critical path "
                 f"{duration(crit['wall_s'])} ({' -> '.join(crit['jobs'])}): no number of cores runs the whole "
                 "in less")
    if sched["unestimated"]:
        lines.append(f"WARNING: {len(sched['unestimated'])} jobs of the graph have no estimate (counted 0 s: the "
                     f"wall is low): {grouped(sched['unestimated'])}")
    return lines


def grouped(names: list[str]) -> str:
    """Job names with a scene's chunk jobs as one entry: 'chunk/x/* (41 jobs), gather/x'."""
    counts = {}
    for name in names:
        head, _, last = name.rpartition("/")
        key = f"{head}/*" if last.isdigit() else name
        counts[key] = counts.get(key, 0) + 1
    return ", ".join(k if n == 1 and not k.endswith("*") else f"{k} ({n} jobs)" for k, n in counts.items())
