"""Times a user can plan by: the README's table, generated from the committed benchmark records (a
full run at paper fidelity and a smoke run, each measured by ``benchmarks/full_run.py``; the cluster
config's estimate, written by ``sleighsim costs estimate --out``; the tutorial and a judged state, timed by
``benchmarks/commands.py``). Every number names the record it
comes from, its date and commit; a record that is absent gives no row.

    sleighsim costs times                     print the table
    sleighsim costs times --readme README.md  write it into the README's block (a test checks it is in step)
"""

from __future__ import annotations

from pathlib import Path

import yaml

from sleighsim.ops.config import REPO
from sleighsim.ops.walltime import duration

#: The records the table reads, below the repository.
FULL_RUN, SMOKE_RUN = "benchmarks/full_run.yaml", "benchmarks/smoke_run.yaml"
COMMANDS = "benchmarks/commands.yaml"
CLUSTER = "benchmarks/cluster_estimate.yaml"
#: The README's block the table fills (sleighsim.ops.readme).
BLOCK = "times"


def _read(root: Path, rel: str) -> dict | None:
    path = root / rel
    return yaml.safe_load(path.read_text()) if path.is_file() else None


def _source(record: dict, rel: str) -> str:
    """Where a number comes from: the record, its date, commit and machine."""
    machine, load = record.get("machine") or {}, (record.get("run") or {}).get("load_average")
    where = f", {machine['nproc']} cores {machine['cpu_model']}" if machine.get("cpu_model") else ""
    where += f" ({machine['vector']})" if where and machine.get("vector", "unknown") != "unknown" else ""
    where += f" (load average {load[0]:.1f} at the start: a shared machine)" if load else ""
    return f"`{rel}`, {str(record.get('date'))[:10]}, commit {str(record.get('git_commit'))[:8]}{where}"


def _measured_rows(record: dict, rel: str, what: str, command: str) -> list[tuple[str, str, str, str]]:
    """The measured run, and its jobs list-scheduled on more cores."""
    cores = record["run"]["cores"]
    rows = [(f"{what}, {cores} cores (measured)", f"`{command}`",
             f"{duration(record['wall_s'])} ({record['jobs_total']} jobs, {record['cpu_s'] / 3600:.2g} core-h)",
             _source(record, rel))]
    predicted = {int(c): s for c, s in ((record.get("critical_path") or {}).get("predicted_wall_s") or {}).items()
                 if int(c) > cores}
    if predicted:
        rows.append((f"{what} on {' / '.join(map(str, predicted))} cores (predicted)", "`-c<cores>`",
                     " / ".join(duration(s) for s in predicted.values()),
                     f"its measured jobs list-scheduled, no start-up or queue wait (`{rel}`)"))
    return rows


def _cluster_row(record: dict, rel: str) -> tuple[str, str, str, str]:
    """The cluster config's estimated wall per core count and its longest job."""
    sched = record["schedule"]
    cores = " / ".join(map(str, sched["wall_s"]))
    missing = f"; {len(sched['unestimated'])} of its {sched['jobs']} jobs unmeasured (counted 0 s)" if (
        sched["unestimated"]) else ""
    return (f"cluster config on {cores} cores (estimate)",
            "`snakemake --profile profiles/slurm --configfile config/cluster.yaml`",
            " / ".join(duration(s) for s in sched["wall_s"].values())
            + f"; longest job {duration(sched['longest']['wall_s'])} ({record['total_cpu_s'] / 3600:.2g} core-h)",
            f"{_source(record, rel)}, scaled from `{record['measured']['file']}` of "
            f"{str(record['measured']['date'])[:10]}{missing}")


def _command_rows(record: dict, rel: str) -> list[tuple[str, str, str, str]]:
    """Each timed command of benchmarks/commands.py that ended well, one process on one core."""
    return [(f"{r['what']}, one process (measured)", f"`{r['command']}`", duration(r["wall_s"]), _source(record, rel))
            for r in record["runs"] if r["returncode"] == 0]


def rows(root: Path = REPO) -> list[tuple[str, str, str, str]]:
    """(what, command, wall time, source) for every record present."""
    out = []
    if full := _read(root, FULL_RUN):
        out += _measured_rows(full, FULL_RUN, "full run at paper fidelity", "snakemake -c2")
    if smoke := _read(root, SMOKE_RUN):
        out += _measured_rows(smoke, SMOKE_RUN, "smoke run (tiny; not a reproduction)",
                              "snakemake -c2 --configfile config/smoke.yaml")[:1]
    if commands := _read(root, COMMANDS):
        out += _command_rows(commands, COMMANDS)
    if cluster := _read(root, CLUSTER):
        out.append(_cluster_row(cluster, CLUSTER))
    return out


def table(root: Path = REPO) -> str:
    """The Markdown table of :func:`rows`."""
    lines = ["| what | command | wall time | from |", "|---|---|---|---|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows(root)]
    return "\n".join(lines) + "\n"
