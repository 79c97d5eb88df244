"""Snakemake benchmark files (one TSV per job, columns ``s`` for wall seconds and ``cpu_time`` for
CPU seconds) as the workflow lays them out under ``<results>/benchmarks``."""

from __future__ import annotations

import csv


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


#: The workflow's rules of a chunked scene's chunk jobs (chunk_first: those of a scene scheduled first).
CHUNK_RULES = ("chunk", "chunk_first")


def rule_from_path(parts: tuple[str, ...]) -> str:
    """Rule of a benchmark file that is in no job graph, by the workflow's layout
    (<rule>/<wildcards>.tsv, and report/<rule>.tsv for the final rules)."""
    return parts[-1] if parts[0] == "report" and len(parts) == 2 else parts[0]
