"""A Taylor integrator for the sleigh in double-double arithmetic (:mod:`sleighsim.engine.ddarith`,
unit roundoff 2^-106 ~ 1.2e-32), compiled with numba: one orbit at a time (the batched engine, many orbits in
the CPU's vector lanes, is :mod:`sleighsim.engine.ddbatch`; this one is its reference).

The recurrences are derived, not transcribed (:mod:`sleighsim.engine.ddprogram`: the polynomial form of the
equations as a program of Cauchy products, linear combinations, a division and the sine and cosine
recurrences), and evaluated here per Taylor order in pairs: the Cauchy products as Ogita-Rump-Oishi
compensated dot products, S_0, C_0 from ddarith.sincos, the linear combinations' coefficients the exact
fractions of the double parameters rounded to pairs. With a tangent vector (forward mode through the same
recurrences) the vector is renormalised after every step by a power of two (exact), and its log-norm
accumulated.

Order and step as heyoka's taylor_adaptive (its taylor_determine_h): order p = ceil(-ln(tol) / 2 + 1);
rho = min((A / max_i |x_i^[p]|)^(1/p), (A / max_i |x_i^[p-1]|)^(1/(p-1))) over the integrated variables
(with the tangent ones in the tangent variant), A = max(1, max_i |x_i^[0]|); h = rho exp(-0.7 / (p - 1)) / e^2.
As in sleighsim.engine.integrators the stored angle is delta + pi, reduced into [0, 2 pi) after every step
(an exact symmetry; pi and 2 pi in triple-double), so S = -sin(stored), C = -cos(stored).
States are (hi, lo) pairs; times in the flow's time unit, measured from the initial state.
"""

from __future__ import annotations

import math
from functools import cache

import mpmath
import numpy as np
import sympy as sp

from sleighsim.engine import ddarith as dd
from sleighsim.engine.ddarith import jit
from sleighsim.engine.ddprogram import (  # noqa: F401  (re-exported: the program's public names)
    DERIV,
    DIV,
    DIVT,
    LIN,
    MUL,
    MUL2,
    SINCOS,
    Program,
    coefficients,
    program,
    taylor_order,
)
from sleighsim.model import mechanics as mech
from sleighsim.model.params import Params, positive

#: Admissible tolerances: from a little below double-double's rounding to a loose one.
TOL_RANGE = (1e-34, 1e-6)
#: Steps allowed per propagation unless told otherwise.
MAX_STEPS = 10**8
OK, TOO_MANY_STEPS, NOT_FINITE = 0, 1, 2

# ---------------------------------------------------------------- compiled kernels


@jit
def _dot(Xh, Xl, a, b, j0, k, s, c):
    """(s, c) + sum_{j=j0..k} X[a, j] X[b, k - j], unnormalised (Ogita-Rump-Oishi Dot2 on pairs)."""
    for j in range(j0, k + 1):
        ah, al, bh, bl = Xh[a, j], Xl[a, j], Xh[b, k - j], Xl[b, k - j]
        p, e = dd.two_prod(ah, bh)
        s, t = dd.two_sum(s, p)
        c += t + e + dd.fma(ah, bl, al * bh)
    return s, c


@jit
def _store(Xh, Xl, i, k, s, c):
    Xh[i, k], Xl[i, k] = dd.two_sum(s, c)


@jit
def _lin(Xh, Xl, out, start, count, k, lin_src, coef):
    s, c = 0.0, 0.0
    for m in range(start, start + count):
        i = lin_src[m]
        p, e = dd.two_prod(coef[m, 0], Xh[i, k])
        s, t = dd.two_sum(s, p)
        c += t + e + dd.fma(coef[m, 0], Xl[i, k], coef[m, 1] * Xh[i, k])
    _store(Xh, Xl, out, k, s, c)


@jit
def _div(Xh, Xl, op, k):
    """q_k = (N_k - sum_{j=1..k} D_j q_{k-j}) / D_0 and, for DIVT, the tangent's
    q'_k = (N'_k - sum_{j=0..k} D'_j q_{k-j} - sum_{j=1..k} D_j q'_{k-j}) / D_0."""
    out, num, den = op[1], op[2], op[3]
    s, c = _dot(Xh, Xl, den, out, 1, k, 0.0, 0.0)
    if op[0] == DIVT:
        s, c = _dot(Xh, Xl, op[4], op[5], 0, k, s, c)
    rh, rl = dd.sub(Xh[num, k], Xl[num, k], *dd.two_sum(s, c))
    Xh[out, k], Xl[out, k] = dd.div(rh, rl, Xh[den, 0], Xl[den, 0])


@jit
def _sincos(Xh, Xl, op, k):
    """S_k, C_k of sign (sin x, cos x): from x_0 at order 0, else k S_k = (x' C)_{k-1}, k C_k = -(x' S)_{k-1}."""
    S, C, x, w, sign = op[1], op[2], op[3], op[4], op[5]
    if k == 0:
        sh, sl, ch, cl = dd.sincos(Xh[x, 0], Xl[x, 0])
        Xh[S, 0], Xl[S, 0], Xh[C, 0], Xl[C, 0] = sign * sh, sign * sl, sign * ch, sign * cl
        return
    s, c = _dot(Xh, Xl, w, C, 0, k - 1, 0.0, 0.0)
    Xh[S, k], Xl[S, k] = dd.div_d(*dd.two_sum(s, c), float(k))
    s, c = _dot(Xh, Xl, w, S, 0, k - 1, 0.0, 0.0)
    Xh[C, k], Xl[C, k] = dd.div_d(*dd.two_sum(-s, -c), float(k))


@jit
def _order(Xh, Xl, ops, lin_src, coef, k):
    """Every operation of the program at order k (the state's order k + 1 at the end)."""
    for o in range(ops.shape[0]):
        op = ops[o]
        code = op[0]
        if code == MUL:
            _store(Xh, Xl, op[1], k, *_dot(Xh, Xl, op[2], op[3], 0, k, 0.0, 0.0))
        elif code == MUL2:
            s, c = _dot(Xh, Xl, op[2], op[3], 0, k, 0.0, 0.0)
            _store(Xh, Xl, op[1], k, *_dot(Xh, Xl, op[4], op[5], 0, k, s, c))
        elif code == LIN:
            _lin(Xh, Xl, op[1], op[2], op[3], k, lin_src, coef)
        elif code == DIV or code == DIVT:
            _div(Xh, Xl, op, k)
        elif code == SINCOS:
            _sincos(Xh, Xl, op, k)
        else:
            Xh[op[1], k + 1], Xl[op[1], k + 1] = dd.div_d(Xh[op[2], k], Xl[op[2], k], float(k + 1))


@jit
def _step_size(Xh, n_vars, p):
    """heyoka's step: rho from the orders p and p - 1 (relative when the state's max norm exceeds 1)."""
    a, m_p, m_pm1 = 0.0, 0.0, 0.0
    for i in range(n_vars):
        a = max(a, abs(Xh[i, 0]))
        m_p = max(m_p, abs(Xh[i, p]))
        m_pm1 = max(m_pm1, abs(Xh[i, p - 1]))
    a = max(a, 1.0)
    rho = min((a / m_p) ** (1.0 / p), (a / m_pm1) ** (1.0 / (p - 1)))
    return rho * math.exp(-0.7 / (p - 1)) / math.e**2


@jit
def _horner(Xh, Xl, i, p, th, tl):
    """sum_k X[i, k] t^k for the pair t."""
    sh, sl = Xh[i, p], Xl[i, p]
    for k in range(p - 1, -1, -1):
        sh, sl = dd.mul(sh, sl, th, tl)
        sh, sl = dd.add(sh, sl, Xh[i, k], Xl[i, k])
    return sh, sl


@jit
def _emit(Xh, Xl, p, n_vars, grid, g, th, tl, hh, last, out_h, out_l, out_e, scale_exp):
    """Dense output: the step's Taylor polynomials at the grid times from index g that fall in the step
    (every remaining one on the last step). Returns the next grid index."""
    while g < grid.shape[0]:
        tauh, taul = dd.sub(grid[g], 0.0, th, tl)
        if not last and tauh > hh:
            break
        for i in range(n_vars):
            out_h[g, i], out_l[g, i] = _horner(Xh, Xl, i, p, tauh, taul)
        out_e[g] = scale_exp
        g += 1
    return g


@jit
def _renormalise(yh, yl):
    """Scale the tangent vector (variables 4..7) by the power of two 2^-e nearest its norm (exact); returns e."""
    norm = math.sqrt(yh[4] ** 2 + yh[5] ** 2 + yh[6] ** 2 + yh[7] ** 2)
    if not (norm > 0.0 and math.isfinite(norm)):
        return 0
    e = int(round(math.log2(norm)))
    f = math.ldexp(1.0, -e)
    for i in range(4, 8):
        yh[i], yl[i] = yh[i] * f, yl[i] * f
    return e


@jit
def _propagate(Xh, Xl, ops, lin_src, coef, p, n_vars, yh, yl, grid, out_h, out_l, out_e, max_steps):
    """Taylor steps from (yh, yl) at t = 0 to grid[-1], filling the outputs at the grid times. Returns
    (status, steps, t) with status OK, TOO_MANY_STEPS or NOT_FINITE (a non-finite state or step)."""
    T = grid[grid.shape[0] - 1]
    th, tl, g, steps, scale_exp = 0.0, 0.0, 0, 0, 0
    while True:
        if steps >= max_steps:
            return TOO_MANY_STEPS, steps, th
        for i in range(n_vars):
            Xh[i, 0], Xl[i, 0] = yh[i], yl[i]
        for k in range(p):
            _order(Xh, Xl, ops, lin_src, coef, k)
        h = _step_size(Xh, n_vars, p)
        if not h > 0.0:
            return NOT_FINITE, steps, th
        rh, rl = dd.sub(T, 0.0, th, tl)
        last = h >= rh
        hh, hl = (rh, rl) if last else (h, 0.0)
        g = _emit(Xh, Xl, p, n_vars, grid, g, th, tl, hh, last, out_h, out_l, out_e, scale_exp)
        for i in range(n_vars):
            yh[i], yl[i] = _horner(Xh, Xl, i, p, hh, hl)
            if not math.isfinite(yh[i]):
                return NOT_FINITE, steps, th
        th, tl = dd.add(th, tl, hh, hl)
        steps += 1
        yh[3], yl[3] = dd.reduce_angle(yh[3], yl[3])
        if n_vars == 8:
            scale_exp += _renormalise(yh, yl)
        if last:
            return OK, steps, th


@jit
def _jet(Xh, Xl, ops, lin_src, coef, p, n_vars, yh, yl):
    """The normalised Taylor coefficients (orders 0..p) of every series at the state (yh, yl)."""
    for i in range(n_vars):
        Xh[i, 0], Xl[i, 0] = yh[i], yl[i]
    for k in range(p):
        _order(Xh, Xl, ops, lin_src, coef, k)


@jit
def shift_angle(hi, lo, n):
    """Column 3 of the pair arrays (rows) minus n pi (triple-double pi)."""
    for r in range(hi.shape[0]):
        hi[r, 3], lo[r, 3] = dd.sub_triple(hi[r, 3], lo[r, 3], dd.PI, n)


# ---------------------------------------------------------------- the Python interface


def as_pair(y, n: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """A state as double-double (hi, lo) float arrays (n,): from a (hi, lo) tuple, or from an array of
    doubles, long doubles or heyoka real128 (hi its nearest double, lo the nearest double of the rest).
    ValueError on a wrong shape or a non-finite component."""
    if isinstance(y, tuple) and len(y) == 2:
        hi, lo = (np.array(a, dtype=float) for a in y)
    else:
        arr = np.asarray(y)
        hi = arr.astype(float)
        lo = (arr - hi.astype(arr.dtype)).astype(float) if arr.dtype != float else np.zeros_like(hi)
    if hi.shape != (n,) or lo.shape != (n,):
        raise ValueError(f"a state must have {n} components, got shapes {hi.shape} and {lo.shape}")
    if not (np.all(np.isfinite(hi)) and np.all(np.isfinite(lo))):
        raise ValueError(f"the state must be finite, got {hi} + {lo}")
    return hi, lo


def check_grid(t_grid) -> np.ndarray:
    """The sample times (from the initial state, time units): finite, >= 0, non-decreasing, at least one."""
    grid = np.array(t_grid, dtype=float).reshape(-1)
    if grid.size == 0 or not np.all(np.isfinite(grid)) or grid[0] < 0 or np.any(np.diff(grid) < 0):
        raise ValueError("t_grid must hold at least one finite time >= 0, in non-decreasing order")
    return grid


class DDFlow:
    """The sleigh with ``params`` integrated in double-double by the derived Taylor recurrences at
    tolerance ``tol`` (in TOL_RANGE; heyoka's order and step rule). ``steps`` is the number of steps
    of the last propagation. A propagation that exceeds ``max_steps`` or meets a non-finite step or state
    raises RuntimeError naming the time."""

    def __init__(self, params: Params, tol: float = 1e-32, max_steps: int = MAX_STEPS):
        tol = positive("tol", tol)
        if not TOL_RANGE[0] <= tol <= TOL_RANGE[1]:
            raise ValueError(f"tol = {tol:g} is outside the admissible range [{TOL_RANGE[0]:g}, {TOL_RANGE[1]:g}]")
        self.params, self.tol, self.order, self.max_steps = params, tol, taylor_order(tol), int(max_steps)
        self.steps = 0
        self._coef = {t: coefficients(program(t), params) for t in (False, True)}

    def _series(self, yh, yl, tangent: bool):
        """The program, its series arrays (hi, lo) and the stored state (delta + pi reduced into [0, 2 pi))."""
        prog = program(tangent)
        shape = (prog.n_series, self.order + 1)
        Xh, Xl = np.zeros(shape), np.zeros(shape)
        Xh[prog.one, 0] = 1.0
        yh, yl = np.array(yh, dtype=float), np.array(yl, dtype=float)
        yh[3], yl[3] = dd.reduce_angle(*dd.sub_triple(yh[3], yl[3], dd.PI, -1))
        return prog, Xh, Xl, yh, yl

    def jet(self, y0, v0=None) -> tuple[np.ndarray, np.ndarray]:
        """(hi, lo), each (4, order + 1), or (8, order + 1) with a tangent vector v0: the normalised Taylor
        coefficients x^(k)(0) / k! of (u, Omega, omega, delta) (and of v) at y0 (order 0: the stored angle,
        delta + pi reduced into [0, 2 pi))."""
        yh, yl = as_pair(y0)
        if v0 is not None:
            (vh, vl) = as_pair(v0)
            yh, yl = np.r_[yh, vh], np.r_[yl, vl]
        prog, Xh, Xl, yh, yl = self._series(yh, yl, v0 is not None)
        _jet(Xh, Xl, prog.ops, prog.lin_src, self._coef[v0 is not None], self.order, prog.n_vars, yh, yl)
        return Xh[: prog.n_vars].copy(), Xl[: prog.n_vars].copy()

    def _run(self, yh, yl, grid, tangent: bool):
        prog, Xh, Xl, yh, yl = self._series(yh, yl, tangent)
        out_h, out_l = np.empty((grid.size, prog.n_vars)), np.empty((grid.size, prog.n_vars))
        out_e = np.empty(grid.size, dtype=np.int64)
        status, self.steps, t = _propagate(Xh, Xl, prog.ops, prog.lin_src, self._coef[tangent], self.order,
                                           prog.n_vars, yh, yl, grid, out_h, out_l, out_e, self.max_steps)
        if status != OK:
            why = "more than max_steps steps" if status == TOO_MANY_STEPS else "a non-finite step or state"
            raise RuntimeError(f"double-double Taylor integration failed at t = {t:.17g}: {why}")
        shift_angle(out_h, out_l, 1)
        return out_h, out_l, out_e

    def propagate_grid(self, y0, t_grid) -> tuple[np.ndarray, np.ndarray]:
        """(hi, lo), each (n, 4): the states (u, Omega, omega, delta) at the times t_grid (from y0, time
        units; delta as integrated between the step ends, where it is reduced into [-pi, pi))."""
        out_h, out_l, _ = self._run(*as_pair(y0), check_grid(t_grid), tangent=False)
        return out_h, out_l

    def propagate(self, y0, T: float) -> tuple[np.ndarray, np.ndarray]:
        """(hi, lo), each (4,): the state a time T after y0."""
        out_h, out_l = self.propagate_grid(y0, [positive("T", T)])
        return out_h[0], out_l[0]

    def propagate_tangent_grid(self, y0, v0, t_grid):
        """The orbit and one tangent vector (forward-mode through the same recurrences) from (y0, v0):
        (hi, lo) as :meth:`propagate_grid`, log_norm (n,) the natural log of the tangent vector's norm
        (renormalised by powers of two along the way, the scale accumulated) and direction (n, 4), the
        unit tangent vector, at the times t_grid."""
        (yh, yl), (vh, vl) = as_pair(y0), as_pair(v0)
        if not np.any(vh):
            raise ValueError("the tangent vector v0 must be non-zero")
        out_h, out_l, out_e = self._run(np.r_[yh, vh], np.r_[yl, vl], check_grid(t_grid), tangent=True)
        v = out_h[:, 4:] + out_l[:, 4:]
        norm = np.linalg.norm(v, axis=1)
        return out_h[:, :4], out_l[:, :4], out_e * math.log(2.0) + np.log(norm), v / norm[:, None]


@cache
def _energy_mp():
    return sp.lambdify((*mech.STATE, *mech.PHYSICAL), mech.derive().energy, modules="mpmath")


def energy(params: Params, hi, lo, prec: int = 200) -> list:
    """The kinetic energy (mpmath numbers at ``prec`` bits) of the double-double states (rows of hi + lo)."""
    f = _energy_mp()
    hi, lo = np.atleast_2d(hi), np.atleast_2d(lo)
    with mpmath.workprec(prec):
        pars = [mpmath.mpf(v) for v in params.values]
        return [+f(*(mpmath.mpf(a) + mpmath.mpf(b) for a, b in zip(rh[:4], rl[:4])), *pars) for rh, rl in zip(hi, lo)]


def energy_drift(params: Params, hi, lo) -> float:
    """max_t |E(t) - E(0)| / |E(0)| over the rows of (hi, lo), E computed at 200 bits."""
    E = energy(params, hi, lo)
    with mpmath.workprec(200):
        return float(max(abs(e - E[0]) for e in E) / abs(E[0]))


def separation(a, b) -> np.ndarray:
    """Per row of the state pairs a = (hi, lo) and b: max |a - b| over (u, Omega, omega, delta, the angle
    compared modulo 2 pi), relative to max |(u, Omega, omega)| of a; the pairs subtracted in double-double."""
    (ah, al), (bh, bl) = (tuple(np.atleast_2d(np.asarray(x, dtype=float)) for x in p) for p in (a, b))
    d = np.array(dd.sub(ah, al, bh, bl)[0])
    d[:, 3] = (d[:, 3] + np.pi) % (2 * np.pi) - np.pi
    return np.abs(d).max(axis=1) / np.abs(ah[:, :3]).max(axis=1)
