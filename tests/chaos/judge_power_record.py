"""Write tests/chaos/judge_power_record.yaml, the record test_judge_power.py compares with, from a
judge_power dataset and the config that built it:

    python tests/chaos/judge_power_record.py RESULTS/data/judge_power.nc config/config.yaml

Counts per horizon factor, judge and class (and per system), summed over realizations. Prints the
markdown tables of docs/methods.md ("Judges' power") from the same dataset."""

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


def _cell(r: dict) -> str:
    if not r["N"]:
        return "-"
    return (f"{r['correct']}/{r['N']} = {r['p_correct']:.2f} | {r['wrong']} = {r['p_wrong']:.2f} "
            f"(<= {r['wrong_upper95']:.2f}) | {r['undecided']} = {r['p_undecided']:.2f}")


def table(ds: xr.Dataset, by: str = "orbit_class") -> str:
    """Markdown: per judge and class (or system), correct/N, wrong (95% bound), undecided, over all horizons."""
    key = "class" if by == "orbit_class" else "system"
    lines = [f"| judge | {key} | correct / N | wrong (95% upper bound) | undecided |", "|---|---|---|---|---|"]
    lines += [f"| {r['judge']} | {r[key]} | {_cell(r)} |" for r in power.rates(ds, by=by) if r["N"]]
    return "\n".join(lines)


if __name__ == "__main__":
    data, config = sys.argv[1:3]
    block = yaml.safe_load(Path(config).read_text())["scenes"]["judge_power"]
    with xr.open_dataset(data) as ds:
        ds = ds.load()
    text = yaml.safe_dump(record(ds, block), sort_keys=False, width=120)
    print(table(ds), table(ds, by="system"), sep="\n\n")
    Path(__file__).with_name("judge_power_record.yaml").write_text(
        f"# written by tests/chaos/judge_power_record.py from {Path(data).name} (config {config})\n" + text)
