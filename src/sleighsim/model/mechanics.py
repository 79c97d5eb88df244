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

Everything is cached: the derivation (about 0.5 s of CPU with the polynomial form, no blanket ``simplify``)
runs once per process, and its result is kept on disk between processes (``$SLEIGHSIM_CACHE``,
default ``~/.cache/sleighsim``), under a name made from a hash of this module's source and the
SymPy version, so any change to the derivation derives afresh. The file is data, not a pickle: JSON
holding each expression as SymPy's ``srepr`` text and a SHA-256 of them; reading it evaluates only
calls of a few SymPy classes on literals (:func:`parse_srepr`), and its directory must be one only
this user controls (:func:`sleighsim.io.cachedir.private_directory`).
"""

from __future__ import annotations

import ast
import hashlib
import json
import os
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import sympy as sp

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


def cache_file() -> Path:
    """Where :func:`derive` keeps its result between processes: named by a hash of this module's
    source and the SymPy version, in ``$SLEIGHSIM_CACHE`` (default ``~/.cache/sleighsim``)."""
    key = hashlib.sha256(Path(__file__).read_bytes() + sp.__version__.encode()).hexdigest()[:16]
    root = os.environ.get("SLEIGHSIM_CACHE") or Path.home() / ".cache" / "sleighsim"
    return Path(root) / f"derivation-{key}.json"


#: The SymPy names a stored derivation's srepr text may call (every name its expressions use).
SREPR_NAMES = ("Add", "Mul", "Pow", "Integer", "Rational", "Float", "Symbol", "Function", "Derivative", "Tuple",
               "sin", "cos", "ImmutableDenseMatrix", "MutableDenseMatrix")
#: Of these, those whose first argument is a text (a name or digits, never parsed as an expression).
_TEXT_FIRST = ("Symbol", "Function", "Float")


def parse_srepr(text: str):
    """The SymPy object of ``srepr`` ``text``, evaluating nothing but calls of :data:`SREPR_NAMES` on
    numbers, booleans, lists and tuples (text only as the name of a Symbol or Function or the digits of
    a Float); ValueError for anything else (an attribute, another name, an operator)."""
    tree = ast.parse(text, mode="eval")
    texts = {id(c.args[0]) for c in ast.walk(tree) if isinstance(c, ast.Call) and c.args
             and isinstance(c.func, ast.Name) and c.func.id in _TEXT_FIRST}
    for node in ast.walk(tree):
        ok = (isinstance(node, (ast.Expression, ast.Call, ast.keyword, ast.List, ast.Tuple, ast.Load, ast.USub))
              or (isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub))
              or (isinstance(node, ast.Name) and node.id in SREPR_NAMES)
              or (isinstance(node, ast.Constant) and (not isinstance(node.value, str) or id(node) in texts)))
        if not ok:
            raise ValueError(f"text: {ast.dump(node)[:80]} is not part of a SymPy srepr of the derivation")
    return eval(compile(tree, "<srepr>", "eval"), {"__builtins__": {}}, {n: getattr(sp, n) for n in SREPR_NAMES})


def _fields(d: Derivation) -> dict:
    """The derivation's expressions by field name (the polynomial form's flattened in)."""
    poly = d.polynomial
    return {"M": d.M, "f": d.f, "rhs": list(d.rhs), "energy": d.energy, "lagrangian": d.lagrangian,
            "numerators": list(poly.numerators), "denominator": poly.denominator, "K": list(poly.K),
            "coefficients": list(poly.coefficients)}


def _digest(payload: dict) -> str:
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


def dump_derivation(d: Derivation) -> str:
    """``d`` as JSON text: each field's srepr (lists for the tuples) and their SHA-256."""
    payload = {k: [sp.srepr(e) for e in v] if isinstance(v, list) else sp.srepr(v) for k, v in _fields(d).items()}
    return json.dumps({"sha256": _digest(payload), "derivation": payload})


def load_derivation(text: str) -> Derivation:
    """The derivation of :func:`dump_derivation`'s ``text``; ValueError when its checksum does not
    match or it holds anything but srepr text of the derivation (KeyError, TypeError when malformed)."""
    stored = json.loads(text)
    payload = stored["derivation"]
    if stored["sha256"] != _digest(payload):
        raise ValueError("text: its SHA-256 does not match its contents")
    v = {k: [parse_srepr(e) for e in x] if isinstance(x, list) else parse_srepr(x) for k, x in payload.items()}
    poly = PolynomialForm(numerators=tuple(v["numerators"]), denominator=v["denominator"], K=tuple(v["K"]),
                          coefficients=tuple(v["coefficients"]))
    return Derivation(M=v["M"], f=v["f"], rhs=tuple(v["rhs"]), energy=v["energy"], lagrangian=v["lagrangian"],
                      polynomial=poly)


@cache
def derive() -> Derivation:
    """M(delta), f and the explicit reduced vector field: from the disk cache when it holds this
    derivation intact, else derived (and stored; an unwritable cache only costs the time). A cache
    directory another user owns or can write is refused (sleighsim.io.cachedir.UnsafeDirectory)."""
    # deferred: sleighsim.io.netcdf brings xarray, 0.40 s (python -X importtime) on top of this
    # module's 0.24 s, which the benchmarks and the integrator-only imports do not need
    from sleighsim.io.cachedir import private_directory
    from sleighsim.io.netcdf import atomic_path

    path = cache_file()
    try:
        private_directory(path.parent, "SLEIGHSIM_CACHE" if os.environ.get("SLEIGHSIM_CACHE") else "the derivation "
                          "cache (default of SLEIGHSIM_CACHE)")
    except OSError:  # it cannot be created: derive without it
        return _derive()
    try:
        return load_derivation(path.read_text())
    except (OSError, ValueError, KeyError, TypeError, SyntaxError):  # missing, unreadable, stale or corrupt
        pass
    d = _derive()
    try:
        with atomic_path(path) as tmp:
            tmp.write_text(dump_derivation(d))
    except OSError:
        pass
    return d


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
