"""The paper's equations exactly as printed: for the audit only (D1-D4).

Its printed udot does not follow from the mechanics (docs/model.md); its Omegadot and
omegadot agree with the derivation under the paper substitution. Nothing but the audit
integrates these equations.
"""

from __future__ import annotations

import time
from functools import cache

import heyoka as hy
import numpy as np
import sympy as sp
import xarray as xr

from sleighsim.engine import integrators
from sleighsim.model.equations import STATE_NAMES, energy
from sleighsim.model.mechanics import K2, I_c, I_r, Omega, a, b, delta, eps, m_c, m_r, omega, u
from sleighsim.model.params import Params


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


def _integrator(tol: float):
    """The printed system (compiled once per process). Returns (ta, compile_s)."""

    def build():
        return hy.taylor_adaptive(heyoka_system(), [0.0, 0.1, 1.0, 0.0], pars=[0.1, 1.0, 1.1], tol=tol)

    return integrators.compiled(("printed", tol), build, angles={"delta": (3, 0.0)})


def trajectory(params: Params, y0, times, tol: float = 2.0**-52) -> np.ndarray:
    """The printed equations integrated from ``y0`` at times[0], sampled at ``times`` (rows of
    (u, Omega, omega, delta)); ``params`` must be of the paper's form (eps, b, K2)."""
    if not params.is_paper_form:
        raise ValueError("the printed equations exist only for paper-form parameters (Params.paper)")
    ta, _ = _integrator(tol)
    ta.time = float(times[0])
    ta.state[:] = np.asarray(y0, dtype=float)
    ta.pars[:] = [params.eps, params.b, params.K2]
    res = ta.propagate_grid(np.asarray(times, dtype=float), callback=integrators.bounded(ta))
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"the printed equations stopped at t = {ta.time:.6g}: heyoka outcome {res[0].name}")
    return res[5]


def energy_drift(params: Params, y0, times, tol: float = 2.0**-52) -> xr.Dataset:
    """Integrate the printed and the derived equations from ``y0`` (heyoka, same tol)
    and return E(t)/E(0) - 1 for both; E is the mechanics' energy (docs/model.md).

    ``params`` must be of the paper's form (eps, b, K2)."""
    if not params.is_paper_form:
        raise ValueError("the printed equations exist only for paper-form parameters (Params.paper)")
    times = np.asarray(times, dtype=float)
    y0 = np.asarray(y0, dtype=float)
    E0 = float(energy(y0, params))
    start = time.perf_counter()
    printed_states = trajectory(params, y0, times, tol)
    derived, _ = integrators.flow(False, tol)
    derived.time = float(times[0])
    integrators.load(derived, y0)
    integrators.set_pars(derived, params)
    out_d = derived.propagate_grid(times, callback=integrators.bounded(derived))
    rel = {k: energy(Y, params) / E0 - 1.0 for k, Y in (("printed", printed_states),
                                                          ("derived", integrators.samples(derived, out_d[5])))}
    ds = xr.Dataset(
        {f"energy_rel_change_{k}": ("time", v, {"long_name": f"E(t)/E(0) - 1, {k} equations"})
         for k, v in rel.items()},
        coords={"time": times},
    )
    ds.attrs.update(params.attrs())
    ds.attrs.update({f"y0_{n}": float(v) for n, v in zip(STATE_NAMES, y0)})
    ds.attrs.update(
        backend="heyoka", tol=tol, energy_physical=E0,
        printed_max_abs_rel_change=float(np.max(np.abs(rel["printed"]))),
        derived_max_abs_rel_change=float(np.max(np.abs(rel["derived"]))),
        wall_time_s=time.perf_counter() - start,
    )
    return ds

