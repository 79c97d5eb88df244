"""Scene computations: each takes its config block and returns one Dataset.

Scenes store what their figure needs, sampled for the figure, and nothing else.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import numpy as np
import xarray as xr

from . import chaos, model, poincare, spectra, transient
from . import transient_scenes as ts
from .integrate import UNITS, final_state, integrate, sample_grid
from .io import provenance_attrs

log = logging.getLogger("sleighsim")


def initial_state(cfg: dict, params: model.Params) -> np.ndarray:
    """The configured y0, rescaled to ``energy_label`` when one is given."""
    y0 = np.asarray(cfg["y0"], dtype=float)
    if cfg.get("energy_label") is not None:
        y0 = model.state_at_label(y0, params, cfg["energy_label"])
    return y0


def trajectory(cfg: dict, scene: str = "") -> xr.Dataset:
    """Integrate from ``y0`` at t = 0 and sample the kept variables on
    [t_sample_start, t_end] with step dt (F3, F7, F8)."""
    params = model.Params.from_config(cfg["params"])
    y0 = initial_state(cfg, params)
    times = sample_grid(cfg.get("t_sample_start", 0.0), cfg["t_end"], cfg["dt"])
    keep = list(cfg["keep"])
    kinematics = any(v in model.KINEMATIC_NAMES for v in keep)
    ds = integrate(params, y0, times, t0=0.0, kinematics=kinematics, tol=cfg["tol"], scene=scene)
    return ds[keep]


def fig2(cfg: dict, scene: str = "fig2") -> xr.Dataset:
    """The eps = 0 sleigh: phase-portrait trajectories (closed form and integration
    of the full model with a decoupled rotor), the vector field, and a path."""
    start = time.perf_counter()
    b, K2, tol = cfg["b"], cfg["K2"], cfg["tol"]
    params = model.Params.sleigh0(b=b, K2=K2)
    pc = cfg["portrait"]
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
        u_cf[k], Om_cf[k], _ = model.sleigh0_closed_form(t, u0, Om0, b, K2)
        for mask, sign in ((future, 1.0), (past, -1.0)):
            ts = sign * t[mask]
            order = np.argsort(ts)
            ds = integrate(params, [sign * u0, sign * Om0, 0.0, 0.0], ts[order], tol=tol,
                           scene=f"{scene}[{k}]", progress=1)
            idx = np.flatnonzero(mask)[order]
            u_num[k, idx], Om_num[k, idx] = sign * ds.u.values, sign * ds.Omega.values
            drift = max(drift, ds.attrs["energy_max_rel_drift"])
            steps += ds.attrs["steps"]
    err = float(max(np.max(np.abs(u_num - u_cf)), np.max(np.abs(Om_num - Om_cf))))

    ug = np.linspace(*pc["u_range"], pc["n_field"])
    Og = np.linspace(*pc["Omega_range"], pc["n_field"])
    UU, OO = np.meshgrid(ug, Og, indexing="ij")
    field = model.sleigh0_rhs(np.stack([UU, OO], axis=-1), b, K2)

    path_cfg = cfg["path"]
    tp = sample_grid(0.0, path_cfg["t_end"], path_cfg["dt"])
    path = integrate(params, [*path_cfg["y0"], 0.0, 0.0], tp, kinematics=True, tol=tol, scene=f"{scene}.path")
    _, _, theta_cf = model.sleigh0_closed_form(tp, *path_cfg["y0"], b, K2)
    path_err = float(np.max(np.abs(path.theta.values - theta_cf)))

    out = xr.Dataset(
        {
            "u_closed": (("trajectory", "t"), u_cf, {"long_name": "u, closed form", "units": UNITS["u"][1]}),
            "Omega_closed": (("trajectory", "t"), Om_cf, {"long_name": "Omega, closed form", "units": UNITS["Omega"][1]}),
            "u_integrated": (("trajectory", "t"), u_num, {"long_name": "u, heyoka", "units": UNITS["u"][1]}),
            "Omega_integrated": (("trajectory", "t"), Om_num, {"long_name": "Omega, heyoka", "units": UNITS["Omega"][1]}),
            "du": (("u_grid", "Omega_grid"), field[..., 0], {"long_name": "udot on the grid"}),
            "dOmega": (("u_grid", "Omega_grid"), field[..., 1], {"long_name": "Omegadot on the grid"}),
            "path_x": ("path_time", path.x.values, {"units": "length"}),
            "path_y": ("path_time", path.y.values, {"units": "length"}),
            "path_theta": ("path_time", path.theta.values, {"units": "rad"}),
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
    out.attrs.update(provenance_attrs())
    log.info("%s: closed form vs integration max error %.3g, path heading error %.3g", scene, err, path_err)
    return out




def _settle(params, y0, cfg, scene):
    """Integrate the pre-run [0, t_settle] sampled every ``transient.dt``; return the
    end state and the transient report (see sleighsim.transient) as attributes."""
    tc = cfg["transient"]
    pre = integrate(params, y0, sample_grid(0.0, cfg["t_settle"], tc["dt"]), tol=cfg["tol"], scene=f"{scene}.pre")
    report = transient.steady_state_report(pre.time.values, pre.Omega.values, pre.omega.values,
                                           spike_factor=tc["spike_factor"], window=tc["window"], rtol=tc["rtol"],
                                           t_min=tc["t_min"])
    settle = report["settling_time"]
    over = bool(np.isfinite(settle) and settle <= cfg["t_settle"] - 2 * tc["window"])
    attrs = {f"transient_{k}": v for k, v in report.items()}
    attrs.update(transient_over=int(over), transient_window=tc["window"], transient_rtol=tc["rtol"],
                 transient_spike_factor=tc["spike_factor"], transient_rule=transient.RULE,
                 pre_run_energy_max_rel_drift=pre.attrs["energy_max_rel_drift"], pre_run_steps=pre.attrs["steps"])
    log.info("%s: transient %s (settling time %.6g, pre-run to %.6g)", scene, "over" if over else "NOT over",
             settle, cfg["t_settle"])
    return final_state(pre), attrs


def poincare_scene(cfg: dict, scene: str = "") -> xr.Dataset:
    """P_2pi and P_pi/2 iterates after a checked transient, return times, rotation
    number, loop count, and a sampled stretch of the attractor (F9, F12)."""
    start = time.perf_counter()
    params = model.Params.from_config(cfg["params"])
    y0 = initial_state(cfg, params)
    y_settled, attrs = _settle(params, y0, cfg, scene)
    t0, t1 = cfg["t_settle"], cfg["t_settle"] + cfg["t_map"]
    c = poincare.crossings(params, y_settled, t0, t1, tol=cfg["tol"], scene=scene)
    att = integrate(params, y_settled, sample_grid(t0, t0 + cfg["attractor_span"], cfg["attractor_dt"]),
                    tol=cfg["tol"], scene=f"{scene}.attractor", progress=1)
    pts = np.c_[c["u"], c["Omega"], c["omega"]]
    is2pi = c["k"] % 4 == 0
    rt = np.diff(c["time"][is2pi])
    stride = max(1, int(np.ceil(len(pts) / cfg["max_stored_pi2"])))
    stride += 1 - stride % 2  # odd, so thinning keeps all four classes k mod 4
    loops = poincare.count_loops(pts[::stride], c["k"][::stride] % 4, cfg["loop_knn"])
    rot = poincare.rotation_number(pts[is2pi])
    E = model.energy(np.c_[pts, c["k"] * (np.pi / 2)], params)
    E0 = float(model.energy(y0, params))
    units = {"u": UNITS["u"][1], "Omega": UNITS["Omega"][1], "omega": UNITS["omega"][1]}
    data = {f"p2pi_{v}": ("n2pi", c[v][is2pi], {"units": units[v]}) for v in ("u", "Omega", "omega")}
    data["p2pi_time"] = ("n2pi", c["time"][is2pi], {"units": "time"})
    data["return_time"] = ("nret", rt, {"long_name": "t_{n+1} - t_n of P_2pi", "units": "time"})
    data.update({f"ppi2_{v}": ("npi2", c[v][::stride], {"units": units[v]}) for v in ("u", "Omega", "omega")})
    data["ppi2_class"] = ("npi2", (c["k"][::stride] % 4).astype(np.int8), {"long_name": "k mod 4, delta = k pi/2"})
    data["ppi2_cluster"] = ("npi2", loops["labels"].astype(np.int32),
                            {"long_name": "k-NN graph component in the (u, Omega, omega) projection"})
    data.update({f"attractor_{v}": ("natt", att[v].values, {"units": units[v]}) for v in ("u", "Omega", "omega")})
    ds = xr.Dataset(data)
    ds.attrs.update(model.state_attrs(params, y0))
    ds.attrs.update(attrs)
    ds.attrs.update(rot)
    ds.attrs.update(
        scene=scene, backend="heyoka", method="taylor_adaptive + nt_event sin(2 delta)", tol=cfg["tol"],
        energy_max_rel_drift=float(np.max(np.abs(E / E0 - 1))) if E.size else float("nan"),
        t_map_start=t0, t_map_end=t1, n_p2pi=int(is2pi.sum()), n_ppi2=int(len(pts)), ppi2_stride=stride,
        max_crossing_residual=float(c["residual"].max()) if len(pts) else float("nan"),
        return_time_min=float(rt.min()) if rt.size else float("nan"),
        return_time_max=float(rt.max()) if rt.size else float("nan"),
        return_time_min_pairwise_difference=poincare.min_pairwise_difference(rt),
        return_time_resolution=float(2 * np.spacing(t1)),
        return_time_tie_tol=cfg["return_time_tie_tol"],
        return_time_n_adjacent_pairs_within_tie_tol=int(np.sum(np.diff(np.sort(rt)) < cfg["return_time_tie_tol"])),
        p2pi_curve_thickness=poincare.curve_thickness(pts[is2pi]) if is2pi.sum() > 10 else float("nan"),
        n_loops=loops["n_loops"], n_components_projected=loops["n_components_projected"],
        loops_per_class=np.array([loops["loops_per_class"].get(k, 0) for k in range(4)], dtype=np.int32),
        loop_rule=f"per class k mod 4: connected components (>= 1% of the class) of the symmetric "
        f"{cfg['loop_knn']}-nearest-neighbour graph of standardised (u, Omega, omega); n_loops sums over classes",
        steps=int(c["steps"]), compile_time_s=c["compile_time_s"], wall_time_s=time.perf_counter() - start,
    )
    ds.attrs.update(provenance_attrs())
    log.info("%s: %d P_2pi, %d P_pi/2 iterates, %d loops, rotation number %.6g, max residual %.2g", scene,
             is2pi.sum(), len(pts), loops["n_loops"], rot["rotation_number"], ds.attrs["max_crossing_residual"])
    return ds


def spectrum_scene(cfg: dict, scene: str = "") -> xr.Dataset:
    """Welch PSD of u and Omega on the attractor, band edges and near-zero peaks (F13, F14);
    band edges are recomputed at a finer sampling to show they do not move."""
    start = time.perf_counter()
    params = model.Params.from_config(cfg["params"])
    y0 = initial_state(cfg, params)
    y_settled, attrs = _settle(params, y0, cfg, scene)
    t0 = cfg["t_settle"]
    sc = cfg["spectrum"]
    run = integrate(params, y_settled, sample_grid(t0, t0 + cfg["duration"], cfg["dt"]), tol=cfg["tol"], scene=scene)
    fine = integrate(params, y_settled, sample_grid(t0, t0 + cfg["check_duration"], cfg["check_dt"]),
                     tol=cfg["tol"], scene=f"{scene}.check", progress=4)
    coarse = run.sel(time=slice(t0, t0 + cfg["check_duration"]))
    data, out_attrs = {}, {}
    for v in ("u", "Omega"):
        f, S = spectra.psd(run[v].values, cfg["dt"], segment=sc["segment"])
        data[f"psd_{v}"] = ("frequency", S, {"long_name": f"PSD of {v}", "units": f"({UNITS[v][1]})^2 * time"})
        lo, hi, fpk = spectra.band_edges(f, S, f_split=sc["f_split"], rel_threshold=sc["rel_threshold"])
        peaks = spectra.peaks_near_zero(f, S, f_split=sc["f_split"], prominence_decades=sc["prominence_decades"],
                                        floor_rel=sc["floor_rel"])
        out_attrs.update({f"{v}_band_low": lo, f"{v}_band_high": hi, f"{v}_band_peak": fpk,
                          f"{v}_n_peaks_near_zero": int(peaks.size),
                          f"{v}_lowest_peak": float(peaks[0]) if peaks.size else float("nan")})
        for tag, rec, dt in (("coarse", coarse, cfg["dt"]), ("fine", fine, cfg["check_dt"])):
            fc, Sc = spectra.psd(rec[v].values, dt, segment=sc["check_segment"])
            lo_c, hi_c, _ = spectra.band_edges(fc, Sc, f_split=sc["f_split"], rel_threshold=sc["rel_threshold"])
            out_attrs.update({f"{v}_check_{tag}_band_low": lo_c, f"{v}_check_{tag}_band_high": hi_c})
    ds = xr.Dataset(data, coords={"frequency": ("frequency", f, {"units": "cycles/time"}),
                                  "angular_frequency": ("frequency", 2 * np.pi * f, {"units": "rad/time"})})
    ds.attrs.update(model.state_attrs(params, y0))
    ds.attrs.update(attrs)
    ds.attrs.update(out_attrs)
    ds.attrs.update(
        scene=scene, backend="heyoka", method="taylor_adaptive", tol=cfg["tol"],
        energy_max_rel_drift=max(run.attrs["energy_max_rel_drift"], attrs["pre_run_energy_max_rel_drift"]),
        record_start=t0, record_duration=cfg["duration"], sample_dt=cfg["dt"], check_dt=cfg["check_dt"],
        check_duration=cfg["check_duration"], psd_method="scipy.signal.welch", psd_window="hann",
        psd_segment=sc["segment"], psd_check_segment=sc["check_segment"], psd_overlap="50%",
        psd_detrend="constant (mean removed per segment)", frequency_units="cycles per unit time",
        band_rule=f"f > {sc['f_split']}: PSD >= {sc['rel_threshold']} x max PSD above f_split",
        peak_rule=f"0 < f < {sc['f_split']}: local maxima of log10 PSD with prominence >= {sc['prominence_decades']}"
        f" and PSD >= {sc['floor_rel']} x max PSD",
        steps=run.attrs["steps"], wall_time_s=time.perf_counter() - start,
    )
    ds.attrs.update(provenance_attrs())
    log.info("%s: Omega band [%.4g, %.4g], %d peaks near zero", scene, out_attrs["Omega_band_low"],
             out_attrs["Omega_band_high"], out_attrs["Omega_n_peaks_near_zero"])
    return ds


#: Scene name -> function computing its dataset.
SCENES = {"fig2": fig2, "fig3": trajectory, "fig7": trajectory, "fig8": trajectory,
          "fig9_ref": poincare_scene, "fig9_highE": poincare_scene, "fig9_eps001": poincare_scene,
          "psd_eps01": spectrum_scene, "psd_eps001": spectrum_scene,
          "lyap_spectrum": chaos.spectrum, "lyap_protocol": chaos.protocol, "lyap_energy": chaos.energy_sweep,
          "lyap_feasibility": chaos.feasibility}


def attractor_scaling(ref_nc, high_nc) -> xr.Dataset:
    """C17: the P_pi/2 iterates at a higher energy label, divided by c = sqrt(label ratio),
    against those of the reference label (see poincare.scaled_set_distance)."""
    from .io import read_dataset

    ref, high = read_dataset(ref_nc), read_dataset(high_nc)
    c = float(np.sqrt(high.attrs["energy_label"] / ref.attrs["energy_label"]))
    pts = lambda ds: np.c_[ds.ppi2_u, ds.ppi2_Omega, ds.ppi2_omega]  # noqa: E731
    d = poincare.scaled_set_distance(pts(ref), ref.ppi2_class.values, pts(high), high.ppi2_class.values, c)
    ds = xr.Dataset()
    ds.attrs.update({f"distance_{k}": v for k, v in d.items()})
    ds.attrs.update(
        scale_factor_c=c, label_ref=ref.attrs["energy_label"], label_high=high.attrs["energy_label"],
        rotation_number_ref=ref.attrs["rotation_number"], rotation_number_high=high.attrs["rotation_number"],
        n_loops_ref=ref.attrs["n_loops"], n_loops_high=high.attrs["n_loops"],
        method="nearest same-class P_pi/2 iterate of the reference label, distances over the reference "
        "attractor's RMS size; high-label velocities divided by c (scaled) or not (unscaled)",
        sources=f"{Path(ref_nc).name}, {Path(high_nc).name}",
    )
    ds.attrs.update(provenance_attrs())
    log.info("attractor scaling: median distance %.3g scaled, %.3g unscaled (c = %.4g)",
             d["scaled_median"], d["unscaled_median"], c)
    return ds


def audit_scene(cfg: dict, scene: str = "audit") -> xr.Dataset:
    """D1-D6: the printed model against the derivation (sleighsim.audit.model_as_printed)."""
    from .audit import model_as_printed

    params = model.Params.from_config(cfg["params"])
    ds = model_as_printed(params, cfg["y0"], sample_grid(0.0, cfg["t_end"], cfg["dt"]), cfg["tol"])
    ds.attrs.update(scene=scene, energy_label=float(model.energy_label(cfg["y0"], params)))
    log.info("%s: done in %.3g s; printed udot changes E by up to %.3g, derived by %.2g", scene,
             ds.attrs["wall_time_s"], ds.attrs["printed_max_abs_rel_change"], ds.attrs["derived_max_abs_rel_change"])
    return ds


SCENES["audit"] = audit_scene


def hardcases_scene(cfg: dict, scene: str = "hardcases") -> xr.Dataset:
    """Where the numerics get difficult (sleighsim.hardcases.run)."""
    from . import hardcases

    ds = hardcases.run(cfg)
    ds.attrs["scene"] = scene
    return ds


SCENES["hardcases"] = hardcases_scene
SCENES.update(fig4=ts.fig4, fig5=ts.fig5, fig6=ts.fig6, pert_audit=ts.pert_audit, transients=ts.transients)
