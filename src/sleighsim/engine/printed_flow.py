"""The paper's equations as printed (``model.printed``), integrated: for the audit only (D1, and the
printed spikes behind C04/C05). Their printed udot does not follow from the mechanics (docs/model.md)."""

from __future__ import annotations

import time

import heyoka as hy
import numpy as np
import xarray as xr

from sleighsim.engine import integrators
from sleighsim.model.equations import STATE_NAMES, energy
from sleighsim.model.params import Params


def trajectory(params: Params, y0, times, tol: float = 2.0**-52) -> np.ndarray:
    """The printed equations integrated from ``y0`` at times[0], sampled at ``times`` (rows of
    (u, Omega, omega, delta)); ``params`` must be of the paper's form (eps, b, K2)."""
    if not params.is_paper_form:
        raise ValueError("the printed equations exist only for paper-form parameters (Params.paper)")
    ta, _ = integrators.printed(tol)
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
