"""Write the record of a chaos verdict measured with another config (benchmarks/cluster_verdict.yaml: config/
cluster.yaml's decisive stage, which the default run cannot afford), which the report cites on its first
screen:

    python -m sleighsim.ops.verdictrecord CHUNK.nc [CHUNK.nc ...] --config config/cluster.yaml [--out ...]

From the decisive-stage chunk datasets of one state (one per realization): per realization the verdict, each
decisive indicator's verdict, G x rounding, the median spike interval, the energy drift, the wall time and
the commit that made it."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import yaml

from sleighsim.io.netcdf import read_dataset
from sleighsim.ops.config import REPO


def realization(path) -> dict:
    """One realization's decisive stage, from its chunk dataset."""
    d = read_dataset(path)
    return {"realization": int(d.attrs["chunk"]), "state": str(d.state.values[0]),
            "verdict": str(d.decisive_verdict.values[0]), "reason": str(d.decisive_reason.values[0]),
            "indicators": {str(k): str(v) for k, v in zip(d.decisive_indicator.values,
                                                          d.decisive_indicator_verdict.values[0])},
            "log10_gain_rounding": round(float(d.decisive_log10_gain_rounding.values[0]), 2),
            "spike_period": float(np.nanmedian(d.decisive_spike_interval.values[0])),
            "energy_max_rel_drift": float(d.decisive_energy_max_rel_drift.values[0]),
            "wall_time_s": round(float(d.decisive_wall_time_s.values[0]), 1),
            "precision": str(d.attrs["decisive_precision"]), "T": float(d.attrs["decisive_T"]),
            "git_commit": str(d.attrs.get("git_commit", "?")), "created_utc": str(d.attrs.get("created_utc", "?"))}


def main(argv=None) -> int:
    """Write the record from the chunk datasets given."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("chunks", nargs="+", help="decisive-stage chunk datasets, one per realization")
    parser.add_argument("--config", required=True, help="the config overlay the run used")
    parser.add_argument("--out", default=str(REPO / "benchmarks" / "cluster_verdict.yaml"))
    args = parser.parse_args(argv)
    rows = sorted((realization(p) for p in args.chunks), key=lambda r: r["realization"])
    Path(args.out).write_text(yaml.safe_dump({"config": args.config, "realizations": rows}, sort_keys=False))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
