"""What the steady state is (issue 39 item 4, issue 52 item 5): is each orbit started near the main torus
on a torus, is it the reference's or another of a family, and how does the family move with the
perturbation's size a?

The settled point y* (the pre-run from y0 at the energy label, in double at ``tol``, judged by the
transient rule) is integrated from there in double-double (sleighsim.engine.ddtaylor, tolerance
``tol_dd``: it follows the exact orbit where G x rounding << 1): the reference over T_reference, and
perturbed starts y* + d over T, d of relative size a (each of ``amplitudes``) in ``directions`` seeded
random directions on the energy level. Each orbit is sampled every dt and cut by the section delta = 0
(mod 2 pi; one crossing per fast turn, from the samples' Taylor jets). Its cycle events are where u
crosses 0 on the section (sleighsim.analysis.torus.crossings): downward mid-cycle (the reversal: the
sleigh stops and starts backwards), upward inside the Omega spike (the flip). The reversal train is
tested for strict periodicity (sleighsim.analysis.torus.classify); the flip's state (Omega, omega) is
the spike point, one point per torus; the gather compares both with the reference's and fits the
family's laws (period and spike-point offset against a). Chunk jobs hold whole orbits.
"""

from __future__ import annotations

import logging
import math
import re
import time

import numpy as np
import xarray as xr

from sleighsim.analysis import torus
from sleighsim.engine import ddtaylor
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.engine.ddsection import solve_on_jets
from sleighsim.engine.ddtaylor import DDFlow
from sleighsim.engine.transient import settle
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
#: The cycle events: (name, column of (u, Omega, omega), level, direction) on the delta = 0 section.
EVENTS = (("reversal", 0, 0.0, -1), ("flip", 0, 0.0, +1))
CYCLE_VARIABLES = ("reversal_time", "reversal_time_err", "reversal_Omega", "reversal_omega", "flip_time",
                   "flip_time_err", "flip_Omega", "flip_omega", "flip_point_err")


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


def jets_at(flow: DDFlow, hi, lo, rows) -> np.ndarray:
    """Taylor coefficients (n, 4, order + 1) of the orbit at the sample rows, in double (order 0: the
    samples' hi + lo, delta as sampled)."""
    J = np.array([flow.jet((hi[i], lo[i]))[0] for i in rows]).reshape(len(rows), 4, flow.order + 1)
    J[:, :, 0] = hi[rows] + lo[rows]
    return J


def section(flow: DDFlow, hi, lo, grid) -> tuple[np.ndarray, np.ndarray]:
    """Crossings of delta = 0 (mod 2 pi): times (n,) and states (n, 3) (u, Omega, omega), each from the
    Taylor jet of the sample nearest it (|tau| <= dt / 2, well inside the series' radius), solved by
    Newton's method in double (``engine.ddsection.solve_on_jets``). Each sample's delta is taken relative to its
    nearest multiple of 2 pi (|r| <= pi, to a few units of 1e-16): an angle unwrapped over the whole record
    would carry the rounding of a running sum of turns (about 1e-8 rad after 1e4 turns, growing with each
    binade), which moved the section states by about 1e-10 and the events by up to 1e-5 time units."""
    r = hi[:, 3] - TWO_PI * np.round(hi[:, 3] / TWO_PI) + lo[:, 3]
    k = np.flatnonzero((np.sign(r[:-1]) != np.sign(r[1:])) & (np.abs(np.diff(r)) < math.pi))
    rows = np.where(np.abs(r[k]) <= np.abs(r[k + 1]), k, k + 1)
    J = jets_at(flow, hi, lo, rows)
    J[:, 3, 0] = r[rows]
    return solve_on_jets(J, grid[rows])


def propagate_orbits(flow: DDFlow, starts, horizons, dt: float) -> list[dict]:
    """Every orbit from starts[i] over horizons[i], sampled every dt in double-double at flow's settings: the
    orbits of one horizon as the lanes of one ``engine.ddbatch.DDBatch`` (each lane bit for bit ``flow``'s
    orbit, the lanes in the CPU's vector units). Per orbit its grid, (hi, lo) samples, steps and CPU seconds
    (its share of its batch's)."""
    out = [None] * len(starts)
    for T in dict.fromkeys(horizons):
        lanes = [i for i, h in enumerate(horizons) if h == T]
        start = time.process_time()
        grid = np.arange(0.0, T + 0.5 * dt, dt)
        batch = DDBatch(flow.params, flow.tol, max_steps=flow.max_steps)
        hi, lo = batch.propagate_grid(np.array([starts[i] for i in lanes], dtype=float), grid)
        share = (time.process_time() - start) / len(lanes)
        for j, i in enumerate(lanes):
            out[i] = {"grid": grid, "hi": hi[j], "lo": lo[j], "steps": int(batch.steps[j]), "cpu_s": share}
    return out


def cycle_events(flow: DDFlow, run: dict, label: str) -> dict:
    """One orbit's cycle events (:data:`EVENTS`, sleighsim.analysis.torus.crossings on the section): the
    reversal and flip trains with their errors and states, the energy drift over the samples (every
    1000th, at 200 bits) and the CPU seconds (integration and analysis)."""
    start = time.process_time()
    hi, lo, grid = run["hi"], run["lo"], run["grid"]
    t_sec, x_sec = section(flow, hi, lo, grid)
    out = {}
    for name, column, level, direction in EVENTS:
        ev = torus.crossings(t_sec, x_sec, column, level, direction)
        out.update({f"{name}_time": ev["times"], f"{name}_time_err": ev["time_err"],
                    f"{name}_Omega": ev["points"][:, 1], f"{name}_omega": ev["points"][:, 2]})
        if name == "flip":
            out["flip_point_err"] = ev["point_err"][:, 1:].max(axis=1) if ev["times"].size else np.empty(0)
    sub = np.r_[0:grid.size:1000, grid.size - 1]
    out.update(steps=run["steps"], energy_max_rel_drift=ddtaylor.energy_drift(flow.params, hi[sub], lo[sub]),
               cpu_s=run["cpu_s"] + time.process_time() - start)
    log.info("%s: %d reversals, %d flips over %g, %d steps, drift %.2g, %.1f CPU-s", label,
             out["reversal_time"].size, out["flip_time"].size, grid[-1], run["steps"], out["energy_max_rel_drift"],
             out["cpu_s"])
    return out


def chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
    """Orbits index, index + n_chunks, ... of :func:`orbits` (orbit 0, the reference, over T_reference;
    the others over T), each from the settled point (the pre-run repeated by every chunk: it is
    deterministic), with their cycle events NaN-padded along ``cycle``."""
    params, y, pre = settled_point(cfg)
    flow = DDFlow(params, tol=cfg["tol_dd"])
    mine = list(range(len(orbits(cfg))))[index::cfg["n_chunks"]]
    todo = [orbits(cfg)[i] for i in mine]
    starts = [y if k < 0 else perturbed_start(y, params, a, k, cfg["seed"]) for a, k in todo]
    horizons = [cfg["T_reference"] if k < 0 else cfg["T"] for _, k in todo]
    runs = [cycle_events(flow, r, f"{scene}[a={a:g}, direction {k}]")
            for r, (a, k) in zip(propagate_orbits(flow, starts, horizons, cfg["dt"]), todo)]
    width = max(1, *(len(r[v]) for r in runs for v in CYCLE_VARIABLES))
    ds = xr.Dataset({v: (("orbit", "cycle"), nan_padded([r[v] for r in runs], width)) for v in CYCLE_VARIABLES},
                    coords={"orbit": mine})
    for v in ("steps", "energy_max_rel_drift"):
        ds[v] = ("orbit", [r[v] for r in runs])
    ds["cpu_s"] = ("orbit", [r["cpu_s"] for r in runs])
    ds["y0"] = (("orbit", "component"), np.array(starts))
    ds["start_distance"] = ("orbit", ddtaylor.separation((np.tile(y, (len(mine), 1)), np.zeros((len(mine), 4))),
                                                         (np.array(starts), np.zeros((len(mine), 4)))))
    ds.attrs.update(chunk=index, n_chunks=cfg["n_chunks"], settled_state=y, **pre)
    return ds


def _median_points(ds: xr.Dataset, name: str, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Per orbit the median of its ``name`` events' (Omega, omega) and its uncertainty relative to scale: the
    larger of the points' median distance from it and (flips) their median interpolation error."""
    P = np.stack([ds[f"{name}_Omega"].values, ds[f"{name}_omega"].values], axis=-1)
    med = np.nanmedian(P, axis=1)
    spread = np.nanmedian(np.linalg.norm(P - med[:, None, :], axis=-1), axis=1)
    if name == "flip":
        spread = np.maximum(spread, np.nanmedian(ds.flip_point_err.values, axis=1))
    return med, spread / scale


def _train(ds: xr.Dataset, i: int, name: str) -> tuple[np.ndarray, np.ndarray]:
    t, e = ds[f"{name}_time"].values[i], ds[f"{name}_time_err"].values[i]
    ok = np.isfinite(t)
    return t[ok], e[ok]


#: The per-orbit variables the gather adds (each in :data:`VOCABULARY`).
JUDGED = ("n_cycles", "period", "period_err", "train_residual", "train_resolution", "train_intervals", "torus_class",
          "class_reason", "period_difference", "period_difference_err", "n_spikes", "spike_interval",
          "spike_interval_stderr", "spike_point_offset", "spike_point_err", "reversal_offset", "torus_identity",
          "identity_reason")


def _row(ds: xr.Dataset, i: int, c: dict, ref: dict, points: dict) -> dict:
    """Orbit i's judged row from its reversal train's class c, the reference's ref and the median points."""
    t, e = _train(ds, i, "flip")
    P, R, cc = torus.train_fit(t, 1) if t.size >= 3 else (math.nan, math.nan, math.nan)
    S = float(np.sqrt(np.mean(e**2))) if e.size else math.nan
    (flip, flip_err), rev, scale = points["flip"], points["reversal"], points["scale"]
    row = {**c, "n_cycles": _train(ds, i, "reversal")[0].size - 1, "n_spikes": t.size, "spike_interval": P,
           "spike_interval_stderr": cc * max(R, S), "spike_point_offset": np.linalg.norm(flip[i] - flip[0]) / scale,
           "spike_point_err": flip_err[i], "reversal_offset": np.linalg.norm(rev[i] - rev[0]) / scale,
           "period_difference": c["period"] - ref["period"],
           "period_difference_err": math.hypot(c["period_err"], ref["period_err"]) if i else 0.0}
    return row


def _judged(ds: xr.Dataset, cfg: dict) -> dict:
    """Per orbit (:data:`JUDGED`): the reversal train's class and period (sleighsim.analysis.torus.classify),
    the flips' mean interval, the period's and the spike point's difference from the reference's, and the
    identity; and the velocity scale (max |(u, Omega, omega)| of the reference's start)."""
    scale = float(np.abs(ds.y0.values[0, :3]).max())
    points = {"flip": _median_points(ds, "flip", scale), "reversal": _median_points(ds, "reversal", scale)[0],
              "scale": scale}
    rule = dict(min_intervals=cfg["min_intervals"], factor=cfg["train_factor"], max_intervals=cfg["max_intervals"])
    trains = [torus.classify(*_train(ds, i, "reversal"), **rule) for i in range(ds.sizes["orbit"])]
    rows = []
    for i, c in enumerate(trains):
        row = _row(ds, i, c, trains[0], points)
        ident = (torus.REFERENCE, "the reference orbit") if i == 0 else torus.identity(
            c["torus_class"], row["period_difference"], row["period_difference_err"], row["spike_point_offset"],
            math.hypot(row["spike_point_err"], points["flip"][1][0]), cfg["sigma"])
        rows.append({**row, "torus_identity": ident[0], "identity_reason": ident[1]})
    return {"rows": {k: [r[k] for r in rows] for k in JUDGED}, "scale": scale}


def laws(ds: xr.Dataset, cfg: dict) -> dict:
    """The family's laws (sleighsim.analysis.torus.family_law) over the perturbed orbits shown to be on tori
    with a in ``law_amplitudes``: the period difference against log10 a (slope per decade) and log10 of the
    spike-point offset against log10 a (the power law's exponent)."""
    lo, hi = cfg["law_amplitudes"]
    a = ds.amplitude.values
    sel = (a >= lo) & (a <= hi) & (ds.torus_class.values != torus.NOT_SHOWN) & (ds.orbit.values > 0)
    x, d = np.log10(a[sel]), ds.direction.values[sel]
    with np.errstate(divide="ignore"):
        return {"period": torus.family_law(x, ds.period_difference.values[sel], d),
                "offset": torus.family_law(x, np.log10(ds.spike_point_offset.values[sel]), d)}


#: The per-orbit variables that hold text.
TEXT = ("torus_class", "class_reason", "torus_identity", "identity_reason")


def slug(text: str) -> str:
    """A class's or identity's name as part of an attribute name (n_<slug>)."""
    return re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")


def _law_attrs(ds: xr.Dataset, law: dict, cfg: dict) -> xr.Dataset:
    """The laws' per-direction values as variables (law_direction: every seeded direction) and their
    summaries as attributes."""
    dirs = list(range(cfg["directions"]))
    ds = ds.assign_coords(law_direction=dirs)
    for name, key in (("period_law_slope", "period"), ("offset_law_exponent", "offset")):
        ds[f"{name}_per_direction"] = ("law_direction", [law[key]["per_direction"].get(k, math.nan) for k in dirs])
        ds.attrs.update({name: law[key]["slope"], f"{name}_err": law[key]["slope_err"],
                         f"{name}_residual": law[key]["residual"], f"{name}_directions": law[key]["K"]})
    ds.attrs.update(law_amplitudes=list(cfg["law_amplitudes"]), law_rule=torus.LAW_RULE)
    return ds


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """Every orbit's cycle events (chunks joined in orbit order), its class, period and identity, and the
    family's laws (attributes naming their rules)."""
    parts = [read_dataset(p) for p in paths]
    width = max(d.sizes["cycle"] for d in parts)
    ds = xr.concat([d.pad(cycle=(0, width - d.sizes["cycle"])) for d in parts], dim="orbit",
                   combine_attrs="drop_conflicts").sortby("orbit")
    expected = orbits(cfg)
    if ds.orbit.values.tolist() != list(range(len(expected))):
        raise ValueError(f"chunks hold orbits {ds.orbit.values.tolist()}, expected 0 ... {len(expected) - 1}")
    ds = ds.assign_coords(amplitude=("orbit", [a for a, _ in expected]), direction=("orbit", [k for _, k in expected]))
    j = _judged(ds, cfg)
    for k, v in j["rows"].items():
        ds[k] = ("orbit", np.array(v, dtype=object) if k in TEXT else np.array(v, float))
    ds = _law_attrs(ds, laws(ds, cfg), cfg)
    classes, idents = ds.torus_class.values[1:], ds.torus_identity.values[1:]
    ds.attrs.pop("chunk", None)
    ds.attrs.update(
        Params.from_config(cfg["params"]).attrs(), scene=scene, energy_label=cfg["energy_label"], tol=cfg["tol"],
        tol_dd=cfg["tol_dd"], integrator="double-double Taylor (sleighsim.engine.ddtaylor) from the settled point; "
        "the pre-run heyoka in double", T=cfg["T"], T_reference=cfg["T_reference"], dt=cfg["dt"],
        t_transient=cfg["t_transient"], seed=cfg["seed"], min_intervals=cfg["min_intervals"],
        train_factor=cfg["train_factor"], max_intervals=cfg["max_intervals"], sigma=cfg["sigma"],
        velocity_scale=j["scale"], reference_period=float(ds.period.values[0]),
        reference_period_err=float(ds.period_err.values[0]), reference_n_cycles=int(ds.n_cycles.values[0]),
        reference_class=str(ds.torus_class.values[0]), events=str(EVENTS), crossing_rule=torus.CROSSING_RULE,
        train_rule=torus.TRAIN_RULE, identity_rule=torus.IDENTITY_RULE, perturbation_rule=PERTURBED_START_RULE,
        energy_max_rel_drift=float(np.nanmax(ds.energy_max_rel_drift.values)), cpu_s=float(ds.cpu_s.values.sum()),
        n_perturbed=int(classes.size), **{f"n_{slug(c)}": int(np.sum(classes == c)) for c in torus.CLASSES},
        **{f"n_{slug(c)}": int(np.sum(idents == c)) for c in torus.IDENTITIES[1:]}, summary=_summary(ds))
    return ds


def _summary(ds: xr.Dataset) -> str:
    """One line per amplitude: its directions' classes, identities and periods."""
    lines = []
    for a in np.unique(ds.amplitude.values[1:]):
        sel = np.flatnonzero(ds.amplitude.values == a)
        lines.append(f"a = {a:.0e}: " + "; ".join(
            f"{ds.torus_class.values[i]}, {ds.torus_identity.values[i]} (period {ds.period.values[i]:.10g})"
            for i in sel))
    return (f"reference: {ds.torus_class.values[0]}, period {ds.period.values[0]:.12g} +- "
            f"{ds.period_err.values[0]:.2g} over {int(ds.n_cycles.values[0])} cycles. " + ". ".join(lines))


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
    lo, hi = cfg["law_amplitudes"]
    if not lo < hi:
        raise ConfigError(f"{w}.law_amplitudes = {cfg['law_amplitudes']} must be [low, high] with low < high")


#: The variables only this kind writes: name -> (long_name, kind of quantity) (``sleighsim.io.cf``).
VOCABULARY = {
    "orbit": ("index of the orbit (0: the reference from the settled point, then the perturbed starts)", "1"),
    "direction": ("index of the perturbation's seeded random direction (-1: the reference)", "1"),
    "law_direction": ("index of the seeded direction a law was fitted along", "1"),
    "start_distance": ("relative distance of the start from the settled point (sleighsim.engine.ddtaylor.separation)",
                       "1"),
    "cpu_s": ("CPU time of the orbit's integration and analysis", "s"),
    "reversal_time": ("refined time of each reversal: u crossing 0 downward on the delta = 0 section", "time"),
    "reversal_time_err": ("error of the refined reversal time (crossing_rule)", "time"),
    "reversal_Omega": ("Omega at each reversal", "angular_velocity"),
    "reversal_omega": ("omega at each reversal", "angular_velocity"),
    "flip_time": ("refined time of each flip: u crossing 0 upward on the delta = 0 section, in the Omega spike",
                  "time"),
    "flip_time_err": ("error of the refined flip time (crossing_rule)", "time"),
    "flip_Omega": ("Omega at each flip (the spike point's first coordinate)", "angular_velocity"),
    "flip_omega": ("omega at each flip (the spike point's second coordinate)", "angular_velocity"),
    "flip_point_err": ("interpolation error of the flip's (Omega, omega), the larger (crossing_rule)",
                       "angular_velocity"),
    "n_cycles": ("number of intervals of the reversal train", "1"),
    "period": ("period of the reversal train (train_rule)", "time"),
    "period_err": ("standard error of the period (train_rule)", "time"),
    "train_residual": ("residual rms of the reversal train's chosen fit (train_rule)", "time"),
    "train_resolution": ("rms of the reversal times' errors, the train's resolution (train_rule)", "time"),
    "train_intervals": ("number of repeating intervals of the reversal train (0: none fits)", "1"),
    "torus_class": ("class of the orbit (train_rule)", "text"),
    "class_reason": ("reason for the orbit's class", "text"),
    "period_difference": ("period minus the reference's", "time"),
    "period_difference_err": ("standard error of the period difference (both combined)", "time"),
    "spike_point_offset": ("distance of the orbit's median spike point (Omega, omega at the flip) from the "
                           "reference's, relative to the velocity scale", "1"),
    "spike_point_err": ("uncertainty of the orbit's median spike point, relative to the velocity scale", "1"),
    "reversal_offset": ("distance of the orbit's median (Omega, omega) at the reversal from the reference's, relative "
                        "to the velocity scale", "1"),
    "torus_identity": ("which torus the orbit is on (identity_rule)", "text"),
    "identity_reason": ("reason for the orbit's identity", "text"),
    "period_law_slope_per_direction": ("slope of the period difference per decade of a along one direction "
                                       "(law_rule)", "time"),
    "offset_law_exponent_per_direction": ("exponent of the spike-point offset against a along one direction "
                                          "(law_rule)", "1"),
}


TORUS_STABILITY = SceneKind(
    name="torus_stability",
    title=("what the steady state is: orbits started near the main torus in double-double, each shown to be on a "
           "torus (periodic reversal train) or not, the reference's or another of the family, and the family's "
           "laws against the perturbation (issue 39 item 4, issue 52 item 5, claim C06)"),
    vocabulary=VOCABULARY,
    chunk=chunk, gather=gather, pre_run="t_transient",
    records=lambda c: [*memory.pre_run(c, "t_transient"), memory.span(c, "T_reference", "dt", 8),
                       memory.span(c, "T", "dt", 8, ("orbits per chunk", -(-len(orbits(c)) // c["n_chunks"])))],
    work=lambda cfg: sum(chunk_work(cfg)), chunk_work=chunk_work,
    modelled=lambda leaf: leaf in ("T", "T_reference", "t_transient", "amplitudes", "directions", "n_chunks"),
    checks=_checks)
