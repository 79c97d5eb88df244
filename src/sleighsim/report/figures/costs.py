"""Cost figures: :func:`plot_costs` draws a full-run summary (:mod:`sleighsim.ops.summary`) as CPU
seconds per rule, each bar split into its jobs, with the critical path; :func:`job_costs` and
:func:`plot_job_costs` give the report's run-cost section from its benchmark files. Each has a
``*_figure`` function that returns the matplotlib Figure (in the figures' legible style)."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import matplotlib.pyplot as plt
from matplotlib.patches import Patch

from sleighsim.io.benchmark_files import CHUNK_RULES, read_benchmark, rule_from_path
from sleighsim.report.figures.common import WIDTH, save_figure, subplots


def costs_figure(summary: dict):
    """CPU seconds per rule (horizontal bars, largest on top), each bar split into its jobs (the
    chunk jobs show as separate segments; jobs on the critical path hatched and outlined in red),
    and the critical path beside it: its jobs' wall seconds in order, with its total."""
    rules = list(summary["rules"])
    crit_jobs = [j["job"] for j in (summary.get("critical_path") or {}).get("jobs", [])]
    on_path = set(crit_jobs)
    by_rule = defaultdict(list)
    for j in summary["jobs"]:
        by_rule[j["rule"]].append(j)
    fig, (ax, ax2) = subplots(WIDTH, max(3.5, 0.45 * len(rules) + 1.5), 1, 2, width_ratios=[3, 2])
    cmap = plt.get_cmap("tab10")
    ys = range(len(rules))[::-1]  # largest on top
    for y, rule in zip(ys, rules):
        left = 0.0
        jobs = sorted(by_rule[rule], key=lambda j: -(j["cpu_s"] or 0.0))
        for k, j in enumerate(jobs):
            c = j["cpu_s"] or 0.0
            crit = j["job"] in on_path
            ax.barh(y, c, left=left, height=0.7, color=cmap(k % 10) if rule in CHUNK_RULES else cmap(0),
                    alpha=0.85 if rule in CHUNK_RULES else 0.55 + 0.3 * (k % 2), edgecolor="red" if crit else "white",
                    linewidth=1.5 if crit else 0.6, hatch="//" if crit else None)
            if rule in CHUNK_RULES and "chunk" in (j.get("wildcards") or {}):
                ax.text(left + c / 2, y, j["wildcards"]["chunk"], ha="center", va="center", fontsize=8, clip_on=True)
            left += c
        ax.text(left, y, f" {left:.4g} s ({len(jobs)} job{'s' if len(jobs) != 1 else ''})", va="center", fontsize=8)
    ax.set_yticks(list(ys), rules)
    ax.set_xlabel("CPU seconds (s; segments: jobs)")
    ax.set_xlim(0, max((v["cpu_s"] or 0.0) for v in summary["rules"].values()) * 1.35 or 1.0)
    ax.set_title(f"CPU per rule: {summary['cpu_s']:.4g} s in {summary['jobs_total']} jobs,\n"
                 f"wall {summary['wall_s']:.4g} s")
    ax.legend(handles=[Patch(facecolor="white", edgecolor="red", hatch="//", label="on the critical path"),
                       Patch(facecolor=cmap(1), label="chunk jobs (one colour each, numbered)")],
              loc="lower right", fontsize=8)
    crit = summary.get("critical_path")
    if crit and crit["jobs"]:
        walls = [j["wall_s"] for j in crit["jobs"]]
        cy = range(len(walls))[::-1]
        ax2.barh(list(cy), walls, left=[sum(walls[:i]) for i in range(len(walls))], color="tab:red", alpha=0.7)
        ax2.set_yticks(list(cy), [j["job"] for j in crit["jobs"]], fontsize=8)
        ax2.set_xlabel("wall seconds along the path (s)")
        ax2.set_title(f"Critical path: {crit['wall_s']:.4g} s\nof {summary['wall_s']:.4g} s wall")
    else:
        ax2.text(0.5, 0.5, "no job graph: no critical path", ha="center", va="center", transform=ax2.transAxes)
        ax2.set_axis_off()
    cfg = (summary.get("config") or {}).get("label") or "config/config.yaml"
    m = summary.get("machine") or {}
    fig.suptitle(f"Workflow cost ({cfg}; {m.get('nproc', '?')} cores, {m.get('cpu_model', '?')}; "
                 f"{str(summary.get('git_commit', ''))[:12]})", fontsize=9)
    return fig


def plot_costs(summary: dict, png, pdf) -> None:
    """:func:`costs_figure` as PNG and PDF."""
    save_figure(costs_figure(summary), png, pdf)


def job_costs(benchmarks: dict) -> list[dict]:
    """Per job, from the report's benchmark files ({"data/<name>" or "figure/<name>": [TSV paths]}):
    job ("<rule>/<wildcards>"), rule, wall_s and cpu_s (None when never sampled), largest wall first."""
    jobs = {}
    for paths in benchmarks.values():
        for path in map(Path, paths):
            parts = path.with_suffix("").parts
            i = len(parts) - 1 - parts[::-1].index("benchmarks")
            rel = parts[i + 1:]
            jobs["/".join(rel)] = {"job": "/".join(rel), "rule": rule_from_path(rel), **read_benchmark(path)}
    return sorted(jobs.values(), key=lambda j: -j["wall_s"])


def job_costs_figure(jobs: list[dict], top: int = 25):
    """Wall seconds per rule (left) and of the ``top`` costliest jobs (right), from
    :func:`job_costs`; the title gives the total and the lower bound it sets on 2 cores."""
    if not jobs:
        raise ValueError("no benchmark records to plot")
    per_rule = defaultdict(float)
    for j in jobs:
        per_rule[j["rule"]] += j["wall_s"]
    rules = sorted(per_rule, key=per_rule.get)
    colours = {r: plt.get_cmap("tab10")(k % 10) for k, r in enumerate(sorted(per_rule))}
    shown = jobs[:top][::-1]
    fig, (ax, bx) = subplots(WIDTH, max(4.0, 0.3 * len(shown) + 1.5), 1, 2, width_ratios=[2, 3])
    ax.barh(rules, [per_rule[r] for r in rules], color=[colours[r] for r in rules])
    for y, r in enumerate(rules):
        ax.text(per_rule[r], y, f" {per_rule[r]:.4g} s", va="center", fontsize=8)
    ax.set_xlabel("wall seconds, summed over the rule's jobs (s)")
    ax.set_xlim(0, max(per_rule.values()) * 1.3)
    bx.barh([j["job"] for j in shown], [j["wall_s"] for j in shown], color=[colours[j["rule"]] for j in shown])
    bx.tick_params(axis="y", labelsize=8)
    bx.set_xlabel("wall seconds of the job (s)")
    total = sum(per_rule.values())
    fig.suptitle(f"Run cost from the Snakemake benchmark files: {len(jobs)} jobs, {total:.4g} job-seconds "
                 f"(at least {total / 2:.4g} s of wall on 2 cores);\nthe {len(shown)} costliest jobs on the right",
                 fontsize=9)
    return fig


def plot_job_costs(jobs: list[dict], png, pdf=None, top: int = 25) -> None:
    """:func:`job_costs_figure` as PNG and as PDF beside it (``pdf``, by default the PNG's name
    with .pdf)."""
    save_figure(job_costs_figure(jobs, top), png, pdf or Path(png).with_suffix(".pdf"), dpi=120)
