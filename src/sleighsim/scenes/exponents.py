"""Lyapunov scenes at one eps and one label: the four-exponent spectrum (C18, C19) and the paper's
protocol (C19); the energy sweep is :mod:`sleighsim.scenes.energy_sweep`, small and formal eps
:mod:`sleighsim.scenes.formal`. The Benettin engine is :mod:`sleighsim.chaos.benettin`."""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.analysis import fits
from sleighsim.chaos import benettin
from sleighsim.engine import integrators
from sleighsim.engine.integrate import final_state, integrate, orbit_samples
from sleighsim.engine.transient import settle
from sleighsim.io import cf
from sleighsim.model import equations
from sleighsim.model.attrs import state_attrs
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.checks import blocks
from sleighsim.scenes.common import steady_arithmetic
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def _run(params, y, *, k, cfg, compact, label, T=None, seed=0):
    """Benettin from y with k vectors in the block's steady-state arithmetic (:func:`.common.steady_arithmetic`)."""
    arith = steady_arithmetic(cfg)
    ta, compile_s = integrators.sleigh_tangent(k, arith["tol"], compact, arith["precision"])
    integrators.set_pars(ta, params)
    out = benettin.benettin(ta, 4, k, y, t_align=cfg["t_align"], T=cfg["T"] if T is None else T, tau=cfg["tau"],
                            n_blocks=cfg["n_blocks"], seed=seed, label=label)
    out["compile_time_s"] = compile_s
    return out


def lyapunov_attrs(params, y0, cfg, scene):
    """The attributes every Lyapunov scene records: the state, the method, the arithmetic and the horizons."""
    out = state_attrs(params, y0)
    out.update(scene=scene, backend="heyoka", method="Benettin QR on var_ode_sys (QR of the tangent vectors in double)",
               **steady_arithmetic(cfg), transient_tol=cfg["tol"], transient_precision=Precision.DOUBLE,
               tau=cfg["tau"], t_align=cfg["t_align"])
    return out


def _running(growth, tau, n_points=60):
    """The replicas' mean finite-time exponents lambda_i(T) on a log-spaced grid of T (growth: steps, k, B)."""
    steps = growth.shape[0]
    at = np.unique(np.geomspace(1, steps, n_points).astype(int))
    cum = np.cumsum(growth, axis=0)[at - 1]  # (points, k, B)
    return at * tau, (cum / (at * tau)[:, None, None]).mean(axis=2)


def _spectrum_dataset(res: dict, div: np.ndarray, replicas: np.ndarray, T_grid: np.ndarray,
                      running: np.ndarray) -> xr.Dataset:
    """The spectrum's variables: exponents and standard errors (per i), each replica's exponents,
    mean divergence and start state (per replica), and the running lambda_i(T) (per T); rates in
    1/time unit."""
    lam, err, per = res["exponents"], res["stderr"], res["per_replica"]
    return xr.Dataset(
        {
            "exponent": ("i", lam, cf.attrs("Lyapunov exponent lambda_i (mean over replicas)", "rate")),
            "stderr": ("i", err, cf.attrs("standard error over independent replicas", "rate")),
            "replica_exponent": (("replica", "i"), per, cf.attrs("Lyapunov exponent lambda_i of each replica", "rate")),
            "replica_divergence": ("replica", div, cf.attrs("mean trace of J over the replica's window", "rate")),
            "replica_y0": (("replica", "component"), replicas),
            "running": (("T", "i"), running, cf.attrs("finite-time estimate lambda_i(T), mean over replicas", "rate")),
        },
        coords={"i": np.arange(1, 5), "T": ("T", T_grid, cf.attrs("horizon T of the finite-time estimate", "time")),
                "replica": np.arange(len(replicas)),
                "component": list(equations.STATE_NAMES)},
    )


def spectrum(cfg: dict, scene: str = "") -> xr.Dataset:
    """All four exponents on the steady state reached from y0 after a checked transient, from
    independent replicas along the settled orbit (one SIMD lane each, run in rounds until lambda_1
    is resolved): exponents with the replicas' standard error, per-replica values, lambda_i(T), and
    over the same windows the mean divergence of the plain flow (C18) with its own replica spread."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    y0 = state_at_label(cfg["y0"], params, cfg["energy_label"])
    y, transient_attrs = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=cfg["tol"], label=scene,
                                progress=1)
    arith = steady_arithmetic(cfg)
    replicas, _ = orbit_samples(params, y, cfg["replicas"], cfg["replica_spacing"], **arith, scene=scene)
    B = cfg["replicas"]
    ta, compile_s = benettin.sleigh_tangent_lanes(B, arith["tol"], cfg["compact_mode"], k=4,
                                                  precision=arith["precision"])
    integrators.set_pars(ta, params)
    res = benettin.replica_exponents(ta, 4, 4, replicas, cfg["tau"], T_round=cfg["T_round"],
                                     max_rounds=cfg["max_rounds"], target_rel=cfg["target_rel"], t_align=cfg["t_align"],
                                     regular_floor=cfg["regular_floor"], sigma=cfg["sigma"], label=scene)
    # The mean divergence (trace of the Jacobian) over each replica's window, without tangent vectors:
    # an independent estimate of the sum of the exponents, with its own spread over replicas.
    div = np.array([benettin.mean_divergence(params, _advance(params, x, cfg["t_align"], cfg["tol"]), res["T"],
                                             cfg["tol"])
                    for x in replicas])
    T_grid, running = _running(res["log_growth"], cfg["tau"])
    lam, err, per = res["exponents"], res["stderr"], res["per_replica"]
    sums = per.sum(axis=1)
    ds = _spectrum_dataset(res, div, replicas, T_grid, running)
    ds.attrs.update(lyapunov_attrs(params, y0, cfg, scene))
    ds.attrs.update(transient_attrs)
    ds.attrs.update(
        settled_state=np.asarray(y, float), **_lambda_observables(per),
        t_transient=cfg["t_transient"], T=res["T"], replicas=B, replica_spacing=cfg["replica_spacing"],
        status=res["status"], rule=res["rule"],
        uncertainty="standard error of the mean over independent replicas (points along the settled orbit, "
                    f"{cfg['replica_spacing']:g} time units apart)",
        mean_divergence=float(div.mean()), mean_divergence_stderr=float(div.std(ddof=1) / math.sqrt(B)),
        sum_all=float(sums.mean()), sum_all_stderr=float(sums.std(ddof=1) / math.sqrt(B)),
        sum_lambda_1_4=float(lam[0] + lam[3]),
        sum_lambda_1_4_stderr=float((per[:, 0] + per[:, 3]).std(ddof=1) / math.sqrt(B)),
        sum_minus_divergence_max=float(np.max(np.abs(sums - div))),
        lambda_1_decay_slope_last_decade=_decay_slope(T_grid, running[:, 0]),
        compile_time_s=compile_s, wall_time_s=time.perf_counter() - start,
        energy_max_rel_drift=float(np.max(np.abs(
            equations.energy(res["final_state"], params) / equations.energy(y0, params) - 1))),
    )
    log.info("%s: exponents %s +- %s (%s, T = %.4g per replica); sum %.3g +- %.2g vs mean divergence %.3g +- %.2g",
             scene, lam, err, res["status"], res["T"], sums.mean(), ds.attrs["sum_all_stderr"], div.mean(),
             ds.attrs["mean_divergence_stderr"])
    return ds


LYAPUNOV_SPECTRUM = SceneKind(
    name="lyapunov_spectrum",
    title="the four Lyapunov exponents of the steady state from independent replicas (claims C18, C19)",
    compute=spectrum, realizable=True, observables=("lambda_1", "lambda_4"),
    records=lambda c: [*memory.pre_run(c, "t_transient"), *memory.benettin(c, 8)], pre_run="t_transient")


def _lambda_observables(per) -> dict:
    """The ladder observables of a spectrum or the protocol (1/time): lambda_1 and lambda_4, each the
    mean over the independent runs ``per`` (runs, 4: replicas along one orbit, or the protocol's
    states) with its standard error as uncertainty."""
    err = per.std(axis=0, ddof=1) / math.sqrt(per.shape[0])
    return {"lambda_1": float(per[:, 0].mean()), "lambda_1_uncertainty": float(err[0]),
            "lambda_4": float(per[:, 3].mean()), "lambda_4_uncertainty": float(err[3])}


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
    """The paper's protocol (pre-run, T) from several initial states on one energy level, to show the
    spread of its finite-time exponents (C19). Renormalised every tau instead of the paper's
    paper_tau: Benettin's accumulated sums do not depend on the interval in exact arithmetic (the
    R factors of successive QR steps multiply), and the first state measures the agreement of the
    two intervals over tau_check, a window short enough that the two step sequences' rounding has
    not grown."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    states = [state_at_label(s, params, cfg["energy_label"]) for s in cfg["states"]]
    exps, errs, settled = [], [], []
    for j, y0 in enumerate(states):
        y = _advance(params, y0, cfg["t_transient"], cfg["tol"])
        settled.append(y)
        r = _run(params, y, k=4, cfg=cfg, compact=True, label=f"{scene}[{j}]", seed=j)
        exps.append(r["exponents"])
        errs.append(r["stderr"])
        log.info("%s[%d]: %s", scene, j, r["exponents"])
    check = {tau: _run(params, settled[0], k=4, cfg=dict(cfg, tau=tau, t_align=0.0), compact=True, T=cfg["tau_check"],
                       label=f"{scene}[0, tau = {tau:g}]")["exponents"] for tau in (cfg["tau"], cfg["paper_tau"])}
    agreement = float(np.max(np.abs(check[cfg["paper_tau"]] / check[cfg["tau"]] - 1.0)))
    ds = xr.Dataset(
        {"exponent": (("state", "i"), np.array(exps), cf.attrs("Lyapunov exponent lambda_i of each state", "rate")),
         "stderr": (("state", "i"), np.array(errs), cf.attrs("block standard error of the exponent", "rate")),
         "y0": (("state", "component"), np.array(states))},
        coords={"i": np.arange(1, 5), "component": list(equations.STATE_NAMES)},
    )
    ds.attrs.update(lyapunov_attrs(params, states[0], cfg, scene))
    ds.attrs.update(settled_state=np.ravel(settled), **_lambda_observables(np.array(exps)),
                    t_transient=cfg["t_transient"], T=cfg["T"], n_blocks=cfg["n_blocks"], paper_tau=cfg["paper_tau"],
                    tau_check=cfg["tau_check"], tau_equivalence_max_rel_diff=agreement,
                    tau_equivalence=f"renormalised every {cfg['tau']:g} instead of the paper's {cfg['paper_tau']:g}: "
                                    "equal in exact arithmetic; over the first {:g} time units of state 0 the four "
                                    "exponents agree to {:.1g} (relative)".format(cfg["tau_check"], agreement),
                    wall_time_s=time.perf_counter() - start, spread_lambda_1=float(np.ptp(np.array(exps)[:, 0])))
    log.info("%s: tau %g and %g agree to %.2g over %g", scene, cfg["tau"], cfg["paper_tau"], agreement,
             cfg["tau_check"])
    return ds


def _protocol_checks(w, cfg):
    blocks(w, cfg, "T")
    blocks(w, dict(cfg, tau=max(cfg["tau"], cfg["paper_tau"])), "tau_check")


LYAPUNOV_PROTOCOL = SceneKind(
    name="lyapunov_protocol",
    title="the paper's Lyapunov protocol from several start states on one level (claim C19)",
    compute=protocol, realizable=True, observables=("lambda_1", "lambda_4"),
    records=lambda c: [memory.span(c, "T", "tau"), memory.span(c, "tau_check", "paper_tau")],
    checks=_protocol_checks)
