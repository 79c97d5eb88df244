#!/usr/bin/env python
"""What extended precision costs here: the sleigh's flow and its tangent system in double, long double and
quad, compact mode on and off, and heyoka's high_accuracy mode in double (its cost and what it buys).

    taskset -c 1 python benchmarks/precision_cost.py [--out benchmarks/precision_cost.yaml] [--quick]

Rows: every (system, precision, compact_mode, high_accuracy) with system "flow" (the 4-state sleigh) or
"tangent" (the sleigh plus one tangent vector, heyoka's variational equations, k = 1), precision one of
sleighsim.precision.Precision, each at its own machine epsilon as tolerance, and high_accuracy on only in
double. Integrators come from the project's builders (integrators.flow: compact mode off in double and
long double, on in quad; integrators.sleigh_tangent; integrators.tangent_integrator for quad); where they have
no such option
(compact_mode for the flow, high_accuracy anywhere) the integrator is built the way they build it with that
option changed, and registered with integrators.compiled so its angle is kept bounded like theirs.

Per row:
- compile_s: CPU and wall seconds of building the integrator (the full run: heyoka's disk cache off and its
  in-memory cache cleared before each build, so a real compilation; --quick: the disk cache as this
  process finds it, so possibly a cache load), after one untimed throwaway build (LLVM start-up) and the
  SymPy side of the model built once;
- per time unit: the paper's main state (eps 0.1, b 1, K2 1.1; y0 = (0, 0.1, 1, 0) at energy label 0.1127)
  propagated over a transient (6000 time units, double) first; every timed run starts from that settled
  state (the tangent vector from benettin.initial_directions(4, 1, seed 0)). Windows: "long" (3000 time
  units, more than one spike cycle of about 2400; double and long double) and "short" (300 time units,
  before the first spike; every precision, so quad's ratio to double is taken on the same stretch of
  orbit). The flow runs in one propagate_for; the tangent system in legs of tau = 10 with the vector
  renormalised after each (as benettin.benettin does). One untimed warm-up (over the window, the short
  window for quad), then the median of the repeats (5; 3 in quad). The cost is CPU seconds (process time,
  so other load on the machine does not count), wall seconds beside it; steps per time unit from heyoka.

High accuracy: the separation of double and double + high_accuracy from a long-double orbit, and of
long double from a quad orbit (the full run only), all started from the same double settled state, each
at its arithmetic's epsilon (compact mode off), sampled every 0.5 time units. The separation at t is
max |difference| of (u, Omega, omega) divided by max |(u, Omega, omega)| over the reference record; it is
reported half-way to the first spike, 50 time units after the first and the second spike (spikes of
Omega in the reference by transient.spike_times with the project's settings), and as the maximum over
the 100 time units after each spike. Also: the cost ratio high_accuracy / plain per system and mode.
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from functools import partial
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

import heyoka as hy
import numpy as np

from sleighsim.chaos import benettin
from sleighsim.engine import integrators, transient
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_LABEL, REFERENCE_STATE, state_at_label
from sleighsim.ops import benchio
from sleighsim.precision import Precision

say = partial(benchio.say, "precision_cost")

SCHEMA = "sleighsim.precision_cost/1"
# heyoka's: double, long double, quad (double-double: benchmarks/doubledouble.py)
PRECISIONS = tuple(p.value for p in Precision if p is not Precision.DOUBLE_DOUBLE)
SYSTEMS = ("flow", "tangent")
PARAMS = {"eps": 0.1, "b": 1.0, "K2": 1.1}
TAU = 10.0  # renormalisation interval of the tangent vector (config: lyapunov tau)
SPIKES = {"factor": 1.8, "block": 50.0, "min_separation": 300.0}  # transient.spike_times, as configured
AFTER_SPIKE = 50.0
SPIKE_WINDOW = 100.0
SAMPLE_DT = 0.5

FULL = {"t_transient": 6000.0, "long": 3000.0, "short": 300.0, "repeats": 5, "repeats_quad": 3, "t_accuracy": 5000.0,
        "quad_reference": True, "cold_compile": True}
QUICK = {"t_transient": 6000.0, "long": 300.0, "short": 10.0, "repeats": 3, "repeats_quad": 3, "t_accuracy": 5000.0,
         "quad_reference": False, "cold_compile": False}


def rows():
    """Yield the rows' (system, precision, compact_mode, high_accuracy); high_accuracy on in double only."""
    for system in SYSTEMS:
        for precision in PRECISIONS:
            for compact in (True, False):
                for ha in ((False, True) if precision == "double" else (False,)):
                    yield system, precision, compact, ha


def _flow_variant(tol, precision, compact, ha):
    """integrators.flow's build with compact_mode and high_accuracy set (kinematics off)."""
    fp = precision.fp_type

    def build():
        y0 = np.array([0.0, 0.1, 1.0, integrators.DELTA_SHIFT]).astype(fp)
        return hy.taylor_adaptive(equations.heyoka_system(False, integrators.DELTA_SHIFT), y0, tol=fp(tol),
                                  pars=equations.compile_pars(fp), fp_type=fp, compact_mode=compact, high_accuracy=ha)

    return integrators.compiled(("precision_cost flow", tol, precision, compact, ha), build)[0]


def _tangent_variant(tol, precision, compact, ha):
    """integrators.sleigh_tangent's build (k = 1) in any precision, with high_accuracy set."""
    fp = precision.fp_type
    sys_ = equations.heyoka_system(delta_shift=integrators.DELTA_SHIFT)

    def build():
        if not ha:
            return integrators.tangent_integrator(sys_, 1, tol, equations.compile_pars(fp), compact_mode=compact,
                                               precision=precision)[0]
        import heyoka as hy  # integrators.tangent_integrator with high_accuracy on

        vsys = hy.var_ode_sys(sys_, [v for v, _ in sys_[:1]], order=1)
        return hy.taylor_adaptive(vsys, np.full(len(sys_), 0.1, dtype=fp), tol=fp(tol), pars=equations.compile_pars(fp),
                                  compact_mode=compact, fp_type=fp, high_accuracy=True)

    return integrators.compiled(("precision_cost tangent", 1, tol, precision, compact, ha), build)[0]


def build(system, name, compact, ha):
    """The integrator of one row (``name``: the precision's config name): the project's builder where
    it has the options, else its build."""
    precision = Precision.parse(name)
    tol, quad = precision.epsilon, precision is Precision.QUAD
    if system == "flow":
        if compact == quad and not ha:  # integrators.flow: full mode in double and long double, compact in quad
            return integrators.flow(False, tol, precision)[0], "integrators.flow"
        return _flow_variant(tol, precision, compact, ha), "integrators.flow's build, options changed"
    if not quad and not ha:
        return integrators.sleigh_tangent(1, tol, compact, precision)[0], "integrators.sleigh_tangent"
    how = "integrators.tangent_integrator" if not ha else "integrators.tangent_integrator's build, high_accuracy on"
    return _tangent_variant(tol, precision, compact, ha), how


def _check(ta, res, what):
    if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(np.asarray(ta.state, float))):
        raise RuntimeError(f"{what}: propagation stopped at t = {float(ta.time):.6g}: heyoka outcome {res[0].name}")


def propagate(ta, system, y0, T, what=""):
    """Propagate ``ta`` over T from y0 (the tangent system in legs of TAU, vector renormalised after each):
    (cpu s, wall s, steps)."""
    fp = ta.state.dtype.type
    callback = integrators.bounded(ta)
    ta.time = fp(0)
    integrators.load(ta, y0)
    if system == "tangent":
        ta.state[4:] = benettin.initial_directions(4, 1, 0).ravel().astype(ta.state.dtype)
    c0, w0 = time.process_time(), time.perf_counter()
    if system == "flow":
        res = ta.propagate_for(fp(T), callback=callback)
        _check(ta, res, what)
        steps = res[3]
    else:
        steps, leg = 0, fp(TAU)
        for _ in range(round(T / TAU)):
            res = ta.propagate_for(leg, callback=callback)
            _check(ta, res, what)
            steps += res[3]
            ta.time = fp(0)  # autonomous: keep the clock small
            norm = math.sqrt(float(np.sum(np.asarray(ta.state[4:], float) ** 2)))
            ta.state[4:] = ta.state[4:] / fp(norm)
    return time.process_time() - c0, time.perf_counter() - w0, int(steps)


def measure(ta, system, y0, T, repeats, warmup_T, what):
    """Cost of propagating ``ta`` over T time units from y0: one untimed warm-up over warmup_T, then
    ``repeats`` timed runs; medians per time unit (CPU and wall seconds), steps per time unit, each run's
    seconds. ``what`` names the row in errors."""
    propagate(ta, system, y0, warmup_T, what)  # warm-up, untimed
    runs = [propagate(ta, system, y0, T, what) for _ in range(repeats)]
    cpu, wall = [r[0] for r in runs], [r[1] for r in runs]
    return {"T": T, "repeats": repeats, "cpu_s_per_tu": statistics.median(cpu) / T,
            "wall_s_per_tu": statistics.median(wall) / T, "steps_per_tu": runs[0][2] / T,
            "cpu_s": [round(c, 6) for c in cpu], "wall_s": [round(w, 6) for w in wall]}


def settled_state(params, y0, t_transient):
    """The sleigh state (u, Omega, omega, delta) after ``t_transient`` time units from y0 at ``params``,
    in double at its machine epsilon (angle kept bounded), as a float array; raises if the run stops early."""
    ta = integrators.flow(False, Precision.DOUBLE.epsilon)[0]
    integrators.set_pars(ta, params)
    ta.time = 0.0
    integrators.load(ta, y0)
    res = ta.propagate_until(float(t_transient), callback=integrators.bounded(ta))
    _check(ta, res, "transient")
    return integrators.read(ta, 4).astype(float)


def orbit(ta, params, y0, T):
    """Samples (every SAMPLE_DT up to T, in the integrator's type) of the orbit from y0, and the CPU seconds."""
    fp = ta.state.dtype.type
    integrators.set_pars(ta, params)
    ta.time = fp(0)
    integrators.load(ta, y0)
    grid = (SAMPLE_DT * np.arange(round(T / SAMPLE_DT) + 1)).astype(ta.state.dtype)
    c0 = time.process_time()
    res = ta.propagate_grid(grid, callback=integrators.bounded(ta))
    _check(ta, res, "accuracy orbit")
    return integrators.samples(ta, res[5]), time.process_time() - c0


def _split(Y):
    """Y (double, long double or real128) as hi + lo, two double arrays (exact for long double; to 2^-106
    relative for real128): differences across types without a common numpy type."""
    hi = np.asarray(Y, float)
    return hi, (np.asarray(Y - hi, float) if np.asarray(Y).dtype != np.float64 else np.zeros_like(hi))


def separations(Y, ref, spikes) -> dict:
    """Separation of Y from ref (see the module docstring) at the reported times."""
    n = min(len(Y), len(ref))
    (ah, al), (bh, bl) = _split(Y[:n, :3]), _split(ref[:n, :3])
    diff = np.abs((ah - bh) + (al - bl)).max(axis=1)
    scale = float(np.abs(np.asarray(ref[:, :3], float)).max())
    sep = diff / scale

    def at(time_):
        return float(sep[round(time_ / SAMPLE_DT)])

    out = {"half_way_to_first_spike": at(spikes[0] / 2)}
    for name, s in zip(("first", "second"), spikes[:2]):
        i0, i1 = round(s / SAMPLE_DT) + 1, round((s + SPIKE_WINDOW) / SAMPLE_DT) + 1
        out[f"after_{name}_spike"] = at(s + AFTER_SPIKE)
        out[f"max_within_{SPIKE_WINDOW:g}_after_{name}_spike"] = float(sep[i0:i1].max())
    return out


def accuracy(params, s, opts):
    """Separations of double, double + high_accuracy (from long double) and long double (from quad)."""
    tol = {p.value: p.epsilon for p in Precision}
    runs = {"double": integrators.flow(False, tol["double"])[0],
            "double_high_accuracy": _flow_variant(tol["double"], Precision.DOUBLE, False, True),
            "long_double": integrators.flow(False, tol["long double"], Precision.LONG_DOUBLE)[0]}
    T = opts["t_accuracy"]
    Y, cpu = {}, {}
    for name, ta in runs.items():
        say(f"accuracy: {name} over {T:g}")
        Y[name], cpu[name] = orbit(ta, params, s, T)
    t = SAMPLE_DT * np.arange(len(Y["long_double"]))
    spikes = transient.spike_times(t, np.asarray(Y["long_double"][:, 1], float), **SPIKES)
    if len(spikes) < 2 or spikes[1] + SPIKE_WINDOW > T:
        raise RuntimeError(f"accuracy: fewer than two spikes within {T:g} time units of the long-double orbit "
                           f"(spikes at {spikes.tolist()})")
    out = {
        "start": "the settled double state (exact in every arithmetic)",
        "compact_mode": False,
        "tolerances": {"double": tol["double"], "double_high_accuracy": tol["double"],
                       "long_double": tol["long double"], "quad": tol["quad"]},
        "sample_dt": SAMPLE_DT,
        "separation": "max |y - y_ref| over (u, Omega, omega) / max |y_ref| over (u, Omega, omega) and the record",
        "spike_times": [float(x) for x in spikes[:2]],
        "spike_rule": f"transient.spike_times on Omega of the long-double orbit, {SPIKES}",
        "reported_at": {"half_way_to_first_spike": float(spikes[0] / 2),
                        "after_first_spike": float(spikes[0] + AFTER_SPIKE),
                        "after_second_spike": float(spikes[1] + AFTER_SPIKE)},
        "vs_long_double": {name: separations(Y[name], Y["long_double"], spikes)
                           for name in ("double", "double_high_accuracy")},
    }
    if opts["quad_reference"]:
        Tq = float(spikes[1] + SPIKE_WINDOW + SAMPLE_DT)
        say(f"accuracy: quad reference over {Tq:g} (about {Tq * 9e-3:.0f} s)")
        Yq, cpu["quad"] = orbit(integrators.flow(False, tol["quad"], Precision.QUAD)[0], params, s, Tq)
        out["vs_quad"] = {name: separations(Y[name], Yq, spikes) for name in Y}
    else:
        out["vs_quad"] = None
        out["vs_quad_note"] = "--quick: no quad reference"
    ratio = {}
    for key in out["vs_long_double"]["double"]:
        plain, ha = out["vs_long_double"]["double"][key], out["vs_long_double"]["double_high_accuracy"][key]
        ratio[key] = ha / plain if plain > 0 else float("nan")
    out["high_accuracy_over_plain_separation"] = ratio
    out["orbit_cpu_s"] = cpu
    return out


def run(opts) -> dict:
    """The measurement with options ``opts`` (FULL or QUICK: transient, windows and accuracy horizon in time
    units, repeats, quad_reference, cold_compile): one row per (system, precision, compact_mode,
    high_accuracy) with compile seconds and cost per time unit, and the high-accuracy separations, as a
    YAML-ready dict."""
    params = Params.paper(**PARAMS)
    y0 = state_at_label(REFERENCE_STATE, params, REFERENCE_LABEL)
    load = {"start": benchio.loadavg()}

    # start-up outside the compile timings: the SymPy model, the runtime parameters, LLVM
    equations.heyoka_system(False, integrators.DELTA_SHIFT)
    for fp in (float, np.longdouble, hy.real128):
        equations.compile_pars(fp)
    integrators.guarded_heyoka()  # heyoka's JIT cache checked before the first build (issue 54)
    x = hy.make_vars("x")
    hy.taylor_adaptive([(x, -x)], [1.0])
    if opts["cold_compile"]:
        hy.llvm_state.set_diskcache_enabled(False)  # this process only

    table = []
    for system, precision, compact, ha in rows():
        hy.llvm_state.clear_memcache()
        c0, w0 = time.process_time(), time.perf_counter()
        ta, how = build(system, precision, compact, ha)
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
        say(f"built {system} {precision} compact={compact} high_accuracy={ha}: {wall:.2f} s")
        table.append({"system": system, "precision": precision, "compact_mode": compact, "high_accuracy": ha,
                      "tol": Precision.parse(precision).epsilon, "order": int(ta.order), "builder": how,
                      "compile_cpu_s": cpu, "compile_wall_s": wall, "_ta": ta})
    load["after_compile"] = benchio.loadavg()

    s = settled_state(params, y0, opts["t_transient"])
    say(f"settled state after {opts['t_transient']:g}: {s.tolist()}")
    for row in table:
        ta = row.pop("_ta")
        integrators.set_pars(ta, params)
        quad = row["precision"] == "quad"
        reps = opts["repeats_quad"] if quad else opts["repeats"]
        what = f"{row['system']} {row['precision']} compact={row['compact_mode']} high_accuracy={row['high_accuracy']}"
        windows = {"short": measure(ta, row["system"], s, opts["short"], reps, opts["short"], what)}
        if not quad:
            windows["long"] = measure(ta, row["system"], s, opts["long"], reps, opts["long"], what)
        row["windows"] = windows
        row["window"] = "short" if quad else "long"
        row["cost_s_per_tu"] = windows[row["window"]]["cpu_s_per_tu"]
        row["steps_per_tu"] = windows[row["window"]]["steps_per_tu"]
        say(f"{what}: {row['cost_s_per_tu']:.3e} s per time unit ({row['window']} window), "
            f"{row['steps_per_tu']:.2f} steps per time unit")
    load["after_timing"] = benchio.loadavg()

    def plain_double(row):
        return next(r for r in table if r["system"] == row["system"] and r["compact_mode"] == row["compact_mode"]
                    and r["precision"] == "double" and not r["high_accuracy"])

    for row in table:
        ref = plain_double(row)
        for name, w in row["windows"].items():
            w["ratio_to_double"] = w["cpu_s_per_tu"] / ref["windows"][name]["cpu_s_per_tu"]
        row["ratio_to_double"] = row["windows"][row["window"]]["ratio_to_double"]

    ha_cost = {}
    for row in table:
        if row["high_accuracy"]:
            ref = plain_double(row)
            ha_cost[f"{row['system']} compact_mode={row['compact_mode']}"] = {
                w: row["windows"][w]["cpu_s_per_tu"] / ref["windows"][w]["cpu_s_per_tu"] for w in row["windows"]}

    acc = accuracy(params, s, opts)
    acc["cost_ratio_high_accuracy_over_plain"] = ha_cost
    load["end"] = benchio.loadavg()

    return {
        **benchio.header(SCHEMA, opts is QUICK, {"heyoka": hy.__version__, "numpy": np.__version__}, load),
        "setup": {
            "params": PARAMS, "y0": [float(v) for v in y0], "energy_label": REFERENCE_LABEL,
            "t_transient": opts["t_transient"], "settled_state": [float(v) for v in s],
            "windows": {"long": opts["long"], "short": opts["short"]},
            "repeats": {"double and long double": opts["repeats"], "quad": opts["repeats_quad"]},
            "warm_up": "one untimed run over the same window before the repeats",
            "tangent": f"k = 1 (variational equations w.r.t. u's initial value), legs of {TAU:g} time units, "
                       "vector renormalised after each",
            "cost": "median CPU seconds (process time) per time unit; wall beside it; ratio_to_double on the same "
                    "window, same system and compact mode",
            "compile": ("heyoka disk cache off, in-memory cache cleared before each build: a real compilation"
                        if opts["cold_compile"] else
                        "heyoka disk cache as found (possibly a cache load), in-memory cache cleared"),
        },
        "rows": table,
        "high_accuracy": acc,
    }


def main() -> int:
    """The command line (--out, --quick); exit status 0."""
    return benchio.main("precision_cost", __doc__, run, FULL, QUICK, REPO / "benchmarks" / "precision_cost.yaml",
                        "short windows, no quad reference, disk cache as found (a test run; not a measurement)")


if __name__ == "__main__":
    raise SystemExit(main())
