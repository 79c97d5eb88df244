"""Symbolic derivation of the reduced sleigh-rotor equations (SymPy).

Configuration (x, y, theta, beta): sleigh centre C at (x, y), heading theta,
rotor angle beta. The rotor's centre sits at C + a (cos beta, sin beta). The
runner at P, a distance b behind C, cannot slip sideways:

    -xdot sin(theta) + ydot cos(theta) - b thetadot = 0.

Admissible velocities are qdot = S(theta) v with body velocities
v = (u, Omega, omega): u the runner's longitudinal speed, Omega = thetadot,
omega = betadot. Projecting the Euler-Lagrange equations onto the admissible
directions (Lagrange-d'Alembert) eliminates the multiplier and gives

    M(delta) vdot = f(u, Omega, omega, delta),   deltadot = Omega - omega,

with delta = theta - beta. The projected equations are invariant under
rotations of the plane, so they are evaluated at theta = 0 (beta = -delta);
a test checks that invariance at random headings.

The derivation (about 0.3 s of CPU with the polynomial form, no blanket ``simplify``) runs once per
process and is kept in memory only. It was once cached on disk as SymPy text, which read back became
code (issue 54: a Symbol's name is pasted into the source ``lambdify`` runs); reading it saved 0.26 s
per process, about 1.5% of a full run's CPU, so nothing of it is read from disk any more.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import sympy as sp

from sleighsim.io.cachedir import project_cache

# Physical parameters, state and accelerations (all public: other modules build on them).
m_c, m_r, I_c, I_r, a, b = sp.symbols("m_c m_r I_c I_r a b", positive=True)
PHYSICAL = (m_c, m_r, I_c, I_r, a, b)
u, Omega, omega, delta = sp.symbols("u Omega omega delta", real=True)
STATE = (u, Omega, omega, delta)
theta = sp.Symbol("theta", real=True)
eps, K2 = sp.symbols("epsilon K2", positive=True)
_udot, _Omegadot, _omegadot = sp.symbols("udot Omegadot omegadot")
#: sin(delta) and cos(delta) in the polynomial form of the equations.
S, C = sp.symbols("S C", real=True)


@dataclass(frozen=True)
class PolynomialForm:
    """The velocity equations as vdot_i = N_i / D: N_i polynomials in (u, Omega, omega, S, C) and D
    in S (S = sin delta, C = cos delta; C^2 reduced to 1 - S^2) whose coefficients are the symbols
    K[j]; ``coefficients[j]`` is K[j] as a polynomial in the physical parameters. The coefficients
    are evaluated once per parameter set instead of at every step of an integrator."""

    numerators: tuple
    denominator: sp.Expr
    K: tuple
    coefficients: tuple

    def explicit(self) -> list:
        """The three N_i / D with S, C and every K[j] written out (sin delta, cos delta and the
        coefficients in the physical parameters)."""
        back = {S: sp.sin(delta), C: sp.cos(delta), **dict(zip(self.K, self.coefficients))}
        return [(n / self.denominator).subs(back) for n in self.numerators]


@dataclass(frozen=True)
class Derivation:
    """The reduced equations in physical parameters.

    M: 3x3 locked inertia, f: right-hand side of M vdot = f,
    rhs: explicit (udot, Omegadot, omegadot, deltadot) = (adj(M) f / det M, Omega - omega),
    energy: 1/2 v^T M v, polynomial: the same vdot as a :class:`PolynomialForm`.
    """

    M: sp.Matrix
    f: sp.Matrix
    rhs: tuple
    energy: sp.Expr
    lagrangian: sp.Expr
    polynomial: PolynomialForm


def _lagrangian():
    t = sp.Symbol("t")
    x, y, th, be = (sp.Function(n)(t) for n in ("x", "y", "theta", "beta"))
    xr, yr = x + a * sp.cos(be), y + a * sp.sin(be)
    L = (
        m_c * (x.diff(t) ** 2 + y.diff(t) ** 2)
        + m_r * (xr.diff(t) ** 2 + yr.diff(t) ** 2)
        + I_c * th.diff(t) ** 2
        + I_r * be.diff(t) ** 2
    ) / 2
    return t, (x, y, th, be), L


@cache
def projected_equations(theta_value=0):
    """S^T (d/dt dL/dqdot - dL/dq) with qdot = S v, at heading ``theta_value``.

    Returns a 3-vector linear in (udot, Omegadot, omegadot). ``theta_value``
    may be a symbol, to check rotation invariance.
    """
    t, q, L = _lagrangian()
    Q = sp.symbols("X Y TH BE")
    Qd = sp.symbols("Xd Yd THd BEd")
    Qdd = sp.symbols("Xdd Ydd THdd BEdd")
    to_plain = {}
    for fq, s, sd, sdd in zip(q, Q, Qd, Qdd):
        to_plain[fq.diff(t, 2)] = sdd
        to_plain[fq.diff(t)] = sd
        to_plain[fq] = s
    el = [sp.expand((L.diff(fq.diff(t)).diff(t) - L.diff(fq)).subs(to_plain)) for fq in q]
    TH = Q[2]
    S = sp.Matrix(
        [[sp.cos(TH), -b * sp.sin(TH), 0], [sp.sin(TH), b * sp.cos(TH), 0], [0, 1, 0], [0, 0, 1]]
    )
    v = sp.Matrix([u, Omega, omega])
    vd = sp.Matrix([_udot, _Omegadot, _omegadot])
    qd = S * v
    qdd = S * vd + S.diff(TH) * Omega * v
    sub = {Qd[i]: qd[i] for i in range(4)} | {Qdd[i]: qdd[i] for i in range(4)}
    projected = S.T * sp.Matrix([e.subs(sub) for e in el])
    projected = projected.subs({TH: theta_value, Q[3]: theta_value - delta})
    return sp.expand(projected)


def _old_cache_files() -> list[Path]:
    """Derivation files an earlier sleighsim kept between processes (``$SLEIGHSIM_CACHE``, default
    ``~/.cache/sleighsim``): listed by name for :func:`derive`'s warning, never opened."""
    try:
        return sorted(project_cache()[0].glob("derivation-*.json"))
    except OSError:
        return []


@cache
def derive() -> Derivation:
    """M(delta), f and the explicit reduced vector field, derived once per process (about 0.3 s of
    CPU). Nothing is read from disk; a derivation file an earlier sleighsim cached is named in a
    warning and ignored."""
    for path in _old_cache_files():
        warnings.warn(f"{path}: a derivation cached by an earlier sleighsim, ignored: the derivation is no "
                      "longer read from disk, where code could hide in it (issue 54); delete the file",
                      stacklevel=2)
    return _derive()


def _derive() -> Derivation:
    """Derive M(delta), f and the explicit reduced vector field."""
    # sin^2 + cos^2 = 1 is the only identity needed; no blanket simplify.
    red = sp.expand(projected_equations(0).subs(sp.sin(delta) ** 2, 1 - sp.cos(delta) ** 2))
    acc = sp.Matrix([_udot, _Omegadot, _omegadot])
    M = red.jacobian(acc)
    f = sp.expand(-(red - M * acc))
    det = M.det(method="berkowitz")
    vdot = M.adjugate() * f / det
    v = sp.Matrix([u, Omega, omega])
    energy = (v.T * M * v)[0, 0] / 2
    _, _, L = _lagrangian()
    return Derivation(M=M, f=f, rhs=(*vdot, Omega - omega), energy=energy, lagrangian=L,
                      polynomial=_polynomial_form(vdot))


def _polynomial_form(vdot) -> PolynomialForm:
    """vdot (explicit, in sin and cos of delta) as a :class:`PolynomialForm`: each component over
    a common denominator, sin and cos named S and C, C^2 reduced to 1 - S^2, every coefficient of a
    monomial in (u, Omega, omega, S, C) that is not a number named K[j] (equal coefficients share
    one name)."""
    trig = {sp.sin(delta): S, sp.cos(delta): C}
    names: dict = {}

    def reduced(p):
        p = sp.expand(sp.rem(sp.expand(p.subs(trig)), C**2 + S**2 - 1, C))
        out = sp.S.Zero
        for powers, c in sp.Poly(p, u, Omega, omega, S, C).terms():
            c = sp.factor(c)
            if not c.is_Number:
                c = names.setdefault(c, sp.Symbol(f"K{len(names)}"))
            out += c * sp.Mul(*(g**m for g, m in zip((u, Omega, omega, S, C), powers)))
        return out

    parts = [sp.fraction(sp.together(e)) for e in vdot]
    dens = {sp.expand(d) for _, d in parts}
    if len(dens) != 1:
        raise ValueError(f"the velocity equations have {len(dens)} different denominators, expected one")
    nums = tuple(reduced(n) for n, _ in parts)
    den = reduced(dens.pop())
    return PolynomialForm(numerators=nums, denominator=den, K=tuple(names.values()), coefficients=tuple(names))


def paper_substitution():
    """Physical parameters in terms of the paper's (epsilon, b, K2), docs/model.md.

    m = 1, m_r = eps, a = eps b, I_c = (K2 - 1) b^2, I_r = eps^3 b^2 (K2 - 1 + eps).
    Under this map the printed Omegadot and omegadot equal the derived ones.
    """
    return {
        m_c: 1 - eps,
        m_r: eps,
        a: eps * b,
        I_c: (K2 - 1) * b**2,
        I_r: eps**3 * b**2 * (K2 - 1 + eps),
    }


@cache
def b_free_form():
    """The derived equations in the paper's parameters for (v, Omega, omega, delta), v = u / b.

    With K2 held fixed, b is a length scale: none of these right-hand sides contains b (tested),
    so lambda(eps, b) = lambda(eps, 1) and a solution at one b maps to every other by u -> u b'/b."""
    v = sp.Symbol("v", real=True)
    rhs = [e.subs(paper_substitution()).subs(u, b * v) for e in derive().rhs]
    return (sp.cancel(sp.together(rhs[0] / b)), *(sp.cancel(sp.together(e)) for e in rhs[1:])), v
