"""Numerical model built from the symbolic derivation in :mod:`sleighsim.mechanics`.

State y = (u, Omega, omega, delta): runner speed u [length/time], sleigh and
rotor angular velocities Omega, omega [rad/time], relative angle
delta = theta - beta [rad]. The optional kinematic extension appends
(theta, x, y): heading [rad] and the centre C in the plane [length].

Parameters are physical (m_c, m_r, I_c, I_r, a, b) throughout; the paper's
(eps, b, K2) form maps onto them as in SCIENCE.md (m = 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp

from . import mechanics as mech

STATE_NAMES = ("u", "Omega", "omega", "delta")
KINEMATIC_NAMES = ("theta", "x", "y")
PARAM_NAMES = ("m_c", "m_r", "I_c", "I_r", "a", "b")

#: The paper's reference state at eps = 0.1 and the energy label it quotes for it.
REFERENCE_STATE = (0.0, 0.1, 1.0, 0.0)
REFERENCE_LABEL = 0.1127


def _finite(name, value):
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} = {value} is not a finite number")
    return value


@dataclass(frozen=True)
class Params:
    """Physical parameters: masses m_c, m_r, inertias I_c (about C), I_r (rotor),
    rotor offset a and runner distance b. Build with :meth:`physical` or :meth:`paper`."""

    m_c: float
    m_r: float
    I_c: float
    I_r: float
    a: float
    b: float

    @classmethod
    def physical(cls, *, m_c, m_r, I_c, I_r, a, b) -> "Params":
        vals = {k: _finite(k, v) for k, v in dict(m_c=m_c, m_r=m_r, I_c=I_c, I_r=I_r, a=a, b=b).items()}
        for k in ("m_c", "b"):
            if vals[k] <= 0:
                raise ValueError(f"{k} = {vals[k]} is outside the admissible range (0, inf)")
        for k in ("m_r", "I_c", "I_r", "a"):
            if vals[k] < 0:
                raise ValueError(f"{k} = {vals[k]} is outside the admissible range [0, inf)")
        p = cls(**vals)
        p._check_positive_definite()
        return p

    @classmethod
    def paper(cls, *, eps, b=1.0, K2=None, formal: bool = False) -> "Params":
        """The paper's form: m_r/m = a/b = eps, m = 1, K2 = 1 + I_c/(m b^2) (default 1 + eps).

        ``formal=True`` admits eps >= 1, the formal system with a negative sleigh
        mass m_c = 1 - eps (not a mechanical system; the inertia stays positive definite)."""
        eps = _finite("eps", eps)
        b = _finite("b", b)
        K2 = 1.0 + eps if K2 is None else _finite("K2", K2)
        if not (0.0 < eps < 1.0 or (formal and eps >= 1.0)):
            why = ("eps = m_r/m must be positive" if eps <= 0 else
                   "eps = m_r/m, and eps >= 1 makes m_c <= 0; pass formal=True for the formal system")
            raise ValueError(f"eps = {eps} is outside the admissible range (0, 1): {why}")
        if b <= 0:
            raise ValueError(f"b = {b} is outside the admissible range (0, inf)")
        if K2 <= 1:
            raise ValueError(f"K2 = {K2} is outside the admissible range (1, inf): K2 = 1 + I_c/(m b^2)")
        if eps >= 1.0:
            p = cls(m_c=1.0 - eps, m_r=eps, I_c=(K2 - 1.0) * b**2, I_r=eps**3 * b**2 * (K2 - 1.0 + eps),
                    a=eps * b, b=b)
            p._check_positive_definite()
            return p
        return cls.physical(
            m_c=1.0 - eps,
            m_r=eps,
            I_c=(K2 - 1.0) * b**2,
            I_r=eps**3 * b**2 * (K2 - 1.0 + eps),
            a=eps * b,
            b=b,
        )

    @classmethod
    def sleigh0(cls, *, b=1.0, K2=1.1) -> "Params":
        """The rotor-free sleigh (eps = 0) inside the full model: the rotor is massless,
        centred (a = 0) and decoupled (it spins at constant omega)."""
        return cls.physical(m_c=1.0, m_r=0.0, I_c=(K2 - 1.0) * b**2, I_r=1.0, a=0.0, b=b)

    @classmethod
    def from_config(cls, cfg: dict) -> "Params":
        """From a config block: either {eps, b, K2} or {m_c, m_r, I_c, I_r, a, b}."""
        if "eps" in cfg:
            return cls.paper(eps=cfg["eps"], b=cfg.get("b", 1.0), K2=cfg.get("K2"))
        missing = [k for k in PARAM_NAMES if k not in cfg]
        if missing:
            raise ValueError(f"parameter block needs eps (paper form) or all of {PARAM_NAMES}; missing {missing}")
        return cls.physical(**{k: cfg[k] for k in PARAM_NAMES})

    def _check_positive_definite(self):
        # det M(delta) is linear in cos^2(delta): check both ends.
        m = self.m
        J = self.I_c + m * self.b**2
        R = self.I_r + self.m_r * self.a**2
        c = self.m_r * self.a
        det_min = min(m * J * R - m * (c * self.b) ** 2, m * J * R - J * c**2)
        if not det_min > 1e-14 * m * J * max(R, 1e-300):
            raise ValueError(
                f"inertia is not positive definite (min det M = {det_min:.3g}): "
                "I_r + m_r a^2 must exceed the rotor coupling; increase I_r or reduce m_r a"
            )

    @property
    def m(self) -> float:
        return self.m_c + self.m_r

    @property
    def eps(self) -> float:
        """m_r / m (the paper's small parameter)."""
        return self.m_r / self.m

    @property
    def K2(self) -> float:
        """1 + I_c / (m b^2), the paper's K^2 (with its typo I_r -> I_c corrected)."""
        return 1.0 + self.I_c / (self.m * self.b**2)

    @property
    def is_paper_form(self) -> bool:
        """True when (m = 1, a = eps b, I_r = eps^3 b^2 (K2 - 1 + eps)) hold, so eps, b, K2 describe it exactly."""
        e, b, K2 = self.eps, self.b, self.K2
        return (
            math.isclose(self.m, 1.0, rel_tol=1e-12)
            and math.isclose(self.a, e * b, rel_tol=1e-12, abs_tol=1e-300)
            and math.isclose(self.I_r, e**3 * b**2 * (K2 - 1 + e), rel_tol=1e-12, abs_tol=1e-300)
        )

    @property
    def values(self) -> tuple:
        return tuple(getattr(self, k) for k in PARAM_NAMES)

    def attrs(self) -> dict:
        """Flat netCDF-friendly attributes: physical and paper form."""
        out = {f"param_{k}": v for k, v in zip(PARAM_NAMES, self.values)}
        out.update(param_eps=self.eps, param_K2=self.K2, param_is_paper_form=int(self.is_paper_form))
        return out


# ---------------------------------------------------------------- numeric functions


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


def heyoka_system(kinematics: bool = False):
    """[(var, expr), ...] for heyoka; parameters are par[0..5] in PARAM_NAMES order."""
    import heyoka as hy

    names = STATE_NAMES + (KINEMATIC_NAMES if kinematics else ())
    hv = hy.make_vars(*names)
    smap = {s: v for s, v in zip(mech.STATE, hv)}
    smap.update({s: hy.par[i] for i, s in enumerate(mech.PHYSICAL)})
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


# ---------------------------------------------------------------- paper audit


@lru_cache(maxsize=None)
def _printed_lambdified():
    args = (*mech.STATE, mech.eps, mech.b, mech.K2)
    return sp.lambdify(args, list(mech.paper_printed()), modules="numpy", cse=True)


def printed_heyoka_system():
    """The printed (eps, b, K2) system for heyoka, par[0..2] = (eps, b, K2). Audit only."""
    import heyoka as hy

    hv = hy.make_vars(*STATE_NAMES)
    smap = {s: v for s, v in zip(mech.STATE, hv)}
    smap.update({mech.eps: hy.par[0], mech.b: hy.par[1], mech.K2: hy.par[2]})
    return [(v, hy.from_sympy(e, smap)) for v, e in zip(hv, mech.paper_printed())]


def paper_printed_rhs(y, eps, b, K2) -> np.ndarray:
    """The paper's printed right-hand side (audit only; its udot is wrong)."""
    y = np.asarray(y, dtype=float)
    out = _printed_lambdified()(*(y[..., i] for i in range(4)), eps, b, K2)
    return np.stack([np.broadcast_to(np.asarray(o, float), y.shape[:-1]) for o in out], axis=-1)


# ---------------------------------------------------------------- energy labels


def energy_label(y, params: Params) -> np.ndarray:
    """The paper's energy label of state y: REFERENCE_LABEL times E(y) / E(reference state)."""
    return REFERENCE_LABEL * energy(y, params) / energy(REFERENCE_STATE, params)


def state_at_label(y, params: Params, label: float) -> np.ndarray:
    """y with its velocities scaled (time-scaling symmetry) so that its energy label is ``label``."""
    label = _finite("energy label", label)
    if label <= 0:
        raise ValueError(f"energy label = {label} is outside the admissible range (0, inf)")
    y = np.array(y, dtype=float)
    current = float(energy_label(y, params))
    if current <= 0:
        raise ValueError("cannot rescale a state with zero kinetic energy to a label")
    y[:3] *= math.sqrt(label / current)
    return y


# ---------------------------------------------------------------- eps = 0 sleigh


def sleigh0_rhs(y, b, K2) -> np.ndarray:
    """The rotor-free sleigh, y = (u, Omega): (b Omega^2, -u Omega / (b K2))."""
    y = np.asarray(y, dtype=float)
    u, Om = y[..., 0], y[..., 1]
    return np.stack([b * Om**2, -u * Om / (b * K2)], axis=-1)


def sleigh0_closed_form(t, u0, Omega0, b, K2):
    """Exact solution of the rotor-free sleigh from (u0, Omega0) at t = 0.

    u = V tanh(s), Omega = sign(Omega0) V sech(s) / (K b), s = s0 + V t / (b K2),
    V^2 = u0^2 + K2 b^2 Omega0^2, tanh(s0) = u0 / V; heading
    theta - theta0 = sign(Omega0) K (gd(s) - gd(s0)), gd the Gudermannian.
    Returns (u, Omega, theta - theta0) as arrays over t.
    """
    t = np.asarray(t, dtype=float)
    K = math.sqrt(K2)
    V = math.sqrt(u0**2 + K2 * b**2 * Omega0**2)
    if V == 0 or Omega0 == 0:
        return np.full_like(t, u0), np.zeros_like(t), np.zeros_like(t)
    sgn = math.copysign(1.0, Omega0)
    s0 = math.atanh(u0 / V)
    s = s0 + V * t / (b * K2)

    def gd(z):
        return 2.0 * np.arctan(np.tanh(z / 2.0))

    return V * np.tanh(s), sgn * V / (K * b * np.cosh(s)), sgn * K * (gd(s) - gd(s0))


def state_attrs(params: Params, y0) -> dict:
    """Dataset attributes for a run from y0: parameters, initial state, physical energy and label."""
    y0 = np.asarray(y0, dtype=float)
    out = params.attrs()
    out.update({f"y0_{n}": float(v) for n, v in zip(STATE_NAMES, y0)})
    out.update(energy_physical=float(energy(y0[:4], params)), energy_label=float(energy_label(y0[:4], params)))
    return out
