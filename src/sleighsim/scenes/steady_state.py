"""Steady-state scenes after a checked transient: Poincare maps and return times (F9, F12),
power spectra (F13, F14), and the attractor under the time-scaling law (C17)."""

from __future__ import annotations

import logging
import time
from pathlib import Path

import numpy as np
import xarray as xr

from sleighsim.analysis import spectra
from sleighsim.engine import poincare
from sleighsim.engine.integrate import integrate, sample_grid
from sleighsim.engine.transient import settle
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset
from sleighsim.io.vocabulary import STATE_KINDS
from sleighsim.model import equations
from sleighsim.model.attrs import state_attrs
from sleighsim.model.params import Params
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.common import initial_state, steady_arithmetic
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def _map_variables(c: dict, is2pi, rt, stride: int, loops: dict) -> dict:
    """The Poincare maps' variables: the P_2pi iterates and their times, the return times, and the
    thinned P_pi/2 iterates with their class and loop cluster."""
    kind, vel = STATE_KINDS, ("u", "Omega", "omega")
    data = {f"p2pi_{v}": ("n2pi", c[v][is2pi], cf.attrs(f"{v} at the P_2pi iterates (delta = 0 mod 2 pi)", kind[v]))
            for v in vel}
    data["p2pi_time"] = ("n2pi", c["time"][is2pi], cf.attrs("time of the P_2pi iterates", "time"))
    data["return_time"] = ("nret", rt, cf.attrs("t_{n+1} - t_n of P_2pi", "time"))
    data.update({f"ppi2_{v}": ("npi2", c[v][::stride], cf.attrs(f"{v} at the P_pi/2 iterates (delta = k pi/2)",
                                                                  kind[v])) for v in vel})
    data["ppi2_class"] = ("npi2", (c["k"][::stride] % 4).astype(np.int8), cf.attrs("k mod 4, delta = k pi/2"))
    data["ppi2_cluster"] = ("npi2", loops["labels"].astype(np.int32),
                            cf.attrs("k-NN graph component in the (u, Omega, omega) projection"))
    return data


def _return_times(rt, t1: float, tie_tol: float) -> dict:
    """Statistics of the P_2pi return times ``rt`` (NaN without any), their resolution at the map's
    end t1 and the adjacent pairs closer than ``tie_tol``."""
    return {
        "return_time_min": float(rt.min()) if rt.size else float("nan"),
        "return_time_max": float(rt.max()) if rt.size else float("nan"),
        "return_time_mean": float(rt.mean()) if rt.size else float("nan"),
        "return_time_min_pairwise_difference": poincare.min_pairwise_difference(rt),
        "return_time_resolution": float(2 * np.spacing(t1)),
        "return_time_tie_tol": tie_tol,
        "return_time_n_adjacent_pairs_within_tie_tol": int(np.sum(np.diff(np.sort(rt)) < tie_tol)),
    }


def _settled(cfg: dict, scene: str) -> dict:
    """The scene's parameters, start state y0 and the state settled from it (the checked pre-run in
    double, deterministic) with the pre-run's attributes."""
    params = Params.from_config(cfg["params"])
    y0 = initial_state(cfg, params)
    y_settled, attrs = settle(params, y0, cfg["t_settle"], **cfg["transient"], tol=cfg["tol"], label=scene)
    return {"params": params, "y0": y0, "y": y_settled, "attrs": attrs}


def _attractor_grid(cfg: dict) -> np.ndarray:
    """The attractor stretch's sample times: from t_settle over attractor_span every attractor_dt."""
    return sample_grid(cfg["t_settle"], cfg["t_settle"] + cfg["attractor_span"], cfg["attractor_dt"])


def _one_orbit(cfg: dict, s: dict, scene: str) -> tuple[dict | None, np.ndarray | None]:
    """In double-double, the maps' crossings over t_map and the attractor stretch's (u, Omega, omega) from one
    integration (the stretch a second lane of the maps' DDBatch: ``poincare.dd_crossings`` with samples, bit for
    bit the runs of their own at about the price of one); (None, None) in heyoka's arithmetics (two runs)."""
    arith = steady_arithmetic(cfg)
    if Precision.parse(arith["precision"]) is not Precision.DOUBLE_DOUBLE:
        return None, None
    t0 = cfg["t_settle"]
    c = poincare.dd_crossings(s["params"], s["y"], t0, t0 + cfg["t_map"], tol=arith["tol"], scene=scene,
                              samples=_attractor_grid(cfg))
    return c, c.pop("samples")[:, :3]


def _maps(cfg: dict, s: dict, scene: str, c: dict | None = None) -> xr.Dataset:
    """P_2pi and P_pi/2 iterates over t_map from the settled state ``s`` (:func:`_settled`) in the
    block's steady-state arithmetic, return times, rotation number and loop count (the crossings ``c`` when
    given, as ``poincare.crossings`` returns them)."""
    params, y0, y_settled = s["params"], s["y0"], s["y"]
    arith = steady_arithmetic(cfg)
    t0, t1 = cfg["t_settle"], cfg["t_settle"] + cfg["t_map"]
    c = poincare.crossings(params, y_settled, t0, t1, **arith, scene=scene) if c is None else c
    pts = np.c_[c["u"], c["Omega"], c["omega"]]
    is2pi = c["k"] % 4 == 0
    rt = np.diff(c["time"][is2pi])
    stride = max(1, int(np.ceil(len(pts) / cfg["max_stored_pi2"])))
    stride += 1 - stride % 2  # odd, so thinning keeps all four classes k mod 4
    loops = poincare.count_loops(pts[::stride], c["k"][::stride] % 4, cfg["loop_knn"])
    rot = poincare.rotation_number(pts[is2pi])
    E = equations.energy(np.c_[pts, c["k"] * (np.pi / 2)], params)
    E0 = float(equations.energy(y0, params))
    ds = xr.Dataset(_map_variables(c, is2pi, rt, stride, loops))
    ds.attrs.update(state_attrs(params, y0))
    ds.attrs.update(s["attrs"])
    ds.attrs.update(rot)
    ds.attrs.update(
        scene=scene, backend=c["backend"], method=c["method"], **arith,
        transient_tol=cfg["tol"], transient_precision=Precision.DOUBLE, settled_state=np.asarray(y_settled, float),
        energy_max_rel_drift=float(np.max(np.abs(E / E0 - 1))) if E.size else float("nan"),
        t_map_start=t0, t_map_end=t1, attractor_dt=cfg["attractor_dt"], n_p2pi=int(is2pi.sum()), n_ppi2=int(len(pts)),
        ppi2_stride=stride,
        max_crossing_residual=float(c["residual"].max()) if len(pts) else float("nan"),
        **_return_times(rt, t1, cfg["return_time_tie_tol"]),
        p2pi_curve_thickness=poincare.curve_thickness(pts[is2pi]) if is2pi.sum() > 10 else float("nan"),
        p2pi_recurrence=poincare.recurrence(pts[is2pi]),
        p2pi_recurrence_rule="smallest over q = 1..50 of the median |x_(n+q) - x_n| of the P_2pi iterates, in units of "
                             "their RMS size: about 0 for a periodic orbit",
        n_loops=loops["n_loops"], n_components_projected=loops["n_components_projected"],
        loops_per_class=np.array([loops["loops_per_class"].get(k, 0) for k in range(4)], dtype=np.int32),
        loop_rule=f"per class k mod 4: connected components (>= 1% of the class) of the symmetric "
        f"{cfg['loop_knn']}-nearest-neighbour graph of standardised (u, Omega, omega); n_loops sums over classes",
        steps=int(c["steps"]), compile_time_s=c["compile_time_s"],
    )
    log.info("%s: %d P_2pi, %d P_pi/2 iterates, %d loops, rotation number %.6g, max residual %.2g", scene,
             is2pi.sum(), len(pts), loops["n_loops"], rot["rotation_number"], ds.attrs["max_crossing_residual"])
    return ds


def _attractor(cfg: dict, s: dict, scene: str, x: np.ndarray | None = None) -> xr.Dataset:
    """A stretch of the attractor (attractor_span, sampled every attractor_dt) from the settled state
    ``s`` (:func:`_settled`) in the block's steady-state arithmetic, and its flatness (its samples of (u, Omega,
    omega) ``x`` when given)."""
    if x is None:
        att = integrate(s["params"], s["y"], _attractor_grid(cfg), **steady_arithmetic(cfg),
                        scene=f"{scene}.attractor", progress=1)
        x = np.c_[att.u.values, att.Omega.values, att.omega.values]
    ds = xr.Dataset({f"attractor_{v}": ("natt", x[:, i],
                                        cf.attrs(f"{v} along a sampled stretch of the attractor", STATE_KINDS[v]))
                     for i, v in enumerate(("u", "Omega", "omega"))})
    ds.attrs.update(
        attractor_flatness=poincare.flatness(x),
        attractor_flatness_rule="smallest over largest singular value of the centred (u, Omega, omega) samples")
    return ds


def _with_attractor(maps: xr.Dataset, att: xr.Dataset, wall_s: float) -> xr.Dataset:
    """The scene's dataset: the maps' variables and attributes, the attractor stretch's beside them."""
    ds = maps.assign(att.data_vars)
    ds.attrs.update(att.attrs, wall_time_s=wall_s)
    return ds


def poincare_maps(cfg: dict, scene: str = "") -> xr.Dataset:
    """P_2pi and P_pi/2 iterates after a checked transient, return times, rotation
    number, loop count, and a sampled stretch of the attractor (F9, F12)."""
    start = time.perf_counter()
    s = _settled(cfg, scene)
    c, x = _one_orbit(cfg, s, scene)
    maps, att = _maps(cfg, s, scene, c), _attractor(cfg, s, scene, x)
    return _with_attractor(maps, att, time.perf_counter() - start)


def _precision_jobs(cfg: dict) -> int:
    """Jobs of the scene in a finer precision: ``precision_chunks`` (1 when unset), at most 2."""
    return min(cfg.get("precision_chunks", 1), 2)


def poincare_chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
    """Part ``index`` of the scene in a finer precision run as two jobs: 0 the maps, 1 the attractor
    stretch (two integrations from the settled state that share nothing but it); each job settles the
    same state (the pre-run in double, deterministic). :func:`poincare_gather` makes the dataset."""
    start = time.perf_counter()
    s = _settled(cfg, scene)
    ds = (_maps, _attractor)[index](cfg, s, scene)
    ds.attrs.update(chunk=index, settled_state=np.asarray(s["y"], float), wall_time_s=time.perf_counter() - start)
    return ds


def poincare_gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """The scene's dataset (as :func:`poincare_maps` makes it) from its two parts, wall times summed.
    Raises when the parts did not start from one settled state."""
    maps, att = sorted((read_dataset(p) for p in paths), key=lambda d: int(d.attrs["chunk"]))
    if not np.array_equal(maps.attrs["settled_state"], att.attrs["settled_state"]):
        raise ValueError(f"{scene}: the parts start from different settled states {maps.attrs['settled_state']}, "
                         f"{att.attrs['settled_state']}")
    wall = maps.attrs["wall_time_s"] + att.attrs["wall_time_s"]
    for d in (maps, att):
        d.attrs.pop("chunk")
    att.attrs = {k: v for k, v in att.attrs.items() if k.startswith("attractor_flatness")}
    return _with_attractor(maps, att, wall)


POINCARE = SceneKind(
    name="poincare",
    title="Poincare maps P_2pi and P_pi/2, return times and loops of a steady state",
    compute=poincare_maps, chunk=poincare_chunk, gather=poincare_gather, chunk_count=_precision_jobs,
    observables=("rotation_number", "return_time_mean", "n_loops"),
    records=lambda c: [*memory.pre_run(c, "t_settle"), memory.span(c, "attractor_span", "attractor_dt")],
    pre_run="t_settle")


def psd(cfg: dict, scene: str = "") -> xr.Dataset:
    """Welch PSD of u and Omega on the attractor, band edges and near-zero peaks (F13, F14);
    band edges are recomputed at a finer sampling to show they do not move."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    y0 = initial_state(cfg, params)
    y_settled, attrs = settle(params, y0, cfg["t_settle"], **cfg["transient"], tol=cfg["tol"], label=scene)
    arith = steady_arithmetic(cfg)
    t0 = cfg["t_settle"]
    sc = cfg["welch"]
    run = integrate(params, y_settled, sample_grid(t0, t0 + cfg["duration"], cfg["dt"]), **arith, scene=scene)
    fine = integrate(params, y_settled, sample_grid(t0, t0 + cfg["check_duration"], cfg["check_dt"]),
                     **arith, scene=f"{scene}.check", progress=4)
    coarse = run.sel(time=slice(t0, t0 + cfg["check_duration"]))
    data, out_attrs = {}, {}
    for v in ("u", "Omega"):
        f, S = spectra.psd(run[v].values, cfg["dt"], segment=sc["segment"])
        data[f"psd_{v}"] = ("frequency", S, cf.attrs(f"PSD of {v}", f"psd_{STATE_KINDS[v]}"))
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
    ds = xr.Dataset(data, coords={"frequency": ("frequency", f, cf.attrs("frequency", "frequency")),
                                  "angular_frequency": ("frequency", 2 * np.pi * f,
                                                        cf.attrs("angular frequency", "angular_frequency"))})
    ds.attrs.update(state_attrs(params, y0))
    ds.attrs.update(attrs)
    ds.attrs.update(out_attrs)
    ds.attrs.update(
        scene=scene, backend=run.attrs["backend"], method=run.attrs.get("method", ""), **arith,
        transient_tol=cfg["tol"], transient_precision=Precision.DOUBLE, settled_state=np.asarray(y_settled, float),
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
    log.info("%s: Omega band [%.4g, %.4g], %d peaks near zero", scene, out_attrs["Omega_band_low"],
             out_attrs["Omega_band_high"], out_attrs["Omega_n_peaks_near_zero"])
    return ds


def _psd_checks(w, cfg):
    if cfg["check_duration"] > cfg["duration"]:
        raise ConfigError(f"{w}.check_duration = {cfg['check_duration']} must lie in (0, duration = {cfg['duration']}]")
    for key, span in (("segment", cfg["duration"]), ("check_segment", cfg["check_duration"])):
        if cfg["welch"][key] > span:
            raise ConfigError(f"{w}.welch.{key} = {cfg['welch'][key]} must lie in (0, {span}]")


PSD = SceneKind(
    name="psd",
    title="power spectra of u and Omega on the attractor",
    compute=psd,
    observables=("Omega_band_low", "Omega_band_high", "Omega_band_peak", "u_band_peak", "Omega_n_peaks_near_zero"),
    records=lambda c: [*memory.pre_run(c, "t_settle"), memory.span(c, "duration", "dt"),
                       memory.span(c, "check_duration", "check_dt")],
    checks=_psd_checks, pre_run="t_settle")


def attractor_scaling(cfg: dict, inputs: dict, scene: str = "") -> xr.Dataset:
    """C17: the P_pi/2 iterates of the ``scaled`` input (a higher energy label), divided by
    c = sqrt(label ratio), against those of the ``reference`` input (poincare.scaled_set_distance)."""
    ref_nc, high_nc = inputs["reference"], inputs["scaled"]
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
    log.info("attractor scaling: median distance %.3g scaled, %.3g unscaled (c = %.4g)",
             d["scaled_median"], d["unscaled_median"], c)
    return ds


#: Reads two poincare datasets and integrates nothing: it holds no records.
ATTRACTOR_SCALING = SceneKind(
    name="attractor_scaling",
    title=("the attractor at a higher energy label mapped by the time-scaling law onto the reference one "
           "(claim C17)"),
    compute=attractor_scaling, inputs=("reference", "scaled"),
                              integrates=False, records=lambda c: [])
