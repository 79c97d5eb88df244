"""The likely causes of the paper's numbers that we do not reproduce, each computed, so that the
ledger can say which cause explains a difference and which does not.

- ``k2_sweep``: the paper never states K. The observables of C04, C05, C09, C10, C11 and C23
  against K2 over a range, from the paper's reference state.
- ``integration_error``: the paper used MATLAB; its likely integrator family is an explicit
  Runge-Kutta pair with loose default tolerances (ode45: rtol 1e-3). SciPy's RK45 stands in for
  it: the first spike and spike interval (C04, C05), the error of the perturbation series at
  t = 100 (C11) and the paper's Lyapunov protocol (C19) against its rtol.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.analysis import spectra
from sleighsim.chaos import benettin
from sleighsim.engine import transient
from sleighsim.engine.hierarchy import integrate_hierarchy
from sleighsim.engine.integrate import final_state, integrate, sample_grid
from sleighsim.engine.transient import settle
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.scenes import memory
from sleighsim.scenes.hierarchy import hierarchy_numbers, series_errors
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")

#: The numbers each K2 gives, with the claim they bear on.
K2_OBSERVABLES = {"first_spike": "C04", "spike_interval": "C05", "Omega2_amplitude": "C09", "phi1_over_pi": "C09",
                  "T2": "C10", "B": "C10", "omega2_growth": "C10", "omega_rel_error": "C11",
                  "band_low": "C23", "band_high": "C23"}


def _spikes(record, tc) -> tuple[float, float, float, int]:
    """(first spike, mean interval, its standard error, number of spikes) of a record by the phase rule."""
    ph = transient.phases(record.time.values, record.u.values, record.Omega.values, record.omega.values, **tc)
    n = ph["n_spikes"]
    stderr = ph["spike_interval_std"] / math.sqrt(n - 2) if n > 2 else math.nan
    return ph["first_spike"], ph["spike_interval_mean"], stderr, n


def _series_omega_error(params, y0, sc, tol) -> float:
    """Relative error of omega at sc.t_end between the order-sc.order series and the exact flow."""
    times = sample_grid(0.0, sc["t_end"], sc["dt"])
    exact = integrate(params, y0, times, tol=tol, progress=1)
    h = integrate_hierarchy(sc["order"], y0, times, b=params.b, K2=params.K2,
                                 kappa_value=(params.K2 - 1.0) / params.eps, tol=tol)
    return float(series_errors(exact, h, params.eps, sc["order"])["omega_rel_error"][1][-1])


def _band(params, y0, pc, tol, label) -> tuple[float, float]:
    """The Omega band of the PSD on the attractor (sleighsim.analysis.spectra.band_edges)."""
    y, _ = settle(params, y0, pc["t_settle"], **pc["transient"], tol=tol, label=label, progress=1)
    run = integrate(params, y, sample_grid(0.0, pc["duration"], pc["dt"]), tol=tol, progress=1)
    f, S = spectra.psd(run.Omega.values, pc["dt"], segment=pc["welch"]["segment"])
    lo, hi, _ = spectra.band_edges(f, S, f_split=pc["welch"]["f_split"], rel_threshold=pc["welch"]["rel_threshold"])
    return lo, hi


def k2_sweep(cfg: dict, scene: str = "") -> xr.Dataset:
    """The observables of the claims the unstated K bears on, at every K2 of the config (eps and b
    fixed, y0 the paper's reference state): first spike and steady spike interval (phase rule on a
    run to t_end), the C09/C10 numbers of the order-2 hierarchy (kappa = (K2 - 1) / eps), the
    relative error of omega at t = 100 of the series (C11), and the Omega band of the PSD (C23)."""
    start = time.perf_counter()
    K2s = np.asarray(cfg["K2"], float)
    y0 = np.asarray(cfg["y0"], float)
    rows = {k: [] for k in ("first_spike", "spike_interval", "spike_interval_stderr", "n_spikes",
                            "energy_max_rel_drift", "Omega2_amplitude", "phi1_over_pi", "T2", "B", "omega2_growth",
                            "omega_rel_error", "band_low", "band_high")}
    hc = cfg["hierarchy"]
    for K2 in K2s:
        p = Params.paper(eps=cfg["params"]["eps"], b=cfg["params"]["b"], K2=K2)
        label = f"{scene}[K2={K2:g}]"
        run = integrate(p, y0, sample_grid(0.0, cfg["t_end"], cfg["dt"]), tol=cfg["tol"], scene=label, progress=2)
        first, interval, stderr, n = _spikes(run, cfg["transient"])
        _, numbers = hierarchy_numbers(y0, sample_grid(0.0, hc["t_end"], hc["dt"]), b=p.b, K2=K2,
                                       kappa=(K2 - 1.0) / p.eps, tol=cfg["tol"], fit_window=hc["fit_window"])
        lo, hi = _band(p, state_at_label(y0, p, cfg["psd"]["energy_label"]), cfg["psd"], cfg["tol"], label)
        values = dict(first_spike=first, spike_interval=interval, spike_interval_stderr=stderr, n_spikes=n,
                      energy_max_rel_drift=run.attrs["energy_max_rel_drift"],
                      omega_rel_error=_series_omega_error(p, y0, cfg["series"], cfg["tol"]), band_low=lo, band_high=hi,
                      **{k: numbers[k] for k in ("Omega2_amplitude", "phi1_over_pi", "T2", "B", "omega2_growth")})
        for k, v in values.items():
            rows[k].append(v)
        log.info("%s: first spike %.5g, interval %.5g, A %.4g, phi1 %.4f pi, omega error %.3g, band [%.4g, %.4g]",
                 label, first, interval, values["Omega2_amplitude"], values["phi1_over_pi"],
                 values["omega_rel_error"], lo, hi)
    ds = xr.Dataset({k: ("K2", np.asarray(v, float)) for k, v in rows.items()}, coords={"K2": K2s})
    ds.attrs.update(
        scene=scene, param_eps=cfg["params"]["eps"], param_b=cfg["params"]["b"], tol=cfg["tol"], t_end=cfg["t_end"],
        y0=y0, backend="heyoka", wall_time_s=time.perf_counter() - start,
        observables=" ; ".join(f"{k}: {c}" for k, c in K2_OBSERVABLES.items()),
        method="first spike and interval: sleighsim.engine.transient.phases on a run from y0 to t_end; C09, C10: the "
               "order-2 hierarchy with kappa = (K2 - 1) / eps fitted on the hierarchy fit window; C11: omega's error "
               "at series.t_end; C23: Omega band of the Welch PSD after a checked pre-run",
    )
    return ds


K2_SWEEP = SceneKind(
    name="k2_sweep",
    title="the observables the unstated K bears on, against K2 (likely causes of C04, C05, C09-C11, C13, C23)",
    compute=k2_sweep,
    records=lambda c: [memory.span(c, "t_end", "dt"), *memory.hierarchy(c, "hierarchy."),
                       *memory.series(c, "series.", c["series"]["order"]),
                       memory.span(c, "psd.t_settle", "psd.transient.dt"), memory.span(c, "psd.duration", "psd.dt")])


def integration_error(cfg: dict, scene: str = "") -> xr.Dataset:
    """SciPy's ``method`` (RK45 stands in for MATLAB's ode45) at every rtol of the config
    (atol = rtol x atol_factor, right-hand side compiled by heyoka): energy drift, first spike and
    interval of a run from y0 (C04, C05), the relative error of omega at t = 100 between the
    accurate order-2 series and this solver's solution (C11), and, for the rtols of
    ``lyapunov.rtols``, the paper's protocol (pre-run, then k = 4 exponents over T renormalised
    every tau) integrated with this solver (C19)."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    y0 = np.asarray(cfg["y0"], float)
    rtols = np.asarray(cfg["rtols"], float)
    rows = {k: [] for k in ("first_spike", "spike_interval", "spike_interval_stderr", "n_spikes",
                            "energy_max_rel_drift", "omega_rel_error", "wall_time_s")}
    sc = cfg["series"]
    times = sample_grid(0.0, sc["t_end"], sc["dt"])
    h = integrate_hierarchy(sc["order"], y0, times, b=params.b, K2=params.K2,
                                 kappa_value=(params.K2 - 1.0) / params.eps, tol=cfg["tol"])
    for rtol in rtols:
        kw = dict(backend="scipy", method=cfg["method"], rtol=float(rtol), atol=float(rtol * cfg["atol_factor"]),
                  compiled=True, progress=2)
        run = integrate(params, y0, sample_grid(0.0, cfg["t_end"], cfg["dt"]), scene=f"{scene}[rtol={rtol:g}]", **kw)
        first, interval, stderr, n = _spikes(run, cfg["transient"])
        exact = integrate(params, y0, times, **dict(kw, progress=1))
        err = float(series_errors(exact, h, params.eps, sc["order"])["omega_rel_error"][1][-1])
        for k, v in dict(first_spike=first, spike_interval=interval, spike_interval_stderr=stderr, n_spikes=n,
                         energy_max_rel_drift=run.attrs["energy_max_rel_drift"], omega_rel_error=err,
                         wall_time_s=run.attrs["wall_time_s"]).items():
            rows[k].append(v)
        log.info("%s: %s rtol %g: drift %.3g, first spike %.5g, interval %.5g, omega error %.3g", scene,
                 cfg["method"], rtol, run.attrs["energy_max_rel_drift"], first, interval, err)
    data = {k: ("rtol", np.asarray(v, float)) for k, v in rows.items()}
    lc = cfg["lyapunov"]
    lrtols = np.asarray(lc["rtols"], float)
    exps = []
    for rtol in lrtols:
        y = final_state(integrate(params, state_at_label(y0, params, lc["energy_label"]), [0.0, lc["t_transient"]],
                                  backend="scipy", method=cfg["method"], rtol=float(rtol),
                                  atol=float(rtol * cfg["atol_factor"]), compiled=True, progress=1))
        r = benettin.scipy_benettin(params, y, 4, T=lc["T"], tau=lc["tau"], method=cfg["method"], rtol=float(rtol),
                                    atol=float(rtol * cfg["atol_factor"]))
        exps.append(r["exponents"])
        log.info("%s: protocol with %s rtol %g: %s", scene, cfg["method"], rtol, r["exponents"])
    data["protocol_exponent"] = (("lyapunov_rtol", "i"), np.array(exps).reshape(len(lrtols), 4))
    ds = xr.Dataset(data, coords={"rtol": rtols, "lyapunov_rtol": lrtols, "i": np.arange(1, 5)})
    ds.attrs.update(
        scene=scene, backend="scipy", method=cfg["method"], atol_factor=cfg["atol_factor"], t_end=cfg["t_end"],
        y0=y0, param_eps=params.eps, param_b=params.b, param_K2=params.K2, reference_tol=cfg["tol"],
        protocol_t_transient=lc["t_transient"], protocol_T=lc["T"], protocol_tau=lc["tau"],
        wall_time_s=time.perf_counter() - start,
        stand_in=f"SciPy {cfg['method']} with atol = rtol x {cfg['atol_factor']:g} for MATLAB's ode45 "
                 "(a Dormand-Prince 5(4) pair, default rtol 1e-3, atol 1e-6)",
    )
    return ds


INTEGRATION_ERROR = SceneKind(
    name="integration_error",
    title=("SciPy's RK45 (standing in for MATLAB's ode45) against its tolerance: spikes, series error and the "
           "paper's Lyapunov protocol (likely causes of C04, C05, C11, C18-C21)"),
    compute=integration_error,
    records=lambda c: [memory.span(c, "t_end", "dt"), *memory.series(c, "series.", c["series"]["order"]),
                       memory.span(c, "lyapunov.T", "lyapunov.tau")])
