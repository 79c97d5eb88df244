"""Double-double arithmetic: a number is an unevaluated pair (hi, lo) of doubles, value hi + lo, with
|lo| <= ulp(hi) / 2, about 106 significant bits (unit roundoff :data:`ROUNDING` = 2^-106, 1.2e-32).

The pair operations are built on error-free transformations: TwoSum (Knuth: a + b = s + e exactly),
FastTwoSum (Dekker, for |a| >= |b|) and TwoProd (a b = p + e exactly, e = fma(a, b, -p) with the
hardware fused multiply-add, reached through LLVM's ``llvm.fma.f64`` intrinsic). The operations are written
for doubles and compile unchanged for the lane vectors of :mod:`sleighsim.engine.ddsimd` (many pairs at once).
Everything is compiled by numba (``njit(cache=True)``: the compilation is kept on disk beside this module and
paid once).
Algorithms as in Hida, Li and Bailey's QD library ("accurate" addition and division) and Ogita, Rump
and Oishi's compensated dot product (Dot2), which :mod:`sleighsim.engine.ddtaylor` uses for the
Cauchy products.

Constants are derived, not typed: pi / 2, pi and 2 pi as triple-double (three doubles, ~160 bits, from
mpmath), the inverse factorials of the sine and cosine series as pairs from exact fractions.
"""

from __future__ import annotations

import math
from fractions import Fraction
from pathlib import Path

import mpmath
import numba
import numpy as np
from numba.core import types
from numba.extending import intrinsic

from sleighsim.engine import ddsimd
from sleighsim.io.cachedir import private_directory

#: Unit roundoff of double-double (2^-106).
ROUNDING = 2.0**-106


@intrinsic
def fma(typingctx, a, b, c):
    """a b + c with one rounding (LLVM's fma intrinsic: the CPU's fused multiply-add); lane by lane when an
    operand is a vector of :mod:`sleighsim.engine.ddsimd` (the doubles among them broadcast)."""
    vector = ddsimd.vector_signature(a, b, c)
    if vector is not None:
        return vector(a, b, c), ddsimd.fma_codegen
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        return builder.fma(*args)

    return sig, codegen


def pair(x) -> tuple[float, float]:
    """(hi, lo) nearest to ``x`` (a Fraction, int, float, mpmath number or anything Fraction takes):
    hi the double nearest to x, lo the double nearest to x - hi."""
    x = _mpf_fraction(x) if isinstance(x, mpmath.mpf) else Fraction(x)
    hi = float(x)
    return hi, float(x - Fraction(hi))


def _mpf_fraction(x) -> Fraction:
    """The exact value of an mpmath mpf as a Fraction."""
    man, exp = x.man_exp
    return Fraction(man) * Fraction(2) ** exp


def triple(x) -> tuple[float, float, float]:
    """Three doubles whose unevaluated sum is ``x`` (an mpmath number) to about 160 bits."""
    f = _mpf_fraction(mpmath.mpf(x))
    a = float(f)
    b = float(f - Fraction(a))
    return a, b, float(f - Fraction(a) - Fraction(b))


def _constants():
    with mpmath.workprec(240):
        return triple(mpmath.pi / 2), triple(mpmath.pi), triple(2 * mpmath.pi)


HALF_PI, PI, TWO_PI = (np.array(c) for c in _constants())
#: Number of terms of the sine and cosine series on [-pi/4, pi/4]: (pi/4)^(2 N + 1) / (2 N + 1)! < 2^-112.
N_TRIG = next(n for n in range(1, 40) if (math.pi / 4) ** (2 * n + 1) / math.factorial(2 * n + 1) < 2.0**-112)
#: (-1)^j / (2 j + 1)! and (-1)^j / (2 j)! as pairs, j = 0 .. N_TRIG: rows (hi, lo).
SIN_COEF = np.array([pair(Fraction((-1) ** j, math.factorial(2 * j + 1))) for j in range(N_TRIG + 1)])
COS_COEF = np.array([pair(Fraction((-1) ** j, math.factorial(2 * j))) for j in range(N_TRIG + 1)])

#: Without the GIL: a Python thread reports progress while a kernel runs (``engine.progress``).
_njit = numba.njit(cache=True, fastmath=False, error_model="numpy", nogil=True)


def jit(f):
    """numba's ``njit(cache=True)`` of ``f``, its cache directory checked first: numba unpickles what it
    finds there. ``__pycache__`` beside the source is as trusted as Python's bytecode there; any other
    (NUMBA_CACHE_DIR, or ~/.cache/numba when that is not writable) must be one only this user controls
    (:func:`sleighsim.io.cachedir.private_directory`)."""
    dispatcher = _njit(f)
    where = Path(dispatcher._cache.cache_path)
    if where != Path(f.__code__.co_filename).parent / "__pycache__":
        private_directory(where, "numba's cache")
    return dispatcher


@jit
def two_sum(a, b):
    """(s, e) with s = fl(a + b) and a + b = s + e exactly."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@jit
def fast_two_sum(a, b):
    """(s, e) with s = fl(a + b), a + b = s + e exactly, for |a| >= |b| (or a = 0)."""
    s = a + b
    return s, b - (s - a)


@jit
def two_prod(a, b):
    """(p, e) with p = fl(a b) and a b = p + e exactly (fused multiply-add)."""
    p = a * b
    return p, fma(a, b, -p)


@jit
def add(ah, al, bh, bl):
    """(ah, al) + (bh, bl), relative error below 2 ROUNDING (QD's accurate addition)."""
    s, e = two_sum(ah, bh)
    t, f = two_sum(al, bl)
    e += t
    s, e = fast_two_sum(s, e)
    e += f
    return fast_two_sum(s, e)


@jit
def sub(ah, al, bh, bl):
    """(ah, al) - (bh, bl)."""
    return add(ah, al, -bh, -bl)


@jit
def mul(ah, al, bh, bl):
    """(ah, al) x (bh, bl), relative error below 4 ROUNDING (the al bl term, below ROUNDING^2, is dropped)."""
    p, e = two_prod(ah, bh)
    e += fma(ah, bl, al * bh)
    return fast_two_sum(p, e)


@jit
def mul_d(ah, al, b):
    """(ah, al) x b for a double b."""
    p, e = two_prod(ah, b)
    e += al * b
    return fast_two_sum(p, e)


@jit
def div(ah, al, bh, bl):
    """(ah, al) / (bh, bl): three quotient digits (QD's accurate division)."""
    q1 = ah / bh
    ph, pl = mul_d(bh, bl, q1)
    rh, rl = sub(ah, al, ph, pl)
    q2 = rh / bh
    ph, pl = mul_d(bh, bl, q2)
    rh, rl = sub(rh, rl, ph, pl)
    q3 = rh / bh
    q1, q2 = fast_two_sum(q1, q2)
    return add(q1, q2, q3, 0.0)


@jit
def div_d(ah, al, b):
    """(ah, al) / b for a double b."""
    q1 = ah / b
    p, e = two_prod(q1, b)
    s, t = two_sum(ah, -p)
    t = t - e + al
    return fast_two_sum(q1, (s + t) / b)


@jit
def sub_triple(ah, al, c, n):
    """(ah, al) - n (c[0] + c[1] + c[2]) for a triple-double constant c and a small integer n (|n| < 2^20:
    each n c[i] is then exact as a pair by TwoProd)."""
    for i in range(3):
        ph, pl = two_prod(float(n), c[i])
        ah, al = sub(ah, al, ph, pl)
    return ah, al


@jit
def _series(rh, rl, r2h, r2l, coef):
    """sum_j coef[j] r2^j (Horner, pairs)."""
    n = coef.shape[0]
    sh, sl = coef[n - 1, 0], coef[n - 1, 1]
    for j in range(n - 2, -1, -1):
        sh, sl = mul(sh, sl, r2h, r2l)
        sh, sl = add(sh, sl, coef[j, 0], coef[j, 1])
    return sh, sl


@jit
def sincos(xh, xl):
    """(sin x hi, lo, cos x hi, lo) of a pair x (|x| below 2^20): x reduced by n pi/2 (triple-double pi/2)
    to r in [-pi/4, pi/4], then the sine and cosine series of r, the quadrant from n mod 4."""
    n = np.round(xh / HALF_PI[0])
    rh, rl = sub_triple(xh, xl, HALF_PI, n)
    r2h, r2l = mul(rh, rl, rh, rl)
    sh, sl = _series(rh, rl, r2h, r2l, SIN_COEF)
    sh, sl = mul(sh, sl, rh, rl)
    ch, cl = _series(rh, rl, r2h, r2l, COS_COEF)
    q = int(n) % 4
    if q == 0:
        return sh, sl, ch, cl
    if q == 1:
        return ch, cl, -sh, -sl
    if q == 2:
        return -sh, -sl, -ch, -cl
    return -ch, -cl, sh, sl


@jit
def reduce_angle(ah, al):
    """The pair a reduced by whole turns into [0, 2 pi) (triple-double 2 pi; the test is on the reduced
    value, so a pair just below 2 pi whose hi rounds to 2 pi's is left alone)."""
    while ah < 0.0:
        ah, al = sub_triple(ah, al, TWO_PI, -1)
    while True:
        dh, dl = sub_triple(ah, al, TWO_PI, 1)
        if dh < 0.0:
            return ah, al
        ah, al = dh, dl
