"""The largest Lyapunov exponent against the energy label (F10, C20): one lane per label, each the
time-scaling image of one state settled at the reference label (:func:`_sweep_lanes`)."""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.analysis import fits
from sleighsim.chaos import benettin
from sleighsim.engine import integrators
from sleighsim.engine.transient import settle
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.scenes import memory
from sleighsim.scenes.checks import blocks
from sleighsim.scenes.common import steady_arithmetic
from sleighsim.scenes.exponents import lyapunov_attrs
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def _energy_observables(lam, err, labels, ref: int) -> dict:
    """The energy sweep's ladder observables (1/time): lambda_1 at the reference label and at the
    lowest label, each with its lane's block standard error."""
    low = int(np.argmin(labels))
    return {"lambda_1_reference": float(lam[ref]), "lambda_1_reference_uncertainty": float(err[ref]),
            "lambda_1_lowest_label": float(lam[low]), "lambda_1_lowest_label_uncertainty": float(err[low])}


def _sweep_lanes(cfg: dict, labels: np.ndarray, scene: str) -> dict:
    """lambda_1 at ``labels``, one lane each (SIMD lanes in double, one after another in a finer
    precision, :func:`sleighsim.chaos.benettin.sleigh_tangent_lanes`): every lane starts from the
    image, under the time-scaling law, of one state settled at the reference label (the pre-run in
    double) and runs the same number of renormalisations (T, t_align and tau scaled by
    sqrt(reference_label / label)). A lane's numbers depend on its label alone, not on the other lanes.
    Uncertainty: the block standard error within each lane's run. Rates in 1/time unit, times in time units."""
    params = Params.from_config(cfg["params"])
    scale = np.sqrt(cfg["reference_label"] / labels)  # time unit at each label relative to the reference
    y0 = state_at_label(cfg["y0"], params, cfg["reference_label"])
    y, transient_attrs = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=cfg["tol"], label=scene,
                                progress=1)
    lanes = np.array([np.r_[y[:3] / s, y[3]] for s in scale])  # the time-scaling images of the settled state
    arith = steady_arithmetic(cfg)
    ta, compile_s = benettin.sleigh_tangent_lanes(labels.size, arith["tol"], cfg["compact_mode"],
                                                  precision=arith["precision"])
    integrators.set_pars(ta, params)
    steps = int(round(cfg["T"] / cfg["tau"]))
    tau, T = cfg["tau"] * scale, steps * cfg["tau"] * scale  # per label
    r = benettin.batch_benettin(ta, 4, 1, lanes, tau, n_steps=steps,
                                t_align_steps=int(math.ceil(cfg["t_align"] / cfg["tau"])), label=scene)
    g = r["log_growth"][:, 0, :]  # (steps, lanes)
    blocks = _in_order(g[: (steps // cfg["n_blocks"]) * cfg["n_blocks"]].reshape(cfg["n_blocks"], -1, labels.size), 1)
    block_est = blocks / (steps // cfg["n_blocks"] * cfg["tau"] * scale)
    return {"lambda_1": _in_order(g, 0) / T, "stderr": block_est.std(axis=0, ddof=1) / math.sqrt(cfg["n_blocks"]),
            "T": T, "tau": tau, "params": params, "y0": y0, "settled_state": np.asarray(y, float),
            "transient_attrs": transient_attrs, "compile_time_s": compile_s}


def _in_order(x: np.ndarray, axis: int) -> np.ndarray:
    """Sums over ``axis`` term after term (np.cumsum's order), whatever the number of lanes: np.sum
    over several lanes adds in that order, over a single lane pairwise, so a lane's sum would depend
    on how many lanes ran beside it."""
    return np.take(np.cumsum(x, axis=axis), -1, axis=axis)


def _lanes_dataset(lanes: dict, labels: np.ndarray) -> xr.Dataset:
    """The per-label variables of :func:`_sweep_lanes` (rates in 1/time unit, times in time units)."""
    return xr.Dataset(
        {"lambda_1": ("label", lanes["lambda_1"], cf.attrs("largest Lyapunov exponent lambda_1 per label", "rate")),
         "stderr": ("label", lanes["stderr"], cf.attrs("block standard error of lambda_1 within the label's run",
                                                       "rate")),
         "T": ("label", lanes["T"], cf.attrs("horizon per label", "time")),
         "tau": ("label", lanes["tau"], cf.attrs("renormalisation interval per label", "time"))},
        coords={"label": ("label", labels, cf.attrs("paper energy label"))},
    )


def _sweep_dataset(ds: xr.Dataset, cfg: dict, lanes: dict, scene: str, wall_s: float) -> xr.Dataset:
    """The sweep's dataset from the per-label variables of every label (``ds``) and the run's
    settled state, transient and compile time (``lanes``): the time-scaling law's prediction from the
    reference lane and the exponent fitted over the positive lanes."""
    labels, lam, err = ds.label.values, ds.lambda_1.values, ds.stderr.values
    ref = int(np.argmin(np.abs(np.log(labels / cfg["reference_label"]))))
    law = lam[ref] * np.sqrt(labels / labels[ref])
    ok = lam > 0
    slope, _, slope_err = fits.loglog(labels[ok], lam[ok], err[ok], min_points=3)
    ds = ds.assign(law=("label", law, cf.attrs("time-scaling law from the reference label", "rate")))
    ds = ds[["lambda_1", "stderr", "law", "T", "tau"]]
    ds.attrs.update(lyapunov_attrs(lanes["params"], lanes["y0"], cfg, scene))
    ds.attrs.update(lanes["transient_attrs"])
    ds.attrs.update(
        settled_state=lanes["settled_state"], **_energy_observables(lam, err, labels, ref),
        reference_label=cfg["reference_label"], T_reference=cfg["T"], t_transient_reference=cfg["t_transient"],
        n_blocks=cfg["n_blocks"], compile_time_s=lanes["compile_time_s"],
        horizon_rule="one settled state at the reference label, mapped to every label by the time-scaling law; T, "
                     "t_align and tau scaled by sqrt(reference_label / label)",
        fitted_exponent=slope, fitted_exponent_stderr=slope_err, n_positive=int(ok.sum()),
        max_rel_deviation_from_law=float(np.max(np.abs(lam / law - 1))), wall_time_s=wall_s,
    )
    return ds


def energy_sweep(cfg: dict, scene: str = "") -> xr.Dataset:
    """Max LE at several energy labels, one per SIMD lane of one batch run (:func:`_sweep_lanes`),
    the time-scaling law's prediction from the reference lane and a fitted exponent."""
    start = time.perf_counter()
    labels = np.asarray(cfg["labels"], float)
    lanes = _sweep_lanes(cfg, labels, scene)
    return _sweep_dataset(_lanes_dataset(lanes, labels), cfg, lanes, scene, time.perf_counter() - start)


def _precision_chunks(cfg: dict) -> int:
    """Jobs of the sweep in a finer precision: ``precision_chunks`` (1 when unset), at most one per label."""
    return min(cfg.get("precision_chunks", 1), len(cfg["labels"]))


def energy_chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
    """Labels index, index + chunks, ... of the sweep in a finer precision, whose lanes run one after
    another (no SIMD): each chunk job settles the same state (the pre-run in double, deterministic)
    and runs its own labels' lanes, which give the numbers they give in one job (a lane depends on
    its label alone). Per-label variables only; :func:`energy_gather` makes the dataset."""
    start = time.perf_counter()
    labels = np.asarray(cfg["labels"], float)[index::_precision_chunks(cfg)]
    lanes = _sweep_lanes(cfg, labels, f"{scene}[chunk {index}]")
    ds = _lanes_dataset(lanes, labels)
    ds.attrs.update(chunk=index, settled_state=lanes["settled_state"], compile_time_s=lanes["compile_time_s"],
                    wall_time_s=time.perf_counter() - start, **lanes["transient_attrs"])
    return ds


def energy_gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """The sweep's dataset (as :func:`energy_sweep` makes it) from its chunk files; wall and compile
    times summed over the chunks. Raises when the chunks did not start from one settled state or
    do not hold every label once."""
    chunks = [read_dataset(p) for p in paths]
    starts = [np.asarray(c.attrs["settled_state"], float) for c in chunks]
    if any(not np.array_equal(starts[0], s) for s in starts[1:]):
        raise ValueError(f"{scene}: the chunks start from different settled states {starts}")
    labels = np.asarray(cfg["labels"], float)
    ds = xr.concat(chunks, dim="label", combine_attrs="drop")
    if sorted(ds.label.values.tolist()) != sorted(labels.tolist()):
        raise ValueError(f"{scene}: chunks hold labels {ds.label.values.tolist()}, expected {labels.tolist()}")
    ds = ds.sel(label=labels)
    params, first = Params.from_config(cfg["params"]), chunks[0].attrs  # the pre-run's attributes: any chunk's
    lanes = {**{v: ds[v].values for v in ("lambda_1", "stderr", "T", "tau")},
             "params": params, "y0": state_at_label(cfg["y0"], params, cfg["reference_label"]),
             "settled_state": starts[0], "compile_time_s": sum(c.attrs["compile_time_s"] for c in chunks),
             "transient_attrs": {k: v for k, v in first.items() if k.startswith(("transient_", "pre_run_"))}}
    return _sweep_dataset(_lanes_dataset(lanes, labels), cfg, lanes, scene, sum(c.attrs["wall_time_s"] for c in chunks))


LYAPUNOV_ENERGY = SceneKind(
    name="lyapunov_energy",
    title="the largest Lyapunov exponent against the energy label (figure F10, claim C20)",
    compute=energy_sweep, chunk=energy_chunk, gather=energy_gather,
    chunk_count=_precision_chunks, realizable=True, observables=("lambda_1_reference", "lambda_1_lowest_label"),
    records=lambda c: [*memory.pre_run(c, "t_transient"), memory.span(c, "T", "tau", 5, memory.count(c, "labels"))],
    checks=lambda w, cfg: blocks(w, cfg, "T"), pre_run="t_transient")
