#!/usr/bin/env python
"""The batched double-double engine (sleighsim.engine.ddbatch) beside the scalar one and heyoka's arithmetics, in
one run: cost per orbit and time unit against the error after one spike cycle, measured against a 256-bit orbit.

    taskset -c 1 python benchmarks/ddbatch.py [--out benchmarks/ddbatch.yaml] [--quick]

Setup (as benchmarks/doubledouble.py): eps 0.1, b 1, K2 1.1; y0 = (0, 0.1, 1, 0) (energy label 0.1127); the
transient (2e4 time units) in double; the spike cycle T = the mean spike interval of the settled orbit (double,
12000 time units, transient.spike_times with the project's settings), rounded. Starts: 16 double states along the
settled orbit, T/16 apart (independent stretches of the orbit, one per lane).

Candidates, each run over one cycle T from the first n starts (n its orbits per run): DDFlow (scalar, tol 1e-32);
DDBatch at 1, 2, 4, 8, 16 lanes with per-lane steps, and at 16 lanes with the common step; heyoka double (2^-52),
its SIMD batch of 4 and 8 lanes, long double (2^-63), real128 (2^-112); the tangent variants of DDFlow and DDBatch
(16 lanes; one tangent vector per orbit); a row of 16 eps values (0.05 .. 0.20, the settled state in every lane)
with per-lane and with common steps. Cost: CPU seconds (process time, this process pinned to one core) per orbit
and time unit, the median over the repeats (5; 3 for real128), the candidates interleaved in every repeat (so all
see the same load), after one untimed warm-up run each. Error: ddtaylor.separation (at 400 bits) of the end state
after T from the reference, heyoka's MPFR real at 256 bits and tol 1e-48, for each of the 16 starts (every
candidate run untimed over all 16; median and max); the reference checked on the first start against 320 bits at
tol 2^-300. bit_identical: DDBatch's lanes against DDFlow from the same starts (states equal bit for bit).
Vectorisation: ddlanes.jet compiled afresh at 8 and 16 lanes, the packed-double instructions of its assembly
counted per function. The plot (benchmarks/ddbatch.png) is drawn from the YAML.
"""

from __future__ import annotations

import re
import statistics
import sys
import time
from collections import Counter
from functools import partial
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))
sys.path.insert(0, str(REPO / "benchmarks"))

import arith_runs as ar  # noqa: E402
import heyoka as hy  # noqa: E402
import numba  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402

from sleighsim.engine import ddlanes, ddprogram, transient  # noqa: E402
from sleighsim.engine.ddbatch import DDBatch  # noqa: E402
from sleighsim.model.params import Params  # noqa: E402
from sleighsim.model.symmetries import REFERENCE_LABEL, REFERENCE_STATE, state_at_label  # noqa: E402
from sleighsim.ops import benchio  # noqa: E402

say = partial(benchio.say, "ddbatch")

SCHEMA = "sleighsim.ddbatch/1"
PARAMS = {"eps": 0.1, "b": 1.0, "K2": 1.1}
SPIKES = {"factor": 1.8, "block": 50.0, "min_separation": 300.0}
TOL_DD = 1e-32
REFERENCE = {"prec": 256, "tol": 1e-48}
CHECK = {"prec": 320, "tol": 2.0**-300}
EPS_ROW = (0.05, 0.20)
FULL = {"t_transient": 2e4, "t_window": 12000.0, "cycle": None, "starts": 16, "repeats": 5, "repeats_quad": 3,
        "check": True}
QUICK = {"t_transient": 2e4, "t_window": 3000.0, "cycle": 20.0, "starts": 16, "repeats": 1, "repeats_quad": 1,
         "check": False}


def candidates(params):
    """(name, engine, arithmetic, orbits per run, run, whether errors are measured) of every candidate."""
    rows = [row for row in _dd_rows(params)]
    rows += [("heyoka double", "heyoka", "double", 1, ar.heyoka_runner(params, "double", 2.0**-52), True)]
    rows += [(f"heyoka double batch {B}", "heyoka batch", "double", B, ar.batch_runner(params, 2.0**-52, B), True)
             for B in (4, 8)]
    rows += [("heyoka long double", "heyoka", "long double", 1, ar.heyoka_runner(params, "long double", 2.0**-63),
              True), ("heyoka real128", "heyoka", "quad", 1, ar.heyoka_runner(params, "quad", 2.0**-112), True)]
    eps = np.linspace(*EPS_ROW, 16)
    row_params = [Params.paper(eps=float(e), b=PARAMS["b"], K2=PARAMS["K2"]) for e in eps]
    rows += [(f"dd batch 16 eps row {s}", "ddbatch eps row", "double-double", 16,
              _same_start(ar.dd_runner(row_params, TOL_DD, 16, step=s)), False) for s in ("lane", "common")]
    return rows


def _dd_rows(params):
    yield "dd scalar", "ddtaylor", "double-double", 1, ar.dd_runner(params, TOL_DD), True
    for L in (1, 2, 4, 8, 16):
        yield f"dd batch {L}", "ddbatch", "double-double", L, ar.dd_runner(params, TOL_DD, L), True
    yield "dd batch 16 common step", "ddbatch common", "double-double", 16, ar.dd_runner(params, TOL_DD, 16,
                                                                                        step="common"), True
    yield "dd scalar tangent", "ddtaylor tangent", "double-double", 1, ar.dd_runner(params, TOL_DD, tangent=True), False
    yield "dd batch 16 tangent", "ddbatch tangent", "double-double", 16, ar.dd_runner(params, TOL_DD, 16,
                                                                                    tangent=True), False


def _same_start(run):
    """run with every lane started from the first row (the eps row: one state, 16 parameter sets)."""
    return lambda rows, T: run(np.repeat(np.atleast_2d(rows)[:1], 16, axis=0), T)


def setup(params, opts):
    """The settled state, the spike cycle T and the 16 starts along the settled orbit."""
    y0 = state_at_label(REFERENCE_STATE, params, REFERENCE_LABEL)
    s = ar.settled(params, y0, opts["t_transient"])
    grid = 0.5 * np.arange(round(opts["t_window"] / 0.5) + 1)
    Y = ar.orbit_states(params, s, grid)
    spikes = transient.spike_times(grid, Y[:, 1], **SPIKES)
    interval, spread = transient.interval_stats(spikes)
    T = float(opts["cycle"] or round(interval))
    starts = ar.orbit_states(params, s, T / opts["starts"] * np.arange(opts["starts"]))
    return s, spikes, interval, spread, T, starts


def timings(cands, starts, T, opts):
    """CPU seconds per orbit and time unit of every candidate: warm-up, then the repeats interleaved."""
    cpu = {c[0]: [] for c in cands}
    steps = {}
    for name, _, _, n, run, _ in cands:
        run(starts[:n], T if "real128" not in name else min(T, 50.0))
    for rep in range(opts["repeats"]):
        say(f"repeat {rep + 1} of {opts['repeats']} (load {benchio.loadavg()})")
        for name, _, _, n, run, _ in cands:
            if "real128" in name and rep >= opts["repeats_quad"]:
                continue
            c0 = time.process_time()
            _, st = run(starts[:n], T)
            cpu[name].append((time.process_time() - c0) / (n * T))
            steps[name] = st / (n * T)
    return cpu, steps


def errors(cands, starts, T, ref):
    """Each measured candidate's separation from the reference after T, from every start (untimed runs)."""
    out = {}
    for name, _, _, _, run, measured in cands:
        if not measured:
            continue
        say(f"errors: {name}")
        ends = run(starts, T)[0]
        out[name] = [ar.separation(r, e) for r, e in zip(ref, ar.mp_rows(ends))]
    return out


def bit_identical(params, starts, T) -> bool:
    """DDBatch's 16 lanes (per-lane steps) against DDFlow from the same starts: equal bit for bit."""
    (bh, bl), _ = ar.dd_runner(params, TOL_DD, 16)(starts, T)
    (sh, sl), _ = ar.dd_runner(params, TOL_DD)(starts, T)
    return bool(np.array_equal(bh, sh) and np.array_equal(bl, sl))


def eps_row_separation(cands, starts, T) -> float:
    """max separation between the eps row's per-lane and common-step end states."""
    runs = {c[0]: c[4] for c in cands}
    a = ar.mp_rows(runs["dd batch 16 eps row lane"](starts, T)[0])
    b = ar.mp_rows(runs["dd batch 16 eps row common"](starts, T)[0])
    return max(ar.separation(x, y) for x, y in zip(a, b))


def _demangle(symbol: str) -> str:
    """module.function of a numba symbol (_ZN<len><name>...), enough to tell the functions apart."""
    parts, rest = [], symbol[3:] if symbol.startswith("_ZN") else symbol
    while (m := re.match(r"(\d+)", rest)) and not rest.startswith(m.group(1) + "B"):
        n = int(m.group(1))
        parts.append(rest[len(m.group(1)):len(m.group(1)) + n])
        rest = rest[len(m.group(1)) + n:]
    return ".".join(parts) or symbol


def vector_evidence() -> dict:
    """ddlanes.jet compiled afresh (numba's cache keeps no assembly) at 8 and 16 lanes: per function of its
    assembly, the count of each packed-double instruction (mnemonic ending in pd) by register width."""
    params = Params.paper(**PARAMS)
    out = {}
    for W in (8, 16):
        jet = numba.njit(ddlanes.jet.py_func, fastmath=False, error_model="numpy")
        batch = DDBatch(params, TOL_DD)
        prog, Xh, Xl, ch, cl, yh, yl = batch._setup(*batch._states(np.tile(REFERENCE_STATE, (W, 1)), None),
                                                    np.arange(W), False)
        jet(Xh, Xl, prog.ops, prog.lin_src, ch, cl, batch.order, 4, yh, yl, (0.0,) * W)
        functions, current = {}, "?"
        for line in jet.inspect_asm(jet.signatures[0]).splitlines():
            if (m := re.match(r"^(_Z\w+):", line)):
                current = _demangle(m.group(1))
            elif (m := re.match(r"\s+(v\w+pd)\s.*%(zmm|ymm|xmm)", line)):
                functions.setdefault(current, Counter())[f"{m.group(1)} {m.group(2)}"] += 1
        out[f"{W} lanes"] = {f: dict(c.most_common()) for f, c in functions.items()}
    return out


def run(opts) -> dict:
    """The measurement (FULL or QUICK options) as a YAML-ready dict."""
    params = Params.paper(**PARAMS)
    load = {"start": benchio.loadavg()}
    s, spikes, interval, spread, T, starts = setup(params, opts)
    say(f"spike interval {interval:.1f} +- {spread:.1f}: T = {T:g}; {len(starts)} starts")
    cands = candidates(params)
    load["after_setup"] = benchio.loadavg()
    cpu, steps = timings(cands, starts, T, opts)
    load["after_timing"] = benchio.loadavg()
    say("reference runs (256 bits)")
    ref_run = ar.heyoka_runner(params, "real", REFERENCE["tol"], REFERENCE["prec"])
    ref = ar.mp_rows(ref_run(starts, T)[0])
    check = None
    if opts["check"]:
        hi = ar.mp_rows(ar.heyoka_runner(params, "real", CHECK["tol"], CHECK["prec"])(starts[:1], T)[0])
        check = ar.separation(hi[0], ref[0])
    err = errors(cands, starts, T, ref)
    load["end"] = benchio.loadavg()
    table = []
    for name, engine, arith, n, _, _ in cands:
        row = {"candidate": name, "engine": engine, "arithmetic": arith, "orbits_per_run": n,
               "cpu_s_per_orbit_tu": statistics.median(cpu[name]), "cpu_s_per_orbit_tu_runs": cpu[name],
               "steps_per_tu": steps[name]}
        if name in err:
            row |= {"error_after_cycle_median": statistics.median(err[name]), "error_after_cycle_max": max(err[name]),
                    "error_after_cycle": err[name]}
        table.append(row)
    versions = {"heyoka": hy.__version__, "numpy": np.__version__, "numba": numba.__version__}
    return {
        **benchio.header(SCHEMA, opts is QUICK, versions, load),
        "setup": {"params": PARAMS, "t_transient": opts["t_transient"], "settled_state": s.tolist(),
                  "spike_times": [float(x) for x in spikes], "spike_interval_mean": interval,
                  "spike_interval_std": spread, "cycle_T": T, "starts": starts.tolist(), "tol_dd": TOL_DD,
                  "order_dd": ddprogram.taylor_order(TOL_DD), "reference": REFERENCE, "reference_check": CHECK,
                  "eps_row": [float(e) for e in np.linspace(*EPS_ROW, 16)],
                  "cost": "median CPU seconds (process time, one core) per orbit and time unit, candidates interleaved",
                  "error": "separation at 400 bits from the reference after one cycle, per start"},
        "reference_error_vs_320_bits": check,
        "bit_identical_lanes_vs_scalar": bit_identical(params, starts, T),
        "eps_row_lane_vs_common_separation": eps_row_separation(cands, starts, T),
        "rows": table,
        "vectorisation": vector_evidence(),
    }


def plot(path: Path) -> Path:
    """benchmarks/ddbatch.png from the YAML: cost per orbit-time-unit against lanes, error against cost."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = yaml.safe_load(path.read_text())
    rows = {r["candidate"]: r for r in data["rows"]}
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    lanes = [1, 2, 4, 8, 16]
    a.loglog(lanes, [rows[f"dd batch {L}"]["cpu_s_per_orbit_tu"] for L in lanes], "o-", label="double-double batch")
    for name, style in (("dd scalar", "k--"), ("heyoka long double", "r:"), ("heyoka real128", "m-."),
                        ("heyoka double", "g:"), ("heyoka double batch 8", "g--")):
        a.axhline(rows[name]["cpu_s_per_orbit_tu"], ls=style[1:], color=style[0], label=name)
    a.set(xlabel="lanes (orbits per batch)", ylabel="CPU s per orbit per time unit", xticks=lanes,
          xticklabels=[str(x) for x in lanes])
    a.legend(fontsize=7)
    markers = iter("os^vD<>phX*8PdH")
    for r in data["rows"]:
        if "error_after_cycle_median" in r:
            b.loglog(r["cpu_s_per_orbit_tu"], max(r["error_after_cycle_median"], 1e-40), next(markers, "o"),
                     label=r["candidate"], alpha=0.8)
    b.legend(fontsize=6, ncol=2)
    b.set(xlabel="CPU s per orbit per time unit",
          ylabel=f"median error after one cycle (T = {data['setup']['cycle_T']:g})")
    fig.suptitle(f"{data['date']} {data['git_commit'][:10]} load {data['loadavg']['after_timing'].split()[0]}",
                 fontsize=8)
    fig.tight_layout()
    out = path.with_suffix(".png")
    fig.savefig(out, dpi=110)
    return out


def main() -> int:
    """The command line (--out, --quick; --plot-only PATH redraws the plot from a YAML); exit status 0."""
    if len(sys.argv) == 3 and sys.argv[1] == "--plot-only":
        say(f"wrote {plot(Path(sys.argv[2]))}")
        return 0
    out = Path(sys.argv[sys.argv.index("--out") + 1]) if "--out" in sys.argv else REPO / "benchmarks" / "ddbatch.yaml"
    status = benchio.main("ddbatch", __doc__, run, FULL, QUICK, REPO / "benchmarks" / "ddbatch.yaml",
                          "a 20-time-unit window, one repeat (a test run; not a measurement)")
    say(f"wrote {plot(out)}")
    return status


if __name__ == "__main__":
    raise SystemExit(main())
