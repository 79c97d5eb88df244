"""Integration of the perturbation hierarchy in eps (derived in ``model.perturbation``) with heyoka."""

from __future__ import annotations

import time

import numpy as np
import xarray as xr

from sleighsim.engine import integrators
from sleighsim.model.perturbation import VARS, state_names


def integrate_hierarchy(order: int, y0, times, *, b=1.0, K2=1.1, kappa_value=1.0, tol=2.0**-52) -> xr.Dataset:
    """Integrate the hierarchy to ``order`` from x0(0) = y0 and all higher orders zero, with
    heyoka (as the exact flow). Variables u0, Omega0, ..., delta_order on ``times``."""
    import heyoka as hy

    times = np.asarray(times, dtype=float)
    ta, compile_s = integrators.hierarchy(order, tol)
    ta.time = float(times[0])
    ta.state[:] = 0.0
    ta.state[:4] = np.asarray(y0, dtype=float)
    ta.pars[:] = [b, K2, kappa_value]
    start = time.perf_counter()
    res = ta.propagate_grid(times, callback=integrators.bounded(ta))
    if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(res[5])):
        raise RuntimeError(f"hierarchy integration to order {order} failed at t = {ta.time:g}: {res[0].name}")
    ds = xr.Dataset({n: ("time", res[5][:, i]) for i, n in enumerate(state_names(order))}, coords={"time": times})
    ds.attrs.update(order=order, b=b, K2=K2, kappa=kappa_value, backend="heyoka", method="taylor_adaptive",
                    tol=tol, steps=int(res[3]), compile_time_s=compile_s, wall_time_s=time.perf_counter() - start,
                    initial_data="order 0 from y0, all higher orders zero")
    ds.attrs.update({f"y0_{v}": float(c) for v, c in zip(VARS, y0)})
    return ds
