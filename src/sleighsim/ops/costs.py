"""What a workflow run costs: measured after the fact, and estimated before a config is launched.

The command line over the cost modules of :mod:`sleighsim.ops`::

    python -m sleighsim.ops.costs estimate --configfile config/cluster.yaml
    python -m sleighsim.ops.costs estimate --configfile config/cluster.yaml --out benchmarks/cluster_estimate.yaml
    python -m sleighsim.ops.costs plot benchmarks/full_run.yaml benchmarks/full_run.png
    python -m sleighsim.ops.costs times --readme README.md

- :mod:`~sleighsim.ops.jobgraph`: the run's job graph from Snakemake's dry runs, its critical path;
- :mod:`~sleighsim.io.benchmark_files`: Snakemake's benchmark files, one per job;
- :mod:`~sleighsim.ops.summary`: a finished run's cost summary (``benchmarks/full_run.py`` writes it);
- :mod:`~sleighsim.report.figures.costs`: the cost figures;
- :mod:`~sleighsim.ops.workmodel` and :mod:`~sleighsim.ops.estimate`: a measured summary scaled to
  the run another config would launch, with the chunk jobs checked against ``chunk_runtime_min``;
- :mod:`~sleighsim.ops.walltime`: that run's wall on N cores, its longest job and critical path;
- :mod:`~sleighsim.ops.plantimes`: the README's table of times to plan by, from the committed records;
- :mod:`~sleighsim.ops.facts`: git commit and machine facts (the merged config: :mod:`~sleighsim.ops.config`).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import math
import sys
from pathlib import Path

from sleighsim.claims.fidelity import config_sha256
from sleighsim.ops import plantimes, walltime
from sleighsim.ops.config import BASE_CONFIG, REPO, merged_config
from sleighsim.ops.estimate import changed_keys, estimate, format_estimate
from sleighsim.ops.facts import git_commit
from sleighsim.ops.helptext import summary
from sleighsim.ops.readme import replaced
from sleighsim.ops.summary import SCHEMA, read_summary, write_summary
from sleighsim.report.figures.costs import plot_costs

DEFAULT_MEASURED = REPO / "benchmarks" / "full_run.yaml"
PROG = "python -m sleighsim.ops.costs"
#: The format of an estimate's record (``estimate --out``).
RECORD_SCHEMA = "sleighsim.estimate/1"


def _parser(prog: str = PROG) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog, description=summary(__doc__))
    sub = parser.add_subparsers(dest="command", required=True)
    what = "estimated core-hours of the full run a config would launch"
    p = sub.add_parser("estimate", help=what, description=what + " (scaled from a measured full run)")
    p.add_argument("--configfile", nargs="*", default=[],
                   help="config file(s) merged onto config/config.yaml as Snakemake does (none: that file alone)")
    p.add_argument("--measured", default=str(DEFAULT_MEASURED),
                   help="full-run summary at paper fidelity (benchmarks/full_run.py; default %(default)s)")
    p.add_argument("--base", default=str(BASE_CONFIG),
                   help="the config the --configfile files are merged onto, as the Snakefile's configfile "
                        "(default %(default)s)")
    p.add_argument("--cores", type=int, nargs="+", default=list(walltime.CORES),
                   help="core counts to give the wall time for (default %(default)s)")
    p.add_argument("--graph", metavar="DIR", help="the config's job graph saved as dag.dot and dryrun.txt "
                   "(default: two Snakemake dry runs, some seconds)")
    p.add_argument("--no-schedule", action="store_true", help="core-hours only: no job graph, no wall time")
    p.add_argument("--out", metavar="FILE", help="also write the estimate as a YAML record (schema "
                   f"{RECORD_SCHEMA}; the README's times table reads benchmarks/cluster_estimate.yaml)")
    what = "the README's table of times to plan by, from the committed benchmark records"
    t = sub.add_parser("times", help=what, description=what)
    t.add_argument("--readme", metavar="FILE", help=f"write the table into FILE's '{plantimes.BLOCK}' block instead "
                   "of printing it")
    q = sub.add_parser("plot", help="the cost figure of a full-run summary",
                       description="the cost figure of a full-run summary (benchmarks/full_run.py's record)")
    q.add_argument("summary", help="the full run's summary (YAML, e.g. benchmarks/full_run.yaml)")
    q.add_argument("png", help="the figure to write (PNG)")
    q.add_argument("--pdf", help="default: the png path with .pdf")
    return parser


def _read_inputs(args, measured: Path) -> tuple[dict | None, str | None]:
    """The measured summary, or why the estimate cannot be made from these files."""
    if not measured.is_file():
        return None, (f"no measured summary at {measured}. Measure a full run at paper fidelity first: "
                      "python benchmarks/full_run.py (writes benchmarks/full_run.yaml), or pass --measured FILE.")
    summary = read_summary(measured)
    if not isinstance(summary, dict) or summary.get("schema") != SCHEMA:
        return None, f"{measured} is not a full-run summary ({SCHEMA})"
    for f in args.configfile:
        if not Path(f).is_file():
            return None, f"no config file {f}"
    if not Path(args.base).is_file():
        return None, f"no base config {args.base}"
    return summary, None


def _schedule(args, target: dict, est: dict, summary: dict) -> dict | None:
    """The estimated run on ``args.cores``; None with --no-schedule or when the job graph cannot be
    had (a warning then says why)."""
    if args.no_schedule:
        return None
    try:
        graph, _ = walltime.dry_run_graph(args.configfile, args.base, args.graph)
    except (RuntimeError, OSError) as why:
        est["warnings"].append(f"no job graph, so no wall time: {why}")
        return None
    return walltime.schedule(est, graph, target.get("results", "results"), summary, args.cores)


def _record(args, target: dict, est: dict, sched: dict | None, summary: dict) -> dict:
    """The estimate as a record: what was estimated, from which measurement, the totals and the schedule."""
    def rel(p):
        p = Path(p).resolve()
        return p.relative_to(REPO).as_posix() if p.is_relative_to(REPO) else str(p)

    return {"schema": RECORD_SCHEMA, "date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
            "git_commit": git_commit(),
            "config": {"files": [rel(f) for f in (args.base, *args.configfile)], "sha256": config_sha256(target)},
            "measured": {"file": rel(args.measured), "date": summary.get("date"),
                         "git_commit": summary.get("git_commit"), "wall_s": summary.get("wall_s")},
            "total_cpu_s": round(est["total_cpu_s"], 1), "jobs_estimated": len(est["jobs"]),
            "unmeasured": est["unmeasured"], "schedule": sched,
            "warnings": [w.replace(f"{REPO}/", "") for w in est["warnings"]]}  # no path of this machine


def _estimate(args) -> int:
    """The ``estimate`` command."""
    measured = Path(args.measured)
    summary, refusal = _read_inputs(args, measured)
    if refusal:
        print(f"{PROG.removeprefix('python -m ')} estimate: {refusal}", file=sys.stderr)
        return 2
    target = merged_config(args.configfile, base=args.base)
    est = estimate(target, summary)
    paper = merged_config(base=args.base)
    off = [n for n in paper["scenes"] if changed_keys(paper["scenes"][n], summary["config"]["values"]
                                                       .get("scenes", {}).get(n))]
    if off:
        est["warnings"].insert(0, f"the measured run's config ({summary['config']['label'] or 'the paper config'}"
                                  f" at commit {str(summary.get('git_commit'))[:12]}) differs from {args.base} in "
                                  f"{len(off)} scenes ({', '.join(off)}): another fidelity or an older config, "
                                  "so the scaling is rough")
    sched = _schedule(args, target, est, summary)
    sys.stdout.write(format_estimate(est, " + ".join(args.configfile) or args.base, summary, measured,
                                     base=args.base, schedule=walltime.format_schedule(sched) if sched else ()))
    if args.out:
        write_summary(_record(args, target, est, sched, summary), args.out)
    return 0 if math.isfinite(est["total_cpu_s"]) else 1


def main(argv=None, prog: str = PROG) -> int:
    """The ``plot`` and ``estimate`` commands (``argv``: the arguments, default sys.argv[1:]). Exit
    status 0; 1 when the estimate is not finite; 2 when its inputs are refused."""
    args = _parser(prog).parse_args(argv)
    if args.command == "plot":
        plot_costs(read_summary(args.summary), args.png, args.pdf or str(Path(args.png).with_suffix(".pdf")))
        return 0
    if args.command == "times":
        return _times(args.readme)
    return _estimate(args)


def _times(readme: str | None) -> int:
    """The ``times`` command: print the table, or write it into ``readme``'s block (exit 2 without one)."""
    text = plantimes.table()
    if readme is None:
        sys.stdout.write(text)
        return 0
    path = Path(readme)
    try:
        path.write_text(replaced(path.read_text(), plantimes.BLOCK, text))
    except ValueError as why:
        print(f"{PROG.removeprefix('python -m ')} times: {path}: {why}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
