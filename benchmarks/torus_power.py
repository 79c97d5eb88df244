#!/usr/bin/env python
"""The power and false rates of the torus-stability scene's train test (sleighsim.analysis.torus.classify)
on orbits of known class (sleighsim.analysis.torus_known), at the numbers of cycles the scene's orbits have.

    python benchmarks/torus_power.py [--out benchmarks/torus_power.yaml] [--quick]

Per family and number of events n (the train t_0 .. t_(n-1), n - 1 intervals): N orbits drawn from two
independent seeded streams (numpy default_rng([2052, family index, stream, draw])): "tuning" and "audit".
Each orbit's section data, its events (torus.crossings with the family's column, level and direction; the
first n), and per k = 1 .. max_intervals the ratio R_k / S of the fit's residual to the resolution. The
tuning stream gives the ratios' ranges: on the 2-tori at their own k, on the other orbits the smallest over
k; a factor between them separates the classes on that stream. The audit stream is classified with the
scene's rule at the paper config's factor, min_intervals and max_intervals (read from config/config.yaml):
power = the share of 2-tori given "torus" with their own k; false rate = the share of chaotic orbits given
any torus class; the 3-torus (Henon-Heiles E = 1/12 with the rotor) reported apart. 95% intervals: Wilson.
"""

from __future__ import annotations

import math
import sys
from functools import partial
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

import numpy as np
import yaml

from sleighsim.analysis import torus, torus_known
from sleighsim.ops import benchio

say = partial(benchio.say, "torus_power")
SCHEMA = "sleighsim.torus_power/1"
FULL = {"N": 50, "events": [12, 24]}
QUICK = {"N": 3, "events": [12]}


def rule() -> dict:
    """The paper config's train rule (config/config.yaml, scene torus_stability)."""
    block = yaml.safe_load((REPO / "config" / "config.yaml").read_text())["scenes"]["torus_stability"]
    return {"min_intervals": block["min_intervals"], "factor": block["train_factor"],
            "max_intervals": block["max_intervals"]}


def wilson(k: int, n: int, z: float = 1.96) -> list[float]:
    """Wilson score interval of k successes in n trials."""
    if n == 0:
        return [math.nan, math.nan]
    p = k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return [max(0.0, c - h), min(1.0, c + h)]


def one(name: str, stream: int, draw: int, n: int, r: dict) -> dict:
    """One orbit: its ratios R_k / S (k = 1 .. max_intervals) and its class under the rule r."""
    fam = torus_known.FAMILIES[name]
    rng = np.random.default_rng([2052, list(torus_known.FAMILIES).index(name), stream, draw])
    d = torus_known.section(name, rng, n)
    ev = torus.crossings(d["t"], d["X"], fam.column, fam.level, fam.direction)
    t, e = ev["times"][:n], ev["time_err"][:n]
    S = float(np.sqrt(np.mean(e**2)))
    ratios = [torus.train_fit(t, k)[1] / S if t.size >= 3 * k else math.nan for k in range(1, r["max_intervals"] + 1)]
    c = torus.classify(t, e, **r)
    return {"events": int(t.size), "ratios": ratios, "class": c["torus_class"], "k": c["train_intervals"]}


def family(name: str, n: int, N: int, r: dict) -> dict:
    """Tuning ranges and audit counts of one family at n events."""
    fam = torus_known.FAMILIES[name]
    tune = [one(name, 0, i, n, r) for i in range(N)]
    audit = [one(name, 1, i, n, r) for i in range(N)]
    own = [o["ratios"][fam.k - 1] for o in tune] if fam.torus else [np.nanmin(o["ratios"]) for o in tune]
    right = sum(o["class"] != torus.NOT_SHOWN and (not fam.torus or o["k"] == fam.k) for o in audit)
    say(f"{name}, {n} events: {right} of {N} " + (f"tori with k = {fam.k}" if fam.torus else "called tori"))
    return {"torus": fam.torus, "k": fam.k, "N": N, "short_trains": sum(o["events"] < n for o in audit + tune),
            "tuning_ratio_min": float(np.nanmin(own)), "tuning_ratio_max": float(np.nanmax(own)),
            "audit_classes": {c: sum(o["class"] == c for o in audit) for c in torus.CLASSES},
            "audit_hits": int(right), "audit_hit_interval": wilson(right, N)}


def run(opts: dict) -> dict:
    """Every family at every number of events; the rates pooled over the 2-tori and over the chaotic orbits."""
    load, r = {"start": benchio.loadavg()}, rule()
    out = {"rule": r, "N_per_family": opts["N"], "results": {}}
    for n in opts["events"]:
        fams = {name: family(name, n, opts["N"], r) for name in torus_known.FAMILIES}
        tori = [f for f in fams.values() if f["torus"]]
        chaos = [f for name, f in fams.items() if not f["torus"] and name in torus_known.CHAOTIC]
        hits, N_t = sum(f["audit_hits"] for f in tori), sum(f["N"] for f in tori)
        false, N_c = sum(f["audit_hits"] for f in chaos), sum(f["N"] for f in chaos)
        out["results"][f"{n} events"] = {
            "families": fams, "power": hits / N_t, "power_interval": wilson(hits, N_t), "power_N": N_t,
            "false_rate": false / N_c, "false_rate_interval": wilson(false, N_c), "false_rate_N": N_c,
            "separating_factors": [max(f["tuning_ratio_max"] for f in tori),
                                   min(f["tuning_ratio_min"] for f in fams.values() if not f["torus"])]}
    load["end"] = benchio.loadavg()
    return {**benchio.header(SCHEMA, opts is QUICK, {"numpy": np.__version__}, load), **out}


def main() -> int:
    """The command line (--out, --quick); exit status 0."""
    return benchio.main("torus_power", __doc__, run, FULL, QUICK, REPO / "benchmarks" / "torus_power.yaml",
                        "3 orbits per family, 12 events (a test run; not a measurement)")


if __name__ == "__main__":
    raise SystemExit(main())
