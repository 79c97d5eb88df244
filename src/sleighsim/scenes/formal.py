"""Beyond the paper's computed range: what small eps costs (C25) and the largest exponent of the formal
system at eps >= 1 (C26)."""

from __future__ import annotations

import logging
import time

import numpy as np
import xarray as xr

from sleighsim.analysis import fits
from sleighsim.chaos import benettin
from sleighsim.engine import integrators, transient
from sleighsim.engine.integrate import integrate, orbit_samples, sample_grid
from sleighsim.engine.transient import settle
from sleighsim.io import cf
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.scenes import formal_gauge, memory, trigger_price
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def small_eps_cost(cfg: dict, scene: str = "") -> xr.Dataset:
    """C25: what small eps costs. Measures, from the reference state at a few eps, the
    length of the transient (first Omega spike, sleighsim.engine.transient) and the steps per time
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
        {"first_spike": ("eps", a[:, 1], cf.attrs("time of the first Omega spike from the reference state", "time")),
         "steps_per_time": ("eps", a[:, 2]),
         "transient_estimate": ("target", t_tr, cf.attrs("transient length (first Omega spike), extrapolated", "time")),
         "steps_estimate": ("target", steps),
         "wall_estimate_s": ("target", steps * us, cf.attrs("wall-clock time of the transient, extrapolated (one core)",
                                                           "s"))},
        coords={"eps": a[:, 0], "target": targets},
    )
    ds.attrs.update(
        transient_exponent=float(k_t), steps_per_time_exponent=float(k_s), seconds_per_step=us,
        budget_core_hours=cfg["budget_core_hours"],
        energy_label=cfg["energy_label"], tol=cfg["tol"], wall_time_s=time.perf_counter() - start,
        method="first Omega spike from the reference state; log-log least squares in eps; cost = transient x "
        "steps per time unit x measured seconds per step (one core)",
    )
    return ds



SMALL_EPS_COST = SceneKind(
    name="small_eps_cost",
    title="what small eps costs: transient length and integrator steps extrapolated in eps (claim C25)",
    compute=small_eps_cost,
                           records=lambda c: [memory.span(c, ("max(horizons)", max(c["horizons"])), "dt")])


def _formal_row(cfg: dict, eps: float, scene: str, record: dict) -> tuple:
    """One eps of formal_exponents: (eps, lambda_1, stderr (1/time), status, T (time), transient_over,
    energy drift, the pre-run's block fluctuation (transient.block_fluctuation), its wall time (s), the row's
    gauge (``formal_gauge.row_gauge`` from gauge.eps_min on, with the price ``record``))."""
    params = Params.paper(eps=eps, b=cfg["b"], K2=cfg["K2"], formal=True)
    y0 = state_at_label(cfg["y0"], params, cfg["energy_label"])
    label = f"{scene}[eps={eps:g}]"
    t0 = time.perf_counter()
    y, pre = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=cfg["tol"], label=label, progress=1,
                    fluctuation=True)
    pre_wall = time.perf_counter() - t0
    replicas, _ = orbit_samples(params, y, cfg["replicas"], cfg["replica_spacing"], tol=cfg["tol"], scene=label)
    ta, _ = integrators.sleigh_tangent_batch(cfg["replicas"], cfg["tol"], cfg["compact_mode"], k=1)
    integrators.set_pars(ta, params)
    res = benettin.replica_exponents(ta, 4, 1, replicas, cfg["tau"], T_round=cfg["T_round"],
                                     max_rounds=cfg["max_rounds"], target_rel=cfg["target_rel"],
                                     t_align=cfg["t_align"], regular_floor=cfg["regular_floor"],
                                     sigma=cfg["sigma"], label=label)
    drift = float(np.max(np.abs(equations.energy(res["final_state"], params) / equations.energy(y0, params) - 1)))
    g = cfg["gauge"]
    gauge = (formal_gauge.row_gauge(params, y, g, cfg["tol"], cfg["compact_mode"], cfg["transient"]["spike_factor"],
                                    record) if eps >= g["eps_min"] else formal_gauge.not_gauged())
    row = (eps, float(res["exponents"][0]), float(res["stderr"][0]), res["status"], float(res["T"]),
           int(pre["transient_over"]), drift, pre["transient_block_fluctuation"], pre_wall, gauge)
    log.info("%s: lambda_1 = %.3g +- %.2g (%s, T = %.3g)%s", label, *row[1:5],
             f"; followed by {gauge['faithful_arithmetic']}" if gauge["faithful_arithmetic"] else "")
    return row


def formal_exponents(cfg: dict, inputs: dict, scene: str = "") -> xr.Dataset:
    """C26: lambda_1 of the formal system (eps >= 1, m_c = 1 - eps <= 0, its inertia still positive
    definite) at each eps of the config, from y0 scaled to the label: a checked pre-run, then
    independent replicas along the settled orbit run in rounds (as lyapunov_spectrum) until lambda_1
    is resolved, regular or capped. The eps of ``elsewhere`` are computed by another config (named in
    the dataset, not here). Each pre-run also records how much omega's block means scatter and its
    wall time, what a judge needs to tell an unfinished transient from one the rule cannot certify. From
    gauge.eps_min on, each row's faithfulness gauge (``formal_gauge.GAUGE_RULE``; ``inputs["price"]``: the price
    record's path)."""
    start = time.perf_counter()
    record = trigger_price.load(inputs["price"])
    rows = [_formal_row(cfg, eps, scene, record) for eps in cfg["eps"]]
    gauges = [r[-1] for r in rows]
    eps, lam, err, status, T, over, drift, fluct, pre_wall = (np.array(c) for c in zip(*(r[:-1] for r in rows)))
    ds = xr.Dataset(
        {"lambda_1": ("eps", lam, cf.attrs("largest Lyapunov exponent lambda_1 of the formal system", "rate")),
         "stderr": ("eps", err, cf.attrs("standard error of lambda_1 over independent replicas", "rate")),
         "status": ("eps", status.astype(object)), "T": ("eps", T, cf.attrs("horizon T per replica", "time")),
         "transient_over": ("eps", over), "energy_max_rel_drift": ("eps", drift),
         "block_fluctuation": ("eps", fluct, cf.attrs("scatter of omega's block means about their line over the "
                                                      "pre-run's second half, relative to their mean", "1")),
         "pre_run_wall_s": ("eps", pre_wall, cf.attrs("wall-clock time of the pre-run (one core)", "s"))},
        coords={"eps": eps},
    )
    ds = ds.assign(_gauge_vars(gauges))
    ds.attrs.update(
        gauge_rule=formal_gauge.GAUGE_RULE, gauge_eps_min=cfg["gauge"]["eps_min"], gauge_T=cfg["gauge"]["T"],
        gauge_tau=cfg["gauge"]["tau"], price_rule=trigger_price.PRICE_RULE,
        price_record_commit=str(record.get("git_commit", "")),
        scene=scene, backend="heyoka", method="Benettin over independent replicas (k = 1), formal system m_c = 1 - eps",
        param_b=cfg["b"], param_K2=cfg["K2"], energy_label=cfg["energy_label"], y0=cfg["y0"],
        tol=cfg["tol"], tau=cfg["tau"], replicas=cfg["replicas"], replica_spacing=cfg["replica_spacing"],
        compact_mode=int(cfg["compact_mode"]), uncertainty="standard error over independent replicas",
        t_transient=cfg["t_transient"], transient_window=cfg["transient"]["window"],
        transient_rtol=cfg["transient"]["rtol"], transient_rule=transient.RULE,
        wall_time_s=time.perf_counter() - start,
        eps_elsewhere=np.asarray(cfg.get("elsewhere", {}).get("eps", []), float),
        elsewhere_config=cfg.get("elsewhere", {}).get("config", ""),
    )
    return ds


def _gauge_vars(gauges: list[dict]) -> dict:
    """The rows' gauge variables (``formal_gauge.FLOATS`` and ``TEXTS``; attributes from its VOCABULARY), each
    (eps,)."""
    out = {v: ("eps", np.array([g[v] for g in gauges], float)) for v in formal_gauge.FLOATS}
    out.update({v: ("eps", np.array([g[v] for g in gauges], dtype=object)) for v in formal_gauge.TEXTS})
    return out


def _formal_exponents_checks(w, cfg):
    both = sorted(set(cfg["eps"]) & set(cfg.get("elsewhere", {}).get("eps", [])))
    if both:
        raise ConfigError(f"{w}.elsewhere.eps: {both} also in {w}.eps (a row is computed here or elsewhere, not both)")


FORMAL_EXPONENTS = SceneKind(
    name="formal_exponents",
    title="the largest Lyapunov exponent of the formal system, eps >= 1 (claim C26)",
    compute=formal_exponents, realizable=True, inputs=("price",), vocabulary=formal_gauge.VOCABULARY,
    records=lambda c: [*memory.pre_run(c, "t_transient"), *memory.benettin(c, 8)],
    checks=_formal_exponents_checks, pre_run="t_transient")
