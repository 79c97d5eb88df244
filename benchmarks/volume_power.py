"""The power and false rate of C18's contraction rule on orbits of known mean divergence
(``sleighsim.claims.volume_power``): at c = 0 (measure-preserving on average, the divergence swinging every fast
turn) how often the rule says "contracts" (the false rate) or "expands"; at c = 1, 2 and 4 times the null's median
sigma how often it says "contracts" (the power), each over independent orbits with one-sided 95% Clopper-Pearson
bounds:

    PYTHONPATH=src python benchmarks/volume_power.py [--quick] [--out benchmarks/volume_power.yaml]
"""

from __future__ import annotations

from pathlib import Path

from sleighsim.claims.faithful import K_SIGMA
from sleighsim.claims.volume_power import ORBITS, audit
from sleighsim.ops import benchio

NAME = "volume_power"
REPO = Path(__file__).resolve().parents[1]
FULL = {"orbits": 200, "multiples": [1.0, 2.0, 4.0]}
QUICK = {"orbits": 6, "multiples": [4.0]}


def run(opts: dict) -> dict:
    """The audit at the options' size, with the known orbits' settings and the rule."""
    load = {"start": benchio.loadavg()}
    benchio.say(NAME, f"{opts['orbits']} orbits per rate, rates 0 and {opts['multiples']} x the null's sigma")
    rows = audit(opts["multiples"], opts["orbits"])
    load["end"] = benchio.loadavg()
    return {**benchio.header("sleighsim.volume_power/1", opts is QUICK, {}, load),
            "rule": f"contracts: mean divergence + {K_SIGMA:g} sigma < 0 (sigma: the windows' standard error and the "
                    "quadrature error in quadrature); expands: mean - the same < 0 reversed",
            "orbits": ORBITS, "rates": rows}


if __name__ == "__main__":
    raise SystemExit(benchio.main(NAME, __doc__, run, FULL, QUICK, REPO / "benchmarks" / "volume_power.yaml",
                                  "6 orbits per rate, the null and 4 sigma only"))
