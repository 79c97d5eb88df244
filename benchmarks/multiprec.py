#!/usr/bin/env python
"""Beyond double-double: what follows the paper's orbit once it has escaped onto a long-period torus, and at what
price. heyoka's MPFR real at 160, 192 and 256 bits, the triple-double engine (sleighsim.engine.tdtaylor) and, for
contrast, double-double and real128, over one spike cycle of the torus against a 320-bit orbit.

    taskset -c 1 python benchmarks/multiprec.py --find-torus   # once: writes benchmarks/torus_state.yaml
    taskset -c 1 python benchmarks/multiprec.py [--out benchmarks/multiprec.yaml] [--quick]
    python benchmarks/multiprec.py --judge benchmarks/multiprec.yaml   # the judgement again, from the errors

--find-torus: eps 0.1, b 1, K2 1.1 from the reference state (0, 0.1, 1, 0), heyoka's real at 256 bits (tol
1e-60) over 20000 time units sampled every 0.5; spikes of Omega by transient.spike_times (the project's
settings); the escape is the first spike after t = 1000; the torus start is that orbit's state 200 time units after
the escape, the cycle P the interval from the escape's spike to the next. Saved with 100 digits, with the state at
start + P. The first passage (start to 7000) amplifies so much that no arithmetic up to 256 bits follows it: the
256-bit orbit and triple-double (tol 1e-47) are compared with a 320-bit orbit (tol 2^-300) at sample times up to
7000, so the saved torus is the 256-bit orbit's, one realisation of where the escape leads.

Measurement (reads torus_state.yaml): every candidate starts from the saved state rounded to its arithmetic and
runs one cycle P sampled at 9 times; error = ddtaylor.separation at 400 bits from a fresh 320-bit run (tol 2^-300)
at each sample time (its own check: its end against the saved end state). Cost per time unit: CPU seconds
(process time, pinned to one core) over a 200-time-unit window from the torus start, the median of 3 runs, the
candidates interleaved, after a warm-up; per cycle: that times P, beside the CPU seconds of the cycle run itself.
Triple-double also at 16 lanes (16 starts along its own orbit over the cycle, the cost per orbit). The gain: the
largest growth over the cycle of 16 random tangent vectors (triple-double, from the torus start), a lower bound on
ln G of the gauge (chaos.faithfulness), kept for the record but not used: it is taken along the triple-double
orbit, which parts from the torus within the cycle. The judgement (``judged``) rests on the measured errors: ln G
over the cycle from the finest candidate whose orbit did not part (error after the cycle / its rounding), a row
follows when its error after the cycle is below PARTED, the bits an MPFR real needs for an error of TARGET, and the
recommendation, the cheapest candidate per cycle within TARGET (None when no candidate reaches it).
"""

from __future__ import annotations

import datetime as dt
import json
import math
import statistics
import sys
import time
from functools import partial
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))
sys.path.insert(0, str(REPO / "benchmarks"))

import arith_runs as ar  # noqa: E402
import heyoka as hy  # noqa: E402
import mpmath  # noqa: E402
import numba  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402

from sleighsim.engine import ddarith, integrators, tdarith, transient  # noqa: E402
from sleighsim.engine.ddbatch import DDBatch  # noqa: E402
from sleighsim.engine.tdtaylor import TDBatch  # noqa: E402
from sleighsim.io.cachedir import private_directory, project_cache  # noqa: E402
from sleighsim.model.params import Params  # noqa: E402
from sleighsim.model.symmetries import REFERENCE_STATE  # noqa: E402
from sleighsim.ops import benchio, facts  # noqa: E402
from sleighsim.precision import Precision  # noqa: E402

say = partial(benchio.say, "multiprec")

SCHEMA = "sleighsim.multiprec/1"
TORUS_SCHEMA = "sleighsim.torus_state/1"
TORUS_FILE = REPO / "benchmarks" / "torus_state.yaml"
PARAMS = {"eps": 0.1, "b": 1.0, "K2": 1.1}
SPIKES = {"factor": 1.8, "block": 50.0, "min_separation": 300.0}
REF = (320, 2.0**-300)
SEARCH = (256, 1e-60)
FIND = {"t_search": 20000.0, "dt": 0.5, "offset": 200.0, "t_first": 7000.0,
        "first_times": [1000, 3000, 5000, 5500, 6000, 6500, 7000]}
#: (name, arithmetic, bits or None, tol, rounding unit): the candidates on the torus.
CANDIDATES = (("real 160", "real", 160, 2.0**-159, 2.0**-160), ("real 192", "real", 192, 2.0**-191, 2.0**-192),
              ("real 256", "real", 256, 2.0**-255, 2.0**-256), ("triple-double", "td", None, 1e-47, tdarith.ROUNDING),
              ("double-double", "dd", None, 1e-32, ddarith.ROUNDING), ("real128", "quad", None, 2.0**-112, 2.0**-113))
FULL = {"window": 200.0, "repeats": 3, "samples": 9, "lanes": 16, "cycle": None}
QUICK = {"window": 5.0, "repeats": 1, "samples": 3, "lanes": 4, "cycle": 20.0}


def digits(x) -> str:
    """x (an mpmath number) as a decimal string of 100 significant digits."""
    return mpmath.nstr(x, 100, min_fixed=-1, max_fixed=-1)


def real_grid(params, y0: list, grid, bits: int, tol: float) -> list:
    """heyoka's real at ``bits`` from y0 (mpmath numbers) sampled on grid: rows of mpmath numbers."""
    ta, fp = ar.real_flow(tol, bits), (lambda x: hy.real(x, bits))
    ta.pars[:] = ar.real_pars(params, bits)
    ta.time = fp(0.0)
    integrators.load(ta, np.array([fp(digits(v)) for v in y0]))
    res = ta.propagate_grid(np.array([fp(float(t)) for t in grid]), callback=integrators.bounded(ta))
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"real {bits}: {res[0]}")
    return ar.mp_rows(integrators.samples(ta, res[5]))


def runner(params, name: str):
    """run(y0 as mpmath numbers, grid) -> rows of mpmath numbers, for a candidate's name."""
    _, arith, bits, tol, _ = next(c for c in CANDIDATES if c[0] == name)
    if arith == "real":
        return lambda y0, grid: real_grid(params, y0, grid, bits, tol)
    if arith == "quad":
        ta = integrators.flow(False, tol, Precision.QUAD)[0]
        integrators.set_pars(ta, params)

        def run_quad(y0, grid):
            ta.time = hy.real128(0)
            integrators.load(ta, np.array([hy.real128(digits(v)) for v in y0]))
            res = ta.propagate_grid(np.array([hy.real128(float(t)) for t in grid]), callback=integrators.bounded(ta))
            return ar.mp_rows(integrators.samples(ta, res[5]))

        return run_quad
    if arith == "td":
        flow = TDBatch(params, tol)
        return lambda y0, grid: td_rows(flow.propagate_grid([y0], grid)[0])
    flow = DDBatch(params, tol)

    def run_dd(y0, grid):
        pairs = np.array([ddarith.pair(v) for v in y0])
        return ar.mp_rows(tuple(x[0] for x in flow.propagate_grid((pairs[None, :, 0], pairs[None, :, 1]), grid)))

    return run_dd


def td_rows(states) -> list:
    """Triple-double states [time, variable, component] as rows of mpmath numbers (exact)."""
    with mpmath.workprec(ar.WORKPREC):
        return [[sum(mpmath.mpf(float(c)) for c in v) for v in row] for row in states]


def search_orbit(params) -> tuple[np.ndarray, list, float]:
    """The searching orbit (real at SEARCH bits) from the reference state, sampled every dt: (grid, rows, CPU s);
    kept as JSON decimal strings (never pickle: read back, a pickle runs code) in a directory only this user
    controls ($SLEIGHSIM_CACHE, default ~/.cache/sleighsim; io.cachedir.private_directory), keyed by its
    settings, so that a failed search is not paid twice."""
    grid = FIND["dt"] * np.arange(round(FIND["t_search"] / FIND["dt"]) + 1)
    where = private_directory(*project_cache())
    cache = where / f"multiprec_search_{SEARCH[0]}_{SEARCH[1]:g}_{FIND['t_search']:g}.json"
    if cache.exists():
        saved = json.loads(cache.read_text())
        with mpmath.workprec(ar.WORKPREC):
            return grid, [[mpmath.mpf(str(v)) for v in row] for row in saved["rows"]], float(saved["cpu"])
    c0 = time.process_time()
    rows = real_grid(params, [mpmath.mpf(v) for v in REFERENCE_STATE], grid, *SEARCH)
    cpu = time.process_time() - c0
    with mpmath.workprec(ar.WORKPREC):
        text = [[digits(v) for v in row] for row in rows]
    cache.write_text(json.dumps({"rows": text, "cpu": cpu}))
    return grid, rows, cpu


def first_passage(params, grid, orbit) -> dict:
    """How the first passage (start to 7000) amplifies: the separations of the searching orbit and of
    triple-double (tol 1e-47) from the 320-bit orbit (REF) at the sample times."""
    times = np.array([0.0] + FIND["first_times"], dtype=float)
    y0 = [mpmath.mpf(v) for v in REFERENCE_STATE]
    ref = real_grid(params, y0, times, *REF)[1:]
    search = [orbit[int(round(t / FIND["dt"]))] for t in times[1:]]
    td = td_rows(TDBatch(params, 1e-47).propagate_grid([REFERENCE_STATE], times)[0])[1:]
    return {"times": times[1:].tolist(),
            f"real {SEARCH[0]} tol {SEARCH[1]:g}": [ar.separation(r, x) for r, x in zip(ref, search)],
            "triple-double tol 1e-47": [ar.separation(r, x) for r, x in zip(ref, td)]}


def find_torus(params) -> dict:
    """The searching orbit from the reference state: spikes, the torus start and cycle, the first passage."""
    grid, orbit, cpu = search_orbit(params)
    spikes = transient.spike_times(grid, np.array([float(r[1]) for r in orbit]), **SPIKES)
    say(f"spikes {list(spikes)}")
    after = [float(s) for s in spikes if s > 1000.0]
    if len(after) < 2 or after[1] + FIND["offset"] > grid[-1]:
        raise RuntimeError(f"no full cycle after the escape within {grid[-1]:g}: spikes {list(spikes)}")
    escape, nxt = after[0], after[1]
    i_start, P = int(round((escape + FIND["offset"]) / FIND["dt"])), nxt - escape
    i_end = i_start + int(round(P / FIND["dt"]))
    say(f"torus start {grid[i_start]:g}, cycle {P:g}")
    return {"schema": TORUS_SCHEMA, "date": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
            "git_commit": facts.git_commit(), "machine": facts.machine_facts(),
            "versions": {"heyoka": hy.__version__, "numba": numba.__version__},
            "params": PARAMS, "y0": list(REFERENCE_STATE), "search": {"bits": SEARCH[0], "tol": SEARCH[1]},
            "search_cpu_s": cpu, "spike_times": [float(s) for s in spikes], "escape_spike": escape,
            "next_spike": nxt, "cycle": P, "t_start": float(grid[i_start]),
            "start": [digits(v) for v in orbit[i_start]], "end": [digits(v) for v in orbit[i_end]],
            "first_passage_separation_from_320_bits": first_passage(params, grid, orbit)}


def measure_cost(params, names, y0, opts) -> dict:
    """CPU seconds per time unit over the window, interleaved repeats after a warm-up."""
    runs = {n: runner(params, n) for n in names}
    window = np.array([0.0, opts["window"]])
    for n in names:
        runs[n](y0, np.array([0.0, min(5.0, opts["window"])]))
    cpu = {n: [] for n in names}
    for rep in range(opts["repeats"]):
        say(f"window repeat {rep + 1} (load {benchio.loadavg()})")
        for n in names:
            c0 = time.process_time()
            runs[n](y0, window)
            cpu[n].append((time.process_time() - c0) / opts["window"])
    return cpu


def lanes_cost(params, starts, T: float, opts) -> float:
    """Triple-double at ``lanes`` lanes from the given starts: CPU seconds per orbit and time unit (median)."""
    flow = TDBatch(params, 1e-47)
    ys = np.array([[tdarith.expansion(v) for v in row] for row in starts])
    flow.propagate(ys, 1.0)
    cpu = []
    for _ in range(opts["repeats"]):
        c0 = time.process_time()
        flow.propagate(ys, T)
        cpu.append((time.process_time() - c0) / (len(ys) * T))
    return statistics.median(cpu)


def gain(params, y0, P: float, lanes: int) -> dict:
    """ln of the largest growth over one cycle of ``lanes`` random unit tangent vectors (triple-double)."""
    v0 = np.random.default_rng(5).normal(size=(lanes, 4))
    v0 /= np.linalg.norm(v0, axis=1)[:, None]
    ys = np.repeat([[tdarith.expansion(v) for v in y0]], lanes, axis=0)
    _, log_norm, _ = TDBatch(params, 1e-47).propagate_tangent_grid(ys, v0, [0.0, P])
    growth = log_norm[:, 1] - log_norm[:, 0]
    return {"ln_growth": growth.tolist(), "ln_G_lower_bound": float(growth.max())}


def measure(params, torus: dict, opts) -> dict:
    """The candidates on the torus: cost per time unit and per cycle, error along the cycle."""
    with mpmath.workprec(ar.WORKPREC):
        y0 = [mpmath.mpf(s) for s in torus["start"]]
        end = [mpmath.mpf(s) for s in torus["end"]]
    P = float(opts["cycle"] or torus["cycle"])
    grid = np.linspace(0.0, P, opts["samples"])
    names = [c[0] for c in CANDIDATES]
    load = {"start": benchio.loadavg()}
    cpu = measure_cost(params, names, y0, opts)
    load["after_window_timing"] = benchio.loadavg()
    say("320-bit reference over the cycle")
    c0 = time.process_time()
    ref = real_grid(params, y0, grid, *REF)
    ref_cpu = time.process_time() - c0
    rows, g = [], gain(params, y0, P, opts["lanes"])
    for name, arith, bits, tol, rounding in CANDIDATES:
        say(f"cycle: {name}")
        c0 = time.process_time()
        out = runner(params, name)(y0, grid)
        cycle_cpu = time.process_time() - c0
        err = [ar.separation(r, x) for r, x in zip(ref, out)]
        rows.append({"candidate": name, "arithmetic": arith, "bits": bits, "tol": tol, "rounding": rounding,
                     "cpu_s_per_tu": statistics.median(cpu[name]), "cpu_s_per_tu_runs": cpu[name],
                     "cpu_s_per_cycle": statistics.median(cpu[name]) * P, "cpu_s_cycle_run": cycle_cpu,
                     "error_along_cycle": err, "error_after_cycle": err[-1]})
    load["after_cycles"] = benchio.loadavg()
    starts = td_rows(TDBatch(params, 1e-47).propagate_grid([[tdarith.expansion(v) for v in y0]],
                                                           np.linspace(0.0, P, opts["lanes"] + 1)[:-1])[0])
    td16 = lanes_cost(params, starts, min(P, 4 * opts["window"]), opts)
    load["end"] = benchio.loadavg()
    return {"cycle": P, "sample_times": grid.tolist(), "reference_cpu_s": ref_cpu,
            "reference_end_vs_saved_end": ar.separation(end, ref[-1]) if not opts["cycle"] else None,
            "gain": g, "rows": rows, "load": load,
            "triple_double_lanes": {"lanes": opts["lanes"], "cpu_s_per_orbit_tu": td16,
                                    "cpu_s_per_orbit_cycle": td16 * P}}


#: An arithmetic's orbit has parted from the reference when its separation after the cycle is at least this.
PARTED = 1e-3
#: The error after a cycle the recommended arithmetic must reach.
TARGET = 1e-20


def judged(rows: list, reference_bits: int) -> dict:
    """What the measured errors say (the tangent lower bound is not used: it is computed along the triple-double
    orbit, which does not follow the torus): ln G over the cycle from the finest candidate that did not part,
    ln(error after the cycle / its rounding) (an estimate: the injected error taken as one rounding); per row
    whether it follows (error after the cycle below PARTED) and log10(G x rounding); the bits an MPFR real needs
    for TARGET; the cheapest candidate per cycle within TARGET, or None."""
    kept = [r for r in rows if r["error_after_cycle"] < PARTED]
    finest = min(kept, key=lambda r: r["rounding"]) if kept else None
    ln_G = math.log(finest["error_after_cycle"] / finest["rounding"]) if finest else math.nan
    for r in rows:
        r["follows"] = bool(r["error_after_cycle"] < PARTED)
        r["log10_G_x_rounding_measured"] = (ln_G + math.log(r["rounding"])) / math.log(10)
        r.pop("log10_G_x_rounding", None)
    good = [r for r in rows if r["error_after_cycle"] < TARGET]
    best = min(good, key=lambda r: r["cpu_s_per_cycle"]) if good else None
    bits = math.ceil((ln_G - math.log(TARGET)) / math.log(2)) if math.isfinite(ln_G) else None
    return {"ln_G_measured": ln_G, "ln_G_from": None if finest is None else finest["candidate"],
            "parted_at": PARTED, "target_error": TARGET, "bits_needed_for_target": bits,
            "reference_bits": reference_bits,
            "recommendation": None if best is None else {"candidate": best["candidate"],
                                                          "cpu_s_per_cycle": best["cpu_s_per_cycle"],
                                                          "error_after_cycle": best["error_after_cycle"]}}


def run(opts) -> dict:
    """The measurement on the saved torus state (FULL or QUICK options) as a YAML-ready dict."""
    params = Params.paper(**PARAMS)
    torus = yaml.safe_load(TORUS_FILE.read_text())
    result = measure(params, torus, opts)
    result["judged"] = judged(result["rows"], REF[0])
    load = result.pop("load")
    versions = {"heyoka": hy.__version__, "numpy": np.__version__, "numba": numba.__version__,
                "mpmath": mpmath.__version__}
    return {**benchio.header(SCHEMA, opts is QUICK, versions, load),
            "torus": {k: torus[k] for k in ("t_start", "cycle", "escape_spike", "next_spike", "start")},
            "cost": "median CPU seconds (process time, one core) per time unit over the window; per cycle x P",
            "error": "separation at 400 bits from the 320-bit orbit at the sample times", **result}


def main() -> int:
    """--find-torus writes torus_state.yaml; otherwise the measurement (--out, --quick)."""
    if "--find-torus" in sys.argv:
        out = find_torus(Params.paper(**PARAMS))
        TORUS_FILE.write_text(yaml.safe_dump(benchio.plain(out), sort_keys=False))
        say(f"wrote {TORUS_FILE}")
        return 0
    if "--judge" in sys.argv:  # the judgement again on a record's measurements (no integration)
        path = Path(sys.argv[sys.argv.index("--judge") + 1])
        record = yaml.safe_load(path.read_text())
        record.pop("recommendation", None)
        record["judged"] = judged(record["rows"], REF[0])
        record["judged_by"] = {"git_commit": facts.git_commit(),
                               "command": f"python benchmarks/multiprec.py --judge {path.name}"}
        path.write_text(yaml.safe_dump(benchio.plain(record), sort_keys=False))
        say(f"judged {path}")
        return 0
    return benchio.main("multiprec", __doc__, run, FULL, QUICK, REPO / "benchmarks" / "multiprec.yaml",
                        "a 20-time-unit cycle, short windows (a test run; not a measurement)")


if __name__ == "__main__":
    raise SystemExit(main())
