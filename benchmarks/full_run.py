#!/usr/bin/env python
"""Measure one full run of the workflow in a fresh directory and write its cost summary.

    python benchmarks/full_run.py [--configfile CONFIG ...] [--cores 2] [--workdir DIR]
                                  [--out benchmarks/full_run.yaml] [--reuse DIR] [--plot PNG]

Runs ``python -m snakemake -s <repo>/workflow/Snakefile -d <fresh workdir> -c<cores> [--configfile ...]``,
timing the whole command, then saves the run's job graph beside it (``<workdir>/costs/dag.dot`` from
``--forceall -n --dag`` and ``<workdir>/costs/dryrun.txt`` from ``--forceall -n``, same workdir and
config) and writes the summary of sleighsim.ops.summary.summarize: wall and CPU seconds in total, per rule,
per scene and per job, jobs per rule, the critical path, machine facts, git commit, date and config.

``--reuse DIR`` analyses a finished run in DIR instead of running the workflow (its wall time is
the one this script recorded in DIR/costs/run.yaml, or else the span of its newest Snakemake log).
The workdir is kept (pass it to --reuse to re-analyse). Progress goes to stderr; a failed workflow
exits non-zero with the log to read.

The committed summary (benchmarks/full_run.yaml) is measured at paper fidelity (no --configfile);
``python -m sleighsim.ops.costs estimate`` scales it to other configs. The smoke run's
(benchmarks/smoke_run.yaml) is ``--configfile config/smoke.yaml --out benchmarks/smoke_run.yaml``; the
README's times table reads both (``sleighsim costs times``).
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

import yaml

from sleighsim.ops import jobgraph
from sleighsim.ops import summary as costsummary
from sleighsim.ops.config import BASE_CONFIG, merged_config
from sleighsim.ops.helptext import plain
from sleighsim.report.figures import costs as plots


def portable(text, workdir: Path) -> str:
    """``text`` with this machine's paths made portable: the repository as <repo>, the run's directory as
    <run>, this Python as python (a record read on another machine names no path of this one)."""
    return str(text).replace(str(workdir), "<run>").replace(str(REPO), "<repo>").replace(sys.executable, "python")


def say(msg: str) -> None:
    """A progress line on stderr, tagged with the time."""
    print(f"[full_run {dt.datetime.now():%H:%M:%S}] {msg}", file=sys.stderr, flush=True)


def snakemake_cmd(workdir: Path, cores: int, configfiles: list[str], *extra: str) -> list[str]:
    """The Snakemake command line running the workflow in ``workdir`` on ``cores`` cores with the
    repository's config/config.yaml, then ``configfiles`` merged onto it, then ``extra`` arguments."""
    # the Snakefile's own configfile is relative to the working directory, which is not the repository:
    # name it, then the overlays merged onto it (as snakemake --configfile does in the repository)
    cmd = [sys.executable, "-m", "snakemake", "-s", str(REPO / "workflow" / "Snakefile"), "-d", str(workdir),
           f"-c{cores}", "--configfile", str(REPO / "config" / "config.yaml"), *configfiles]
    return cmd + list(extra)


def run_workflow(cmd: list[str], workdir: Path) -> float:
    """Run the workflow, its output passed through to stderr; the wall seconds of the command."""
    say(f"running: {shlex.join(cmd)}")
    start = time.perf_counter()
    proc = subprocess.run(cmd, stdout=sys.stderr, stderr=sys.stderr, check=False)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        logs = sorted((workdir / ".snakemake" / "log").glob("*.snakemake.log"))
        where = f"; its log: {logs[-1]}" if logs else ""
        sys.exit(f"full_run: the workflow failed (snakemake exit code {proc.returncode}) after {wall:.0f} s in "
                 f"{workdir}{where}. No summary written.")
    say(f"workflow finished in {wall:.1f} s")
    return wall


def save_job_graph(workdir: Path, cores: int, configfiles: list[str]) -> None:
    """The run's DAG (dot) and its dry-run job listing, for the critical path."""
    out = workdir / jobgraph.COSTS_DIR
    out.mkdir(parents=True, exist_ok=True)
    for extra, name, merge in ((["--forceall", "-n", "--dag"], jobgraph.DAG_FILE, False),
                               (["--forceall", "-n"], jobgraph.DRYRUN_FILE, True)):
        cmd = snakemake_cmd(workdir, cores, configfiles, *extra)
        say(f"job graph: {shlex.join(cmd[2:])}")
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if proc.returncode != 0:
            sys.exit(f"full_run: `{shlex.join(cmd)}` failed (exit {proc.returncode}):\n{proc.stderr[-3000:]}")
        text = proc.stdout + (proc.stderr if merge else "")
        if name == jobgraph.DAG_FILE and "digraph" not in text:
            sys.exit(f"full_run: no dot graph in the output of `{shlex.join(cmd)}`")
        (out / name).write_text(text)


def wall_from_log(workdir: Path) -> float | None:
    """Span of the newest Snakemake log of workdir: its name's start time to its last timestamp."""
    logs = sorted((workdir / ".snakemake" / "log").glob("*.snakemake.log"))
    if not logs:
        return None
    m = re.match(r"(\d{4}-\d{2}-\d{2}T\d{6}\.\d+)", logs[-1].name)
    stamps = re.findall(r"^\[(\w{3} \w{3} +\d+ \d{2}:\d{2}:\d{2} \d{4})\]$", logs[-1].read_text(), re.MULTILINE)
    if not m or not stamps:
        return None
    start = dt.datetime.strptime(m.group(1), "%Y-%m-%dT%H%M%S.%f")
    end = dt.datetime.strptime(" ".join(stamps[-1].split()), "%a %b %d %H:%M:%S %Y")
    return max((end - start).total_seconds(), 0.0)


def main(argv=None) -> int:
    """The command line (``argv``: the arguments, default sys.argv[1:]): run the workflow, or analyse a
    finished run with --reuse, and write the cost summary to --out; exit status 0 (a failed run exits
    non-zero)."""
    head, _, rest = __doc__.partition("\n\n")
    parser = argparse.ArgumentParser(prog="python benchmarks/full_run.py", description=plain(head),
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=plain(rest))
    parser.add_argument("--configfile", nargs="+", default=[],
                        help="merged onto config/config.yaml as snakemake --configfile does (default: none, "
                             "paper fidelity)")
    parser.add_argument("--cores", type=int, default=2, help="snakemake's -c (default 2)")
    parser.add_argument("--workdir", help="fresh (absent or empty) directory to run in; default: a new one in /tmp")
    parser.add_argument("--out", default=str(REPO / "benchmarks" / "full_run.yaml"),
                        help="the summary to write (default benchmarks/full_run.yaml)")
    parser.add_argument("--reuse", metavar="DIR", help="analyse the finished run in DIR; run nothing")
    parser.add_argument("--plot", metavar="PNG", help="also draw the cost figure (PNG and PDF beside it)")
    args = parser.parse_args(argv)
    configfiles = [str(Path(f).resolve()) for f in args.configfile]
    for f in configfiles:
        if not Path(f).is_file():
            sys.exit(f"full_run: no config file {f}")

    if args.reuse:
        workdir = Path(args.reuse).resolve()
        record = workdir / jobgraph.COSTS_DIR / "run.yaml"
        recorded = yaml.safe_load(record.read_text()) if record.exists() else None
        if recorded is not None:
            if args.configfile and configfiles != recorded["configfiles"]:
                sys.exit(f"full_run: {workdir} was run with --configfile {recorded['configfiles']}, not {configfiles}")
            configfiles = recorded["configfiles"]
            wall, source, cmd = recorded["wall_s"], "measured by full_run.py", recorded["command"]
            load = recorded.get("load_average")
        else:
            wall, source, cmd, load = wall_from_log(workdir), "span of the newest .snakemake log", None, None
            if wall is None:
                sys.exit(f"full_run: {workdir} holds no finished run (no costs/run.yaml, no .snakemake log)")
        say(f"reusing {workdir} (wall {wall:.1f} s, {source})")
        if not (workdir / jobgraph.COSTS_DIR / jobgraph.DAG_FILE).exists():
            save_job_graph(workdir, args.cores, configfiles)
    else:
        if args.workdir:
            workdir = Path(args.workdir).resolve()
            if workdir.exists() and any(workdir.iterdir()):
                sys.exit(f"full_run: --workdir {workdir} is not empty (a full run needs a fresh directory; "
                         "use --reuse to analyse a finished one)")
            workdir.mkdir(parents=True, exist_ok=True)
        else:
            workdir = Path(tempfile.mkdtemp(prefix="sleighsim-full-run-"))
        say(f"fresh workdir {workdir}")
        cmd = snakemake_cmd(workdir, args.cores, configfiles)
        load = os.getloadavg()[0]
        wall = run_workflow(cmd, workdir)
        load = [round(load, 2), round(os.getloadavg()[0], 2)]
        source = "measured by full_run.py"
        cmd = shlex.join(cmd)
        (workdir / jobgraph.COSTS_DIR).mkdir(exist_ok=True)
        (workdir / jobgraph.COSTS_DIR / "run.yaml").write_text(yaml.safe_dump(
            {"wall_s": wall, "command": cmd, "configfiles": configfiles, "cores": args.cores, "load_average": load},
            sort_keys=False))
        save_job_graph(workdir, args.cores, configfiles)

    say("reading the benchmark files")
    label = " + ".join(str(Path(f).relative_to(REPO)) if Path(f).is_relative_to(REPO) else f
                       for f in configfiles) or None
    config = merged_config(configfiles)
    summary = costsummary.summarize(workdir, wall, label, config=config)
    summary["config"]["files"] = [portable(f, workdir) for f in (BASE_CONFIG, *configfiles)]
    summary["workdir"] = "<run>"
    sum_wall = sum(j["wall_s"] for j in summary["jobs"])
    crit = (summary["critical_path"] or {}).get("wall_s") or 0.0
    summary["run"] = {"command": portable(cmd, workdir), "cores": args.cores, "workdir": "<run>", "wall_source": source,
                      # no schedule on these cores can beat the longer of these two
                      "lower_bound_s": round(max(crit, sum_wall / args.cores), 3),
                      "job_wall_sum_s": round(sum_wall, 3),
                      # the machine's 1-minute load average at the start and the end (a shared machine's
                      # other work lengthens the wall): None when the run was not timed here
                      "load_average": load}
    previous = costsummary.read_summary(args.out) if Path(args.out).exists() else None
    costsummary.write_summary(costsummary.with_history(summary, previous), args.out)
    say(f"wrote {args.out} (the run before it kept in its history)")
    if args.plot:
        png = Path(args.plot)
        plots.plot_costs(summary, png, png.with_suffix(".pdf"))
        say(f"wrote {png} and {png.with_suffix('.pdf')}")
    top = list(summary["rules"].items())[:3]
    say(f"wall {summary['wall_s']:.1f} s, CPU {summary['cpu_s']:.1f} s in {summary['jobs_total']} jobs; top rules: "
        + ", ".join(f"{r} {v['cpu_s']:.1f} s CPU ({v['jobs']} jobs)" for r, v in top))
    if summary["critical_path"]:
        say(f"critical path {crit:.1f} s: " + " -> ".join(j["job"] for j in summary["critical_path"]["jobs"]))
    say(f"workdir kept: {workdir} (re-analyse with --reuse {workdir})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
