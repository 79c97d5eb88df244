"""Thresholds chosen on one sample, reported on a held-out one: the weighted Birkhoff averages' digits
(birkhoff.DIG_MIN) and MEGNO's y_regular_max (megno.judge_megno, both MEGNO judges of the decisive stage),
from the judge-power audit's numbers:

    PYTHONPATH=src python benchmarks/thresholds.py TUNE.nc [--held-out RECORD.yaml] [--out benchmarks/thresholds.yaml]

TUNE.nc: the audit dataset of the tuning sample (stream 1, ``--configfile benchmarks/judge_power_tune.yaml``);
RECORD.yaml: the judge-power record of the held-out sample (stream 0, benchmarks/judge_power.yaml).

Rules (per horizon factor): DIG_MIN is the smallest multiple of STEP_DIG at least MARGIN_DIG digits above
every chaotic realization's digits at the longest window in the tuning sample; y_regular_max is the largest
multiple of STEP_Y at most MARGIN_Y below every chaotic realization's <Y> + sigma resid (the quantity MEGNO's
regular verdict compares) among those whose <Y> did not grow over the horizon, and never above 2.5 (a
torus with shear tends to 2). The judges keep their thresholds where those are at least as strict as the
chosen ones. On the held-out sample: the largest chaotic value, the margin to the threshold the judges use
(negative: it would have been crossed) and the share of tori that reach it."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import yaml

from sleighsim.ops import benchio

STEP_DIG, MARGIN_DIG = 0.5, 1.0
STEP_Y, MARGIN_Y, Y_CAP = 0.1, 0.2, 2.5
SIGMA = 3.0
MEGNO_JUDGES = ("megno_log_norm", "section_megno")


def _tune_rows(path) -> tuple[list[dict], str]:
    """(system class, horizon, judge, numbers) of every run of a tuning dataset, and its commit."""
    from sleighsim.chaos.known_orbits import SYSTEMS
    from sleighsim.io.netcdf import read_dataset

    ds = read_dataset(path)
    return [{"class": SYSTEMS[str(s)].cls, "horizon": float(h), "judge": str(j), **json.loads(str(n))}
            for s, h, j, n in zip(ds.run_system.values, ds.run_horizon.values, ds.run_judge.values,
                                  ds.run_numbers.values)], str(ds.attrs.get("git_commit", "?"))


def _held_rows(rec: dict) -> list[dict]:
    from sleighsim.chaos.known_orbits import SYSTEMS

    return [{"class": SYSTEMS[r["system"]].cls, "horizon": float(h), "judge": j, **nums}
            for h, runs in rec["runs"].items() for r in runs for j, nums in r["judges"].items()]


def _digits(rows, cls, h) -> np.ndarray:
    return np.array([r["value"] for r in rows if r["judge"] == "birkhoff" and r["class"] == cls
                     and r["horizon"] == h and r["value"] is not None], float)


def _y_upper(rows, cls, h, judge) -> np.ndarray:
    """<Y> + sigma resid of the runs whose <Y> did not grow over the horizon ((slope + sigma err) T < 0.5)."""
    out = []
    for r in rows:
        if r["judge"] != judge or r["class"] != cls or r["horizon"] != h or r.get("Y_mean") is None:
            continue
        span = r["T"] if judge == "megno_log_norm" else r["returns"]
        if r["slope"] is not None and r["slope_err"] is not None and (r["slope"] + SIGMA * r["slope_err"]) * span < 0.5:
            out.append(r["Y_mean"] + SIGMA * r["Y_resid"])
    return np.array(out, float)


def choose(rows) -> dict:
    """The thresholds per horizon from the tuning rows."""
    out = {}
    for h in sorted({r["horizon"] for r in rows}):
        chaos = _digits(rows, "chaotic", h)
        top = float(chaos.max()) if chaos.size else math.nan
        entry = {"dig_min": STEP_DIG * math.ceil((top + MARGIN_DIG) / STEP_DIG), "chaotic_digits_max": top,
                 "chaotic_n": int(chaos.size)}
        for judge in MEGNO_JUDGES:
            low = _y_upper(rows, "chaotic", h, judge)
            floor = float(low.min()) if low.size else math.inf
            y = Y_CAP if math.isinf(floor) else min(Y_CAP, STEP_Y * math.floor((floor - MARGIN_Y) / STEP_Y))
            entry[judge] = {"y_regular_max": y,
                            "chaotic_without_growth": int(low.size), "chaotic_y_upper_min": floor}
        out[h] = entry
    return out


def in_code() -> dict:
    """The thresholds the judges use (birkhoff.DIG_MIN; judge_megno's y_regular_max default)."""
    import inspect

    from sleighsim.chaos.birkhoff import DIG_MIN
    from sleighsim.chaos.megno import judge_megno

    y = float(inspect.signature(judge_megno).parameters["y_regular_max"].default)
    return {"dig_min": DIG_MIN, **{j: {"y_regular_max": y} for j in MEGNO_JUDGES}}


def held_out(chosen: dict, rows) -> dict:
    """The held-out sample's largest chaotic values, and for the thresholds the judges use (``in_code``,
    which must be at least as strict as the chosen ones) the margins and the tori's share reaching them."""
    out, code = {}, in_code()
    for h, c in chosen.items():
        chaos, tori = _digits(rows, "chaotic", h), _digits(rows, "tori", h)
        entry = {"chaotic_digits_max": float(chaos.max()) if chaos.size else math.nan,
                 "dig_min_used": code["dig_min"], "at_least_as_strict": code["dig_min"] >= c["dig_min"],
                 "dig_margin": code["dig_min"] - float(chaos.max()) if chaos.size else math.nan,
                 "tori_reaching_dig_min": float(np.mean(tori >= code["dig_min"])) if tori.size else math.nan}
        for judge in MEGNO_JUDGES:
            low = _y_upper(rows, "chaotic", h, judge)
            yt = _y_upper(rows, "tori", h, judge)
            y = code[judge]["y_regular_max"]
            entry[judge] = {"y_regular_max_used": y, "at_least_as_strict": y <= c[judge]["y_regular_max"],
                            "chaotic_y_upper_min": float(low.min()) if low.size else math.inf,
                            "y_margin": float(low.min()) - y if low.size else math.inf,
                            "tori_below": float(np.mean(yt < y)) if yt.size else math.nan}
        out[h] = entry
    return out


def main(argv=None) -> int:
    """Choose on the tuning dataset, report on the held-out record; write the YAML."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tune")
    ap.add_argument("--held-out", default=None)
    ap.add_argument("--out", default=str(Path(__file__).with_name("thresholds.yaml")))
    a = ap.parse_args(argv)
    rows, commit = _tune_rows(a.tune)
    chosen = choose(rows)
    result = {**benchio.header("sleighsim.thresholds/1", False, {}, {"start": benchio.loadavg()}),
              "tuning_dataset_commit": commit, "rules": __doc__.split("\n\n")[3].replace("\n", " "),
              "chosen": chosen}
    if a.held_out:
        rec = yaml.safe_load(Path(a.held_out).read_text())
        result["held_out_record_commit"] = rec["sources"][0]["git_commit"]
        result["held_out"] = held_out(chosen, _held_rows(rec))
    Path(a.out).write_text(yaml.safe_dump(benchio.plain(result), sort_keys=False))
    print(yaml.safe_dump(benchio.plain({k: result[k] for k in ("chosen", "held_out") if k in result})))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
