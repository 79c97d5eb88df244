"""The finding in one paragraph, from the facts a run's report wrote (``<results>/report/finding.yaml``,
:mod:`sleighsim.report.finding`): printed, kept as the repository's record and written into the README.

    sleighsim finding results/report/finding.yaml
    sleighsim finding results/report/finding.yaml --record docs/finding.yaml --readme README.md

The README cites only a run at the paper's fidelity: ``--record`` and ``--readme`` refuse the facts of any
other (the smoke run's). A test checks the README's paragraph against ``docs/finding.yaml``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import yaml

from sleighsim.io.netcdf import write_text
from sleighsim.ops.helptext import summary
from sleighsim.ops.readme import replaced
from sleighsim.report.finding import SCHEMA, paragraph

#: The README's block the paragraph fills (sleighsim.ops.readme).
BLOCK = "finding"


def _parser(prog: str) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog=prog, description=summary(__doc__))
    p.add_argument("facts", help="a run's report/finding.yaml (or a kept record such as docs/finding.yaml)")
    p.add_argument("--record", metavar="FILE", help="also keep the facts in FILE (the README's source: "
                   "docs/finding.yaml)")
    p.add_argument("--readme", metavar="FILE", help=f"also write the paragraph into FILE's '{BLOCK}' block")
    return p


def main(argv=None, prog: str = "sleighsim finding") -> int:
    """Print the paragraph; with --record or --readme also keep it. Exit 0; 2 when the facts are refused
    (not a finding's facts, or a run not at the paper's fidelity for --record/--readme) or FILE has no block."""
    args = _parser(prog).parse_args(argv)
    text = Path(args.facts).read_text()
    facts = yaml.safe_load(text)
    why = (f"{args.facts} holds no finding's facts ({SCHEMA})" if not isinstance(facts, dict)
           or facts.get("schema") != SCHEMA else
           f"{args.facts} is a {facts['config_label']} run's, not a reproduction: the README cites only a run at "
           "the paper's fidelity" if (args.record or args.readme) and not facts["reproduction"] else "")
    if not why and args.readme:
        try:
            new = replaced(Path(args.readme).read_text(), BLOCK, paragraph(facts) + "\n")
        except ValueError as err:
            why = f"{args.readme}: {err}"
    if why:
        print(f"{prog}: {why}", file=sys.stderr)
        return 2
    if args.record:
        write_text(args.record, text)
    if args.readme:
        write_text(args.readme, new)
    print(paragraph(facts))
    return 0
