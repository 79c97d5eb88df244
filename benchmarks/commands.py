#!/usr/bin/env python
"""Time the documented commands a user waits on besides the workflow: the executed tutorial and one
``sleighsim judge`` (the README's example), each in a fresh process from the repository's root, its wall time,
exit status and the last lines it printed recorded with the machine and the load average before and after.

    python benchmarks/commands.py [--out benchmarks/commands.yaml] [--quick]

``--quick`` times the tutorial only. The README's times table reads the record (``sleighsim costs times``).
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from sleighsim.ops import benchio  # noqa: E402

NAME = "commands"
#: The last lines each command printed on stdout, kept in the record (the judge's verdict, the tutorial's end).
TAIL = 12
#: (what, command as the docs give it): each run from the repository's root.
TUTORIAL = ("the executed tutorial (paper fidelity)", "python docs/tutorial.py")
JUDGE = ("one state judged, the README's example", "sleighsim judge --params eps=0.05 b=1 K2=1.05 --state 0 0.1 1 0 "
         "--out {tmp}/verdict.nc")


def timed(what: str, command: str, tmp: str) -> dict:
    """One command's wall time (s) and exit status, with the load averages around it."""
    line = command.format(tmp=tmp)
    argv = shlex.split(line)
    argv[0] = sys.executable if argv[0] == "python" else str(Path(sys.executable).parent / argv[0])
    env = {**os.environ, "SLEIGHSIM_TUTORIAL_OUT": str(Path(tmp) / "tutorial")}
    before = benchio.loadavg()
    benchio.say(NAME, f"{what}: {line}")
    start = time.perf_counter()
    done = subprocess.run(argv, cwd=REPO, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    benchio.say(NAME, f"{what}: exit {done.returncode} after {wall:.0f} s")
    return {"what": what, "command": command.replace(" --out {tmp}/verdict.nc", " --out results/judge/verdict.nc"),
            "wall_s": wall, "returncode": done.returncode, "loadavg_before": before, "loadavg_after": benchio.loadavg(),
            "printed_tail": done.stdout.splitlines()[-TAIL:]}


def run(opts: dict) -> dict:
    """Every command of ``opts["commands"]`` in turn, in a scratch directory for their outputs."""
    with tempfile.TemporaryDirectory(prefix="sleighsim-commands-") as tmp:
        runs = [timed(what, command, tmp) for what, command in opts["commands"]]
    out = benchio.header("sleighsim.commands/1", opts["quick"], {}, {"end": benchio.loadavg()})
    return {**out, "runs": runs}


if __name__ == "__main__":
    raise SystemExit(benchio.main(NAME, __doc__, run, {"commands": [TUTORIAL, JUDGE], "quick": False},
                                  {"commands": [TUTORIAL], "quick": True}, REPO / "benchmarks" / "commands.yaml",
                                  "time the tutorial only"))
