"""Transient scenes: the transient phases against eps from the reference state (C03-C05), and
many initial states on each of two energy levels run until their steady state (F4, C06)."""

from __future__ import annotations

import logging
import math
import time
import warnings

import numpy as np
import xarray as xr

from sleighsim.analysis import fits
from sleighsim.engine import transient
from sleighsim.engine.integrate import final_state, integrate, sample_grid
from sleighsim.io import cf
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_LABEL, state_at_label
from sleighsim.scenes import memory
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.common import nan_padded
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def _record_phases(rec, tc):
    """sleighsim.engine.transient.phases of a trajectory dataset with a scene's ``transient`` block."""
    return transient.phases(rec.time.values, rec.u.values, rec.Omega.values, rec.omega.values, **tc)


def _phases_of(params, y0, t_end, cfg, scene):
    run = integrate(params, y0, sample_grid(0.0, t_end, cfg["dt"]), tol=cfg["tol"], scene=scene, progress=4)
    return run, _record_phases(run, cfg["transient"])


def transient_scaling(cfg: dict, scene: str = "") -> xr.Dataset:
    """The transient phases (sleighsim.engine.transient.phases) for each eps from the reference state
    (label 0.1127 at every eps), over t_end = t_scale / eps^2, and the log-log slope against eps."""
    start = time.perf_counter()
    eps_list = np.asarray(cfg["eps"], float)
    keys = ("sleigh_phase_end", "first_spike", "n_spikes", "spike_interval_mean", "spike_interval_std",
            "omega_settling_time")
    table = {k: [] for k in keys}
    drift, steps, t_end = [], [], []
    for e in eps_list:
        params = Params.paper(eps=e, b=cfg["b"], K2=1.0 + cfg["kappa"] * e)
        te = cfg["t_scale"] / e**2
        run, ph = _phases_of(params, cfg["y0"], te, cfg, f"{scene}[eps={e:g}]")
        for k in keys:
            table[k].append(ph[k])
        drift.append(run.attrs["energy_max_rel_drift"])
        steps.append(run.attrs["steps"])
        t_end.append(te)
    ds = xr.Dataset({k: ("eps", np.asarray(v, float)) for k, v in table.items()}, coords={"eps": eps_list})
    ds["t_end"] = ("eps", np.asarray(t_end))
    ds["energy_max_rel_drift"] = ("eps", np.asarray(drift))
    ds["steps"] = ("eps", np.asarray(steps))
    ok = np.isfinite(ds.first_spike.values)
    slope, icpt, _ = fits.loglog(eps_list[ok], ds.first_spike.values[ok])
    ok_i = np.isfinite(ds.spike_interval_mean.values)
    slope_i = fits.loglog(eps_list[ok_i], ds.spike_interval_mean.values[ok_i])[0]
    ds.attrs.update(
        scene=scene, b=cfg["b"], kappa=cfg["kappa"], K2_rule="K2 = 1 + kappa eps",
        **{f"y0_{n}": float(v) for n, v in zip(equations.STATE_NAMES, cfg["y0"])}, energy_label=REFERENCE_LABEL,
        t_scale=cfg["t_scale"], dt=cfg["dt"], tol=cfg["tol"], backend="heyoka", rule=transient.PHASES_RULE,
        spike_rule=transient.RULE, first_spike_slope=float(slope), first_spike_prefactor=float(np.exp(icpt)),
        spike_interval_slope=float(slope_i), predicted_slope=-2.0,
        fit_method="least squares of log(time) against log(eps) over the eps with a detected spike",
        wall_time_s=time.perf_counter() - start,
    )
    log.info("%s: done in %.3g s; first spikes %s; slope %.3f", scene, ds.attrs["wall_time_s"],
             ds.first_spike.values.round(1).tolist(), slope)
    return ds


TRANSIENT_SCALING = SceneKind(
    name="transient_scaling",
    title="the transient phases against eps from the reference state (claims C03-C05)",
    compute=transient_scaling,
    records=lambda c: [memory.span(c, ("t_scale / min(eps)^2", c["t_scale"] / min(c["eps"]) ** 2), "dt")])


def _until_steady(params, y0, cfg, scene):
    """Integrate in chunks until the phase detector finds the first spike and ``spikes_after``
    more (the steady state, sampled), or t_max. Returns (record, phases, reached, max relative
    energy drift of the whole record)."""
    dt = cfg["dt"]
    pieces, y, t = [], np.asarray(y0, float), 0.0
    while True:
        chunk = integrate(params, y, sample_grid(t, t + cfg["chunk"], dt), tol=cfg["tol"], scene=scene, progress=1)
        pieces.append(chunk if not pieces else chunk.isel(time=slice(1, None)))
        y, t = final_state(chunk), float(chunk.time.values[-1])
        rec = xr.concat(pieces, dim="time", data_vars="minimal", coords="minimal", compat="override",
                        combine_attrs="override")
        ph = _record_phases(rec, cfg["transient"])
        window_end = ph["first_spike"] + cfg["compare_window"] * cfg["time_unit"]
        reached = ph["n_spikes"] > cfg["spikes_after"] and t >= window_end
        if reached or t >= cfg["t_max"] * cfg["time_unit"]:
            E = equations.energy(np.stack([rec[v].values for v in equations.STATE_NAMES], axis=-1), params)
            E0 = float(equations.energy(y0, params))
            return rec, ph, reached, float(np.max(np.abs(E / E0 - 1.0)))


def _aligned(rec, t_first, tau, c=1.0):
    """omega(t_first + tau / c) / c: the record after its first spike, in level-0 units (time scaling by c)."""
    return np.interp(t_first + tau / c, rec.time.values, rec.omega.values) / c


def _running_mean_same(x, n):
    """Centred running mean over n samples on x's grid; NaN where the window does not fit."""
    out = np.convolve(x, np.ones(n) / n, mode="same")
    out[: n // 2], out[out.size - n // 2:] = np.nan, np.nan
    return out


def _max_distance(curves, others=None):
    """Max over pairs (within ``curves``, or between curves and others) of max |a - b|, NaN samples ignored."""
    pairs = ([(a, b) for i, a in enumerate(curves) for b in curves[i + 1:]] if others is None
             else [(a, b) for a in curves for b in others])
    return float(max(np.nanmax(np.abs(a - b)) for a, b in pairs)) if pairs else float("nan")


def _long_check(params, y0, cfg, scene):
    """Spike times and intervals of one state over a long horizon (is a group a slow transient?)."""
    lc = cfg["long_check"]
    run = integrate(params, y0, sample_grid(0.0, lc["t_end"], lc["dt"]), tol=cfg["tol"], scene=scene, progress=4)
    sp = transient.spike_times(run.time.values, run.Omega.values, factor=cfg["transient"]["spike_factor"],
                               t_min=lc["t_min"])
    return sp, run.attrs["energy_max_rel_drift"]


_PER_RUN = ("first_spike", "sleigh_phase_end", "n_spikes", "spike_interval_mean", "spike_interval_std")


def _level_runs(params, cfg: dict, tau, c_of: list, scene: str) -> dict:
    """Every state of every level run until its steady state, omega aligned at its first spike
    (mirrored when its mean is negative) and smoothed: lists per run, and the per-run facts."""
    dt_cmp, smooth = cfg["compare_dt"], cfg["smooth"]
    per = {k: [] for k in (*_PER_RUN, "omega_mean", "mirrored", "reached", "t_run", "energy_max_rel_drift")}
    runs = {k: [] for k in ("raw", "smoothed", "y0", "label", "level", "state", "c")}
    for li, lv in enumerate(cfg["levels"]):
        for si, s in enumerate(lv["states"]):
            y0 = state_at_label(s, params, lv["label"])
            rec, ph, reached, drift = _until_steady(params, y0, dict(cfg, time_unit=1.0 / c_of[li]),
                                                    f"{scene}[E={lv['label']:g}, state {si}]")
            om = _aligned(rec, ph["first_spike"], tau, c_of[li]) if reached else np.full(tau.size, np.nan)
            mirrored = bool(np.nanmean(om) < 0)
            om = -om if mirrored else om
            runs["raw"].append(om)
            runs["smoothed"].append(_running_mean_same(om, max(1, int(round(smooth / dt_cmp)))))
            for k in _PER_RUN:
                per[k].append(ph[k])
            per["omega_mean"].append(float(np.nanmean(om)))
            per["mirrored"].append(int(mirrored))
            per["reached"].append(int(reached))
            per["t_run"].append(float(rec.time.values[-1]))
            per["energy_max_rel_drift"].append(drift)
            for key, value in zip(("y0", "label", "level", "state", "c"), (y0, lv["label"], li, si, c_of[li])):
                runs[key].append(value)
    return {**runs, "per": per}


def _level_distances(raw, smoothed, level, ok, group, c_of: list, n_levels: int) -> tuple[dict, list, int, float]:
    """Distances between the aligned curves within each level, within its main group and across
    levels (attributes), the number of groups per level, the main group and the scale (mean |omega| of level 0)."""
    scale = float(np.nanmean(np.abs(smoothed[level == 0])))

    def dist(sel_a, sel_b=None, curves=smoothed):
        a = [curves[i] for i in np.flatnonzero(sel_a & ok)]
        b = None if sel_b is None else [curves[i] for i in np.flatnonzero(sel_b & ok)]
        return _max_distance(a, b) / scale

    n_groups = [len(set(group[(level == li) & ok])) for li in range(n_levels)]
    main = np.bincount(group[ok]).argmax() if ok.any() else -1
    attrs = {}
    for li in range(n_levels):
        attrs[f"level{li}_n_groups"] = n_groups[li]
        attrs[f"level{li}_distance_all"] = dist(level == li)
        attrs[f"level{li}_distance_all_raw"] = dist(level == li, curves=raw)
        attrs[f"level{li}_distance_main_group"] = dist((level == li) & (group == main))
    if n_levels > 1:
        attrs["across_levels_distance_main_group_scaled"] = dist((level == 0) & (group == main),
                                                                  (level == 1) & (group == main))
        members = [(level == li) & (group == main) & ok for li in (0, 1)]
        with warnings.catch_warnings():  # a sample time no run of the group reaches: NaN, said here once
            warnings.simplefilter("ignore", RuntimeWarning)
            unscaled = [np.nanmean(smoothed[m], axis=0) * (c_of[li] if li else 1.0)
                        for li, m in enumerate(members) if m.any()]  # a level without a run of the group: no mean
        attrs["across_levels_distance_main_group_unscaled"] = (
            float(np.nanmax(np.abs(unscaled[1] - unscaled[0]))) / scale if len(unscaled) == 2 else float("nan"))
    return attrs, n_groups, main, scale


def attractor_levels(cfg: dict, scene: str = "") -> xr.Dataset:
    """Several initial states on each of two energy levels, each run until its steady state;
    omega aligned at the first spike after the transient and compared within and across levels
    (every level mapped onto the first by the time-scaling law; runs with omega < 0 by the
    mirror symmetry (u, Omega, omega, delta) -> (u, -Omega, -omega, -delta))."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    labels = [lv["label"] for lv in cfg["levels"]]
    c_of = [math.sqrt(L / labels[0]) for L in labels]
    window, dt_cmp, smooth = cfg["compare_window"], cfg["compare_dt"], cfg["smooth"]
    tau = np.arange(0.0, window + 0.5 * dt_cmp, dt_cmp)
    runs = _level_runs(params, cfg, tau, c_of, scene)
    per, y0s, run_level = runs["per"], runs["y0"], runs["level"]
    raw, smoothed = np.array(runs["raw"]), np.array(runs["smoothed"])
    level, ok = np.array(run_level), np.array(per["reached"], bool)
    interval = np.array(per["spike_interval_mean"], float) * np.array(runs["c"])  # in level-0 time units
    group = transient.interval_groups(np.where(ok, interval, np.nan), cfg["group_rel_tol"])
    attrs, n_groups, main, scale = _level_distances(raw, smoothed, level, ok, group, c_of, len(labels))
    # Long horizon: one representative per group, to see whether a group is a slow transient.
    reps = [int(np.flatnonzero((group == g) & ok)[0]) for g in sorted(set(group[ok]))]
    long_sp = [_long_check(params, y0s[r] if run_level[r] == 0 else state_at_label(y0s[r], params, labels[0]),
                           cfg, f"{scene}.long[group {group[r]}]") for r in reps]
    ds = xr.Dataset(
        {
            "omega_aligned": (("run", "tau"), raw, cf.attrs("omega(t_first + tau / c) / c (sign: mirrored)",
                                                            "angular_velocity")),
            "omega_aligned_smooth": (("run", "tau"), smoothed,
                                     cf.attrs(f"running mean over {smooth:g} of omega_aligned", "angular_velocity")),
            "y0": (("run", "component"), np.array(y0s)),
            **{k: ("run", np.asarray(v, float)) for k, v in per.items()},
            "spike_interval_level0_units": ("run", interval),
            "group": ("run", group, cf.attrs("steady spike interval group (group_rel_tol)")),
            "long_spike_time": (("group", "spike"), nan_padded([sp for sp, _ in long_sp])),
            "long_representative_run": ("group", np.array(reps)),
        },
        coords={"tau": ("tau", tau, cf.attrs("time tau after the first spike, on level 0's time scale", "time")),
                "component": list(equations.STATE_NAMES), "label": ("run", runs["label"]),
                "level": ("run", run_level), "state_index": ("run", runs["state"]), "scale_c": ("run", runs["c"]),
                "group_id": ("group", np.array([group[r] for r in reps]))},
    )
    ds.attrs.update(params.attrs())
    ds.attrs.update(attrs)
    ds.attrs.update(
        scene=scene, tol=cfg["tol"], backend="heyoka", labels=np.asarray(labels, float), n_runs=len(raw),
        n_reached=int(ok.sum()), main_group=int(main), group_rel_tol=cfg["group_rel_tol"],
        alignment="first Omega spike after the sleigh-like phase (sleighsim.engine.transient.phases); level k is "
                  "mapped onto level 0 by the time-scaling law (tau -> tau / c, omega -> omega / c); omega < 0 runs "
                  "are mirrored",
        phase_rule=transient.PHASES_RULE, compare_window=window, compare_dt=dt_cmp, smooth=smooth,
        distance_rule="max over pairs of max over tau of |omega_i - omega_j| of the smoothed aligned curves "
                      f"(defined {smooth:g} / 2 inside the window), over the mean |omega| of level 0 ({scale:.4g}); "
                      "raw = unsmoothed",
        group_rule="runs whose steady spike interval (level-0 units) is within group_rel_tol of a group's first member",
        long_check_t_end=cfg["long_check"]["t_end"],
        long_check_energy_max_rel_drift=float(max((d for _, d in long_sp), default=np.nan)),
        energy_max_rel_drift=float(np.max(per["energy_max_rel_drift"])), wall_time_s=time.perf_counter() - start,
    )
    log.info("%s: done in %.3g s; groups per level %s; distances %s", scene, ds.attrs["wall_time_s"], n_groups,
             {k: round(v, 4) for k, v in attrs.items() if "distance" in k})
    return ds


def _attractor_levels_checks(w, cfg):
    for key in ("chunk", "compare_window"):
        if cfg[key] >= cfg["t_max"]:
            raise ConfigError(f"{w}.{key} = {cfg[key]} must lie in (0, t_max = {cfg['t_max']})")
    if cfg["smooth"] >= cfg["compare_window"]:
        raise ConfigError(f"{w}.smooth = {cfg['smooth']} must lie in (0, compare_window = {cfg['compare_window']})")


ATTRACTOR_LEVELS = SceneKind(
    name="attractor_levels",
    title=("several start states on two energy levels, each run to its steady state and compared under the "
           "time-scaling law (figure F4, claim C06)"),
    compute=attractor_levels, checks=_attractor_levels_checks,
    records=lambda c: [memory.span(c, "t_max", "dt"), memory.span(c, "long_check.t_end", "long_check.dt"),
                       memory.span(c, "compare_window", "compare_dt")])
