#!/usr/bin/env python
"""What the double-double Taylor engine (sleighsim.engine.ddtaylor) costs and buys: one spike cycle of the
paper's main steady state in double-double beside heyoka's double, long double and real128, speed against error.

    taskset -c 1 nice -n 5 python benchmarks/doubledouble.py [--out benchmarks/doubledouble.yaml] [--quick]

Setup: eps 0.1, b 1, K2 1.1; y0 = (0, 0.1, 1, 0) scaled to the energy label 0.1127
(symmetries.state_at_label); the transient (2e4 time units) in double at its machine epsilon
(integrators.flow); the end state, a double, is the start of every run (exact in every arithmetic). The spike
cycle's length is measured on the settled orbit (double, 12000 time units sampled every 0.5: transient.spike_times
with the project's settings, mean interval), and the faithfulness gauge (chaos.faithfulness.spike_cycle_gains, the
4 x 4 tangent map in double, tau 5) gives ln G max over the cycles of that stretch.

Rows: (engine, arithmetic, tol): heyoka double (2^-52), long double (2^-63), real128 (2^-112, 1e-33 .. 1e-30),
double-double (1e-20, 1e-24, 1e-28, 1e-32, 1e-34). Each propagates one spike cycle T from the settled state,
sampled at 9 times; cost = median CPU seconds (process time) per time unit over the repeats (5; 3 for real128),
after one untimed warm-up (over T; 100 time units for real128); steps per time unit. Error = ddtaylor.separation
(max |difference| over u, Omega, omega, delta mod 2 pi, over max |(u, Omega, omega)|) from the reference,
real128 at tol 2^-112, at each sample time; the reference's own error is bounded by its separation from real128
at 1e-33 and from double-double at 1e-34. Energy drift of the double-double rows over the cycle at 200 bits.
Error replicas: for dd (1e-32, 1e-34) and real128 (1e-32, 1e-31) the error after one cycle again from 3 start
states a third of a cycle apart along the settled orbit (the first the settled state), each against its own
real128 reference: the spread of the error over independent stretches of the orbit.

Compile time of double-double: in a child process with NUMBA_CACHE_DIR an empty directory (numba compiles) and
again with that directory filled (numba loads): the first propagation's extra CPU seconds over a second one, and
the construction of DDFlow (the program from the SymPy derivation, the coefficients as exact fractions).
"""

from __future__ import annotations

import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from functools import partial
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

import heyoka as hy
import numba
import numpy as np

from sleighsim.chaos import faithfulness
from sleighsim.engine import ddarith, ddtaylor, integrators, transient
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_LABEL, REFERENCE_STATE, state_at_label
from sleighsim.ops import benchio
from sleighsim.precision import Precision

say = partial(benchio.say, "doubledouble")

SCHEMA = "sleighsim.doubledouble/1"
PARAMS = {"eps": 0.1, "b": 1.0, "K2": 1.1}
SPIKES = {"factor": 1.8, "block": 50.0, "min_separation": 300.0}  # transient.spike_times, as configured
SAMPLES = 9
REFERENCE = ("heyoka", "quad", 2.0**-112)
ROWS = (("heyoka", "double", 2.0**-52), ("heyoka", "long double", 2.0**-63), REFERENCE,
        ("heyoka", "quad", 1e-33), ("heyoka", "quad", 1e-32), ("heyoka", "quad", 1e-31), ("heyoka", "quad", 1e-30),
        ("dd", "double-double", 1e-20), ("dd", "double-double", 1e-24), ("dd", "double-double", 1e-28),
        ("dd", "double-double", 1e-32), ("dd", "double-double", 1e-34))
#: Rows whose error after one cycle is also measured from other start states along the settled orbit.
REPLICA_ROWS = (("dd", "double-double", 1e-32), ("dd", "double-double", 1e-34), ("heyoka", "quad", 1e-32),
                ("heyoka", "quad", 1e-31))
FULL = {"t_transient": 2e4, "t_gauge": 12000.0, "cycle": None, "repeats": 5, "repeats_quad": 3, "warmup_quad": 100.0,
        "rows": ROWS, "replicas": 3}
QUICK = {"t_transient": 2e4, "t_gauge": 3000.0, "cycle": 50.0, "repeats": 1, "repeats_quad": 1, "warmup_quad": 5.0,
         "rows": ROWS[:3] + ROWS[10:11], "replicas": 2}


def settled(params, y0, T):
    """The double state after T time units from y0 (integrators.flow in double at its epsilon)."""
    ta = integrators.flow(False, Precision.DOUBLE.epsilon)[0]
    integrators.set_pars(ta, params)
    ta.time = 0.0
    integrators.load(ta, y0)
    res = ta.propagate_until(float(T), callback=integrators.bounded(ta))
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"transient stopped: {res[0]}")
    return integrators.read(ta, 4).astype(float)


def cycle_and_gauge(params, s, T):
    """The mean spike interval on the orbit from s over T (double, sampled every 0.5) and the gauge's result."""
    ta = integrators.flow(False, Precision.DOUBLE.epsilon)[0]
    integrators.set_pars(ta, params)
    ta.time = 0.0
    integrators.load(ta, s)
    grid = 0.5 * np.arange(round(T / 0.5) + 1)
    Y = integrators.samples(ta, ta.propagate_grid(grid, callback=integrators.bounded(ta))[5])
    spikes = transient.spike_times(grid, Y[:, 1], **SPIKES)
    interval, spread = transient.interval_stats(spikes)
    tg, _ = integrators.sleigh_tangent(4, Precision.DOUBLE.epsilon, True)
    integrators.set_pars(tg, params)
    g = faithfulness.spike_cycle_gains(tg, s, T=T, tau=5.0, spike_factor=SPIKES["factor"])
    return spikes, interval, spread, g


def heyoka_runner(params, precision, tol):
    """run(y0, grid) -> (states as pairs (hi, lo), steps) for heyoka's flow in ``precision`` at tol."""
    p = Precision.parse(precision)
    ta = integrators.flow(False, tol, p)[0]
    integrators.set_pars(ta, params)
    fp = p.fp_type

    def run(y0, grid):
        ta.time = fp(0)
        integrators.load(ta, np.asarray(y0).astype(p.dtype))
        res = ta.propagate_grid(np.asarray(grid).astype(p.dtype), callback=integrators.bounded(ta))
        if res[0] != hy.taylor_outcome.time_limit:
            raise RuntimeError(f"{precision} at tol {tol:g}: {res[0]}")
        pairs = [ddtaylor.as_pair(r) for r in integrators.samples(ta, res[5])]
        return (np.array([a for a, _ in pairs]), np.array([b for _, b in pairs])), int(res[3])

    run.order = int(ta.order)
    return run


def dd_runner(params, tol):
    """run(y0, grid) -> (states (hi, lo), steps) for ddtaylor.DDFlow at tol."""
    flow = ddtaylor.DDFlow(params, tol=tol)

    def run(y0, grid):
        out = flow.propagate_grid(y0, grid)
        return out, flow.steps

    run.order = flow.order
    return run


def timed(run, y0, grid, repeats, warmup_grid):
    """One untimed warm-up over warmup_grid, then ``repeats`` timed runs: (last result, steps, CPU seconds list,
    wall seconds list)."""
    run(y0, warmup_grid)
    cpu, wall = [], []
    for _ in range(repeats):
        c0, w0 = time.process_time(), time.perf_counter()
        out, steps = run(y0, grid)
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - w0)
    return out, steps, cpu, wall


def measure_rows(params, s, T, opts):
    """Every row of opts["rows"]: cost per time unit, steps, the states at the sample times."""
    grid = np.linspace(0.0, T, SAMPLES)
    rows = []
    for engine, arith, tol in opts["rows"]:
        quad = arith == "quad"
        run = runner(params, engine, arith, tol)
        warm = np.array([0.0, opts["warmup_quad"]]) if quad else grid
        reps = opts["repeats_quad"] if quad else opts["repeats"]
        say(f"{engine} {arith} tol {tol:g}: {reps} runs over {T:g}")
        out, steps, cpu, wall = timed(run, s, grid, reps, warm)
        rows.append({"engine": engine, "arithmetic": arith, "tol": tol,
                     "order": run.order, "repeats": reps,
                     "cpu_s_per_tu": statistics.median(cpu) / T, "wall_s_per_tu": statistics.median(wall) / T,
                     "steps_per_tu": steps / T, "cpu_s": [round(c, 6) for c in cpu], "_out": out})
        say(f"  {rows[-1]['cpu_s_per_tu']:.3e} s per time unit, {steps / T:.3f} steps per time unit")
    return rows, grid


def errors(rows, params):
    """Each row's separation from the reference at the sample times; energy drift for double-double."""
    ref = next(r for r in rows if (r["engine"], r["arithmetic"], r["tol"]) == REFERENCE)["_out"]
    for r in rows:
        out = r.pop("_out")
        sep = ddtaylor.separation(ref, out)
        r["separation_from_reference"] = [float(x) for x in sep]
        r["error_after_cycle"] = float(sep[-1])
        if r["engine"] == "dd":
            r["energy_drift"] = ddtaylor.energy_drift(params, *out)


def runner(params, engine, arith, tol):
    """The run(y0, grid) of a row."""
    return dd_runner(params, tol) if engine == "dd" else heyoka_runner(params, arith, tol)


def error_replicas(params, s, T, n):
    """Separation after one cycle of REPLICA_ROWS from the reference, from n start states spread over a cycle
    of the settled orbit (s and the double orbit's states at T k / n, k = 1 .. n - 1): independent replicas of
    the error (each a different stretch of the orbit)."""
    starts = [s]
    if n > 1:
        out, _ = heyoka_runner(params, "double", 2.0**-52)(s, T / n * np.arange(n))
        starts = [out[0][k] for k in range(n)]
    grid = np.array([0.0, T])
    runs = {key: runner(params, *key) for key in (REFERENCE, *REPLICA_ROWS)}
    result = {f"{e} {a} {t:g}": [] for e, a, t in REPLICA_ROWS}
    for k, y0 in enumerate(starts):
        say(f"error replica {k}: start {np.asarray(y0).tolist()}")
        ref = runs[REFERENCE](y0, grid)[0]
        for (e, a, t) in REPLICA_ROWS:
            result[f"{e} {a} {t:g}"].append(float(ddtaylor.separation(ref, runs[(e, a, t)](y0, grid)[0])[-1]))
    return {"starts": [np.asarray(y).tolist() for y in starts], "error_after_cycle": result,
            "median": {k: statistics.median(v) for k, v in result.items()},
            "max": {k: max(v) for k, v in result.items()}}


def compile_times() -> dict:
    """Double-double's numba compilation (empty cache) and cache load, in child processes (CPU seconds)."""
    child = ("import time, json; t0 = time.process_time(); "
             "from sleighsim.engine.ddtaylor import DDFlow; from sleighsim.model.params import Params; "
             "t1 = time.process_time(); f = DDFlow(Params.paper(eps=0.1, K2=1.1)); t2 = time.process_time(); "
             "y = [0.0, 0.1, 1.0, 0.0]; f.propagate(y, 1.0); f.propagate_tangent_grid(y, [1.0, 0, 0, 0], [1.0]); "
             "t3 = time.process_time(); f.propagate(y, 1.0); f.propagate_tangent_grid(y, [1.0, 0, 0, 0], [1.0]); "
             "t4 = time.process_time(); print(json.dumps([t1 - t0, t2 - t1, (t3 - t2) - (t4 - t3)]))")
    out = {}
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(REPO / "src")}
        for name in ("compile_empty_cache", "load_filled_cache"):
            res = subprocess.run([sys.executable, "-c", child], env=env, capture_output=True, text=True, check=True)
            imp, build, jit = (float(x) for x in res.stdout.strip().splitlines()[-1].strip("[]").split(","))
            out[name] = {"import_cpu_s": imp, "ddflow_construction_cpu_s": build, "first_calls_extra_cpu_s": jit}
    return out


def run(opts) -> dict:
    """The measurement (FULL or QUICK options) as a YAML-ready dict."""
    params = Params.paper(**PARAMS)
    y0 = state_at_label(REFERENCE_STATE, params, REFERENCE_LABEL)
    load = {"start": benchio.loadavg()}
    say("compile times (child processes)")
    compiled = compile_times()
    s = settled(params, y0, opts["t_transient"])
    say(f"settled state after {opts['t_transient']:g}: {s.tolist()}")
    spikes, interval, spread, g = cycle_and_gauge(params, s, opts["t_gauge"])
    T = opts["cycle"] or round(interval)
    say(f"spike interval {interval:.1f} +- {spread:.1f}; ln G max {g['ln_gain_max']:.2f}; one cycle T = {T:g}")
    load["after_setup"] = benchio.loadavg()
    rows, grid = measure_rows(params, s, T, opts)
    load["after_timing"] = benchio.loadavg()
    errors(rows, params)
    replicas = error_replicas(params, s, T, opts["replicas"])
    ref_cost = {r["arithmetic"]: r["cpu_s_per_tu"] for r in rows if r["tol"] in (2.0**-52, 2.0**-63, 2.0**-112)}
    for r in rows:
        r["ratio_to_double"] = r["cpu_s_per_tu"] / ref_cost["double"]
        if "quad" in ref_cost:
            r["ratio_to_real128_at_its_epsilon"] = r["cpu_s_per_tu"] / ref_cost["quad"]
    gauge = {"ln_gain": [float(x) for x in g["ln_gain"]], "ln_gain_max": g["ln_gain_max"],
             "log10_gain_rounding": {**{str(p): v for p, v in g["log10_gain_rounding"].items()},
                                     "double-double": (g["ln_gain_max"] + math.log(ddarith.ROUNDING)) / math.log(10)},
             "follows": {**{str(p): v for p, v in g["follows"].items()},
                         "double-double": faithfulness.follows(g["ln_gain_max"], ddarith.ROUNDING)}}
    load["end"] = benchio.loadavg()
    return {
        **benchio.header(SCHEMA, opts is QUICK, {"heyoka": hy.__version__, "numpy": np.__version__,
                                                 "numba": numba.__version__}, load),
        "setup": {"params": PARAMS, "y0": [float(v) for v in y0], "energy_label": REFERENCE_LABEL,
                  "t_transient": opts["t_transient"], "settled_state": [float(v) for v in s],
                  "spike_times_from_settled": [float(x) for x in spikes], "spike_interval_mean": interval,
                  "spike_interval_std": spread, "cycle_T": T, "sample_times": [float(x) for x in grid],
                  "reference": {"engine": REFERENCE[0], "arithmetic": REFERENCE[1], "tol": REFERENCE[2]},
                  "cost": "median CPU seconds (process time) per time unit over the repeats, after one untimed "
                          "warm-up", "error": "ddtaylor.separation from the reference at the sample times"},
        "gauge": gauge,
        "compile_dd": compiled,
        "rows": rows,
        "error_replicas": replicas,
    }


def main() -> int:
    """The command line (--out, --quick); exit status 0."""
    return benchio.main("doubledouble", __doc__, run, FULL, QUICK, REPO / "benchmarks" / "doubledouble.yaml",
                        "a 50-time-unit window, one repeat, four rows (a test run; not a measurement)")


if __name__ == "__main__":
    raise SystemExit(main())
