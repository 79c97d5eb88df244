"""Write the judge-power record the chaos verdict votes by (benchmarks/judge_power.yaml) from the judge-power
audit's dataset (``snakemake results/data/judge_power.nc``, from a clean commit):

    python -m sleighsim.ops.powerrecord RESULTS/data/judge_power.nc [--out benchmarks/judge_power.yaml]

The record (schema ``chaos.power.SCHEMA``) holds the audited stage, spike period, settings at factor 1,
each horizon's own settings, each judge's estimator text, and per horizon factor: each judge's counts
per class (N, correct, wrong, undecided) and per system, the voters (on the bound), the decision rule's
counts per class and per system, and every realization's numbers (one line per realization and horizon:
the gated verdict, the numbers it rests on, the gauge's answer, the confirmation and gauge). Its source
names the dataset's full commit; a dataset from a dirty tree is refused. ``chaos.power.stage_vote``
reads the vote from the record. Prints the table per judge and class (markdown)."""

from __future__ import annotations

import argparse
import functools
import json
from pathlib import Path

import numpy as np
import yaml

from sleighsim.chaos import power
from sleighsim.io.netcdf import read_dataset
from sleighsim.io.yamlfile import read_yaml
from sleighsim.ops.config import REPO
from sleighsim.ops.helptext import summary

COMMAND = "python -m sleighsim.ops.powerrecord"


def _keep(row: dict) -> dict:
    return {k: int(row[k]) for k in power.KEEP}


def _per_system(c, classes: dict) -> dict:
    """{system: counts} of a (orbit_class, system, verdict) count array, each on its system's class."""
    verdicts = c.verdict.values.tolist()
    return {s: _keep(power.row(dict(zip(verdicts, c.sel(system=s, orbit_class=cls).values.tolist())), cls))
            for s, cls in classes.items()}


def _per_class(c) -> dict:
    """{class: counts} of a (orbit_class, system, verdict) count array summed over the systems."""
    verdicts = c.verdict.values.tolist()
    return {cls: _keep(power.row(dict(zip(verdicts, c.sel(orbit_class=cls).sum("system").values.tolist())), cls))
            for cls in power.CLASSES}


def _runs(ds, h: float) -> list[dict]:
    """Per realization at horizon h: system, index, the gated verdict and numbers of each judge, the gauge's
    answer, the confirmation and gauge (JSON objects as mappings)."""
    by = {}
    for i in np.flatnonzero(ds.run_horizon.values == h):
        key = (str(ds.run_system.values[i]), int(ds.run_index.values[i]))
        row = by.setdefault(key, {"system": key[0], "index": key[1], **json.loads(str(ds.run_context.values[i])),
                                  "judges": {}})
        row["judges"][str(ds.run_judge.values[i])] = {
            "verdict": str(ds.run_verdict.values[i]), "raw": str(ds.run_raw.values[i]),
            "follows": str(ds.run_follows.values[i]), **json.loads(str(ds.run_numbers.values[i]))}
    return [by[k] for k in sorted(by)]


def record(ds) -> dict:
    """The record of one audit dataset (module docstring)."""
    commit = str(ds.attrs.get("git_commit", "?"))
    if commit.endswith("-dirty") or len(commit) != 40:
        raise ValueError(f"the dataset comes from commit {commit!r}: a record needs a full clean commit")
    settings = json.loads(ds.attrs["settings"])
    horizons = {float(e["factor"]): {"megno_samples": int(e["megno_samples"])} for e in settings.pop("horizons")}
    out = {"schema": power.SCHEMA, "stage": "decisive", "stream": int(ds.attrs["stream"]),
           "spike_period": float(ds.attrs["spike_period"]), "settings": settings, "horizons": horizons,
           "estimators": json.loads(ds.attrs["estimators"]), "vote_rule": power.VOTE_RULE,
           "sequence": str(ds.attrs["sequence"]), "counts": {}, "by_system": {}, "voting": {}, "rule": {},
           "rule_by_system": {}, "runs": {}}
    classes = {str(k): str(v) for k, v in zip(ds.system.values, ds.system_class.values)}
    for h in (float(v) for v in ds.horizon.values):
        c = ds.counts.sel(horizon=h)
        out["counts"][h] = {str(j): _per_class(c.sel(judge=j)) for j in ds.judge.values}
        out["by_system"][h] = {str(j): _per_system(c.sel(judge=j), classes) for j in ds.judge.values}
        out["voting"][h] = sorted(power.voting(ds.sel(horizon=[h])))
        out["rule"][h] = _per_class(ds.rule_counts.sel(horizon=h))
        out["rule_by_system"][h] = _per_system(ds.rule_counts.sel(horizon=h), classes)
        out["runs"][h] = _runs(ds, h)
    out["cost"] = _cost(ds)
    out["sources"] = [{"git_commit": commit, "created_utc": str(ds.attrs.get("created_utc", "?")),
                       "command": COMMAND, "cost_total_s": float(ds.attrs["cost_total_s"])}]
    return out


def _cost(ds) -> dict:
    """Mean wall seconds per realization (every horizon) per system, and the total."""
    out = {}
    for s in ds.system.values:
        w = ds.run_wall_s.values[ds.run_system.values == s]
        n = len({int(i) for i in ds.run_index.values[ds.run_system.values == s]})
        out[str(s)] = round(float(np.sum(w)) / max(n, 1), 2)
    return {"per_realization_s": out, "total_s": round(float(ds.attrs["cost_total_s"]), 1)}


def markdown(rec: dict) -> str:
    """The record's table: per audited horizon factor, judge (and the rule) and class, N and the counts and
    shares of correct, wrong (with the 95% upper bound) and undecided verdicts, and whether it votes."""
    lines = ["| horizon | judge | orbits | N | correct (95% lower) | wrong (95% upper) | undecided | votes |",
             "|---|---|---|---|---|---|---|---|"]
    for h in sorted(float(k) for k in rec["counts"]):
        votes = power.record_voting(rec, h)
        rows = power.record_rates(rec, h)
        rows += [{"judge": "rule", "class": c, **power.from_counts(v)} for c, v in rec["rule"][h].items()]
        lines += [_row(h, r, votes) for r in rows]
    return "\n".join(lines)


def _row(h: float, r: dict, votes: set) -> str:
    vote = "-" if r["judge"] == "rule" else "yes" if r["judge"] in votes else "no"
    return (f"| x{h:g} | {r['judge']} | {r['class']} | {r['N']} | {r['correct']} ({r['p_correct']:.2f}, >= "
            f"{r['correct_lower95']:.3f}) | {r['wrong']} ({r['p_wrong']:.3f}, <= {r['wrong_upper95']:.3f}) | "
            f"{r['undecided']} ({r['p_undecided']:.2f}) | {vote} |")


def empty() -> dict:
    """A record of no audit: nothing is counted, so every judge votes by nothing."""
    return {"schema": power.SCHEMA, "stage": "decisive", "note": "no audit recorded: every judge votes by nothing",
            "horizons": {}, "counts": {}, "rule": {}, "sources": []}


def problems(path) -> list[str]:
    """What makes the record at ``path`` unusable for a vote (``chaos.power.check_record``), or that it is
    missing or not YAML; empty when it can be voted by. Judged once per version of the file (its resolved
    path, modification time and size): a config check asks about the same record for several scenes."""
    path = Path(path)
    if not path.is_file():
        return [f"no such file in the repository (write it with {COMMAND})"]
    stat = path.stat()
    return list(_file_problems(path.resolve(), stat.st_mtime_ns, stat.st_size))


@functools.lru_cache(maxsize=8)
def _file_problems(path: Path, mtime_ns: int, size: int) -> tuple[str, ...]:
    """``problems`` of one version of a file (the time and size are the cache's key only)."""
    try:
        rec = read_yaml(path)
    except yaml.YAMLError as err:
        return (f"not YAML: {err}",)
    return tuple(power.check_record(rec))


def main(argv=None) -> int:
    """Write the record from the dataset given; print its table."""
    parser = argparse.ArgumentParser(prog=COMMAND, description=summary(__doc__))
    parser.add_argument("dataset", nargs="?", help="the judge_power dataset")
    parser.add_argument("--empty", action="store_true", help="a record of no audit (every judge votes by nothing)")
    parser.add_argument("--out", default=str(REPO / "benchmarks" / "judge_power.yaml"))
    args = parser.parse_args(argv)
    if args.empty == bool(args.dataset):
        parser.error("give either a dataset or --empty")
    rec = empty() if args.empty else record(read_dataset(args.dataset))
    Path(args.out).write_text(yaml.safe_dump(rec, sort_keys=False, width=160))
    print(markdown(rec))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
