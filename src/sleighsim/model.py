"""The numerical model, built from the symbolic derivation in :mod:`sleighsim.mechanics`.

State y = (u, Omega, omega, delta): runner speed u [length/time], sleigh and
rotor angular velocities Omega, omega [rad/time], relative angle
delta = theta - beta [rad]. The optional kinematic extension appends
(theta, x, y): heading [rad] and the centre C in the plane [length].
Parameters are physical (:class:`sleighsim.params.Params`).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp

from . import mechanics as mech
from .params import PARAM_NAMES, Params

STATE_NAMES = ("u", "Omega", "omega", "delta")
KINEMATIC_NAMES = ("theta", "x", "y")
#: Angles (state index) that enter the equations only through sin and cos: reducing them by
#: whole turns is an exact symmetry (delta always; theta in the kinematic extension).
DELTA, THETA = 3, 4


def _symbols():
    return (*mech.STATE, *mech.PHYSICAL)


@lru_cache(maxsize=None)
def _lambdified(which: str):
    d = mech.derive()
    if which == "rhs":
        exprs = list(d.rhs)
    elif which == "energy":
        exprs = [d.energy]
    elif which == "jacobian":
        exprs = list(sp.Matrix(d.rhs).jacobian(mech.STATE))
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
    import heyoka as hy

    return hy.make_vars(*(STATE_NAMES + (KINEMATIC_NAMES if kinematics else ())))


def heyoka_symbols(variables, delta_shift: float = 0.0) -> dict:
    """SymPy state and parameter symbols -> heyoka expressions: the state variables (the 4th
    storing delta + delta_shift) and par[0..5] (PARAM_NAMES order)."""
    import heyoka as hy

    smap = {s: v for s, v in zip(mech.STATE, variables)}
    if delta_shift:
        smap[mech.delta] = variables[DELTA] - delta_shift
    smap.update({s: hy.par[i] for i, s in enumerate(mech.PHYSICAL)})
    return smap


def heyoka_system(kinematics: bool = False, delta_shift: float = 0.0):
    """[(var, expr), ...] for heyoka; parameters are par[0..5] in PARAM_NAMES order. The variable
    ``delta`` stores delta + delta_shift (sleighsim.integrators keeps it in [0, 2 pi))."""
    import heyoka as hy

    hv = heyoka_vars(kinematics)
    smap = heyoka_symbols(hv, delta_shift)
    sys = [(v, hy.from_sympy(e, smap)) for v, e in zip(hv, mech.derive().rhs)]
    if kinematics:
        u_, Om_ = hv[0], hv[1]
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


def divergence_expr():
    """trace of d rhs / d y as a SymPy expression (the local phase-space contraction rate)."""
    d = mech.derive()
    return sum(sp.diff(d.rhs[i], s) for i, s in enumerate(mech.STATE))
