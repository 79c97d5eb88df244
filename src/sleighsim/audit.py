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


def model_as_printed(params: "model.Params", y0, times, tol: float = 2.0**-52) -> xr.Dataset:
    """D1-D6: the printed model against the derivation.

    D1 energy drift of the printed udot (integrated beside the derived equations);
    D2 which inertia makes the printed Omegadot hold (I_c as SCIENCE.md says, or I_r as
    printed); D3 entries of the printed locked inertia and right-hand side that differ;
    D4 the term missing from the printed beta equation (dL/dbeta); D5 the physical energy
    of the reference state; D6 whether eps > 1 is admissible."""
    import sympy as sp

    from . import mechanics as mech

    ds = printed_energy_drift(params, y0, times, tol)
    # D2: printed Omegadot against the derivation under two readings of K^2.
    rng = np.random.default_rng(0)
    Y = rng.uniform(-1, 1, (200, 4))
    eps, b, K2 = params.eps, params.b, params.K2
    printed = model.paper_printed_rhs(Y, eps, b, K2)[:, 1]
    as_science = model.rhs(Y, params)[:, 1]
    swapped = model.Params.physical(m_c=params.m_c, m_r=params.m_r, I_c=params.I_r, I_r=params.I_c, a=params.a, b=b)
    as_printed = model.rhs(Y, swapped)[:, 1]
    scale = np.max(np.abs(printed))
    # D3: printed locked inertia and right-hand side against the derivation.
    d = mech.derive()
    M_p, f_p = mech.paper_printed_locked_inertia()
    diffs = [f"M[{i},{j}]: printed {M_p[i, j]}, derived {d.M[i, j]}"
             for i in range(3) for j in range(3) if sp.expand(M_p[i, j] - d.M[i, j]) != 0]
    diffs += [f"f[{i}]: printed {f_p[i]}, derived {sp.factor(d.f[i])}"
              for i in range(3) if sp.expand(f_p[i] - d.f[i]) != 0]
    # D4: dL/dbeta, which the printed beta equation drops.
    dL_dbeta = sp.simplify(d.lagrangian.diff(sp.Function("beta")(sp.Symbol("t"))))
    try:
        model.Params.paper(eps=25.0)
        d6 = "admitted"
    except ValueError as err:
        d6 = str(err)
    ds.attrs.update(
        d2_Omegadot_residual_with_Ic=float(np.max(np.abs(printed - as_science)) / scale),
        d2_Omegadot_residual_with_Ir=float(np.max(np.abs(printed - as_printed)) / scale),
        d3_differences=" | ".join(diffs), d3_n_differences=len(diffs),
        d4_dL_dbeta=str(dL_dbeta),
        d5_reference_energy_physical=float(model.energy(model.REFERENCE_STATE, params)),
        d5_reference_label=model.REFERENCE_LABEL,
        d6_eps_25=d6,
    )
    return ds
