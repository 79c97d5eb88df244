#!/usr/bin/env python
"""Peers at the precisions that matter: work against precision beyond double, heyoka against what a
Python user could use instead.

    taskset -c 0 python benchmarks/extended_peers.py [--out benchmarks/extended_peers.yaml] [--quick]

The paper's sleigh (eps 0.1, b 1, K2 1.1) from y0 = (0, 0.1, 1, 0) (peers.Y0_REFERENCE) over [0, T]
(T = 20 in the full run, 2 with --quick: a horizon where mpmath is affordable). Methods:

- heyoka long double: integrators.flow(False, tol, Precision.LONG_DOUBLE) (full mode), tols 1e-12 .. eps_ld;
- heyoka real128: integrators.flow(False, tol, Precision.QUAD) (compact mode), tols 1e-16 .. 1e-32 and eps_quad;
- heyoka real at 113 bits: the same system and build as real128 (compact mode, delta bounded the same
  way) with heyoka's arbitrary-precision ``real`` (MPFR) at real128's precision, the same tols and the
  very same parameter values (real128's, converted exactly): a cross-check of real128 (its errors should
  match) and the cost of MPFR against quadmath;
- mpmath odefun: mpmath's Taylor integrator (``mpmath.odefun``, its Taylor coefficients from Euler
  steps and finite differences at a raised working precision) at mp.dps = 34, on the sleigh's
  right-hand side lambdified from the project's SymPy derivation with modules="mpmath" (peers'
  polynomial form with its coefficients written out in the physical parameters, so it evaluates at
  whatever precision mpmath works in). Its ``tol`` is its default (2^-(prec + 10)) and looser ones
  (1e-32 .. 1e-16); it fixes its degree from dps (3 + 3 dps / 2 = 54 at dps 34) and caps a step at 1/2.

Every method starts from the same state and parameters: the physical parameters are doubles, exact in
every arithmetic; heyoka's runtime coefficients K_j are computed in each integrator's own arithmetic
(equations.heyoka_pars, as integrators.set_pars gives them), mpmath computes them inside the rhs.

Error: the end state at T against a reference by heyoka ``real`` at 200 bits, tol 2^-200 (checked
against 240 bits, tol 2^-240: ``reference.check``), as max |y - y_ref| over the four components, delta
compared modulo 2 pi (peers.state_error's metric), evaluated in mpmath at 400 bits from the exact binary
values (the stored angle's shift pi is removed there too, not in the integrator's arithmetic).

Timing: wall seconds (time.perf_counter; CPU seconds beside) of one run from setting the initial state
to the end state (heyoka: propagate_until with the angle-reducing callback; mpmath: building the odefun
object and evaluating it at T, which computes every step: odefun caches its steps, so each run needs a
fresh object). One untimed warm-up run over the same horizon, then the median of ``repeats`` runs (5 for
heyoka, 3 for mpmath; 1 timed run where the warm-up took more than 60 s, noted in the row). Setup
(setup_s) apart: heyoka's integrator build (the full run: disk cache off, in-memory cache cleared, so a
real compilation; --quick: disk cache as found), mpmath's lambdify of the rhs. Ratio to heyoka real128
at equal error: a row's wall over the fastest real128 wall whose error is at most the row's error (within
0.1 %: EQUAL_ERROR_SLACK; None where real128 never gets that accurate); ``ratios_at_error_target``: the
same per method and target, the fastest wall of each method reaching the target (the rule of
scenes.bench.peer_ratios).
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
import mpmath
import numpy as np
import sympy as sp

from sleighsim.engine import integrators, peers
from sleighsim.model import equations, mechanics
from sleighsim.model.params import Params
from sleighsim.ops import benchio
from sleighsim.precision import Precision

say = partial(benchio.say, "extended_peers")

SCHEMA = "sleighsim.extended_peers/1"
PARAMS = {"eps": 0.1, "b": 1.0, "K2": 1.1}
Y0 = tuple(float(v) for v in peers.Y0_REFERENCE)  # (u, Omega, omega, delta) = (0, 0.1, 1, 0)
EPS_LD, EPS_QUAD = Precision.LONG_DOUBLE.epsilon, Precision.QUAD.epsilon
QUAD_BITS = 113  # real128's significand
MPMATH_DPS = 34
ERROR_BITS = 400  # mpmath precision of the error evaluation
SLOW_S = 60.0  # a warm-up longer than this: one timed run only

METHODS = {  # method -> precision label
    "heyoka long double": "long double (64-bit significand)",
    "heyoka real128": "quad, real128 (113-bit significand)",
    "heyoka real 113": "real (MPFR) at 113 bits",
    "mpmath odefun": f"mpf at dps {MPMATH_DPS} (116 bits)",
}
OURS = "heyoka real128"

FULL = {
    "t_end": 20.0,
    "ld_tols": [1e-12, 1e-14, 1e-16, 1e-18, EPS_LD],
    "quad_tols": [1e-16, 1e-18, 1e-20, 1e-22, 1e-24, 1e-26, 1e-28, 1e-30, 1e-32, EPS_QUAD],
    "mpmath_tols": [None, 1e-32, 1e-28, 1e-24, 1e-20, 1e-16],  # None: mpmath's default, 2^-(prec + 10)
    "repeats": 5, "repeats_mpmath": 3,
    "ref_prec": 200, "check_prec": 240,
    "cold_compile": True,
}
QUICK = {
    "t_end": 2.0,
    "ld_tols": [1e-12, EPS_LD],
    "quad_tols": [1e-16, 1e-24, 1e-32],
    "mpmath_tols": [None, 1e-16],
    "repeats": 3, "repeats_mpmath": 3,
    "ref_prec": 200, "check_prec": 240,
    "cold_compile": False,
}
ERROR_TARGETS = [1e-12, 1e-16, 1e-20, 1e-24, 1e-28, 1e-32]


# ----------------------------------------------------------------------------- timing


def timed(fn, repeats: int, slow_s: float = SLOW_S) -> dict:
    """One untimed warm-up call of ``fn`` (its wall kept), then the median of ``repeats`` timed calls,
    or of one when the warm-up took more than ``slow_s``."""
    w0 = time.perf_counter()
    result = fn()
    warm = time.perf_counter() - w0
    note = ""
    if warm > slow_s:
        repeats, note = 1, f"one timed run: the warm-up took {warm:.0f} s > {slow_s:g} s"
    walls, cpus = [], []
    for _ in range(repeats):
        c0, w0 = time.process_time(), time.perf_counter()
        result = fn()
        walls.append(time.perf_counter() - w0)
        cpus.append(time.process_time() - c0)
    return {"result": result, "wall_s": statistics.median(walls), "cpu_s": statistics.median(cpus),
            "walls": [round(w, 6) for w in walls], "warmup_wall_s": round(warm, 6), "repeats": repeats, "note": note}


# ----------------------------------------------------------------------------- exact arithmetic of the errors


def to_mpf(x):
    """The exact binary value of x (float, long double, real128, real, mpf) as an mpf at the current precision
    (decimal round trip for real128 and real, 36 and more significant digits: below 1e-35 relative)."""
    if isinstance(x, mpmath.mpf):
        return +x
    if isinstance(x, np.longdouble):
        n, d = x.as_integer_ratio()
        return mpmath.mpf(n) / d
    if isinstance(x, (hy.real128, hy.real)):
        return mpmath.mpf(str(x))
    return mpmath.mpf(float(x))


def model_state(raw, shifted: bool):
    """Four mpf (at ERROR_BITS) in the model's variables from an end state; ``shifted``: delta is stored
    as delta + integrators.DELTA_SHIFT (a double, removed here exactly)."""
    with mpmath.workprec(ERROR_BITS):
        y = [to_mpf(v) for v in list(raw)[:4]]
        if shifted:
            y[peers.DELTA] -= mpmath.mpf(integrators.DELTA_SHIFT)
    return y


def state_error(y, ref) -> float:
    """max |y - ref| over the components, delta modulo 2 pi (peers.state_error), at ERROR_BITS."""
    with mpmath.workprec(ERROR_BITS):
        d = [a - b for a, b in zip(y, ref)]
        two_pi = 2 * mpmath.pi
        d[peers.DELTA] = (d[peers.DELTA] + mpmath.pi) % two_pi - mpmath.pi
        return float(max(abs(v) for v in d))


# ----------------------------------------------------------------------------- heyoka


def _check(ta, res, what):
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"{what}: propagation stopped at t = {float(ta.time):.6g}: heyoka outcome {res[0].name}")


def _build(key, build, cold: bool):
    """(integrator, compile wall s, compile cpu s) through integrators.compiled (so its angle is
    registered for integrators.bounded); heyoka's in-memory cache cleared first when ``cold``."""
    if cold:
        hy.llvm_state.clear_memcache()
    c0 = time.process_time()
    ta, wall = integrators.compiled(key, build)
    return ta, wall, time.process_time() - c0


def flow_native(precision: str, tol: float, cold: bool):
    """The project's integrator, integrators.flow(False, tol, ...), in long double or quad: (integrator,
    build wall s, build cpu s); heyoka's in-memory cache cleared first when ``cold``."""
    if cold:
        hy.llvm_state.clear_memcache()
    c0 = time.process_time()
    ta, wall = integrators.flow(False, tol, Precision.parse(precision))
    return ta, wall, time.process_time() - c0


def real_values(values, prec: int) -> np.ndarray:
    """An array of heyoka ``real`` at ``prec`` bits (values exact in it: doubles, long doubles, real128)."""
    return np.array([hy.real(v, prec) for v in values], dtype=hy.real)


def flow_real(prec: int, tol, pars, cold: bool):
    """integrators.flow's build in heyoka's ``real`` at ``prec`` bits (compact mode, as in quad): same
    system, delta stored shifted and kept in [0, 2 pi) by integrators.bounded. ``pars``: reals at prec."""
    def build():
        y0 = real_values([0.0, 0.1, 1.0, integrators.DELTA_SHIFT], prec)
        t = tol if isinstance(tol, hy.real) else hy.real(tol, prec)
        return hy.taylor_adaptive(equations.heyoka_system(False, integrators.DELTA_SHIFT), y0, tol=t, pars=pars,
                                  fp_type=hy.real, prec=prec, compact_mode=True)

    return _build(("extended_peers real", prec, str(tol)), build, cold)


def heyoka_runner(ta, pars, t_end: float, what: str):
    """run() -> (raw end state, steps): the initial state and parameters set, propagate_until t_end
    with the angle reducer."""
    dtype = ta.state.dtype
    if dtype == hy.real:
        prec = ta.prec
        zero, T = hy.real(0, prec), hy.real(t_end, prec)
        y0 = real_values([*Y0[:3], Y0[3] + integrators.DELTA_SHIFT], prec)  # 0 + pi(double): exact
    else:
        fp = dtype.type
        zero, T = fp(0), fp(t_end)
        y0 = np.array([*Y0[:3], Y0[3] + integrators.DELTA_SHIFT]).astype(dtype)
    callback = integrators.bounded(ta)

    def run():
        ta.time = zero
        ta.state[:] = y0
        ta.pars[:] = pars
        res = ta.propagate_until(T, callback=callback)
        _check(ta, res, what)
        return list(ta.state), int(res[3])

    return run


def reference(params, t_end: float, prec: int, cold: bool):
    """End state (model variables, mpf) at t_end by heyoka ``real`` at ``prec`` bits, tol 2^-prec; the
    coefficients K_j computed in mpmath at prec + 64 bits. Also the steps, order and build seconds."""
    with mpmath.workprec(prec + 64):
        phys = [mpmath.mpf(v) for v in params.values]
        K = _coefficients_mpmath()(*phys)
        digits = int(prec * math.log10(2)) + 20
        pars = np.array([hy.real(float(v), prec) for v in params.values]
                        + [hy.real(mpmath.nstr(k, digits, min_fixed=1, max_fixed=0), prec) for k in K], dtype=hy.real)
    tol = hy.real(2, prec) ** -prec
    ta, wall, _ = flow_real(prec, tol, pars, cold)
    run = heyoka_runner(ta, pars, t_end, f"reference real {prec}")
    w0 = time.perf_counter()
    raw, steps = run()
    return {"state": model_state(raw, True), "prec": prec, "tol": f"2^-{prec}", "order": int(ta.order),
            "steps": steps, "build_s": wall, "run_s": time.perf_counter() - w0}


def _coefficients_mpmath():
    return sp.lambdify(mechanics.PHYSICAL, list(mechanics.derive().polynomial.coefficients), modules="mpmath")


# ----------------------------------------------------------------------------- mpmath


def mpmath_rhs():
    """F(t, y) -> list of 4 mpf: the sleigh's rhs (peers' polynomial form, lambdified with modules="mpmath"),
    and its setup seconds (the lambdify; the SymPy derivation is built beforehand)."""
    peers.lambdified.cache_clear()
    w0 = time.perf_counter()
    lam = peers.lambdified("mpmath")
    setup = time.perf_counter() - w0
    return lam, setup


def mpmath_runner(lam, params, t_end: float, tol, dps: int = MPMATH_DPS):
    """run() -> (end state as mpf, steps): a fresh odefun (it caches its steps) at dps, evaluated at t_end."""
    phys = [mpmath.mpf(v) for v in params.values]  # doubles: exact
    y0 = [mpmath.mpf(v) for v in Y0]

    def F(t, y):
        return list(lam(*y, *phys))

    def run():
        with mpmath.workdps(dps):
            f = mpmath.odefun(F, 0, y0, tol=tol)
            y = f(mpmath.mpf(t_end))
        return y, _odefun_steps(f)

    return run


def _odefun_steps(f):
    """Steps (Taylor expansions) an odefun interpolant has computed, read from its closure (None if that
    changes in another mpmath version)."""
    try:
        cells = dict(zip(f.__code__.co_freevars, (c.cell_contents for c in f.__closure__)))
        gs = cells["get_series"]
        inner = dict(zip(gs.__code__.co_freevars, (c.cell_contents for c in gs.__closure__)))
        return len(inner["series_boundaries"]) - 1
    except (AttributeError, KeyError, TypeError, ValueError):  # pragma: no cover - mpmath internals
        return None


def mpmath_tol_bits(tol, dps: int = MPMATH_DPS) -> int:
    """mpmath odefun's internal tolerance exponent tol_prec (its step h and its radius criterion are
    2^-tol_prec), as odefun computes it."""
    with mpmath.workdps(dps):
        return int(-mpmath.log(tol, 2)) + 10 if tol else mpmath.mp.prec + 10


# ----------------------------------------------------------------------------- the table


#: Errors this close (relative) count as equal in the ratio rule: real128 and real 113 reach the same error
#: up to the last bits, and a strict comparison would then pick a tighter real128 row.
EQUAL_ERROR_SLACK = 1e-3


def ratio_rows(rows) -> None:
    """ratio_to_real128_at_equal_error per row (see the module docstring)."""
    ours = [(r["error"], r["wall_s"]) for r in rows if r["method"] == OURS]
    for r in rows:
        ok = [w for e, w in ours if e <= r["error"] * (1 + EQUAL_ERROR_SLACK)]
        r["ratio_to_real128_at_equal_error"] = r["wall_s"] / min(ok) if ok else None


def target_ratios(rows, targets) -> dict:
    """Per target: per method the fastest wall reaching it, and its ratio to real128's (None where either
    never reaches it)."""
    out = {}
    for t in targets:
        fastest = {}
        for m in METHODS:
            ok = [r["wall_s"] for r in rows if r["method"] == m and r["error"] <= t]
            fastest[m] = min(ok) if ok else None
        base = fastest[OURS]
        out[f"{t:.0e}"] = {m: {"wall_s": w, "ratio_to_real128": (w / base if w is not None and base else None)}
                           for m, w in fastest.items()}
    return out


def run(opts) -> dict:
    """The measurement with options ``opts`` (FULL or QUICK: horizon t_end in time units, tols, repeats,
    cold_compile): the reference, one row per method and tol (error, wall and CPU seconds, steps, setup
    seconds), the real128/real113 cross-check and the ratios at the error targets, as a YAML-ready dict."""
    params = Params.paper(**PARAMS)
    T = float(opts["t_end"])
    load = {"start": benchio.loadavg()}
    cold = opts["cold_compile"]

    # start-up outside every setup timing: the SymPy model, the runtime parameters, LLVM
    mechanics.derive()
    equations.heyoka_system(False, integrators.DELTA_SHIFT)
    for fp in (np.longdouble, hy.real128):
        equations.compile_pars(fp)
    integrators.guarded_heyoka()  # heyoka's JIT cache checked before the first build (issue 54)
    x = hy.make_vars("x")
    hy.taylor_adaptive([(x, -x)], [1.0])
    if cold:
        hy.llvm_state.set_diskcache_enabled(False)  # this process only

    say(f"reference: real {opts['ref_prec']} bits over T = {T:g}")
    ref = reference(params, T, opts["ref_prec"], cold)
    check = reference(params, T, opts["check_prec"], cold)
    ref_diff = state_error(check["state"], ref["state"])
    say(f"reference: {ref['steps']} steps, order {ref['order']}, {ref['run_s']:.2f} s; against {opts['check_prec']} "
        f"bits: {ref_diff:.2e}")

    rows = []

    def add(method, tol, setup_s, t, end_state, steps, order=None, extra=None):
        err = state_error(end_state, ref["state"])
        row = {"method": method, "precision": METHODS[method], "tol": tol, "wall_s": t["wall_s"],
               "setup_s": setup_s, "error": err, "repeats": t["repeats"], "cpu_s": t["cpu_s"], "walls": t["walls"],
               "warmup_wall_s": t["warmup_wall_s"], "steps": steps, "order": order, "note": t["note"]}
        row.update(extra or {})
        row["_state"] = end_state
        rows.append(row)
        say(f"{method:<20} tol {tol:.1e}  error {err:.2e}  wall {t['wall_s'] * 1e3:10.3f} ms  "
            f"setup {setup_s:.2f} s  steps {steps}  {t['note']}")
        return row

    def heyoka_rows(method, precision, tols):
        for tol in tols:
            ta, wall, cpu = flow_native(precision, tol, cold)
            pars = equations.heyoka_pars(params, ta.pars.dtype)  # as integrators.set_pars computes them
            t = timed(heyoka_runner(ta, pars, T, f"{method} tol {tol:g}"), opts["repeats"])
            raw, steps = t["result"]
            add(method, tol, wall, t, model_state(raw, True), steps, int(ta.order), {"setup_cpu_s": cpu})

    heyoka_rows("heyoka long double", "long double", opts["ld_tols"])
    heyoka_rows("heyoka real128", "quad", opts["quad_tols"])

    # real at 113 bits: real128's own parameter values (equations.heyoka_pars in real128), converted exactly
    pars113 = real_values(equations.heyoka_pars(params, hy.real128), QUAD_BITS)
    for tol in opts["quad_tols"]:
        ta, wall, cpu = flow_real(QUAD_BITS, tol, pars113, cold)
        t = timed(heyoka_runner(ta, pars113, T, f"real 113 tol {tol:g}"), opts["repeats"])
        raw, steps = t["result"]
        add("heyoka real 113", tol, wall, t, model_state(raw, True), steps, int(ta.order), {"setup_cpu_s": cpu})
    load["after_heyoka"] = benchio.loadavg()

    lam, setup = mpmath_rhs()
    for tol in opts["mpmath_tols"]:
        bits = mpmath_tol_bits(tol)
        say(f"mpmath odefun dps {MPMATH_DPS} tol {tol or 'default'} over T = {T:g} ...")
        t = timed(mpmath_runner(lam, params, T, tol), opts["repeats_mpmath"])
        y, steps = t["result"]
        add("mpmath odefun", float(tol) if tol else 2.0**-bits, setup, t, model_state(y, False), steps,
            3 + int(3 * MPMATH_DPS / 2.0),
            {"tol_requested": tol if tol else "default", "internal_tol": f"2^-{bits}", "dps": MPMATH_DPS})
    load["end"] = benchio.loadavg()

    ratio_rows(rows)
    cross = []
    for tol in opts["quad_tols"]:
        a = next(r for r in rows if r["method"] == OURS and r["tol"] == tol)
        b = next(r for r in rows if r["method"] == "heyoka real 113" and r["tol"] == tol)
        cross.append({"tol": tol, "error_real128": a["error"], "error_real113": b["error"],
                      "end_state_difference": state_error(a["_state"], b["_state"]),
                      "error_ratio": b["error"] / a["error"],
                      "wall_ratio_real113_over_real128": b["wall_s"] / a["wall_s"],
                      "steps_real128": a["steps"], "steps_real113": b["steps"]})

    for r in rows:
        del r["_state"]
    return {
        **benchio.header(SCHEMA, opts is QUICK,
                         {"heyoka": hy.__version__, "mpmath": mpmath.__version__, "numpy": np.__version__}, load),
        "setup": {
            "params": PARAMS, "y0": list(Y0), "t_end": T,
            "error": "max |y(T) - y_ref(T)| over (u, Omega, omega, delta), delta modulo 2 pi, in mpmath at "
                     f"{ERROR_BITS} bits from the exact binary end states",
            "timing": "wall seconds of one run (state set to end state); one untimed warm-up over the same "
                      f"horizon, then the median of the repeats ({opts['repeats']} heyoka, {opts['repeats_mpmath']} "
                      f"mpmath; 1 where the warm-up took more than {SLOW_S:g} s)",
            "setup_s": ("heyoka: integrator build, disk cache off and in-memory cache cleared (a real compilation)"
                        if cold else "heyoka: integrator build, disk cache as found (possibly a cache load)")
                       + "; mpmath: lambdify of the rhs (the SymPy derivation built beforehand, for both)",
            "heyoka": "long double and real128: integrators.flow (full mode in long double, compact in quad), "
                      "delta kept in [0, 2 pi) by integrators.bounded; real 113: the same build in heyoka.real "
                      "(compact mode) with real128's parameter values",
            "mpmath": f"mpmath.odefun (Taylor, degree {3 + int(3 * MPMATH_DPS / 2.0)}) at dps {MPMATH_DPS}; a "
                      "fresh odefun per run; tol: the requested tol (its default: 2^-(prec + 10)); internal_tol "
                      "2^-tol_prec is its Euler step and radius criterion",
            "ratio_rule": f"wall / fastest heyoka real128 wall with error <= this error (errors within "
                          f"{EQUAL_ERROR_SLACK:g} relative count as equal)",
        },
        "reference": {"method": "heyoka real", "prec": ref["prec"], "tol": ref["tol"], "order": ref["order"],
                      "steps": ref["steps"], "build_s": ref["build_s"], "run_s": ref["run_s"],
                      "state": [mpmath.nstr(v, 40) for v in ref["state"]],
                      "check": {"prec": check["prec"], "tol": check["tol"], "difference": ref_diff}},
        "rows": rows,
        "cross_check_real128_vs_real113": cross,
        "ratios_at_error_target": target_ratios(rows, ERROR_TARGETS),
    }


def main() -> int:
    """The command line (--out, --quick); exit status 0."""
    return benchio.main("extended_peers", __doc__, run, FULL, QUICK, REPO / "benchmarks" / "extended_peers.yaml",
                        "T = 2, fewer tols, disk cache as found (a test run; not a measurement)")


if __name__ == "__main__":
    raise SystemExit(main())
