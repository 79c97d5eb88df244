"""The numerical model, built from the symbolic derivation in :mod:`sleighsim.model.mechanics`.

State y = (u, Omega, omega, delta): runner speed u [length/time], sleigh and
rotor angular velocities Omega, omega [rad/time], relative angle
delta = theta - beta [rad]. The optional kinematic extension appends
(theta, x, y): heading [rad] and the centre C in the plane [length].
Parameters are physical (:class:`sleighsim.model.params.Params`).
"""

from __future__ import annotations

from functools import cache

import heyoka as hy
import numpy as np
import sympy as sp

from sleighsim.model import mechanics as mech
from sleighsim.model.params import PARAM_NAMES, Params, largest

STATE_NAMES = ("u", "Omega", "omega", "delta")
KINEMATIC_NAMES = ("theta", "x", "y")
#: Angles (state index) that enter the equations only through sin and cos: reducing them by
#: whole turns is an exact symmetry (delta always; theta in the kinematic extension).
DELTA, THETA = 3, 4


def _symbols():
    return (*mech.STATE, *mech.PHYSICAL)


@cache
def _lambdified(which: str):
    d = mech.derive()
    if which == "rhs":
        exprs = list(d.rhs)
    elif which == "energy":
        exprs = [d.energy]
    elif which == "jacobian":
        exprs = list(sp.Matrix(d.rhs).jacobian(mech.STATE))
    elif which == "divergence":
        exprs = [sum(sp.diff(f, x) for f, x in zip(d.rhs, mech.STATE))]
    else:  # pragma: no cover - internal
        raise KeyError(which)
    return sp.lambdify(_symbols(), exprs, modules="numpy", cse=True)


def _call(which, y, params: Params):
    y = np.asarray(y, dtype=float)
    if y.shape[-1] < 4:
        raise ValueError(f"state must have at least 4 components (u, Omega, omega, delta); got shape {y.shape}")
    cols = [y[..., i] for i in range(4)]
    out = _lambdified(which)(*cols, *params.values)
    return [np.broadcast_to(np.asarray(o, dtype=float), y.shape[:-1]) for o in out]


def rhs(y, params: Params) -> np.ndarray:
    """d/dt (u, Omega, omega, delta), vectorised over leading axes of y (shape (..., 4))."""
    return np.stack(_call("rhs", y, params), axis=-1)


def energy(y, params: Params) -> np.ndarray:
    """Kinetic energy E = 1/2 v^T M(delta) v in physical units, shape y.shape[:-1]."""
    return _call("energy", y, params)[0]


def jacobian(y, params: Params) -> np.ndarray:
    """d rhs / d y, shape (..., 4, 4)."""
    flat = _call("jacobian", y, params)
    return np.stack(flat, axis=-1).reshape(*np.shape(y)[:-1], 4, 4)


def divergence(y, params: Params) -> np.ndarray:
    """The divergence of the flow, trace of d rhs / d y (1/time), shape y.shape[:-1]: the rate of change of ln of
    a phase-space volume, whose time mean along an orbit is the sum of its Lyapunov exponents."""
    return _call("divergence", y, params)[0]


def second_derivative(y, params: Params, f=None) -> np.ndarray:
    """d^2 y / dt^2 = J(y) rhs(y) along the flow, shape (..., 4); ``f``: rhs(y), if already known."""
    return np.einsum("...ij,...j->...i", jacobian(y, params), rhs(y, params) if f is None else f)


def kinematics_rhs(y_full, params: Params) -> np.ndarray:
    """d/dt (theta, x, y) from (u, Omega, omega, delta, theta, x, y)."""
    y_full = np.asarray(y_full, dtype=float)
    u, Om, th = y_full[..., 0], y_full[..., 1], y_full[..., 4]
    b = params.b
    return np.stack([Om, u * np.cos(th) - b * Om * np.sin(th), u * np.sin(th) + b * Om * np.cos(th)], axis=-1)


def full_rhs(y_full, params: Params) -> np.ndarray:
    """Right-hand side of the 4-state system, or of the 7-state one when y has 7 components."""
    y_full = np.asarray(y_full, dtype=float)
    base = rhs(y_full[..., :4], params)
    if y_full.shape[-1] == 4:
        return base
    return np.concatenate([base, kinematics_rhs(y_full, params)], axis=-1)


def heyoka_vars(kinematics: bool = False):
    """heyoka variables of the state, (theta, x, y) appended when ``kinematics``."""
    return hy.make_vars(*(STATE_NAMES + (KINEMATIC_NAMES if kinematics else ())))


@cache
def _coefficients():
    return sp.lambdify(mech.PHYSICAL, list(mech.derive().polynomial.coefficients), modules="numpy")


def heyoka_pars(params: Params, dtype=float) -> np.ndarray:
    """The runtime parameters of the compiled sleigh: par[0..5] the physical ones (PARAM_NAMES
    order), then the coefficients K[j] of the polynomial form (mechanics.PolynomialForm), computed
    in ``dtype`` (the integrator's floating-point type)."""
    check_coefficients(params)
    values = np.array(params.values, dtype=dtype)
    return np.array([*values, *_coefficients()(*values)], dtype=dtype)


def check_coefficients(params: Params) -> None:
    """ValueError naming the largest parameter when a coefficient K[j] of the equations (a product
    of up to six parameters) overflows double precision, where the integrators would stop at once."""
    with np.errstate(over="ignore", invalid="ignore"):
        coefficients = np.array(_coefficients()(*np.array(params.values, dtype=float)), dtype=float)
    if not np.all(np.isfinite(coefficients)):
        raise ValueError(f"{largest(dict(zip(PARAM_NAMES, params.values)))} is too large: the coefficients of "
                         "the equations overflow double precision")


def compile_pars(dtype=float) -> np.ndarray:
    """Runtime parameters to build a compiled sleigh with (the paper's form at eps = 0.1, in
    ``dtype``); each run sets its own with sleighsim.engine.integrators.set_pars."""
    return heyoka_pars(Params.paper(eps=0.1), dtype)


def n_heyoka_pars() -> int:
    """How many runtime parameters the compiled sleigh takes (:func:`heyoka_pars`)."""
    return len(PARAM_NAMES) + len(mech.derive().polynomial.K)


def _heyoka_polynomial(p, symbols: dict):
    """The SymPy polynomial ``p`` in (u, Omega, omega, S, C) as a heyoka expression: a sum of
    products (powers written as repeated factors) of ``symbols`` (SymPy symbol -> heyoka expression)."""
    gens = (mech.u, mech.Omega, mech.omega, mech.S, mech.C)
    terms = []
    for powers, c in sp.Poly(p, *gens).terms():
        factors = [symbols[c]] if c.is_Symbol else ([] if c == 1 else [hy.expression(float(c))])
        factors += [symbols[g] for g, m in zip(gens, powers) for _ in range(m)]
        terms.append(hy.prod(factors) if len(factors) > 1 else factors[0])
    return hy.sum(terms) if len(terms) > 1 else terms[0]


def heyoka_system(kinematics: bool = False, delta_shift: float = 0.0):
    """[(var, expr), ...] for heyoka, from the polynomial form of the derivation (about a third of
    the operations per Taylor order of the explicit rhs); parameters as :func:`heyoka_pars` orders
    them. The variable ``delta`` stores delta + delta_shift (sleighsim.engine.integrators keeps it in
    [0, 2 pi))."""
    hv = heyoka_vars(kinematics)
    u_, Om_, om_, de_ = hv[:4]
    d = de_ - delta_shift if delta_shift else de_
    form = mech.derive().polynomial
    symbols = {mech.u: u_, mech.Omega: Om_, mech.omega: om_, mech.S: hy.sin(d), mech.C: hy.cos(d)}
    symbols.update({k: hy.par[len(PARAM_NAMES) + j] for j, k in enumerate(form.K)})
    den = _heyoka_polynomial(form.denominator, symbols)
    sys = [(v, _heyoka_polynomial(n, symbols) / den) for v, n in zip(hv[:3], form.numerators)]
    sys.append((de_, Om_ - om_))
    if kinematics:
        th_ = hv[4]
        b_ = hy.par[PARAM_NAMES.index("b")]
        sys += [
            (hv[4], Om_),
            (hv[5], u_ * hy.cos(th_) - b_ * Om_ * hy.sin(th_)),
            (hv[6], u_ * hy.sin(th_) + b_ * Om_ * hy.cos(th_)),
        ]
    return sys


def state_difference(a, b) -> np.ndarray:
    """a - b for states (..., 4 or more), with delta (and theta) compared modulo 2 pi; in long double
    when either is."""
    d = np.asarray(a) - np.asarray(b)
    d = d.astype(np.result_type(d.dtype, float))
    for i in (DELTA, THETA)[: 2 if d.shape[-1] > THETA else 1]:
        d[..., i] = (d[..., i] + np.pi) % (2.0 * np.pi) - np.pi
    return d
