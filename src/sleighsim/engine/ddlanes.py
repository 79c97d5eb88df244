"""The compiled kernels of the batched double-double Taylor engine (:mod:`sleighsim.engine.ddbatch`): the scalar
engine's kernels (:mod:`sleighsim.engine.ddtaylor`) on a block of W lanes held in vectors (:mod:`.ddsimd`).

Layout of a block: series coefficients X[series, order, lane] (hi and lo arrays), states y[variable, lane], the
linear combinations' coefficients coef[term, lane] (each lane its own parameters), all C-contiguous, so a row
X[series, order] is one vector of W lanes. Every operation of the program is evaluated on whole vectors (the
Cauchy products' accumulators in registers), with the scalar engine's sequence of IEEE operations in every lane
and no fast-math: each lane's results are bit for bit the scalar engine's.

Per lane, once per step and not vectorised: S_0, C_0 (ddarith.sincos), the step size (heyoka's rule), dense
output at the lane's grid times, the angle's reduction and the tangent vector's renormalisation.
Times in the flow's time unit from the initial state; a lane's end time is its grid's last time.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.engine import ddarith as dd
from sleighsim.engine import ddsimd as simd
from sleighsim.engine.ddarith import jit
from sleighsim.engine.ddprogram import DIV, DIVT, LIN, MUL, MUL2, SINCOS

#: Lane status: finished (or a padding lane), still running (the batch stopped for another lane), or failed.
OK, RUNNING, TOO_MANY_STEPS, NOT_FINITE = 0, 1, 2, 3


@jit
def _dot(Xh, Xl, a, b, j0, k, s, c):
    """(s, c) + sum_{j=j0..k} X[a, j] X[b, k - j] in every lane, unnormalised (Dot2 on pairs, ddtaylor._dot)."""
    for j in range(j0, k + 1):
        ah, al = simd.load(Xh[a, j], s), simd.load(Xl[a, j], s)
        bh, bl = simd.load(Xh[b, k - j], s), simd.load(Xl[b, k - j], s)
        p, e = dd.two_prod(ah, bh)
        s, t = dd.two_sum(s, p)
        c = c + (t + e + dd.fma(ah, bl, al * bh))
    return s, c


@jit
def _store(Xh, Xl, i, k, s, c):
    hi, lo = dd.two_sum(s, c)
    simd.store(Xh[i, k], hi)
    simd.store(Xl[i, k], lo)


@jit
def _lin(Xh, Xl, out, start, count, k, lin_src, ch, cl, z):
    """X[out, k] = sum_m coef_m X[lin_src[m], k] over the terms start .. start + count - 1 (ddtaylor._lin)."""
    s, c = z, z
    for m in range(start, start + count):
        i = lin_src[m]
        xh, xl, kh, kl = simd.load(Xh[i, k], z), simd.load(Xl[i, k], z), simd.load(ch[m], z), simd.load(cl[m], z)
        p, e = dd.two_prod(kh, xh)
        s, t = dd.two_sum(s, p)
        c = c + (t + e + dd.fma(kh, xl, kl * xh))
    _store(Xh, Xl, out, k, s, c)


@jit
def _div(Xh, Xl, op, k, z):
    """q_k = (N_k - sum_{j=1..k} D_j q_{k-j}) / D_0 and, for DIVT, the tangent's (ddtaylor._div)."""
    out, num, den = op[1], op[2], op[3]
    s, c = _dot(Xh, Xl, den, out, 1, k, z, z)
    if op[0] == DIVT:
        s, c = _dot(Xh, Xl, op[4], op[5], 0, k, s, c)
    rh, rl = dd.sub(simd.load(Xh[num, k], z), simd.load(Xl[num, k], z), *dd.two_sum(s, c))
    _store(Xh, Xl, out, k, *dd.div(rh, rl, simd.load(Xh[den, 0], z), simd.load(Xl[den, 0], z)))


@jit
def _sincos(Xh, Xl, op, k, z):
    """S_k, C_k of sign (sin x, cos x) (ddtaylor._sincos); at order 0 lane by lane."""
    S, C, x, w, sign = op[1], op[2], op[3], op[4], op[5]
    if k == 0:
        for lane in range(Xh.shape[2]):
            sh, sl, kh, kl = dd.sincos(Xh[x, 0, lane], Xl[x, 0, lane])
            Xh[S, 0, lane], Xl[S, 0, lane], Xh[C, 0, lane], Xl[C, 0, lane] = sign * sh, sign * sl, sign * kh, sign * kl
        return
    s, c = _dot(Xh, Xl, w, C, 0, k - 1, z, z)
    _store(Xh, Xl, S, k, *dd.div_d(*dd.two_sum(s, c), float(k)))
    s, c = _dot(Xh, Xl, w, S, 0, k - 1, z, z)
    _store(Xh, Xl, C, k, *dd.div_d(*dd.two_sum(-s, -c), float(k)))


@jit
def order(Xh, Xl, ops, lin_src, ch, cl, k, z):
    """Every operation of the program at order k in every lane (z: a zero vector of the block's width)."""
    for o in range(ops.shape[0]):
        op = ops[o]
        code = op[0]
        if code == MUL or code == MUL2:
            s, c = _dot(Xh, Xl, op[2], op[3], 0, k, z, z)
            if code == MUL2:
                s, c = _dot(Xh, Xl, op[4], op[5], 0, k, s, c)
            _store(Xh, Xl, op[1], k, s, c)
        elif code == LIN:
            _lin(Xh, Xl, op[1], op[2], op[3], k, lin_src, ch, cl, z)
        elif code == SINCOS:
            _sincos(Xh, Xl, op, k, z)
        elif code == DIV or code == DIVT:
            _div(Xh, Xl, op, k, z)
        else:
            h, lo = dd.div_d(simd.load(Xh[op[2], k], z), simd.load(Xl[op[2], k], z), float(k + 1))
            simd.store(Xh[op[1], k + 1], h)
            simd.store(Xl[op[1], k + 1], lo)


@jit
def jet(Xh, Xl, ops, lin_src, ch, cl, p, n_vars, yh, yl, like):
    """The normalised Taylor coefficients (orders 0..p) of every series at the states y[variable, lane];
    ``like`` a tuple of W doubles (the block's width)."""
    z = simd.splat(0.0, like)
    for i in range(n_vars):
        simd.store(Xh[i, 0], simd.load(yh[i], z))
        simd.store(Xl[i, 0], simd.load(yl[i], z))
    for k in range(p):
        order(Xh, Xl, ops, lin_src, ch, cl, k, z)


@jit
def _step_size(Xh, n_vars, p, lane):
    """heyoka's step for one lane (ddtaylor._step_size)."""
    a, m_p, m_pm1 = 0.0, 0.0, 0.0
    for i in range(n_vars):
        a = max(a, abs(Xh[i, 0, lane]))
        m_p = max(m_p, abs(Xh[i, p, lane]))
        m_pm1 = max(m_pm1, abs(Xh[i, p - 1, lane]))
    a = max(a, 1.0)
    rho = min((a / m_p) ** (1.0 / p), (a / m_pm1) ** (1.0 / (p - 1)))
    return rho * math.exp(-0.7 / (p - 1)) / math.e**2


@jit
def _horner(Xh, Xl, i, p, th, tl, lane):
    """sum_k X[i, k, lane] t^k for the pair t."""
    sh, sl = Xh[i, p, lane], Xl[i, p, lane]
    for k in range(p - 1, -1, -1):
        sh, sl = dd.mul(sh, sl, th, tl)
        sh, sl = dd.add(sh, sl, Xh[i, k, lane], Xl[i, k, lane])
    return sh, sl


@jit
def _advance(Xh, Xl, p, n_vars, hh, hl, nh, nl, z):
    """n[i, lane] = sum_k X[i, k, lane] h[lane]^k (Horner, every lane at its own step)."""
    th, tl = simd.load(hh, z), simd.load(hl, z)
    for i in range(n_vars):
        sh, sl = simd.load(Xh[i, p], z), simd.load(Xl[i, p], z)
        for k in range(p - 1, -1, -1):
            sh, sl = dd.mul(sh, sl, th, tl)
            sh, sl = dd.add(sh, sl, simd.load(Xh[i, k], z), simd.load(Xl[i, k], z))
        simd.store(nh[i], sh)
        simd.store(nl[i], sl)


@jit
def _emit(Xh, Xl, p, n_vars, grid, lane, g, th, tl, hh, last, out_h, out_l, out_e, scale_exp):
    """Dense output of one lane (ddtaylor._emit): its grid times from index g in the step. Returns the next g."""
    while g < grid.shape[1]:
        tauh, taul = dd.sub(grid[lane, g], 0.0, th, tl)
        if not last and tauh > hh:
            break
        for i in range(n_vars):
            out_h[lane, g, i], out_l[lane, g, i] = _horner(Xh, Xl, i, p, tauh, taul, lane)
        out_e[lane, g] = scale_exp
        g += 1
    return g


@jit
def _renormalise(yh, yl, lane):
    """Scale one lane's tangent vector (variables 4..7) by the power of two 2^-e nearest its norm; returns e."""
    norm = math.sqrt(yh[4, lane] ** 2 + yh[5, lane] ** 2 + yh[6, lane] ** 2 + yh[7, lane] ** 2)
    if not (norm > 0.0 and math.isfinite(norm)):
        return 0
    e = int(round(math.log2(norm)))
    f = math.ldexp(1.0, -e)
    for i in range(4, 8):
        yh[i, lane], yl[i, lane] = yh[i, lane] * f, yl[i, lane] * f
    return e


@jit
def _sizes(Xh, p, n_vars, grid, common, status, th, tl, hh, hl, last):
    """Each running lane's step (hh, hl) and whether it is its last (heyoka's rule per lane, or with ``common``
    the smallest over the running lanes for all), cut at the lane's end time. Returns the first lane whose
    step is not a positive number (its status NOT_FINITE), else -1."""
    hmin = np.inf
    for lane in range(th.shape[0]):
        if status[lane] == RUNNING:
            hh[lane] = _step_size(Xh, n_vars, p, lane)
            if not hh[lane] > 0.0:
                status[lane] = NOT_FINITE
                return lane
            hmin = min(hmin, hh[lane])
    for lane in range(th.shape[0]):
        if status[lane] == RUNNING:
            h = hmin if common else hh[lane]
            rh, rl = dd.sub(grid[lane, grid.shape[1] - 1], 0.0, th[lane], tl[lane])
            last[lane] = h >= rh
            hh[lane], hl[lane] = (rh, rl) if last[lane] else (h, 0.0)
        else:
            hh[lane], hl[lane] = 0.0, 0.0
    return -1


@jit
def _land(yh, yl, nh, nl, lane, th, tl, hh, hl, steps, scale):
    """One lane's new state from the step's polynomials (False if it is not finite), its time, step count,
    reduced angle and renormalised tangent vector."""
    n_vars = yh.shape[0]
    for i in range(n_vars):
        if not math.isfinite(nh[i, lane]):
            return False
        yh[i, lane], yl[i, lane] = nh[i, lane], nl[i, lane]
    th[lane], tl[lane] = dd.add(th[lane], tl[lane], hh[lane], hl[lane])
    steps[lane] += 1
    yh[3, lane], yl[3, lane] = dd.reduce_angle(yh[3, lane], yl[3, lane])
    if n_vars == 8:
        scale[lane] += _renormalise(yh, yl, lane)
    return True


@jit
def propagate(Xh, Xl, ops, lin_src, ch, cl, p, yh, yl, grid, out_h, out_l, out_e, max_steps, common, status,
              steps, th, like):
    """Taylor steps of every lane from y[variable, lane] at t = 0 to its grid's last time, the states at its
    grid times into out[lane, time, variable] (out_e: the tangent's accumulated power-of-two scale); ``like``
    a tuple of W doubles, the block's width. Running lanes have status RUNNING on entry (padding lanes OK).
    Stops when every lane is done (status OK) or at the first lane that fails (status TOO_MANY_STEPS or
    NOT_FINITE; the others keep RUNNING): returns that lane, or -1. steps and th (the time reached, hi part)
    per lane; ``common``: every lane steps by the smallest of their steps."""
    n_vars, L = yh.shape
    z, tl, scale = simd.splat(0.0, like), np.zeros(L), np.zeros(L, np.int64)
    hh, hl, last, g = np.zeros(L), np.zeros(L), np.zeros(L, np.bool_), np.zeros(L, np.int64)
    nh, nl = np.empty((n_vars, L)), np.empty((n_vars, L))
    while True:
        for lane in range(L):
            if status[lane] == RUNNING and steps[lane] >= max_steps:
                status[lane] = TOO_MANY_STEPS
                return lane
        jet(Xh, Xl, ops, lin_src, ch, cl, p, n_vars, yh, yl, like)
        failed = _sizes(Xh, p, n_vars, grid, common, status, th, tl, hh, hl, last)
        if failed >= 0:
            return failed
        _advance(Xh, Xl, p, n_vars, hh, hl, nh, nl, z)
        running = 0
        for lane in range(L):
            if status[lane] != RUNNING:
                continue
            g[lane] = _emit(Xh, Xl, p, n_vars, grid, lane, g[lane], th[lane], tl[lane], hh[lane], last[lane],
                            out_h, out_l, out_e, scale[lane])
            if not _land(yh, yl, nh, nl, lane, th, tl, hh, hl, steps, scale):
                status[lane] = NOT_FINITE
                return lane
            if last[lane]:
                status[lane] = OK
            else:
                running += 1
        if running == 0:
            return -1
