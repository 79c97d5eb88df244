"""Write tests/chaos/judge_power_record.yaml, the record test_judge_power.py compares with, from a
judge_power dataset and the config that built it:

    python tests/chaos/judge_power_record.py RESULTS/data/judge_power.nc config/config.yaml

Counts per horizon factor, judge and class (and per system), summed over realizations."""

import sys
from pathlib import Path

import xarray as xr
import yaml

from sleighsim.chaos import power


def record(ds: xr.Dataset, block: dict) -> dict:
    """The record: the block's settings and the verdict counts of ``ds`` by horizon, judge and class."""
    out = {"spike_period": block["spike_period"], "sleigh": block["sleigh"], "systems": block["systems"],
           "horizons": block["horizons"], "samples": block["samples"], "counts": {}, "by_system": {}}
    for h in ds.horizon.values:
        one = ds.sel(horizon=[h])
        keep = ("N", "correct", "wrong", "undecided")
        out["counts"][float(h)] = {j: {r["class"]: {k: r[k] for k in keep} for r in power.rates(one)
                                       if r["judge"] == j} for j in ds.judge.values.tolist()}
        out["by_system"][float(h)] = {j: {r["system"]: {k: r[k] for k in keep} for r in power.rates(one, by="system")
                                          if r["judge"] == j and r["N"]} for j in ds.judge.values.tolist()}
    out["voting"] = sorted(power.voting(ds))
    return out


if __name__ == "__main__":
    data, config = sys.argv[1:3]
    block = yaml.safe_load(Path(config).read_text())["scenes"]["judge_power"]
    with xr.open_dataset(data) as ds:
        text = yaml.safe_dump(record(ds.load(), block), sort_keys=False, width=120)
    Path(__file__).with_name("judge_power_record.yaml").write_text(
        f"# written by tests/chaos/judge_power_record.py from {Path(data).name} (config {config})\n" + text)
