"""The paper's equations exactly as printed: for the audit only (D1-D4).

Its printed udot does not follow from the mechanics (docs/model.md); its Omegadot and
omegadot agree with the derivation under the paper substitution. Nothing but the audit
integrates these equations (``engine.printed_flow``).
"""

from __future__ import annotations

from functools import cache

import heyoka as hy
import numpy as np
import sympy as sp

from sleighsim.model.equations import STATE_NAMES
from sleighsim.model.mechanics import K2, I_c, I_r, Omega, a, b, delta, eps, m_c, m_r, omega, u


@cache
def equations():
    """The paper's equations (eq:u)-(eq:delta_dot) exactly as printed, K^2 -> K2.

    For the audit only: the printed udot does not follow from the mechanics.
    """
    D = eps * (K2 - 1) * sp.cos(delta) ** 2 + K2**2
    common = eps**2 * b * omega**2 * sp.sin(delta) + u * Omega
    udot = (
        K2**2 * b * Omega**2
        + eps * (K2 - 1) * (b * Omega**2 * sp.cos(delta) ** 2 + u * Omega * sp.sin(delta) * sp.cos(delta))
    ) / D + b * omega**2 * eps * (eps * (K2 - 1) + K2) * sp.cos(delta) / D
    Omegadot = -K2 * common / (b * D)
    omegadot = -(K2 - 1) * sp.cos(delta) * common / (eps * b * D)
    return (udot, Omegadot, omegadot, Omega - omega)


def locked_inertia():
    """The printed locked inertia tensor and right-hand side (audit, D3)."""
    m = m_c + m_r
    M = sp.Matrix(
        [
            [m_c, 0, m_r * a * sp.sin(delta)],
            [0, I_c + m * b**2, m_r * a * b * sp.cos(delta)],
            [m_r * a * sp.sin(delta), m_r * a * b * sp.cos(delta), I_r + m_r * a**2],
        ]
    )
    f = sp.Matrix(
        [
            m_c * b * Omega**2 + m_r * a * omega**2 * sp.cos(delta),
            -m_c * b * u * Omega - m_r * a * b * omega**2 * sp.sin(delta),
            -m_r * a * u * omega * sp.cos(delta),
        ]
    )
    return M, f


@cache
def _lambdified():
    return sp.lambdify((u, Omega, omega, delta, eps, b, K2), list(equations()), modules="numpy", cse=True)


def rhs(y, eps_value, b_value, K2_value) -> np.ndarray:
    """The printed right-hand side at (eps, b, K2), vectorised over leading axes of y."""
    y = np.asarray(y, dtype=float)
    out = _lambdified()(*(y[..., i] for i in range(4)), eps_value, b_value, K2_value)
    return np.stack([np.broadcast_to(np.asarray(o, float), y.shape[:-1]) for o in out], axis=-1)


def heyoka_system():
    """The printed (eps, b, K2) system for heyoka, par[0..2] = (eps, b, K2)."""
    hv = hy.make_vars(*STATE_NAMES)
    smap = {s: v for s, v in zip((u, Omega, omega, delta), hv)}
    smap.update({eps: hy.par[0], b: hy.par[1], K2: hy.par[2]})
    return [(v, hy.from_sympy(e, smap)) for v, e in zip(hv, equations())]
