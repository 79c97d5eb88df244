"""The sleigh's Taylor recurrences as a program of series operations, derived from SymPy; the double-double
(:mod:`sleighsim.engine.ddtaylor`, :mod:`sleighsim.engine.ddbatch`) and multi-double
(:mod:`sleighsim.engine.mdtaylor`) engines evaluate it.

The polynomial form of the equations (``mechanics.derive().polynomial``: d(u, Omega, omega)/dt =
N_i(u, Omega, omega, S, C) / D(S, C) with S = sin delta, C = cos delta, and d delta/dt from ``derive().rhs``)
is turned into operations on the normalised Taylor coefficients x_k = x^(k)(t) / k!:

- a product of monomial factors, one Cauchy product per factor (shared sub-products computed once):
  (a b)_k = sum_{j=0..k} a_j b_{k-j};
- a linear combination with the coefficients K[j] (exact fractions of the double parameters):
  N_k = sum_m K_m (monomial_m)_k;
- the division q = N / D: q_k = (N_k - sum_{j=1..k} D_j q_{k-j}) / D_0;
- sine and cosine of delta: k S_k = sum_{j=1..k} j delta_j C_{k-j} = (delta' C)_{k-1}, likewise
  k C_k = -(delta' S)_{k-1}, with delta' the series of d delta/dt;
- the state's next order: y_{k+1} = f_k / (k + 1).

With a tangent vector v the program is differentiated forward (dual numbers through the same recurrences):
(a b)' = a' b + a b', (N / D)': q'_k = (N'_k - (D' q)_k - sum_{j=1..k} D_j q'_{k-j}) / D_0, S' = C delta',
C' = -S delta'. The stored angle is delta + pi (so S = -sin(stored), C = -cos(stored)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from functools import cache

import numpy as np
import sympy as sp

from sleighsim.engine import ddarith as dd
from sleighsim.model import mechanics as mech
from sleighsim.model.params import Params

#: Operation codes of a program's rows.
MUL, MUL2, LIN, DIV, DIVT, SINCOS, DERIV = range(7)


def taylor_order(tol: float) -> int:
    """heyoka's Taylor order for a tolerance: ceil(-ln(tol) / 2 + 1) (38 at 1e-32, 20 at 2^-52)."""
    return math.ceil(-math.log(tol) / 2 + 1)


class _Builder:
    """Series operations in evaluation order: rows (code, out, a, b, c, d); ``terms`` the (coefficient,
    series) of the linear combinations. Series 0..3 are (u, Omega, omega, stored delta), 4..7 their
    tangents when ``tangent``; ``tan`` maps a series to its tangent (``zero`` for a constant)."""

    def __init__(self, tangent: bool):
        self.tangent, self.ops, self.terms = tangent, [], []
        self.n = 8 if tangent else 4
        self.one = self.new()
        self.zero = self.new() if tangent else -1
        self.tan = {i: i + 4 for i in range(4)} | {self.one: self.zero}

    def new(self) -> int:
        """A fresh series index."""
        self.n += 1
        return self.n - 1

    def emit(self, code, *args) -> None:
        """Append an operation."""
        self.ops.append((code, *args, *[0] * (5 - len(args))))

    def _lin_raw(self, terms, out=None) -> int:
        out = self.new() if out is None else out
        self.emit(LIN, out, len(self.terms), len(terms))
        self.terms += terms
        return out

    def mul(self, a: int, b: int) -> int:
        """a b (and a' b + a b')."""
        out = self.new()
        self.emit(MUL, out, a, b)
        if self.tangent:
            da, db = self.tan[a], self.tan[b]
            t = self.new()
            if da == self.zero:
                self.emit(MUL, t, a, db)
            elif db == self.zero:
                self.emit(MUL, t, da, b)
            else:
                self.emit(MUL2, t, da, b, a, db)
            self.tan[out] = t
        return out

    def lin(self, terms, out=None) -> int:
        """sum of coefficient x series over ``terms`` [(SymPy coefficient, series)], into series ``out``
        (a new one when None)."""
        out = self._lin_raw(terms, out)
        if self.tangent:
            moving = [(c, self.tan[s]) for c, s in terms if self.tan[s] != self.zero]
            self.tan[out] = self._lin_raw(moving) if moving else self.zero
        return out

    def div(self, num: int, den: int) -> int:
        """num / den."""
        out = self.new()
        self.emit(DIV, out, num, den)
        if self.tangent:
            self.tan[out] = self.new()
            self.emit(DIVT, self.tan[out], self.tan[num], den, self.tan[den], out)
        return out

    def sincos(self, x: int, w: int, sign: int) -> tuple[int, int]:
        """(S, C) = sign (sin x, cos x), w the series of dx/dt (filled later in the same order)."""
        S, C = self.new(), self.new()
        self.emit(SINCOS, S, C, x, w, sign)
        if self.tangent:
            self.tan[S] = self.new()
            self.emit(MUL, self.tan[S], C, self.tan[x])
            s_dx = self.new()
            self.emit(MUL, s_dx, S, self.tan[x])
            self.tan[C] = self._lin_raw([(sp.Integer(-1), s_dx)])
        return S, C

    def deriv(self, y: int, f: int) -> None:
        """y_{k+1} = f_k / (k + 1)."""
        self.emit(DERIV, y, f)
        if self.tangent:
            self.emit(DERIV, self.tan[y], self.tan[f])


def _monomial(b: _Builder, memo: dict, powers: tuple) -> int:
    """The series of the monomial with exponents ``powers``: the largest known divisor times the rest."""
    if powers not in memo:
        divisors = [d for d in memo if any(d) and d != powers and all(x <= y for x, y in zip(d, powers))]
        d = max(sorted(divisors), key=sum)
        rest = tuple(y - x for x, y in zip(d, powers))
        memo[powers] = b.mul(memo[d], _monomial(b, memo, rest))
    return memo[powers]


@dataclass(frozen=True)
class Program:
    """The derived recurrences: ``ops`` (n_ops, 6) int64, the linear combinations' series ``lin_src`` and
    SymPy coefficients ``lin_coef`` (in the K[j] of the polynomial form), the number of series, of
    integrated variables (4, or 8 with the tangent) and the index of the constant series 1."""

    ops: np.ndarray
    lin_src: np.ndarray
    lin_coef: tuple
    n_series: int
    n_vars: int
    one: int


@cache
def program(tangent: bool = False) -> Program:
    """The Taylor recurrences of the sleigh (with one tangent vector when ``tangent``), from
    ``mechanics.derive()``: monomials of the polynomial form, its numerators and denominator, and
    d delta/dt (``derive().rhs[3]``, linear in the state)."""
    d = mech.derive()
    form = d.polynomial
    b = _Builder(tangent)
    gens = (mech.u, mech.Omega, mech.omega, mech.S, mech.C)
    rate = sp.Poly(d.rhs[3], *mech.STATE[:3]).terms()
    if any(sum(powers) != 1 for powers, _ in rate):
        raise ValueError(f"d delta/dt = {d.rhs[3]} is not linear in (u, Omega, omega)")
    w = b.new()  # d delta/dt: used by the sine and cosine from order 1 on, filled after the velocities
    S, C = b.sincos(3, w, -1)  # the stored angle is delta + pi
    memo = {(0,) * 5: b.one} | {tuple(int(i == j) for j in range(5)): s for i, s in enumerate((0, 1, 2, S, C))}

    def combination(p):
        return b.lin([(c, _monomial(b, memo, powers)) for powers, c in sorted(sp.Poly(p, *gens).terms())])

    den = combination(form.denominator)
    q = [b.div(combination(n), den) for n in form.numerators]
    b.lin([(c, powers.index(1)) for powers, c in rate], out=w)
    for i, qi in enumerate(q):
        b.deriv(i, qi)
    b.deriv(3, w)
    return Program(np.array(b.ops, dtype=np.int64), np.array([s for _, s in b.terms], dtype=np.int64),
                   tuple(c for c, _ in b.terms), b.n, 8 if tangent else 4, b.one)


def exact_coefficients(prog: Program, params: Params) -> list[Fraction]:
    """The linear combinations' coefficients for ``params``: the K[j] of the polynomial form evaluated
    exactly (fractions of the double parameters)."""
    form = mech.derive().polynomial
    exact = {s: sp.Rational(Fraction(v)) for s, v in zip(mech.PHYSICAL, params.values)}
    K = {k: sp.expand(c.subs(exact)) for k, c in zip(form.K, form.coefficients)}
    return [Fraction(int(v.p), int(v.q)) for v in (sp.Rational(c.subs(K)) for c in prog.lin_coef)]


def coefficients(prog: Program, params: Params) -> np.ndarray:
    """:func:`exact_coefficients` rounded to double-double pairs, (n, 2)."""
    return np.array([dd.pair(v) for v in exact_coefficients(prog, params)]).reshape(-1, 2)
