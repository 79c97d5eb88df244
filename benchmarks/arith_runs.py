"""What benchmarks/ddbatch.py and benchmarks/multiprec.py share: integrators in every arithmetic behind one call,
run(rows of start states, T) -> end states, and the end states compared at high precision.

Arithmetics: heyoka's double, long double, real128 (integrators.flow), MPFR ``real`` at any precision (the same
system, compact mode, the angle reduced after every step like the others), double's SIMD batch
(taylor_adaptive_batch), the double-double engines (scalar DDFlow, batched DDBatch) and the multi-double engine
(MDBatch). End states are mpmath numbers (400 bits): from pairs exactly, from heyoka's types through their full
decimal expansion. Times in the flow's time unit; the start states are doubles (exact in every arithmetic).
"""

from __future__ import annotations

from fractions import Fraction

import heyoka as hy
import mpmath
import numpy as np

from sleighsim.engine import integrators
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.engine.ddtaylor import DDFlow
from sleighsim.model import equations
from sleighsim.precision import Precision

WORKPREC = 400


def settled(params, y0, T: float) -> np.ndarray:
    """The double state after T time units from y0 (integrators.flow in double at its epsilon)."""
    return _double_orbit(params, y0, np.array([0.0, float(T)]))[-1]


def orbit_states(params, y0, times) -> np.ndarray:
    """Double states (rows) of the orbit from y0 at ``times`` (from 0, increasing; double at its epsilon)."""
    return _double_orbit(params, y0, np.asarray(times, dtype=float))


def _double_orbit(params, y0, grid):
    ta = integrators.flow(False, Precision.DOUBLE.epsilon)[0]
    integrators.set_pars(ta, params)
    ta.time = 0.0
    integrators.load(ta, np.asarray(y0, dtype=float))
    res = ta.propagate_grid(grid, callback=integrators.bounded(ta))
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"double orbit stopped: {res[0]}")
    return integrators.samples(ta, res[5]).astype(float)


def mp_rows(x) -> list:
    """Rows of states as lists of mpmath numbers: from (hi, lo) pair arrays exactly, else from any numeric array
    (heyoka's real and real128 through their decimal expansion)."""
    with mpmath.workprec(WORKPREC):
        if isinstance(x, tuple):
            return [[mpmath.mpf(float(h)) + mpmath.mpf(float(lo)) for h, lo in zip(rh, rl)]
                    for rh, rl in zip(np.atleast_2d(x[0]), np.atleast_2d(x[1]))]
        return [[mpmath.mpf(str(v)) for v in row] for row in np.atleast_2d(np.asarray(x))]


def separation(a: list, b: list) -> float:
    """ddtaylor.separation at WORKPREC bits for one pair of states (lists of mpf): max |a - b| over (u, Omega,
    omega, delta modulo 2 pi) over max |(u, Omega, omega)| of a."""
    with mpmath.workprec(WORKPREC):
        d = [abs(x - y) for x, y in zip(a[:3], b[:3])]
        turn = 2 * mpmath.pi
        d.append(abs((a[3] - b[3] + mpmath.pi) % turn - mpmath.pi))
        return float(max(d) / max(abs(x) for x in a[:3]))


def real_flow(tol: float, prec: int):
    """heyoka's sleigh in MPFR ``real`` at ``prec`` bits (compact mode, the angle bounded), compiled once."""
    fp = _real(prec)

    def build():
        sys_ = equations.heyoka_system(False, integrators.DELTA_SHIFT)
        y0 = np.array([fp(0.0), fp(0.1), fp(1.0), fp(np.pi)])
        pars = np.array([fp(float(v)) for v in equations.compile_pars()])
        return hy.taylor_adaptive(sys_, y0, tol=fp(tol), pars=pars, fp_type=hy.real, compact_mode=True, prec=prec)

    return integrators.compiled(("bench real", tol, prec), build)[0]


def _real(prec: int):
    return lambda x: hy.real(x, prec)


def heyoka_runner(params, arithmetic: str, tol: float, prec: int | None = None):
    """run(rows, T) -> (end states as heyoka numbers (rows, 4), steps) of heyoka's flow: ``arithmetic`` "double",
    "long double", "quad" (integrators.flow) or "real" (MPFR at ``prec`` bits)."""
    if arithmetic == "real":
        ta, fp = real_flow(tol, prec), _real(prec)
        ta.pars[:] = real_pars(params, prec)
    else:
        p = Precision.parse(arithmetic)
        ta, fp = integrators.flow(False, tol, p)[0], p.fp_type
        integrators.set_pars(ta, params)

    def run(rows, T):
        out, steps = [], 0
        for y in np.atleast_2d(rows):
            ta.time = fp(0.0)
            integrators.load(ta, np.array([fp(float(v)) for v in y]))
            res = ta.propagate_until(fp(float(T)), callback=integrators.bounded(ta))
            if res[0] != hy.taylor_outcome.time_limit:
                raise RuntimeError(f"{arithmetic} at tol {tol:g}: {res[0]}")
            out.append(integrators.read(ta, 4))
            steps += int(res[3])
        return np.array(out), steps

    return run


def real_pars(params, prec: int) -> np.ndarray:
    """The runtime parameters (equations.heyoka_pars' order) at ``prec`` bits: the physical ones (doubles, exact)
    and the coefficients K[j] of the polynomial form evaluated exactly from them, then rounded (heyoka_pars
    computes them in the integrator's own type, which at prec bits would mean in double)."""
    import sympy as sp

    from sleighsim.model import mechanics as mech

    exact = {s: sp.Rational(Fraction(v)) for s, v in zip(mech.PHYSICAL, params.values)}
    values = [exact[s] for s in mech.PHYSICAL] + [sp.Rational(sp.expand(c.subs(exact)))
                                                  for c in mech.derive().polynomial.coefficients]
    with mpmath.workprec(prec + 64):
        text = [mpmath.nstr(mpmath.mpf(int(v.p)) / int(v.q), int(prec * 0.302) + 10) for v in values]
    return np.array([hy.real(t, prec) for t in text])


def batch_runner(params, tol: float, B: int):
    """run(rows, T) for heyoka's double SIMD batch of B lanes (rows in groups of B, the last padded)."""
    npars = equations.n_heyoka_pars()

    def build():
        sys_ = equations.heyoka_system(False, integrators.DELTA_SHIFT)
        return hy.taylor_adaptive_batch(sys_, np.full((4, B), 0.1), tol=tol, pars=np.zeros((npars, B)))

    ta = integrators.compiled(("bench batch", tol, B), build)[0]
    integrators.set_pars(ta, params)

    def run(rows, T):
        rows = np.atleast_2d(rows)
        out, steps = [], 0
        for start in range(0, len(rows), B):
            block = rows[start:start + B]
            ta.set_time(0.0)
            integrators.load(ta, np.r_[block, np.repeat(block[:1], B - len(block), axis=0)].T)
            ta.propagate_until(float(T), callback=integrators.bounded(ta))
            if any(r[0] != hy.taylor_outcome.time_limit for r in ta.propagate_res):
                raise RuntimeError(f"double batch: {ta.propagate_res}")
            out += list(integrators.read(ta, 4).T[: len(block)])
            steps += sum(int(r[3]) for r in ta.propagate_res[: len(block)])
        return np.array(out), steps

    return run


def dd_runner(params, tol: float, lanes: int | None = None, step: str = "lane", tangent: bool = False):
    """run(rows, T) -> ((hi, lo) end states, steps): DDFlow one row at a time (lanes None) or DDBatch over
    ``lanes`` rows at a time; with ``tangent`` each orbit carries one tangent vector (1, 0, 0, 0)."""
    engine = DDFlow(params, tol) if lanes is None else DDBatch(params, tol, step=step)
    group = 1 if lanes is None else lanes

    def run(rows, T):
        rows = np.atleast_2d(rows)
        hi, lo, steps = [], [], 0
        for start in range(0, len(rows), group):
            block = rows[start:start + group]
            v = np.tile([1.0, 0.0, 0.0, 0.0], (len(block), 1))
            if lanes is None:
                out = (engine.propagate_tangent_grid(block[0], v[0], [T]) if tangent
                       else engine.propagate_grid(block[0], [T]))
                h, lo_ = out[0][-1:], out[1][-1:]
            else:
                out = engine.propagate_tangent_grid(block, v, [T]) if tangent else engine.propagate_grid(block, [T])
                h, lo_ = out[0][:, -1], out[1][:, -1]
            hi += list(h)
            lo += list(lo_)
            steps += int(np.sum(engine.steps))
        return (np.array(hi), np.array(lo)), steps

    return run
