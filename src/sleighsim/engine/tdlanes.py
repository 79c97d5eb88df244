"""The compiled kernels of the triple-double Taylor engine (:mod:`sleighsim.engine.tdtaylor`): the batched
double-double kernels (:mod:`sleighsim.engine.ddlanes`) with triples (:mod:`sleighsim.engine.tdarith`).

Layout of a block of W lanes: series coefficients X[series, order, component, lane] (components 0, 1, 2 of each
triple), states y[variable, component, lane], coefficients K[term, component, lane], all C-contiguous, so that
X[series, order, component] is one vector of W lanes (:mod:`sleighsim.engine.ddsimd`). The Cauchy products
accumulate in tdarith's three levels (registers); everything else is as in ddlanes: heyoka's step rule per lane
(or the smallest for all), S_0 and C_0, dense output, the angle's reduction and the tangent's renormalisation
lane by lane. Times in the flow's time unit from the initial state, held as triples.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.engine import ddsimd as simd
from sleighsim.engine import tdarith as td
from sleighsim.engine.ddarith import jit
from sleighsim.engine.ddlanes import NOT_FINITE, OK, RUNNING, TOO_MANY_STEPS, _step_size
from sleighsim.engine.ddprogram import DIV, DIVT, LIN, MUL, MUL2, SINCOS


@jit
def _get(X, i, k, z):
    """The triple X[i, k] of every lane (three vectors)."""
    return simd.load(X[i, k, 0], z), simd.load(X[i, k, 1], z), simd.load(X[i, k, 2], z)


@jit
def _put(X, i, k, r0, r1, r2):
    simd.store(X[i, k, 0], r0)
    simd.store(X[i, k, 1], r1)
    simd.store(X[i, k, 2], r2)


@jit
def _dot(X, a, b, j0, k, s0, s1, s2):
    """The accumulator (s0, s1, s2) plus sum_{j=j0..k} X[a, j] X[b, k - j] in every lane."""
    for j in range(j0, k + 1):
        a0, a1, a2 = _get(X, a, j, s0)
        b0, b1, b2 = _get(X, b, k - j, s0)
        s0, s1, s2 = td.mac(s0, s1, s2, a0, a1, a2, b0, b1, b2)
    return s0, s1, s2


@jit
def _lin(X, out, start, count, k, lin_src, K, z):
    """X[out, k] = sum_m K_m X[lin_src[m], k] over the terms start .. start + count - 1."""
    s0, s1, s2 = z, z, z
    for m in range(start, start + count):
        x0, x1, x2 = _get(X, lin_src[m], k, z)
        k0, k1, k2 = simd.load(K[m, 0], z), simd.load(K[m, 1], z), simd.load(K[m, 2], z)
        s0, s1, s2 = td.mac(s0, s1, s2, k0, k1, k2, x0, x1, x2)
    _put(X, out, k, *td.renorm(s0, s1, s2))


@jit
def _div(X, op, k, z):
    """q_k = (N_k - sum_{j=1..k} D_j q_{k-j}) / D_0 and, for DIVT, the tangent's (ddtaylor._div)."""
    out, num, den = op[1], op[2], op[3]
    s0, s1, s2 = _dot(X, den, out, 1, k, z, z, z)
    if op[0] == DIVT:
        s0, s1, s2 = _dot(X, op[4], op[5], 0, k, s0, s1, s2)
    r0, r1, r2 = td.renorm(s0, s1, s2)
    n0, n1, n2 = _get(X, num, k, z)
    d0, d1, d2 = _get(X, den, 0, z)
    _put(X, out, k, *td.div(*td.add(n0, n1, n2, -r0, -r1, -r2), d0, d1, d2))


@jit
def _sincos(X, op, k, z):
    """S_k, C_k of sign (sin x, cos x); at order 0 lane by lane (tdarith.sincos)."""
    S, C, x, w, sign = op[1], op[2], op[3], op[4], op[5]
    if k == 0:
        for lane in range(X.shape[3]):
            r = td.sincos(X[x, 0, 0, lane], X[x, 0, 1, lane], X[x, 0, 2, lane])
            for c in range(3):
                X[S, 0, c, lane], X[C, 0, c, lane] = sign * r[c], sign * r[3 + c]
        return
    s0, s1, s2 = td.renorm(*_dot(X, w, C, 0, k - 1, z, z, z))
    _put(X, S, k, *td.div_d(s0, s1, s2, float(k)))
    s0, s1, s2 = td.renorm(*_dot(X, w, S, 0, k - 1, z, z, z))
    _put(X, C, k, *td.div_d(-s0, -s1, -s2, float(k)))


@jit
def order(X, ops, lin_src, K, k, z):
    """Every operation of the program at order k in every lane (z: a zero vector of the block's width)."""
    for o in range(ops.shape[0]):
        op = ops[o]
        code = op[0]
        if code == MUL or code == MUL2:
            s0, s1, s2 = _dot(X, op[2], op[3], 0, k, z, z, z)
            if code == MUL2:
                s0, s1, s2 = _dot(X, op[4], op[5], 0, k, s0, s1, s2)
            _put(X, op[1], k, *td.renorm(s0, s1, s2))
        elif code == LIN:
            _lin(X, op[1], op[2], op[3], k, lin_src, K, z)
        elif code == SINCOS:
            _sincos(X, op, k, z)
        elif code == DIV or code == DIVT:
            _div(X, op, k, z)
        else:
            _put(X, op[1], k + 1, *td.div_d(*_get(X, op[2], k, z), float(k + 1)))


@jit
def jet(X, ops, lin_src, K, p, n_vars, y, like):
    """The normalised Taylor coefficients (orders 0..p) of every series at the states y[variable, component,
    lane]; ``like`` a tuple of W doubles (the block's width)."""
    z = simd.splat(0.0, like)
    for i in range(n_vars):
        for c in range(3):
            simd.store(X[i, 0, c], simd.load(y[i, c], z))
    for k in range(p):
        order(X, ops, lin_src, K, k, z)


@jit
def _horner(X, i, p, t0, t1, t2, lane):
    """sum_k X[i, k, lane] t^k for the triple t."""
    s0, s1, s2 = X[i, p, 0, lane], X[i, p, 1, lane], X[i, p, 2, lane]
    for k in range(p - 1, -1, -1):
        s0, s1, s2 = td.mul(s0, s1, s2, t0, t1, t2)
        s0, s1, s2 = td.add(s0, s1, s2, X[i, k, 0, lane], X[i, k, 1, lane], X[i, k, 2, lane])
    return s0, s1, s2


@jit
def _sizes(X, p, n_vars, grid, common, status, t, h, last):
    """Each running lane's step h[component, lane] and whether it is its last (ddlanes._sizes)."""
    hmin = np.inf
    for lane in range(t.shape[1]):
        if status[lane] == RUNNING:
            h[0, lane] = _step_size(X[:, :, 0, :], n_vars, p, lane)
            if not h[0, lane] > 0.0:
                status[lane] = NOT_FINITE
                return lane
            hmin = min(hmin, h[0, lane])
    for lane in range(t.shape[1]):
        step = hmin if common else h[0, lane]
        r0, r1, r2 = td.add(grid[lane, grid.shape[1] - 1], 0.0, 0.0, -t[0, lane], -t[1, lane], -t[2, lane])
        last[lane] = status[lane] == RUNNING and step >= r0
        h[0, lane], h[1, lane], h[2, lane] = (r0, r1, r2) if last[lane] else (step, 0.0, 0.0)
        if status[lane] != RUNNING:
            h[0, lane], h[1, lane], h[2, lane] = 0.0, 0.0, 0.0
    return -1


@jit
def _emit(X, p, n_vars, grid, lane, g, t, h, last, out, out_e, scale_exp):
    """Dense output of one lane: its grid times from index g in the step. Returns the next g."""
    while g < grid.shape[1]:
        r0, r1, r2 = td.add(grid[lane, g], 0.0, 0.0, -t[0, lane], -t[1, lane], -t[2, lane])
        if not last and r0 > h[0, lane]:
            break
        for i in range(n_vars):
            out[lane, g, i, 0], out[lane, g, i, 1], out[lane, g, i, 2] = _horner(X, i, p, r0, r1, r2, lane)
        out_e[lane, g] = scale_exp
        g += 1
    return g


@jit
def _land(X, p, y, lane, t, h):
    """One lane's new state from its step's polynomials (False if not finite), its time and reduced angle."""
    n_vars = y.shape[0]
    for i in range(n_vars):
        y[i, 0, lane], y[i, 1, lane], y[i, 2, lane] = _horner(X, i, p, h[0, lane], h[1, lane], h[2, lane], lane)
        if not math.isfinite(y[i, 0, lane]):
            return False
    t[0, lane], t[1, lane], t[2, lane] = td.add(t[0, lane], t[1, lane], t[2, lane], h[0, lane], h[1, lane],
                                                h[2, lane])
    y[3, 0, lane], y[3, 1, lane], y[3, 2, lane] = td.reduce_angle(y[3, 0, lane], y[3, 1, lane], y[3, 2, lane])
    return True


@jit
def _renormalise(y, lane):
    """Scale one lane's tangent vector (variables 4..7) by the power of two nearest its norm; returns e."""
    norm = math.sqrt(y[4, 0, lane] ** 2 + y[5, 0, lane] ** 2 + y[6, 0, lane] ** 2 + y[7, 0, lane] ** 2)
    if not (norm > 0.0 and math.isfinite(norm)):
        return 0
    e = int(round(math.log2(norm)))
    f = math.ldexp(1.0, -e)
    for i in range(4, 8):
        for c in range(3):
            y[i, c, lane] *= f
    return e


@jit
def propagate(X, ops, lin_src, K, p, y, grid, out, out_e, max_steps, common, status, steps, t, like):
    """ddlanes.propagate in triples: y[variable, component, lane], out[lane, time, variable, component], t the
    time reached [component, lane]. Returns the first lane that fails, or -1 when every lane is done."""
    n_vars, L = y.shape[0], y.shape[2]
    h, last, g, scale = np.zeros((3, L)), np.zeros(L, np.bool_), np.zeros(L, np.int64), np.zeros(L, np.int64)
    while True:
        for lane in range(L):
            if status[lane] == RUNNING and steps[lane] >= max_steps:
                status[lane] = TOO_MANY_STEPS
                return lane
        jet(X, ops, lin_src, K, p, n_vars, y, like)
        failed = _sizes(X, p, n_vars, grid, common, status, t, h, last)
        if failed >= 0:
            return failed
        running = 0
        for lane in range(L):
            if status[lane] != RUNNING:
                continue
            g[lane] = _emit(X, p, n_vars, grid, lane, g[lane], t, h, last[lane], out, out_e, scale[lane])
            if not _land(X, p, y, lane, t, h):
                status[lane] = NOT_FINITE
                return lane
            steps[lane] += 1
            if n_vars == 8:
                scale[lane] += _renormalise(y, lane)
            if last[lane]:
                status[lane] = OK
            else:
                running += 1
        if running == 0:
            return -1
