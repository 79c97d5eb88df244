"""Write the judge-power record the chaos verdict votes by (benchmarks/judge_power.yaml) from judge-power
audit datasets (``snakemake judge_power``; several when the judges were audited in separate runs):

    python -m sleighsim.ops.powerrecord RESULTS/data/judge_power.nc [MORE.nc ...] [--out benchmarks/judge_power.yaml]

The record holds, per horizon factor, judge and orbit class, the measured counts (N, correct, wrong,
undecided) and where they came from; ``sleighsim.chaos.power.record_voting`` reads the vote from it.
Prints the table per judge and class (markdown, for docs/methods.md)."""

from __future__ import annotations

import argparse
from pathlib import Path

import yaml

from sleighsim.chaos import power
from sleighsim.io.netcdf import read_dataset
from sleighsim.ops.config import REPO


def markdown(rec: dict) -> str:
    """The record's table: per audited horizon factor, judge and class, N and the counts and shares of
    correct, wrong (with the 95% upper bound) and undecided verdicts, and whether the judge votes there."""
    lines = ["| horizon | judge | orbits | N | correct | wrong (95% bound) | undecided | votes |",
             "|---|---|---|---|---|---|---|---|"]
    for h in sorted(float(h) for h in rec["counts"]):
        votes = power.record_voting(rec, h)
        lines += [_row(h, r, votes) for r in power.record_rates(rec, h)]
    return "\n".join(lines)


def _row(h: float, r: dict, votes: set) -> str:
    """One line of the table."""
    return (f"| x{h:g} | {r['judge']} | {r['class']} | {r['N']} | {r['correct']} ({r['p_correct']:.2f}) | "
            f"{r['wrong']} ({r['p_wrong']:.3f}, <= {r['wrong_upper95']:.3f}) | {r['undecided']} "
            f"({r['p_undecided']:.2f}) | {'yes' if r['judge'] in votes else 'no'} |")


def main(argv=None) -> int:
    """Write the record from the datasets given; print its table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("datasets", nargs="+", help="judge_power datasets (one per audit run)")
    parser.add_argument("--out", default=str(REPO / "benchmarks" / "judge_power.yaml"))
    args = parser.parse_args(argv)
    rec = power.merged_records([power.record(read_dataset(p)) for p in args.datasets])
    rec["voting"] = {float(h): sorted(power.record_voting(rec, float(h))) for h in rec["counts"]}
    Path(args.out).write_text(yaml.safe_dump(rec, sort_keys=False))
    print(markdown(rec))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
