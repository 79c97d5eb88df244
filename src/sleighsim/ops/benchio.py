"""What the measurement scripts under benchmarks/ share: progress lines, the load average beside each
measurement, and writing a result as plain YAML from a command line with --out and --quick."""

from __future__ import annotations

import argparse
import datetime as dt
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import yaml

from sleighsim.ops import facts


def say(name: str, msg: str) -> None:
    """A progress line on stderr, tagged with the script's name and the time."""
    print(f"[{name} {dt.datetime.now():%H:%M:%S}] {msg}", file=sys.stderr, flush=True)


def loadavg() -> str:
    """/proc/loadavg as text ("unknown" where there is none)."""
    try:
        return Path("/proc/loadavg").read_text().strip()
    except OSError:
        return "unknown"


def header(schema: str, quick: bool, versions: dict, load: dict) -> dict:
    """The head of a measurement's YAML: schema, date, git commit, command, quick, machine facts,
    versions, the cores the process may run on and the load averages taken along the way."""
    try:
        affinity = sorted(os.sched_getaffinity(0))
    except AttributeError:
        affinity = None
    return {"schema": schema, "date": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
            "git_commit": facts.git_commit(), "command": " ".join([Path(sys.executable).name, *sys.argv]),
            "quick": quick, "machine": facts.machine_facts(), "versions": versions, "cpu_affinity": affinity,
            "loadavg": load}


def plain(x):
    """x with numpy scalars as Python numbers and mappings' keys as strings (for yaml.safe_dump)."""
    if isinstance(x, dict):
        return {str(k): plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [plain(v) for v in x]
    if isinstance(x, (np.floating, float)):
        return float(x)
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    return x


def main(name: str, doc: str, run: Callable[[dict], dict], full: dict, quick: dict, default_out: Path,
         quick_help: str) -> int:
    """The command line of a measurement script: run(full or quick options), its total wall time
    added as total_wall_s, written as YAML to --out."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--out", default=str(default_out))
    ap.add_argument("--quick", action="store_true", help=quick_help)
    a = ap.parse_args()
    start = time.perf_counter()
    result = run(quick if a.quick else full)
    result["total_wall_s"] = time.perf_counter() - start
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(yaml.safe_dump(plain(result), sort_keys=False))
    say(name, f"wrote {a.out} in {result['total_wall_s']:.0f} s")
    return 0
