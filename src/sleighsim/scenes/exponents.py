"""Lyapunov scenes at one eps: the four-exponent spectrum (C18, C19), the paper's protocol
(C19), the largest exponent against energy (F10, C20), and what small eps costs (C25).
The Benettin engine is :mod:`sleighsim.lyapunov`."""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from .. import fits, lyapunov, model, transient
from ..attrs import state_attrs
from ..integrate import final_state, integrate, sample_grid
from ..params import Params
from ..symmetries import state_at_label
from ..transient import settle

log = logging.getLogger("sleighsim")


def _run(params, y, *, k, cfg, compact, label, T=None, seed=0):
    ta, compile_s = lyapunov.sleigh_tangent(k, cfg["tol"], compact)
    ta.pars[:] = params.values
    out = lyapunov.benettin(ta, 4, k, y, t_align=cfg["t_align"], T=cfg["T"] if T is None else T, tau=cfg["tau"],
                            n_blocks=cfg["n_blocks"], seed=seed, label=label)
    out["compile_time_s"] = compile_s
    return out


def _common_attrs(params, y0, cfg, scene):
    out = state_attrs(params, y0)
    out.update(scene=scene, backend="heyoka", method="Benettin QR on var_ode_sys", tol=cfg["tol"],
               tau=cfg["tau"], t_align=cfg["t_align"], n_blocks=cfg["n_blocks"])
    return out


def spectrum(cfg: dict, scene: str = "") -> xr.Dataset:
    """All four exponents at one state after a transient, lambda_i(T) on a log grid, the
    independent mean divergence over the same window (C18), and the alignment effect."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    y0 = state_at_label(cfg["y0"], params, cfg["energy_label"])
    y, transient_attrs = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=cfg["tol"], label=scene,
                                progress=1)
    res = _run(params, y, k=4, cfg=cfg, compact=cfg["compact_mode"], label=scene)
    # The same window without alignment shows the bias of the initial directions.
    no_align = _run(params, y, k=4, cfg=dict(cfg, t_align=0.0), compact=cfg["compact_mode"], label=f"{scene}.noalign",
                    T=cfg["T_bias_check"])
    aligned_short = res["running"][max(0, np.searchsorted(res["T_grid"], cfg["T_bias_check"], side="right") - 1)]
    div = lyapunov.mean_divergence(params, _advance(params, y, cfg["t_align"], cfg["tol"]), cfg["T"], cfg["tol"])
    ds = xr.Dataset(
        {
            "exponent": ("i", res["exponents"], {"long_name": "Lyapunov exponent", "units": "1/time"}),
            "stderr": ("i", res["stderr"], {"long_name": "standard error from block estimates", "units": "1/time"}),
            "block_estimate": (("block", "i"), res["block_estimates"], {"units": "1/time"}),
            "running": (("T", "i"), res["running"], {"long_name": "finite-time estimate lambda_i(T)", "units": "1/time"}),
        },
        coords={"i": np.arange(1, 5), "T": ("T", res["T_grid"], {"units": "time"}),
                "block": np.arange(cfg["n_blocks"])},
    )
    ds.attrs.update(_common_attrs(params, y0, cfg, scene))
    ds.attrs.update(transient_attrs)
    lam = res["exponents"]
    ds.attrs.update(
        t_transient=cfg["t_transient"], T=cfg["T"],
        mean_divergence=div, sum_lambda_1_4=float(lam[0] + lam[3]), sum_all=float(lam.sum()),
        T_bias_check=cfg["T_bias_check"],
        lambda_1_no_alignment=float(no_align["exponents"][0]), lambda_1_aligned_at_T_bias_check=float(aligned_short[0]),
        lambda_1_decay_slope_last_decade=_decay_slope(res["T_grid"], res["running"][:, 0]),
        compile_time_s=res["compile_time_s"], wall_time_s=time.perf_counter() - start,
        energy_max_rel_drift=float(abs(model.energy(res["final_state"], params) / model.energy(y0, params) - 1)),
    )
    log.info("%s: exponents %s +- %s; lambda1+lambda4 %.3g vs mean divergence %.3g", scene, lam, res["stderr"],
             lam[0] + lam[3], div)
    return ds


def _advance(params, y, t, tol):
    if t <= 0:
        return y
    out = integrate(params, y, [0.0, t], tol=tol, progress=1)
    return final_state(out)


def _decay_slope(T, lam):
    """Slope of log|lambda_1(T)| against log T over the last decade of T: about -1 for
    a zero exponent (bounded tangent growth), about 0 for a converged nonzero one."""
    sel = T >= T[-1] / 10
    a = np.abs(lam[sel])
    if np.any(a == 0):
        return float("nan")
    return fits.loglog(T[sel], a, min_points=3)[0]


def protocol(cfg: dict, scene: str = "") -> xr.Dataset:
    """The paper's protocol (pre-run, T, renormalisation interval tau) from several initial
    states on one energy level, to show the spread of its finite-time exponents (C19)."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    states = [state_at_label(s, params, cfg["energy_label"]) for s in cfg["states"]]
    exps, errs = [], []
    for j, y0 in enumerate(states):
        y = _advance(params, y0, cfg["t_transient"], cfg["tol"])
        r = _run(params, y, k=4, cfg=cfg, compact=True, label=f"{scene}[{j}]", seed=j)
        exps.append(r["exponents"])
        errs.append(r["stderr"])
        log.info("%s[%d]: %s", scene, j, r["exponents"])
    ds = xr.Dataset(
        {"exponent": (("state", "i"), np.array(exps), {"units": "1/time"}),
         "stderr": (("state", "i"), np.array(errs), {"units": "1/time"}),
         "y0": (("state", "component"), np.array(states))},
        coords={"i": np.arange(1, 5), "component": list(model.STATE_NAMES)},
    )
    ds.attrs.update(_common_attrs(params, states[0], cfg, scene))
    ds.attrs.update(t_transient=cfg["t_transient"], T=cfg["T"], wall_time_s=time.perf_counter() - start,
                    spread_lambda_1=float(np.ptp(np.array(exps)[:, 0])))
    return ds


def energy_sweep(cfg: dict, scene: str = "") -> xr.Dataset:
    """Max LE at several energy labels, horizons scaled by the time-scaling law so every
    label costs the same; the law's prediction from the reference label; a fitted exponent."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    labels = np.asarray(cfg["labels"], float)
    lam, err = np.empty(labels.size), np.empty(labels.size)
    for j, lab in enumerate(labels):
        s = math.sqrt(cfg["reference_label"] / lab)  # time unit at this label relative to the reference
        y0 = state_at_label(cfg["y0"], params, lab)
        y = _advance(params, y0, cfg["t_transient"] * s, cfg["tol"])
        r = _run(params, y, k=1, cfg=dict(cfg, t_align=cfg["t_align"] * s, tau=cfg["tau"] * s),
                 compact=cfg["compact_mode"], label=f"{scene}[E={lab:g}]", T=cfg["T"] * s)
        lam[j], err[j] = r["exponents"][0], r["stderr"][0]
        log.info("%s: E label %g: lambda_1 = %.4g +- %.2g", scene, lab, lam[j], err[j])
    ref = int(np.argmin(np.abs(np.log(labels / cfg["reference_label"]))))
    law = lam[ref] * np.sqrt(labels / labels[ref])
    ok = lam > 0
    slope, _, slope_err = fits.loglog(labels[ok], lam[ok], err[ok], min_points=3)
    ds = xr.Dataset(
        {"lambda_1": ("label", lam, {"units": "1/time"}), "stderr": ("label", err, {"units": "1/time"}),
         "law": ("label", law, {"long_name": "time-scaling law from the reference label", "units": "1/time"})},
        coords={"label": ("label", labels, {"long_name": "paper energy label"})},
    )
    ds.attrs.update(_common_attrs(params, state_at_label(cfg["y0"], params, cfg["reference_label"]), cfg, scene))
    ds.attrs.update(
        reference_label=cfg["reference_label"], T_reference=cfg["T"], t_transient_reference=cfg["t_transient"],
        horizon_rule="T, t_transient, t_align and tau scaled by sqrt(reference_label / label)",
        fitted_exponent=slope, fitted_exponent_stderr=slope_err, n_positive=int(ok.sum()),
        max_rel_deviation_from_law=float(np.max(np.abs(lam / law - 1))), wall_time_s=time.perf_counter() - start,
    )
    return ds


def small_eps_cost(cfg: dict, scene: str = "") -> xr.Dataset:
    """C25: what small eps costs. Measures, from the reference state at a few eps, the
    length of the transient (first Omega spike, sleighsim.transient) and the steps per time
    unit on the attractor; fits power laws in eps and extrapolates both, with the measured
    time per step, to the target eps values."""
    start = time.perf_counter()
    rows = []
    for eps, horizon in zip(cfg["eps"], cfg["horizons"]):
        p = Params.paper(eps=eps)
        y0 = state_at_label(cfg["y0"], p, cfg["energy_label"])
        ds = integrate(p, y0, sample_grid(0.0, horizon, cfg["dt"]), tol=cfg["tol"], scene=f"{scene}[eps={eps:g}]")
        spikes = transient.spike_times(ds.time.values, ds.Omega.values, t_min=cfg["t_min"])
        rows.append((eps, float(spikes[0]) if spikes.size else np.nan, ds.attrs["steps"] / horizon,
                     ds.attrs["wall_time_s"] / ds.attrs["steps"]))
        log.info("%s: eps %g: first spike %.6g, %.3g steps per time unit", scene, *rows[-1][:3])
    a = np.array(rows)
    ok = np.isfinite(a[:, 1])
    k_t, c_t, _ = fits.loglog(a[ok, 0], a[ok, 1])
    k_s, c_s, _ = fits.loglog(a[:, 0], a[:, 2])
    us = float(np.median(a[:, 3]))
    targets = np.asarray(cfg["targets"], float)
    t_tr = np.exp(c_t) * targets**k_t
    steps = t_tr * np.exp(c_s) * targets**k_s
    ds = xr.Dataset(
        {"first_spike": ("eps", a[:, 1], {"units": "time"}), "steps_per_time": ("eps", a[:, 2]),
         "transient_estimate": ("target", t_tr, {"units": "time"}), "steps_estimate": ("target", steps),
         "wall_estimate_s": ("target", steps * us, {"units": "s"})},
        coords={"eps": a[:, 0], "target": targets},
    )
    ds.attrs.update(
        transient_exponent=float(k_t), steps_per_time_exponent=float(k_s), seconds_per_step=us,
        energy_label=cfg["energy_label"], tol=cfg["tol"], wall_time_s=time.perf_counter() - start,
        method="first Omega spike from the reference state; log-log least squares in eps; cost = transient x "
        "steps per time unit x measured seconds per step (one core)",
    )
    return ds

