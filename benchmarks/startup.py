#!/usr/bin/env python
"""Per-job start-up of a workflow job, with heyoka's on-disk JIT cache off and on: CPU seconds
(process time, so other load on the machine does not count) for the imports, the SymPy
derivation, compiling the plain flow and the 4-lane tangent batch; median of --repeats fresh
processes per mode (the first "on" process may fill the cache).

    python benchmarks/startup.py [--repeats 3]
"""

import argparse
import json
import statistics
import subprocess
import sys

PROBE = r"""
import json, sys, time
t0 = time.process_time()
import heyoka as hy
hy.llvm_state.set_diskcache_enabled(sys.argv[1] == "on")
from sleighsim.chaos import benettin
from sleighsim.engine import integrators
from sleighsim.model import mechanics
t1 = time.process_time(); mechanics.derive()
t2 = time.process_time(); integrators.flow(False, 2.220446049250313e-16)
t3 = time.process_time(); integrators.sleigh_tangent_batch(4, 2.220446049250313e-16, True, k=4)
t4 = time.process_time()
print(json.dumps(dict(imports=t1 - t0, derive=t2 - t1, flow=t3 - t2, tangent_batch=t4 - t3, total=t4 - t0)))
"""


def main() -> int:
    """Print the median CPU seconds of each start-up stage, JIT cache off and on; exit status 0."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    for mode in ("off", "on"):
        runs = [json.loads(subprocess.run([sys.executable, "-c", PROBE, mode], capture_output=True, text=True,
                                          check=True).stdout) for _ in range(a.repeats)]
        med = {k: statistics.median(r[k] for r in runs) for k in runs[0]}
        print(f"JIT cache {mode:3s}: " + ", ".join(f"{k} {v:.2f} s" for k, v in med.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
