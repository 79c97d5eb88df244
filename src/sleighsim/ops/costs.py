"""What a workflow run costs: measured after the fact, and estimated before a config is launched.

The command line over the cost modules of :mod:`sleighsim.ops`::

    python -m sleighsim.ops.costs estimate --configfile config/cluster.yaml
    python -m sleighsim.ops.costs plot benchmarks/full_run.yaml benchmarks/full_run.png

- :mod:`~sleighsim.ops.jobgraph`: the run's job graph from Snakemake's dry runs, its critical path;
- :mod:`~sleighsim.io.benchmark_files`: Snakemake's benchmark files, one per job;
- :mod:`~sleighsim.ops.summary`: a finished run's cost summary (``benchmarks/full_run.py`` writes it);
- :mod:`~sleighsim.report.figures.costs`: the cost figures;
- :mod:`~sleighsim.ops.workmodel` and :mod:`~sleighsim.ops.estimate`: a measured summary scaled to
  the run another config would launch, with the chunk jobs checked against ``chunk_runtime_min``;
- :mod:`~sleighsim.ops.facts`: git commit and machine facts (the merged config: :mod:`~sleighsim.ops.config`).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from sleighsim.ops.config import BASE_CONFIG, REPO, merged_config
from sleighsim.ops.estimate import changed_keys, estimate, format_estimate
from sleighsim.ops.helptext import summary
from sleighsim.ops.summary import SCHEMA, read_summary
from sleighsim.report.figures.costs import plot_costs

DEFAULT_MEASURED = REPO / "benchmarks" / "full_run.yaml"
PROG = "python -m sleighsim.ops.costs"


def _parser(prog: str = PROG) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog, description=summary(__doc__))
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


def main(argv=None, prog: str = PROG) -> int:
    """The ``plot`` and ``estimate`` commands (``argv``: the arguments, default sys.argv[1:]). Exit
    status 0; 1 when the estimate is not finite; 2 when its inputs are refused."""
    args = _parser(prog).parse_args(argv)
    if args.command == "plot":
        plot_costs(read_summary(args.summary), args.png, args.pdf or str(Path(args.png).with_suffix(".pdf")))
        return 0
    measured = Path(args.measured)
    summary, refusal = _read_inputs(args, measured)
    if refusal:
        print(f"{PROG.removeprefix('python -m ')} estimate: {refusal}", file=sys.stderr)
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
