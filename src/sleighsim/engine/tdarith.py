"""Triple-double arithmetic: a number is an unevaluated sum a0 + a1 + a2 of three doubles, each about a unit
roundoff of double below the one before, about 159 significant bits (measured unit roundoff below
:data:`ROUNDING` = 2^-150, 7e-46, tests/engine/test_tdtaylor.py).

Built, like :mod:`sleighsim.engine.ddarith`, on TwoSum and TwoProd (with the fused multiply-add), with an
accumulator of three levels for sums of products: a term of size 1 enters level 0, its rounding error level 1,
that one's level 2, where plain additions suffice (their errors are of order 2^-159 of the sum). Products drop
the terms a_i b_j with i + j > 2; a result is renormalised by two passes of TwoSum. Division is long division
(four quotient digits). The operations are written for doubles and compile unchanged for the lane vectors of
:mod:`sleighsim.engine.ddsimd`, except the sine and cosine and the angle's reduction (doubles only, once per step).

Constants are derived, not typed: pi / 2, pi and 2 pi as four doubles (~210 bits, from mpmath), the sine and
cosine series' inverse factorials as triples from exact fractions.
"""

from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import numpy as np

from sleighsim.engine.ddarith import _mpf_fraction, fast_two_sum, fma, jit, two_prod, two_sum

#: Bound on the relative rounding error of one operation (add, mul, div measured at most 2^-157.7).
ROUNDING = 2.0**-150


def expansion(x, n: int = 3) -> tuple[float, ...]:
    """n doubles whose unevaluated sum is ``x`` (a Fraction, int, float, str or mpmath number), each the double
    nearest to what the ones before leave."""
    f = _mpf_fraction(x) if isinstance(x, mpmath.mpf) else Fraction(x)
    out = []
    for _ in range(n):
        out.append(float(f))
        f -= Fraction(out[-1])
    return tuple(out)


def _constants():
    with mpmath.workprec(320):
        return [np.array(expansion(c, 4)) for c in (mpmath.pi / 2, +mpmath.pi, 2 * mpmath.pi)]


HALF_PI4, PI4, TWO_PI4 = _constants()
#: Terms of the sine and cosine series on [-pi/4, pi/4]: (pi/4)^(2 N + 1) / (2 N + 1)! < 2^-165.
N_TRIG = next(n for n in range(1, 60) if (math.pi / 4) ** (2 * n + 1) / math.factorial(2 * n + 1) < 2.0**-165)
#: (-1)^j / (2 j + 1)! and (-1)^j / (2 j)! as triples, rows j = 0 .. N_TRIG.
SIN_COEF = np.array([expansion(Fraction((-1) ** j, math.factorial(2 * j + 1))) for j in range(N_TRIG + 1)])
COS_COEF = np.array([expansion(Fraction((-1) ** j, math.factorial(2 * j))) for j in range(N_TRIG + 1)])


@jit
def renorm(s0, s1, s2):
    """The triple nearest to s0 + s1 + s2 (levels of decreasing size, possibly overlapping): two TwoSum passes."""
    t1, t2 = two_sum(s1, s2)
    r0, t1 = two_sum(s0, t1)
    r1, r2 = two_sum(t1, t2)
    return r0, r1, r2


@jit
def mac(s0, s1, s2, a0, a1, a2, b0, b1, b2):
    """The accumulator levels (s0, s1, s2) plus the product a b (unnormalised; renorm gives the triple)."""
    p, e = two_prod(a0, b0)
    p01, e01 = two_prod(a0, b1)
    p10, e10 = two_prod(a1, b0)
    s0, t = two_sum(s0, p)
    s1, u1 = two_sum(s1, t)
    s1, u2 = two_sum(s1, e)
    s1, u3 = two_sum(s1, p01)
    s1, u4 = two_sum(s1, p10)
    s2 = s2 + (((u1 + u2) + (u3 + u4)) + ((e01 + e10) + fma(a0, b2, fma(a1, b1, a2 * b0))))
    return s0, s1, s2


@jit
def add(a0, a1, a2, b0, b1, b2):
    """a + b."""
    s0, t = two_sum(a0, b0)
    s1, u1 = two_sum(a1, b1)
    s1, u2 = two_sum(s1, t)
    return renorm(s0, s1, (a2 + b2) + (u1 + u2))


@jit
def mul(a0, a1, a2, b0, b1, b2):
    """a b (the products a_i b_j with i + j > 2 dropped: below 2^-159 of the result)."""
    return renorm(*mac(a0 * 0.0, a0 * 0.0, a0 * 0.0, a0, a1, a2, b0, b1, b2))


@jit
def _sub_mul_d(r0, r1, r2, q, d0, d1, d2):
    """r - q d for a double q with q d0 close to r0 (a remainder of long division), renormalised."""
    p, e = two_prod(q, d0)
    p1, e1 = two_prod(q, d1)
    s0, t = two_sum(r0, -p)
    s1, u1 = two_sum(r1, t)
    s1, u2 = two_sum(s1, -e)
    s1, u3 = two_sum(s1, -p1)
    return renorm(s0, s1, ((r2 - e1) - q * d2) + ((u1 + u2) + u3))


@jit
def div(a0, a1, a2, d0, d1, d2):
    """a / d: four quotient digits, each from the remainder's leading double."""
    q0 = a0 / d0
    r0, r1, r2 = _sub_mul_d(a0, a1, a2, q0, d0, d1, d2)
    q1 = r0 / d0
    r0, r1, r2 = _sub_mul_d(r0, r1, r2, q1, d0, d1, d2)
    q2 = r0 / d0
    r0, r1, r2 = _sub_mul_d(r0, r1, r2, q2, d0, d1, d2)
    q0, q1 = fast_two_sum(q0, q1)
    return renorm(q0, q1, q2 + r0 / d0)


@jit
def div_d(a0, a1, a2, b):
    """a / b for a double b."""
    return div(a0, a1, a2, b, 0.0 * b, 0.0 * b)


@jit
def sub_expansion(a0, a1, a2, c, n):
    """a - n (c[0] + c[1] + c[2] + c[3]) for a constant of four doubles and a small integer n (|n| < 2^20:
    each n c[i] exact by TwoProd)."""
    for i in range(4):
        p, e = two_prod(float(n), c[i])
        a0, a1, a2 = add(a0, a1, a2, -p, -e, 0.0)
    return a0, a1, a2


@jit
def _series(r0, r1, r2, coef):
    """sum_j coef[j] r^j (Horner, triples)."""
    n = coef.shape[0]
    s0, s1, s2 = coef[n - 1, 0], coef[n - 1, 1], coef[n - 1, 2]
    for j in range(n - 2, -1, -1):
        s0, s1, s2 = mul(s0, s1, s2, r0, r1, r2)
        s0, s1, s2 = add(s0, s1, s2, coef[j, 0], coef[j, 1], coef[j, 2])
    return s0, s1, s2


@jit
def sincos(x0, x1, x2):
    """(sin x as three doubles, cos x as three) of a triple x (|x| below 2^20): reduced by n pi/2 to
    [-pi/4, pi/4], the series there, the quadrant from n mod 4."""
    n = np.round(x0 / HALF_PI4[0])
    r0, r1, r2 = sub_expansion(x0, x1, x2, HALF_PI4, n)
    q0, q1, q2 = mul(r0, r1, r2, r0, r1, r2)
    s0, s1, s2 = mul(*_series(q0, q1, q2, SIN_COEF), r0, r1, r2)
    c0, c1, c2 = _series(q0, q1, q2, COS_COEF)
    quadrant = int(n) % 4
    if quadrant == 0:
        return s0, s1, s2, c0, c1, c2
    if quadrant == 1:
        return c0, c1, c2, -s0, -s1, -s2
    if quadrant == 2:
        return -s0, -s1, -s2, -c0, -c1, -c2
    return -c0, -c1, -c2, s0, s1, s2


@jit
def reduce_angle(a0, a1, a2):
    """The triple a reduced by whole turns into [0, 2 pi) (the test on the reduced value, as ddarith's)."""
    while a0 < 0.0:
        a0, a1, a2 = sub_expansion(a0, a1, a2, TWO_PI4, -1)
    while True:
        d0, d1, d2 = sub_expansion(a0, a1, a2, TWO_PI4, 1)
        if d0 < 0.0:
            return a0, a1, a2
        a0, a1, a2 = d0, d1, d2
