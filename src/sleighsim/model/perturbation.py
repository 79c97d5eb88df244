"""The regular perturbation hierarchy in eps, derived from the mechanics (SymPy).

The convention, :data:`CONVENTION` (written into the hierarchy datasets): K2 held fixed, K2 - 1 =
kappa eps, so that the hierarchy is regular at eps = 0.

Substituting x = x0 + eps x1 + eps^2 x2 + ... for x in (u, Omega, omega, delta)
and equating powers of eps gives the hierarchy: order 0 is the eps = 0 sleigh,
order k is linear in the order-k unknowns with forcing from lower orders. F is
even in its explicit eps, so odd orders start from zero and stay zero when their
initial data vanish (the paper's case).
"""

from __future__ import annotations

from functools import cache

import numpy as np
import sympy as sp
import xarray as xr

from sleighsim.model import mechanics as mech

#: The paper's convention, made explicit (attribute ``convention`` of the hierarchy datasets).
CONVENTION = (
    "Convention (the paper's, made explicit): K2 = K^2 is held fixed as an O(1) parameter and K2 - 1 = kappa "
    "eps with kappa explicit (default 1, so that K2 = 1 + eps is the model's default). The derived right-hand "
    "sides are brought to the form N(eps, K2) / (eps D), D = K2^2 + eps (K2 - 1) cos^2(delta) (the paper's "
    "denominator, sin^2 = 1 - cos^2 reduced); in every coefficient of eps in N and in D, each factor (K2 - 1) "
    "is replaced by kappa eps. The result F(eps; K2, kappa) equals the derived system identically when kappa = "
    "(K2 - 1)/eps (a test checks it) and is regular at eps = 0."
)
kappa = sp.Symbol("kappa", positive=True)
VARS = ("u", "Omega", "omega", "delta")
_S, _C = sp.symbols("S C")  # sin(delta), cos(delta) while the equations are polynomial


def _reduce_trig(p):
    """p with sin^2 = 1 - cos^2 applied (p polynomial in S, C)."""
    return sp.expand(sp.rem(sp.expand(p), _S**2 + _C**2 - 1, _S))


def _strip_K2_minus_1(coeff):
    """(j, rest) with coeff = (K2 - 1)^j rest and rest not divisible by K2 - 1."""
    j = 0
    while True:
        q, r = sp.div(coeff, mech.K2 - 1, mech.K2)
        if r != 0 or coeff == 0:
            return j, coeff
        coeff, j = q, j + 1


def _kappa_form(poly_in_eps):
    """Replace every factor (K2 - 1) of each eps-coefficient by kappa eps."""
    P = sp.Poly(sp.expand(poly_in_eps), mech.eps)
    out = 0
    for (k,), c in P.terms():
        j, rest = _strip_K2_minus_1(sp.factor(c))
        out += mech.eps ** (k + j) * kappa**j * rest
    return sp.expand(out)


@cache
def paper_form():
    """(F_u, F_Omega, F_omega) as rational functions of (u, Omega, omega, S, C; eps, b, K2, kappa).

    deltadot = Omega - omega is exact and not listed."""
    d = mech.derive()
    D = mech.K2**2 + mech.eps * (mech.K2 - 1) * _C**2
    trig = {sp.sin(mech.delta): _S, sp.cos(mech.delta): _C}
    Dk = _kappa_form(D)
    out = []
    for e in d.rhs[:3]:
        num, den = sp.fraction(sp.together(e.subs(mech.paper_substitution()).subs(trig) * D * mech.eps))
        N = sp.cancel(_reduce_trig(num) / _reduce_trig(den))  # a polynomial: D divides out
        Nk = _kappa_form(sp.expand(N))
        lead = Nk.subs(mech.eps, 0)
        if lead != 0:  # pragma: no cover - a property of the mechanics, tested
            raise ArithmeticError(f"eps-singular term survives the K2 - 1 = kappa eps substitution: {lead}")
        out.append(sp.expand(Nk / mech.eps) / Dk)
    return tuple(out)


def paper_form_rhs():
    """paper_form() with S, C back to sin(delta), cos(delta) (for comparisons)."""
    back = {_S: sp.sin(mech.delta), _C: sp.cos(mech.delta)}
    return tuple(f.subs(back) for f in paper_form())


def symbols(order: int) -> dict:
    """{'u': (u0, ..., u_order), ...} SymPy symbols of the hierarchy variables."""
    return {v: sp.symbols(f"{v}0:{order + 1}", real=True) for v in VARS}


# ------------------------------------------------------------ truncated series


class _Series:
    """Power series in eps truncated after ``order`` (a list of SymPy coefficients)."""

    def __init__(self, coeffs, order):
        self.c = [sp.expand(x) for x in coeffs] + [sp.Integer(0)] * (order + 1 - len(coeffs))
        self.n = order

    def __add__(self, other):
        return _Series([a + b for a, b in zip(self.c, other.c)], self.n)

    def __mul__(self, other):
        return _Series([sum(self.c[i] * other.c[k - i] for i in range(k + 1)) for k in range(self.n + 1)], self.n)

    def scale(self, x):
        return _Series([x * a for a in self.c], self.n)

    def inverse(self):
        inv = [1 / self.c[0]]
        for k in range(1, self.n + 1):
            inv.append(-sum(self.c[j] * inv[k - j] for j in range(1, k + 1)) / self.c[0])
        return _Series(inv, self.n)


def _trig_series(delta_k, order):
    """Series of sin(delta), cos(delta) with delta = delta0 + eps delta1 + ..."""
    one = _Series([1], order)
    Delta = _Series([0, *delta_k[1:]], order)
    cosD, sinD, power = _Series([1], order), _Series([0], order), one
    for n in range(1, order + 1):
        power = power * Delta
        term = power.scale(sp.Integer((-1) ** (n // 2)) / sp.factorial(n))
        if n % 2:
            sinD = sinD + term
        else:
            cosD = cosD + term
    s0, c0 = sp.sin(delta_k[0]), sp.cos(delta_k[0])
    return sinD.scale(c0) + cosD.scale(s0), cosD.scale(c0) + sinD.scale(-s0)


def _series_of(poly, base, order):
    gens = list(base)
    P = sp.Poly(poly, *gens)
    powers: dict = {}
    total = _Series([0], order)
    for mon, coef in P.terms():
        acc = _Series([coef], order)
        for g, e in zip(gens, mon):
            if e:
                if (g, e) not in powers:
                    p = _Series([1], order)
                    for _ in range(e):
                        p = p * base[g]
                    powers[(g, e)] = p
                acc = acc * powers[(g, e)]
        total = total + acc
    return total


@cache
def hierarchy(order: int) -> dict:
    """The hierarchy to ``order``: {'u': [udot_0, ..., udot_order], 'Omega': [...], 'omega': [...],
    'delta': [...]} as SymPy expressions in the symbols of :func:`symbols` and (b, K2, kappa)."""
    if order < 0:
        raise ValueError(f"order = {order} must be >= 0")
    x = symbols(order)
    S, C = _trig_series(x["delta"], order)
    base = {mech.eps: _Series([0, 1], order), _S: S, _C: C}
    base.update({getattr(mech, v): _Series(list(x[v]), order) for v in ("u", "Omega", "omega")})
    out = {}
    for v, F in zip(("u", "Omega", "omega"), paper_form()):
        num, den = sp.fraction(sp.together(F))
        out[v] = [sp.expand(c) for c in (_series_of(num, base, order) * _series_of(den, base, order).inverse()).c]
    out["delta"] = [x["Omega"][k] - x["omega"][k] for k in range(order + 1)]
    return out


# ------------------------------------------------------------ the paper's printed hierarchy


def printed_hierarchy() -> dict:
    """Equations (eq:u0)-(eq:omega2) of the paper as printed, K^2 -> K2 (orders 0-2).

    The paper gives no delta_k equations; deltadot_k = Omega_k - omega_k is implied."""
    x = symbols(2)
    u, Om, om, de = x["u"], x["Omega"], x["omega"], x["delta"]
    b, K2 = mech.b, mech.K2
    s0, c0 = sp.sin(de[0]), sp.cos(de[0])
    return {
        "u": [b * Om[0] ** 2, 2 * b * Om[0] * Om[1],
              u[0] * Om[0] * s0 * c0 / K2**3 + b * Om[1] ** 2 + 2 * b * Om[0] * Om[2] + b * K2 * om[0] ** 2 * c0],
        "Omega": [-u[0] * Om[0] / (b * K2), -u[1] * Om[0] / (b * K2) - Om[1] * u[0] / (b * K2),
                  u[0] * Om[0] * c0**2 / (b * K2**3) - u[2] * Om[0] / (b * K2) - u[1] * Om[1] / (b * K2)
                  - u[0] * Om[2] / (b * K2) - om[0] ** 2 * s0 / K2],
        "omega": [-u[0] * Om[0] * c0 / (b * K2**2), -(u[1] * Om[0] + u[0] * Om[1]) * c0 / (b * K2**2),
                  (u[0] * Om[0] * c0**2 / (b * K2**4) - u[2] * Om[0] / (b * K2**2) - u[1] * Om[1] / (b * K2**2)
                   - u[0] * Om[2] / (b * K2**2) - om[0] ** 2 * s0 / K2**2) * c0
                  + u[0] * Om[0] * de[2] * s0 / (K2**2 * b)],
    }


def _terms(expr, order):
    """{monomial: coefficient} of expr over the hierarchy variables and sin/cos(delta0), sin^2 reduced."""
    x = symbols(order)
    s0, c0 = sp.sin(x["delta"][0]), sp.cos(x["delta"][0])
    gens = [g for v in VARS for g in x[v]] + [s0, c0]
    P = sp.Poly(sp.expand(expr), *gens)
    P = sp.Poly(sp.rem(P.as_expr(), s0**2 + c0**2 - 1, s0), *gens)
    return {sp.Mul(*[g**e for g, e in zip(gens, mon)]): c for mon, c in P.terms()}


def compare_printed(kappa_value=1) -> list[dict]:
    """Every term where the derived hierarchy (orders 0-2, kappa = ``kappa_value``) and the
    printed one differ: equation, term, derived and printed coefficients."""
    derived, printed = hierarchy(2), printed_hierarchy()
    rows = []
    for v in ("u", "Omega", "omega"):
        for k in range(3):
            dt = _terms(derived[v][k], 2)
            dk = {m: sp.factor(c.subs(kappa, kappa_value)) for m, c in dt.items()}
            pt = {m: sp.factor(c) for m, c in _terms(printed[v][k], 2).items()}
            for mono in sorted(set(dk) | set(pt), key=sp.default_sort_key):
                cd, cp = dk.get(mono, sp.Integer(0)), pt.get(mono, sp.Integer(0))
                if sp.simplify(cd - cp) != 0:
                    rows.append({"equation": f"d{v}{k}/dt", "term": str(mono), "derived": str(cd),
                                 "derived_with_kappa": str(sp.factor(dt.get(mono, 0))), "printed": str(cp)})
    return rows


# ------------------------------------------------------------ integration (heyoka)


def state_names(order: int) -> list[str]:
    """The hierarchy's state names to ``order``, order by order: u0, Omega0, omega0, delta0, u1, ..."""
    return [f"{v}{k}" for k in range(order + 1) for v in VARS]


def partial_sum(ds: xr.Dataset, var: str, eps: float, upto: int) -> np.ndarray:
    """var0 + eps var1 + ... + eps^upto var_upto from a hierarchy dataset."""
    return sum(eps**k * ds[f"{var}{k}"].values for k in range(upto + 1))


def forcing_terms(order: int, var: str) -> list:
    """The terms of d var_order/dt that contain no order-``order`` unknown (its forcing)."""
    x = symbols(order)
    own = {x[v][order] for v in VARS}
    return [t for t in sp.Add.make_args(hierarchy(order)[var][order]) if not (t.free_symbols & own)]


def lambdify_terms(terms, order: int):
    """A NumPy function of a hierarchy dataset's columns (in state_names order) and (b, K2, kappa)."""
    x = symbols(order)
    args = [x[v][k] for k in range(order + 1) for v in VARS] + [mech.b, mech.K2, kappa]
    return sp.lambdify(args, list(terms), modules="numpy")
