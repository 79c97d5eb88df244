"""Trajectory scenes: the rotor-free sleigh against its closed form (F2), and sampled runs
of the full model (F3, F7, F8)."""

from __future__ import annotations

import logging
import time

import numpy as np
import xarray as xr

from sleighsim.engine.integrate import integrate, sample_grid
from sleighsim.engine.transient import phases, settle, spike_times
from sleighsim.io import cf
from sleighsim.model import equations
from sleighsim.model.attrs import state_attrs
from sleighsim.model.params import Params
from sleighsim.model.sleigh0 import closed_form
from sleighsim.model.sleigh0 import rhs as sleigh0_rhs
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.checks import SPIKE_BLOCK, ConfigError, increasing
from sleighsim.scenes.common import initial_state, steady_arithmetic
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def trajectory(cfg: dict, scene: str = "") -> xr.Dataset:
    """Integrate from ``y0`` at t = 0 and sample the kept variables on [t_sample_start, t_end] with
    step dt (F3, F7, F8). With a ``transient`` block the run to t_sample_start is a checked pre-run
    (sleighsim.engine.transient.settle, in double) and the path (theta, x, y) is measured from the window's
    start. The sampled run is in the block's ``precision`` (:func:`.common.steady_arithmetic`); without
    a pre-run that is the whole run, transient included. Its key observables (:func:`observed`) are
    stated with their uncertainties for the precision ladder."""
    params = Params.from_config(cfg["params"])
    y0 = initial_state(cfg, params)
    start = cfg.get("t_sample_start", 0.0)
    times = sample_grid(start, cfg["t_end"], cfg["dt"])
    keep = list(cfg["keep"])
    kinematics = any(v in equations.KINEMATIC_NAMES for v in keep)
    pre = {}
    if "transient" in cfg and start > 0:
        y0, pre = settle(params, y0, start, **cfg["transient"], tol=cfg["tol"], label=scene)
    arith = steady_arithmetic(cfg)
    run = integrate(params, y0, times, t0=0.0 if not pre else start, kinematics=kinematics, **arith, scene=scene)
    ds = run[keep]
    ds.attrs.update(pre)
    ds.attrs.update(observed(run, pre_run=bool(pre), spike_factor=cfg.get("transient", {}).get("spike_factor", 1.8)))
    ds.attrs.update(**arith, settled_state=np.asarray(y0, float)[:4],
                    transient_precision=Precision.DOUBLE if pre else arith["precision"], transient_tol=cfg["tol"])
    if pre:
        ds.attrs.update(state_attrs(params, initial_state(cfg, params)),
                        path_origin="the window's start (t_sample_start)")
        ds.attrs["energy_max_rel_drift"] = max(ds.attrs["energy_max_rel_drift"], pre["pre_run_energy_max_rel_drift"])
    return ds


def _trajectory_checks(w, cfg):
    start, end = cfg.get("t_sample_start", 0.0), cfg["t_end"]
    if start >= end:
        raise ConfigError(f"{w}.t_sample_start = {start} must lie in [0, t_end = {end})")
    if "transient" in cfg and start > 0 and end - start < 2 * SPIKE_BLOCK:
        raise ConfigError(f"{w}.t_end = {end} must be at least t_sample_start + {2 * SPIKE_BLOCK:g} = "
                          f"{start + 2 * SPIKE_BLOCK:g}: the window's spikes are found in blocks of {SPIKE_BLOCK:g}")


TRAJECTORY = SceneKind(
    name="trajectory",
    title="one run of the sleigh: velocities, heading and path, through its transients into the steady state",
    compute=trajectory,
    observables=("n_spikes", "first_spike_time", "spike_interval_mean", "path_reach"),
    records=lambda c: [memory.span(c, ("(t_end - t_sample_start)", c["t_end"] - c.get("t_sample_start", 0.0)),
                                   "dt", 7),
                       *memory.pre_run(c, "t_sample_start")],
    checks=_trajectory_checks, pre_run="t_sample_start")


#: Written into every trajectory dataset (attribute observables_rule).
OBSERVED_RULE = (
    "A trajectory's key observables (time units, lengths in b) with their uncertainties: the number of Omega "
    "spikes (exact), the first spike's time (uncertainty: the sampling step), the mean spike interval "
    "(uncertainty: the difference between the means of the intervals' two halves, a block estimate; from four "
    "intervals), and with a path its reach, the farthest distance from the window's start (uncertainty: the "
    "difference between the farthest distances of the path's two halves, a block estimate). A run from t = 0 "
    "finds its spikes after the sleigh-like phase (:func:`sleighsim.engine.transient.phases`, as the judges "
    "do), a window after a pre-run from its start. Observables a run cannot state are left out."
)


def observed(run: xr.Dataset, *, pre_run: bool, spike_factor: float) -> dict:
    """Applies :data:`OBSERVED_RULE`, the rule as the datasets record it (just above)."""
    t, Omega = run.time.values, run.Omega.values
    if pre_run:
        spikes = spike_times(t, Omega, factor=spike_factor, t_min=float(t[0]))
    else:
        spikes = phases(t, run.u.values, Omega, run.omega.values, spike_factor=spike_factor)["spikes"]
    out = {"n_spikes": int(spikes.size), "observables_rule": OBSERVED_RULE}
    if spikes.size:
        out.update(first_spike_time=float(spikes[0]), first_spike_time_uncertainty=float(t[1] - t[0]))
    d = np.diff(spikes)
    if d.size >= 4:
        h = d.size // 2
        out.update(spike_interval_mean=float(d.mean()),
                   spike_interval_mean_uncertainty=float(abs(d[:h].mean() - d[h:].mean())))
    if "x" in run:
        r = np.hypot(run.x.values - run.x.values[0], run.y.values - run.y.values[0])
        h = r.size // 2
        out.update(path_reach=float(r.max()), path_reach_uncertainty=float(abs(r[:h].max() - r[h:].max())))
    return out


def _portrait(params, pc: dict, b: float, K2: float, tol: float, scene: str) -> tuple:
    """The phase portrait of the eps = 0 sleigh: its times t, start states, u and Omega in closed form
    and integrated (trajectory x t), the largest energy drift and the steps taken."""
    t = np.linspace(-pc["t_half"], pc["t_half"], pc["n_samples"])
    starts = np.asarray(pc["states"], dtype=float)  # states at t = 0
    u_cf = np.empty((len(starts), t.size))
    Om_cf = np.empty_like(u_cf)
    u_num = np.empty_like(u_cf)
    Om_num = np.empty_like(u_cf)
    drift, steps = 0.0, 0
    # Both halves run from t = 0 in their stable direction: forward for t >= 0; for t <= 0
    # the reversal symmetry y(-s) = -y~(s), y~ the solution from -y(0), gives the past.
    # (Integrating forward from t = -t_half would start beside the unstable branch u = -V.)
    past, future = t <= 0, t >= 0
    for k, (u0, Om0) in enumerate(starts):
        u_cf[k], Om_cf[k], _ = closed_form(t, u0, Om0, b, K2)
        for mask, sign in ((future, 1.0), (past, -1.0)):
            ts = sign * t[mask]
            order = np.argsort(ts)
            ds = integrate(params, [sign * u0, sign * Om0, 0.0, 0.0], ts[order], tol=tol,
                           scene=f"{scene}[{k}]", progress=1)
            idx = np.flatnonzero(mask)[order]
            u_num[k, idx], Om_num[k, idx] = sign * ds.u.values, sign * ds.Omega.values
            drift = max(drift, ds.attrs["energy_max_rel_drift"])
            steps += ds.attrs["steps"]
    return t, starts, u_cf, Om_cf, u_num, Om_num, drift, steps


def sleigh0(cfg: dict, scene: str = "") -> xr.Dataset:
    """The eps = 0 sleigh: phase-portrait trajectories (closed form and integration
    of the full model with a decoupled rotor), the vector field, and a path."""
    start = time.perf_counter()
    b, K2, tol = cfg["b"], cfg["K2"], cfg["tol"]
    params = Params.sleigh0(b=b, K2=K2)
    pc = cfg["portrait"]
    t, starts, u_cf, Om_cf, u_num, Om_num, drift, steps = _portrait(params, pc, b, K2, tol, scene)
    err = float(max(np.max(np.abs(u_num - u_cf)), np.max(np.abs(Om_num - Om_cf))))

    ug = np.linspace(*pc["u_range"], pc["n_field"])
    Og = np.linspace(*pc["Omega_range"], pc["n_field"])
    UU, OO = np.meshgrid(ug, Og, indexing="ij")
    field = sleigh0_rhs(np.stack([UU, OO], axis=-1), b, K2)

    path_cfg = cfg["path"]
    tp = sample_grid(0.0, path_cfg["t_end"], path_cfg["dt"])
    path = integrate(params, [*path_cfg["y0"], 0.0, 0.0], tp, kinematics=True, tol=tol, scene=f"{scene}.path")
    _, _, theta_cf = closed_form(tp, *path_cfg["y0"], b, K2)
    path_err = float(np.max(np.abs(path.theta.values - theta_cf)))

    out = xr.Dataset(
        {
            "u_closed": (("trajectory", "t"), u_cf, cf.attrs("u, closed form", "speed")),
            "Omega_closed": (("trajectory", "t"), Om_cf, cf.attrs("Omega, closed form", "angular_velocity")),
            "u_integrated": (("trajectory", "t"), u_num, cf.attrs("u, heyoka", "speed")),
            "Omega_integrated": (("trajectory", "t"), Om_num, cf.attrs("Omega, heyoka", "angular_velocity")),
            "du": (("u_grid", "Omega_grid"), field[..., 0], cf.attrs("udot on the grid", "acceleration")),
            "dOmega": (("u_grid", "Omega_grid"), field[..., 1],
                       cf.attrs("Omegadot on the grid", "angular_acceleration")),
            "path_x": ("path_time", path.x.values, cf.attrs("path: centre C, x", "length")),
            "path_y": ("path_time", path.y.values, cf.attrs("path: centre C, y", "length")),
            "path_theta": ("path_time", path.theta.values, cf.attrs("path: sleigh heading theta", "angle")),
        },
        coords={"t": t, "u_grid": ug, "Omega_grid": Og, "path_time": tp,
                "u_start": ("trajectory", starts[:, 0]), "Omega_start": ("trajectory", starts[:, 1])},
    )
    out.attrs.update(params.attrs())
    out.attrs.update(
        scene=scene, backend="heyoka", method="taylor_adaptive", tol=tol, param_eps=0.0,
        closed_form_max_abs_error=err, path_theta_max_abs_error=path_err,
        energy_max_rel_drift=max(drift, path.attrs["energy_max_rel_drift"]),
        path_y0_u=path_cfg["y0"][0], path_y0_Omega=path_cfg["y0"][1],
        wall_time_s=time.perf_counter() - start, steps=steps + path.attrs["steps"],
    )
    log.info("%s: closed form vs integration max error %.3g, path heading error %.3g", scene, err, path_err)
    return out


def _sleigh0_checks(w, cfg):
    for key in ("u_range", "Omega_range"):
        increasing(f"{w}.portrait.{key}", cfg["portrait"][key])


SLEIGH0 = SceneKind(
    name="sleigh0",
    title=("the rotor-free sleigh (eps = 0): phase portrait against the closed form, vector field and a path "
           "(figure F2, claim C01)"),
    compute=sleigh0, checks=_sleigh0_checks,
    records=lambda c: [memory.span(c, "portrait.n_samples", None, 4, memory.count(c, "portrait.states")),
                       memory.span(c, ("portrait.n_field^2", c["portrait"]["n_field"] ** 2), None, 4),
                       memory.span(c, "path.t_end", "path.dt", 7)])
