"""The sleighsim command: one entry point for the project's tools, each a subcommand.

    sleighsim claims ...     judge the claims ledger from a results tree
    sleighsim diff OLD NEW   compare two result trees dataset by dataset (python -m sleighsim.resultdiff)
    sleighsim costs ...      the run's measured cost, its estimate for a config, and the cost plot
    sleighsim configdoc ...  config/README.md from the config schema (--check: in step with it)
    sleighsim judge ...      the chaos verdict of a start state of one's own, by the workflow's rule
    sleighsim finding FILE   the finding in one paragraph, from a run's report/finding.yaml
    sleighsim verify DIR     check every dataset under DIR against its recorded checksum

Each subcommand takes the options of the module it runs (``sleighsim SUBCOMMAND --help``) and
returns its exit status: 0 success, 1 a difference or a failed check (a corrupt dataset), 2 a usage error, 3 a
ledger written from an incomplete results tree.
"""

from __future__ import annotations

import argparse
import importlib
import sys

#: subcommand -> (the module whose main it runs, imported only for that subcommand: `verify` then
#: loads neither matplotlib nor heyoka, which want a writable HOME; its one-line help)
COMMANDS = {
    "claims": ("sleighsim.cli.claims", "judge every claim of CLAIMS.md from a results tree; write the ledger"),
    "diff": ("sleighsim.ops.resultdiff", "compare two result trees dataset by dataset (exit 1 when they differ)"),
    "costs": ("sleighsim.ops.costs", "the run's measured cost, its estimate for another config, and the cost plot"),
    "configdoc": ("sleighsim.ops.configdoc",
                  "write config/README.md from the schema (--check: exit 1 when out of step)"),
    "judge": ("sleighsim.cli.judge", "is the steady state a start state of one's own reaches chaotic? The workflow's "
              "verdict for it"),
    "finding": ("sleighsim.cli.finding", "the finding in one paragraph from a run's report/finding.yaml (--readme: "
                "into the README)"),
    "verify": ("sleighsim.cli.verify", "check every dataset of a results tree against its recorded checksum (exit 1 on "
               "any)"),
}


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="sleighsim", description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="Run 'sleighsim SUBCOMMAND --help' for a subcommand's options.")
    sub = ap.add_subparsers(dest="command", metavar="SUBCOMMAND", required=True)
    for name, (_, text) in COMMANDS.items():
        sub.add_parser(name, help=text, add_help=False)
    return ap


def main(argv: list[str] | None = None) -> int:
    """Run ``sleighsim SUBCOMMAND [OPTIONS]``; returns the subcommand's exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    name = _parser().parse_args(argv[:1]).command
    module, _ = COMMANDS[name]  # the subcommand parses the rest, its usage naming it
    run = importlib.import_module(module).main
    try:
        return int(run(argv[1:], prog=f"sleighsim {name}") or 0)
    except SystemExit as stop:  # argparse's usage errors and --help inside a subcommand
        return stop.code if isinstance(stop.code, int) else 1
