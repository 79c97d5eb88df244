"""What the steady state is (issue 39 item 4): do orbits started near a point of the main torus return
to it, stay on neighbouring tori, or leave?

The settled point y* (the pre-run from y0 at the energy label, in double at ``tol``, judged by the
transient rule) is integrated from there in double-double (sleighsim.engine.ddtaylor, tolerance
``tol_dd``: it follows the exact orbit where G x rounding << 1, about 5e-17 per cycle on this torus):
the reference over T_reference, and perturbed starts y* + d over T, d of relative size a (each amplitude
of ``amplitudes``, times max |(u, Omega, omega)| of y*) in ``directions`` seeded random directions
projected onto the tangent plane of the energy level, then put on the level exactly by rescaling the
velocities (the time-scaling symmetry). Each orbit is sampled every dt; its spikes are found by the
transient rule on Omega (``spike_factor``) and refined to the peak of |Omega| on the delta = 0 section
(crossings from the samples' Taylor jets, one per fast turn; sleighsim.analysis.torus.spike_peaks);
its spike section is (delta mod 2 pi; u, Omega, omega) at the refined spike times, the state taken on
the delta = 0 section (interpolated to the spike time), so that on a torus it is one point (the
section's slow phase fixed by the peak) whatever the fast phase at the spike: a fast-phase-dependent
state would need the reference to cover every fast phase, which a near-resonant torus does not do in
any affordable horizon. The gather fits the
reference's spike-section curve, measures every perturbed orbit's distance to it and its period
difference, and classifies it (sleighsim.analysis.torus.classify). Chunk jobs hold whole orbits.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.analysis import torus
from sleighsim.engine import ddtaylor
from sleighsim.engine.ddtaylor import DDFlow
from sleighsim.engine.transient import settle, spike_times
from sleighsim.io.netcdf import read_dataset
from sleighsim.model.equations import energy
from sleighsim.model.params import Params
from sleighsim.model.symmetries import energy_label, state_at_label
from sleighsim.scenes import memory
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.common import nan_padded
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")
TWO_PI = 2.0 * math.pi
SPIKE_VARIABLES = ("spike_time", "spike_phase", "spike_u", "spike_Omega", "spike_omega")


def settled_point(cfg: dict) -> tuple[Params, np.ndarray, dict]:
    """(params, y*, the pre-run's attributes): y0 at the energy label settled in double over t_transient."""
    params = Params.from_config(cfg["params"])
    y0 = state_at_label(cfg["y0"], params, cfg["energy_label"])
    y, pre = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=cfg["tol"], label="torus", progress=1)
    return params, np.asarray(y, float), pre


def energy_gradient(y, params: Params, h: float = 1e-7) -> np.ndarray:
    """dE/dy at y by central differences (step h; only its direction is used)."""
    e = np.eye(4) * h
    return np.array([(energy(y + e[i], params) - energy(y - e[i], params)) / (2 * h) for i in range(4)])


#: Written into the torus_stability dataset (attribute perturbation_rule).
PERTURBED_START_RULE = (
    "y + d on y's energy level: z standard normal (generator seeded by (seed, direction)), projected onto the "
    "level's tangent plane, scaled to amplitude x max |(u, Omega, omega)| of y, then the velocities rescaled "
    "onto the level (second order in d)."
)


def perturbed_start(y, params: Params, amplitude: float, direction: int, seed: int) -> np.ndarray:
    """Applies :data:`PERTURBED_START_RULE`, the rule as the datasets record it (just above)."""
    z = np.random.default_rng([seed, direction]).standard_normal(4)
    g = energy_gradient(y, params)
    z -= (z @ g) / (g @ g) * g
    d = amplitude * np.abs(y[:3]).max() * z / np.linalg.norm(z)
    return state_at_label(y + d, params, float(energy_label(y, params)))


def orbits(cfg: dict) -> list[tuple[float, int]]:
    """(amplitude, direction) of every orbit: the reference (0, -1) first, then each amplitude's directions."""
    return [(0.0, -1)] + [(float(a), k) for a in cfg["amplitudes"] for k in range(cfg["directions"])]


def _horner(coef, tau):
    """sum_k coef[..., k] tau^k, vectorised over the leading axes."""
    out = np.zeros(np.shape(tau))
    for k in range(coef.shape[-1] - 1, -1, -1):
        out = out * tau + coef[..., k]
    return out


def jets_at(flow: DDFlow, hi, lo, rows) -> np.ndarray:
    """Taylor coefficients (n, 4, order + 1) of the orbit at the sample rows, in double (order 0: the
    samples' hi + lo, delta as sampled)."""
    J = np.array([flow.jet((hi[i], lo[i]))[0] for i in rows]).reshape(len(rows), 4, flow.order + 1)
    J[:, :, 0] = hi[rows] + lo[rows]
    return J


def section(flow: DDFlow, hi, lo, grid) -> tuple[np.ndarray, np.ndarray]:
    """Crossings of delta = 0 (mod 2 pi): times (n,) and states (n, 3) (u, Omega, omega), each from the
    Taylor jet of the sample nearest it (|tau| <= dt / 2, well inside the series' radius), solved by
    Newton's method in double."""
    d = np.unwrap(hi[:, 3])
    turn = np.floor(d / TWO_PI)
    k = np.flatnonzero(np.diff(turn) != 0)
    target = np.maximum(turn[k], turn[k + 1]) * TWO_PI
    rows = np.where(np.abs(d[k] - target) <= np.abs(d[k + 1] - target), k, k + 1)
    J = jets_at(flow, hi, lo, rows)
    J[:, 3, 0] = (d[rows] - target) + lo[rows, 3]
    tau = -J[:, 3, 0] / J[:, 3, 1]
    for _ in range(8):
        dcoef = J[:, 3, 1:] * np.arange(1, J.shape[2])
        tau = tau - _horner(J[:, 3], tau) / _horner(dcoef, tau)
    return grid[rows] + tau, np.stack([_horner(J[:, c], tau) for c in range(3)], axis=1)


def fast_phase(flow: DDFlow, hi, lo, grid, t_spike) -> np.ndarray:
    """delta mod 2 pi at the times t_spike, from the jets of the nearest samples."""
    rows = np.clip(np.rint((t_spike - grid[0]) / (grid[1] - grid[0])).astype(int), 0, grid.size - 1)
    J = jets_at(flow, hi, lo, rows)
    return np.mod(_horner(J[:, 3], t_spike - grid[rows]), TWO_PI) if rows.size else np.empty(0)


def orbit(flow: DDFlow, y0, T: float, cfg: dict, label: str) -> dict:
    """One orbit from y0 over T in double-double, sampled every dt: spike times (coarse by the transient
    rule, refined on the delta = 0 section), its spike section (the section's state interpolated to the
    spike time, and the fast phase delta mod 2 pi there), the energy drift over the samples (every
    1000th, at 200 bits) and the wall time."""
    start = time.perf_counter()
    grid = np.arange(0.0, T + 0.5 * cfg["dt"], cfg["dt"])
    hi, lo = flow.propagate_grid(y0, grid)
    steps = flow.steps
    coarse = spike_times(grid, hi[:, 1], factor=cfg["spike_factor"])
    t_sec, x_sec = section(flow, hi, lo, grid)
    spikes, x = torus.spike_peaks(t_sec, x_sec, coarse, cfg["spike_half_width"])
    phase = fast_phase(flow, hi, lo, grid, spikes)
    sub = np.r_[0:grid.size:1000, grid.size - 1]
    drift = ddtaylor.energy_drift(flow.params, hi[sub], lo[sub])
    out = {"spike_time": spikes, "spike_phase": phase, "spike_u": x[:, 0], "spike_Omega": x[:, 1],
           "spike_omega": x[:, 2], "steps": steps, "energy_max_rel_drift": drift,
           "wall_time_s": time.perf_counter() - start}
    log.info("%s: %d spikes over %g, mean interval %.6g, %d steps, drift %.2g, %.1f s", label, spikes.size, T,
             torus.mean_interval(spikes)[0], steps, drift, out["wall_time_s"])
    return out


def chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
    """Orbits index, index + n_chunks, ... of :func:`orbits` (orbit 0, the reference, over T_reference;
    the others over T), each from the settled point (the pre-run repeated by every chunk: it is
    deterministic), with their spike sections NaN-padded along ``spike``."""
    params, y, pre = settled_point(cfg)
    flow = DDFlow(params, tol=cfg["tol_dd"])
    mine = list(range(len(orbits(cfg))))[index::cfg["n_chunks"]]
    runs, starts = [], []
    for i in mine:
        a, k = orbits(cfg)[i]
        y0 = y if i == 0 else perturbed_start(y, params, a, k, cfg["seed"])
        T = cfg["T_reference"] if i == 0 else cfg["T"]
        runs.append(orbit(flow, y0, T, cfg, f"{scene}[a={a:g}, direction {k}]"))
        starts.append(y0)
    ds = xr.Dataset({v: (("orbit", "spike"), nan_padded([r[v] for r in runs], 1)) for v in SPIKE_VARIABLES},
                    coords={"orbit": mine})
    for v in ("steps", "energy_max_rel_drift", "wall_time_s"):
        ds[v] = ("orbit", [r[v] for r in runs])
    ds["y0"] = (("orbit", "component"), np.array(starts))
    ds["start_distance"] = ("orbit", ddtaylor.separation((np.tile(y, (len(mine), 1)), np.zeros((len(mine), 4))),
                                                         (np.array(starts), np.zeros((len(mine), 4)))))
    ds.attrs.update(chunk=index, n_chunks=cfg["n_chunks"], settled_state=y, **pre)
    return ds


def _judged(ds: xr.Dataset, cfg: dict) -> dict:
    """Per orbit: spike count, mean interval +- standard error, the late mean interval's difference from the
    reference's mean (:func:`sleighsim.analysis.torus.late_interval`), distance of each spike-section point to
    the reference's curve (relative to the reference's max |(u, Omega, omega)|), its early and late
    medians, and the class with its reason; and the reference curve's order and relative floor."""
    x = np.stack([ds[v].values for v in ("spike_u", "spike_Omega", "spike_omega")], axis=-1)
    phase, ok = ds.spike_phase.values, np.isfinite(ds.spike_time.values)
    scale = float(np.abs(ds.y0.values[0, :3]).max())
    curve = torus.section_curve(phase[0, ok[0]], x[0, ok[0]], cfg["curve_order"])
    floor = curve["floor"] / scale
    T_ref, err_ref = torus.mean_interval(ds.spike_time.values[0, ok[0]])
    rows = {k: [] for k in ("n_spikes", "mean_interval", "mean_interval_err", "distance_early", "distance_late",
                            "period_difference", "period_difference_err", "torus_class", "class_reason")}
    D = np.full(phase.shape, np.nan)
    for i in range(ds.sizes["orbit"]):
        n = int(ok[i].sum())
        D[i, ok[i]] = torus.curve_distance(curve, phase[i, ok[i]], x[i, ok[i]]) / scale if n else []
        T, err = torus.mean_interval(ds.spike_time.values[i, ok[i]])
        T_late, err_late = torus.late_interval(ds.spike_time.values[i, ok[i]])
        dT, dT_err = T_late - T_ref, math.hypot(err_late, err_ref)
        klass, why = ("reference", "the reference orbit") if i == 0 else torus.classify(
            D[i, ok[i]], n, dT, dT_err, floor, min_spikes=cfg["min_spikes"], leave=cfg["leave_distance"],
            change=cfg["change_factor"], same=cfg["same_factor"], sigma=cfg["sigma"],
            period_floor=cfg["period_rtol"] * T_ref)
        early, late = torus.quarters(D[i, ok[i]]) if n else (math.nan, math.nan)
        for k, v in zip(rows, (n, T, err, early, late, dT, dT_err, klass, why)):
            rows[k].append(v)
    return {"rows": rows, "D": D, "order": curve["order"], "floor": floor, "scale": scale, "T_ref": T_ref}


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """Every orbit's spike section (chunks joined in orbit order), its distance to the reference's
    spike-section curve, its period difference and its class (attribute classification_rule)."""
    parts = [read_dataset(p) for p in paths]
    width = max(d.sizes["spike"] for d in parts)
    ds = xr.concat([d.pad(spike=(0, width - d.sizes["spike"])) for d in parts], dim="orbit",
                   combine_attrs="drop_conflicts").sortby("orbit")
    expected = orbits(cfg)
    if ds.orbit.values.tolist() != list(range(len(expected))):
        raise ValueError(f"chunks hold orbits {ds.orbit.values.tolist()}, expected 0 ... {len(expected) - 1}")
    j = _judged(ds, cfg)
    ds = ds.assign_coords(amplitude=("orbit", [a for a, _ in expected]), direction=("orbit", [k for _, k in expected]))
    for k, v in j["rows"].items():
        ds[k] = ("orbit", np.array(v, dtype=object) if k in ("torus_class", "class_reason") else np.array(v, float))
    ds["curve_distance"] = (("orbit", "spike"), j["D"])
    classes = ds.torus_class.values[1:]
    ds.attrs.pop("chunk", None)
    ds.attrs.update(
        Params.from_config(cfg["params"]).attrs(), scene=scene, energy_label=cfg["energy_label"], tol=cfg["tol"],
        tol_dd=cfg["tol_dd"], integrator="double-double Taylor (sleighsim.engine.ddtaylor) from the settled point; "
        "the pre-run heyoka in double", T=cfg["T"], T_reference=cfg["T_reference"], dt=cfg["dt"],
        t_transient=cfg["t_transient"], seed=cfg["seed"], spike_factor=cfg["spike_factor"],
        spike_half_width=cfg["spike_half_width"], curve_order=j["order"], curve_floor=j["floor"],
        velocity_scale=j["scale"], reference_interval=j["T_ref"], min_spikes=cfg["min_spikes"],
        leave_distance=cfg["leave_distance"], change_factor=cfg["change_factor"], same_factor=cfg["same_factor"],
        sigma=cfg["sigma"], period_rtol=cfg["period_rtol"], classification_rule=torus.CLASSIFY_RULE,
        perturbation_rule=PERTURBED_START_RULE, spike_rule=torus.SPIKE_PEAKS_RULE, curve_rule=torus.SECTION_CURVE_RULE,
        energy_max_rel_drift=float(np.nanmax(ds.energy_max_rel_drift.values)),
        wall_time_s=float(ds.wall_time_s.values.sum()), n_perturbed=int(classes.size),
        **{f"n_{c.replace(' ', '_')}": int(np.sum(classes == c)) for c in torus.CLASSES},
        summary=_summary(ds))
    return ds


def _summary(ds: xr.Dataset) -> str:
    """One line per amplitude: the classes of its directions, their mean periods and late distances."""
    lines = []
    for a in np.unique(ds.amplitude.values[1:]):
        sel = np.flatnonzero(ds.amplitude.values == a)
        lines.append(f"a = {a:.0e}: " + "; ".join(
            f"{ds.torus_class.values[i]} (period {ds.mean_interval.values[i]:.6g}, D late "
            f"{ds.distance_late.values[i]:.2g})" for i in sel))
    return f"reference period {ds.mean_interval.values[0]:.7g}. " + ". ".join(lines)


def _orbit_work(cfg: dict) -> list[float]:
    """Time units each orbit integrates in double-double: T_reference, then T per perturbed orbit."""
    return [cfg["T_reference"]] + [cfg["T"]] * (len(orbits(cfg)) - 1)


def chunk_work(cfg: dict) -> list[float]:
    """Work of each chunk job: its orbits (:func:`chunk`) plus the double pre-run (t_transient)."""
    w, n = _orbit_work(cfg), cfg["n_chunks"]
    return [cfg["t_transient"] + sum(w[k::n]) for k in range(n)]


def _checks(w: str, cfg: dict) -> None:
    n = len(orbits(cfg))
    if cfg["n_chunks"] > n:
        raise ConfigError(f"{w}.n_chunks = {cfg['n_chunks']} must lie in [1, {n}] (the orbits: the reference and "
                          "len(amplitudes) x directions)")
    if cfg["T_reference"] < cfg["T"]:
        raise ConfigError(f"{w}.T_reference = {cfg['T_reference']} must be at least T = {cfg['T']}")


#: The variables only this kind writes: name -> (long_name, kind of quantity) (``sleighsim.io.cf``).
VOCABULARY = {
    "orbit": ("index of the orbit (0: the reference from the settled point, then the perturbed starts)", "1"),
    "direction": ("index of the perturbation's seeded random direction (-1: the reference)", "1"),
    "start_distance": ("relative distance of the start from the settled point (sleighsim.engine.ddtaylor.separation)",
                       "1"),
    "spike_phase": ("delta mod 2 pi at each spike, the fast phase of the spike section", "angle"),
    "spike_u": ("u at each spike", "speed"),
    "spike_Omega": ("Omega at each spike", "angular_velocity"),
    "spike_omega": ("omega at each spike", "angular_velocity"),
    "mean_interval": ("mean interval between the orbit's refined spikes", "time"),
    "mean_interval_err": ("standard error of the mean spike interval, std / sqrt(n) over the intervals", "time"),
    "curve_distance": ("distance of each spike-section point to the reference's spike-section curve, relative to the "
                       "reference's max |(u, Omega, omega)|", "1"),
    "distance_early": ("median distance to the reference's spike-section curve over the first quarter of spikes", "1"),
    "distance_late": ("median distance to the reference's spike-section curve over the last quarter of spikes", "1"),
    "period_difference": ("mean spike interval over the second half of the spikes minus the reference's mean", "time"),
    "period_difference_err": ("standard error of the period difference (both orbits' combined)", "time"),
    "torus_class": ("class of the orbit: same torus, neighbouring torus or leaves (reference: the reference)", "text"),
    "class_reason": ("reason for the orbit's class", "text"),
}


TORUS_STABILITY = SceneKind(
    name="torus_stability",
    title=("what the steady state is: orbits started near the main torus in double-double, each on its torus, "
           "a neighbouring one, or gone (issue 39 item 4, claim C06)"),
    vocabulary=VOCABULARY,
    chunk=chunk, gather=gather, pre_run="t_transient",
    records=lambda c: [*memory.pre_run(c, "t_transient"), memory.span(c, "T_reference", "dt", 8)],
    work=lambda cfg: sum(chunk_work(cfg)), chunk_work=chunk_work,
    modelled=lambda leaf: leaf in ("T", "T_reference", "t_transient", "amplitudes", "directions", "n_chunks"),
    checks=_checks)
