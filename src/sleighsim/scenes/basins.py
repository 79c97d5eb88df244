"""Basin fractions on one energy level (C06 made quantitative): initial states sampled on the
level, each run until its transient is over, grouped by the steady state it reaches, and the
fraction of each group with a 95% interval. Runs as independent chunk jobs (samples k,
k + n_chunks, ...) gathered into one dataset.

The sampling measure: the velocity direction (u, Omega, omega) from an isotropic standard normal,
scaled along itself (the time-scaling symmetry) onto the level; delta uniform on [0, 2 pi). A
steady state is named by its steady spike interval (the C06 rule, sleighsim.engine.transient): a run
joins the group of the first reference state (the chaos verdict's states, run in chunk 0) whose
interval is within ``group_rel_tol``; runs matching no reference form further groups; runs whose
transient is not over by the cap are "unsettled", settled runs with fewer than ``min_spikes``
spikes "no spike interval".
Mirror images (mean omega < 0, by (u, Omega, omega, delta) -> (u, -Omega, -omega, -delta)) share
their state's group; their share is reported per group.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.engine import transient
from sleighsim.engine.integrate import integrate, sample_grid
from sleighsim.engine.transient import settle
from sleighsim.io.netcdf import read_dataset
from sleighsim.io.vocabulary import VOCABULARY as SHARED
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.scenes import memory
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")

RUN_VARIABLES = ("settled", "t_settled", "n_spikes", "interval", "interval_std", "omega_sign",
                 "energy_max_rel_drift", "wall_time_s")
UNSETTLED = "unsettled"
NO_INTERVAL = "no spike interval"
MEASURE = ("velocity direction (u, Omega, omega) isotropic standard normal, scaled onto the energy label; "
           "delta uniform on [0, 2 pi)")


def sample_states(params: Params, label: float, n: int, seed: int) -> np.ndarray:
    """n initial states (n, 4) on the energy label, drawn from :data:`MEASURE`."""
    rng = np.random.default_rng(seed)
    v, delta = rng.standard_normal((n, 3)), rng.uniform(0.0, 2 * np.pi, n)
    return np.array([state_at_label(np.r_[vi, d], params, label) for vi, d in zip(v, delta)])


def run_to_steady(params: Params, y0, cfg: dict, label: str = "") -> dict:
    """Pre-runs of ``t_round`` from y0 until the transient rule says over (at most ``max_rounds``),
    then a record of ``T_measure`` sampled every ``dt_measure``: its spikes, the mean and spread
    of their intervals and the sign of mean omega."""
    start = time.perf_counter()
    y, over, rounds, drift = np.asarray(y0, float), False, 0, 0.0
    while not over and rounds < cfg["max_rounds"]:
        y, pre = settle(params, y, cfg["t_round"], **cfg["transient"], tol=cfg["tol"], label=label, progress=0)
        over, rounds = bool(pre["transient_over"]), rounds + 1
        drift = max(drift, pre["pre_run_energy_max_rel_drift"])
    rec = integrate(params, y, sample_grid(0.0, cfg["T_measure"], cfg["dt_measure"]), tol=cfg["tol"],
                    scene=f"{label}.measure", progress=0)
    spikes = transient.spike_times(rec.time.values, rec.Omega.values, factor=cfg["transient"]["spike_factor"])
    interval, interval_std = transient.interval_stats(spikes)
    return {"settled": int(over), "t_settled": rounds * cfg["t_round"] if over else np.nan,
            "n_spikes": spikes.size, "interval": interval, "interval_std": interval_std,
            "omega_sign": float(np.sign(rec.omega.values.mean())),
            "energy_max_rel_drift": max(drift, rec.attrs["energy_max_rel_drift"]),
            "wall_time_s": time.perf_counter() - start}


def _runs(params, states, cfg, names, scene):
    rows = []
    for k, (name, y0) in enumerate(zip(names, states)):
        rows.append(run_to_steady(params, y0, cfg, label=f"{scene}[{name}]"))
        r = rows[-1]
        log.info("%s: %s (%d / %d): %s, %d spikes, interval %.5g, %.2f s", scene, name, k + 1, len(states),
                 "settled" if r["settled"] else "NOT settled", r["n_spikes"], r["interval"], r["wall_time_s"])
    return {v: np.array([r[v] for r in rows], float) for v in RUN_VARIABLES}


def chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
    """The samples index, index + n_chunks, ... of the level's sample; chunk 0 also runs the
    reference states (scaled onto the level)."""
    params = Params.from_config(cfg["params"])
    states = sample_states(params, cfg["energy_label"], cfg["n_samples"], cfg["seed"])
    ids = np.arange(cfg["n_samples"])[index::cfg["n_chunks"]]
    runs = _runs(params, states[ids], cfg, [f"sample {i}" for i in ids], scene)
    ds = xr.Dataset({v: ("sample", runs[v]) for v in RUN_VARIABLES},
                    coords={"sample": ids, "component": ["u", "Omega", "omega", "delta"]})
    ds["y0"] = (("sample", "component"), states[ids])
    if index == 0:
        names = list(cfg["references"])
        refs = np.array([state_at_label(cfg["references"][n], params, cfg["energy_label"]) for n in names])
        r = _runs(params, refs, cfg, names, scene)
        ds = ds.assign_coords(reference=names)
        for v in RUN_VARIABLES:
            ds[f"reference_{v}"] = ("reference", r[v])
    ds.attrs.update(chunk=index, n_chunks=cfg["n_chunks"])
    return ds


def classify(ref_names, ref_intervals, ref_ok, intervals, settled, has_interval, rel_tol: float) -> np.ndarray:
    """The group name of each run: "unsettled" (transient not over), "no spike interval" (settled,
    too few spikes), else the first reference (with an interval, ``ref_ok``) whose steady interval
    is within rel_tol, else "other k" (grouped among themselves by the same rule)."""
    names = [n for n, o in zip(ref_names, ref_ok) if o]
    heads = np.asarray(ref_intervals, float)[np.asarray(ref_ok, bool)]
    ok = np.asarray(settled, bool) & np.asarray(has_interval, bool)
    labels = transient.interval_groups(np.r_[heads, np.where(ok, intervals, np.nan)], rel_tol)[heads.size:]
    named = [names[g] if 0 <= g < len(names) else f"other {g - len(names) + 1}" for g in labels]
    return np.array([UNSETTLED if not s else NO_INTERVAL if not h else n
                     for s, h, n in zip(settled, has_interval, named)], dtype=object)


def fractions(groups, omega_sign, confidence: float = 0.95, always=()) -> dict:
    """Per group: count, fraction, its Wilson interval at ``confidence`` (binomial, the samples
    independent by construction) and the share of mirror images (mean omega < 0; NaN for an empty
    group). The groups named in ``always`` (the reference states) are listed even when no run
    reached them: their interval then bounds the basin from above."""
    from scipy.stats import binomtest  # here: at the top it costs every job start-up (scenes.catalog)

    groups, n = np.asarray(groups, dtype=object), len(groups)
    names = sorted(set(groups) | set(always), key=lambda g: (g in (UNSETTLED, NO_INTERVAL), -np.sum(groups == g), g))
    out = {k: [] for k in ("count", "fraction", "ci_low", "ci_high", "mirrored")}
    for g in names:
        sel = groups == g
        k = int(sel.sum())
        ci = binomtest(k, n).proportion_ci(confidence_level=confidence, method="wilson")
        out["count"].append(k)
        out["fraction"].append(k / n)
        out["ci_low"].append(ci.low)
        out["ci_high"].append(ci.high)
        out["mirrored"].append(float(np.mean(np.asarray(omega_sign)[sel] < 0)) if k else math.nan)
    return {"group": names, **{k: np.array(v, float) for k, v in out.items()}}


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """Every chunk's runs in sample order, each run's group, and the fraction of each group with
    its 95% Wilson interval."""
    chunks = [read_dataset(p) for p in paths]
    first = next(c for c in chunks if int(c.attrs["chunk"]) == 0)
    runs = xr.concat([c[["y0", *RUN_VARIABLES]] for c in chunks], dim="sample", combine_attrs="drop").sortby("sample")
    if runs.sample.values.tolist() != list(range(cfg["n_samples"])):
        raise ValueError(f"chunks hold samples {runs.sample.values.tolist()}, expected 0 ... {cfg['n_samples'] - 1}")
    refs = first[[f"reference_{v}" for v in RUN_VARIABLES]]
    ref_ok = (refs.reference_settled.values == 1) & (refs.reference_n_spikes.values >= cfg["min_spikes"])
    groups = classify(refs.reference.values.tolist(), refs.reference_interval.values, ref_ok, runs.interval.values,
                      runs.settled.values == 1, runs.n_spikes.values >= cfg["min_spikes"], cfg["group_rel_tol"])
    f = fractions(groups, runs.omega_sign.values, cfg["confidence"],
                  always=[r for r, o in zip(refs.reference.values.tolist(), ref_ok) if o])
    ds = xr.merge([runs, refs])
    ds["group_of"] = ("sample", groups.astype(str))
    ds = ds.assign_coords(group=f["group"])
    for k in ("count", "fraction", "ci_low", "ci_high", "mirrored"):
        ds[k] = ("group", f[k])
    ds["group_interval"] = ("group", [float(np.nanmean(runs.interval.values[groups == g]))
                                      if g not in (UNSETTLED, NO_INTERVAL) else np.nan for g in f["group"]])
    ds.attrs.update(Params.from_config(cfg["params"]).attrs())
    ds.attrs.update(
        energy_label=cfg["energy_label"], n_samples=cfg["n_samples"], seed=cfg["seed"],
        measure=MEASURE, t_round=cfg["t_round"], max_rounds=cfg["max_rounds"], T_measure=cfg["T_measure"],
        dt_measure=cfg["dt_measure"], min_spikes=cfg["min_spikes"], group_rel_tol=cfg["group_rel_tol"],
        confidence=cfg["confidence"], tol=cfg["tol"], backend="heyoka", transient_rule=transient.RULE,
        rule=("a run is settled when the transient rule says over within max_rounds pre-runs of t_round (else "
              "'unsettled'); a settled run whose record of T_measure has fewer than min_spikes spikes is 'no spike "
              "interval'; the others join the first reference (then the first earlier run) whose steady spike "
              "interval is within group_rel_tol"),
        uncertainty=f"Wilson score interval at {cfg['confidence']:g} for a binomial fraction (independent samples)",
        energy_max_rel_drift=float(np.nanmax(runs.energy_max_rel_drift.values)),
        wall_time_s=float(runs.wall_time_s.values.sum() + refs.reference_wall_time_s.values.sum()),
        n_unsettled=int((groups == UNSETTLED).sum()))
    log.info("%s: %s", scene, "; ".join(f"{g}: {c:.0f} ({lo:.2f}-{hi:.2f})" for g, c, lo, hi in
                                        zip(f["group"], f["count"], f["ci_low"], f["ci_high"])))
    return ds


def _checks(w, cfg):
    if cfg["n_chunks"] > cfg["n_samples"]:
        raise ConfigError(f"{w}.n_chunks = {cfg['n_chunks']} must lie in [1, n_samples = {cfg['n_samples']}]")


#: The variables only this kind writes: name -> (long_name, kind of quantity) (``sleighsim.io.cf``).
VOCABULARY = {
    "sample": ("index of the sampled start state", "1"),
    "group_of": ("steady-state group of the run", "text"),
    "count": ("runs in the group", "1"),
    "fraction": ("fraction of the runs in the group", "1"),
    "ci_low": ("lower end of the fraction's Wilson interval", "1"),
    "ci_high": ("upper end of the fraction's Wilson interval", "1"),
    "group_interval": ("mean steady spike interval of the group", "time"),
}
# a reference state's run has the run's variables
VOCABULARY.update({f"reference_{v}": (f"{SHARED[v][0]}, reference state", SHARED[v][1])
                   for v in ("settled", "t_settled", "n_spikes", "interval", "interval_std", "omega_sign",
                             "energy_max_rel_drift", "wall_time_s")})


BASINS = SceneKind(
    name="basins",
    title="basin fractions of the steady states on one energy level (claim C06 made quantitative)",
    vocabulary=VOCABULARY,
    chunk=chunk, gather=gather, checks=_checks, pre_run="t_round",
    records=lambda c: [*memory.pre_run(c, "t_round"), memory.span(c, "T_measure", "dt_measure"),
                       memory.span(c, "n_samples", None, 8)])
