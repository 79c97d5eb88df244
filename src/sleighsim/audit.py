"""The model as printed: how far the paper's equations stray from the mechanics."""

from __future__ import annotations

import time

import numpy as np
import xarray as xr

from . import model
from .integrate import heyoka_integrator
from .io import provenance_attrs


def printed_energy_drift(params: model.Params, y0, times, tol: float = 2.0**-52) -> xr.Dataset:
    """Integrate the printed and the derived equations from ``y0`` (heyoka, same tol)
    and return E(t)/E(0) - 1 for both; E is the mechanics' energy (SCIENCE.md).

    ``params`` must be of the paper's form (eps, b, K2)."""
    import heyoka as hy

    if not params.is_paper_form:
        raise ValueError("the printed equations exist only for paper-form parameters (Params.paper)")
    times = np.asarray(times, dtype=float)
    y0 = np.asarray(y0, dtype=float)
    E0 = float(model.energy(y0, params))
    start = time.perf_counter()
    printed = hy.taylor_adaptive(model.printed_heyoka_system(), y0.tolist(),
                                 pars=[params.eps, params.b, params.K2], tol=tol)
    printed.time = float(times[0])
    out_p = printed.propagate_grid(times)
    derived, _ = heyoka_integrator(False, tol)
    derived.time = float(times[0])
    derived.state[:] = y0
    derived.pars[:] = params.values
    out_d = derived.propagate_grid(times)
    rel = {k: model.energy(r[5], params) / E0 - 1.0 for k, r in (("printed", out_p), ("derived", out_d))}
    ds = xr.Dataset(
        {f"energy_rel_change_{k}": ("time", v, {"long_name": f"E(t)/E(0) - 1, {k} equations"})
         for k, v in rel.items()},
        coords={"time": times},
    )
    ds.attrs.update(params.attrs())
    ds.attrs.update({f"y0_{n}": float(v) for n, v in zip(model.STATE_NAMES, y0)})
    ds.attrs.update(
        backend="heyoka", tol=tol, energy_physical=E0,
        printed_max_abs_rel_change=float(np.max(np.abs(rel["printed"]))),
        derived_max_abs_rel_change=float(np.max(np.abs(rel["derived"]))),
        wall_time_s=time.perf_counter() - start,
    )
    ds.attrs.update(provenance_attrs())
    return ds
