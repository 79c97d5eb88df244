"""Write the record of a chaos verdict measured with another config (benchmarks/cluster_verdict.yaml, which the
report cites on its first screen when it exists; the default run decides its own states, so the repository
keeps none):

    python -m sleighsim.ops.verdictrecord DECISIVE.nc --config config/cluster.yaml [--out ...]

From the decisive-stage job's dataset (every realization of every state a lane, ``scenes.verdict_lanes``): per
lane the verdict, each decisive indicator's verdict, value and uncertainty, the Birkhoff digits and frequency
spreads per window split, G x rounding, the spike intervals, the energy drift, the wall time and the commit that
made it (refused when that commit is not a full clean one: a record anyone can check)."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import yaml

from sleighsim.io.netcdf import full_clean_commit, read_dataset
from sleighsim.ops.config import REPO
from sleighsim.scenes.verdict_lanes import unpack


def _floats(x) -> list[float]:
    return [float(v) for v in np.asarray(x, float)]


def lane(r: int, d, job) -> dict:
    """One lane (realization ``r``, its one-state dataset ``d``) of the decisive job's dataset ``job``."""
    names = [str(k) for k in d.decisive_indicator.values]
    return {"realization": r, "state": str(d.state.values[0]),
            "verdict": str(d.decisive_verdict.values[0]), "reason": str(d.decisive_reason.values[0]),
            "indicators": {k: {"verdict": str(v), "value": float(x), "uncertainty": float(e)} for k, v, x, e in
                           zip(names, d.decisive_indicator_verdict.values[0], d.decisive_indicator_value.values[0],
                               d.decisive_indicator_uncertainty.values[0])},
            "voters": list(d.attrs["decisive_voters"]), "vote_horizon": float(d.attrs["decisive_vote_horizon"]),
            "splits": [int(k) for k in d.decisive_split.values],
            "birkhoff_digits": _floats(d.decisive_birkhoff_digits.values[0]),
            "frequency_D": _floats(d.decisive_frequency_D.values[0]),
            "megno_Y_final": float(d.decisive_megno_Y_mean.values[0][-1]),
            "log10_gain_rounding": float(d.decisive_log10_gain_rounding.values[0]),
            "spike_intervals": _floats(d.decisive_spike_interval.values[0]),
            "energy_max_rel_drift": float(d.decisive_energy_max_rel_drift.values[0]),
            "wall_time_s": float(d.decisive_wall_time_s.values[0]),
            "precision": str(d.attrs["decisive_precision"]), "T": float(d.attrs["decisive_T"]),
            "git_commit": str(job.attrs.get("git_commit", "?")), "created_utc": str(job.attrs.get("created_utc", "?"))}


def record(job, config: str) -> dict:
    """The record of the decisive job's dataset ``job`` run with ``config``; ValueError when its commit is
    not a full clean one."""
    commit = str(job.attrs.get("git_commit", ""))
    if not full_clean_commit(commit):
        raise ValueError(f"made at commit {commit!r}, not a full clean commit: a record nobody could check")
    return {"config": config, "realizations": [lane(r, d, job) for r, d in unpack(job)]}


def main(argv=None) -> int:
    """Write the record from the chunk datasets given."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("job", help="the decisive-stage job's dataset (the chaos verdict's last chunk)")
    parser.add_argument("--config", required=True, help="the config overlay the run used")
    parser.add_argument("--out", default=str(REPO / "benchmarks" / "cluster_verdict.yaml"))
    args = parser.parse_args(argv)
    Path(args.out).write_text(yaml.safe_dump(record(read_dataset(args.job), args.config), sort_keys=False))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
