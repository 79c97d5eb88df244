"""The largest Lyapunov exponent against eps (rows) and b (F11, C21), as independent chunk jobs
(whole eps rows) gathered into one dataset. The same rows, at more eps and with the Poincare
observables, are the regime diagram.

b is an exact symmetry at fixed K2: (u / b, Omega, omega, delta) obeys b-free equations
(mechanics.b_free_form), so lambda_1(eps, b) = lambda_1(eps) at a fixed label. Each row is
computed once, at b = 1, and the b axis is filled by the symmetry; the reference row is also
computed directly at the ``b_check`` values, from the same replicas mapped by the symmetry.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.chaos import benettin
from sleighsim.chaos.faithfulness import DOES_NOT_FOLLOW, FOLLOWS, UNKNOWN, settled_gains
from sleighsim.engine import integrators, poincare, transient
from sleighsim.engine.integrate import orbit_samples
from sleighsim.engine.transient import settle
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset
from sleighsim.io.yamlfile import read_yaml
from sleighsim.model.params import Params
from sleighsim.model.symmetries import b_image, state_at_label
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.checks import ConfigError, increasing
from sleighsim.scenes.common import steady_arithmetic
from sleighsim.scenes.grid_verdict import (
    FLOATS,
    MARGIN,
    ROW_VERDICT_FLAGS,
    ROW_VERDICT_RULE,
    TEXTS,
    judge_row,
    not_judged,
)
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")

ROW_VARIABLES = ("lambda_1", "stderr", "T", "tau", "status_code", "transient_over", "omega_block_drift", "steady",
                 "settling_time", "t_pre", "spike_interval", "spike_interval_std", "rotation_number",
                 "curve_thickness", "b_check_max_diff", "b_check_bound", "wall_time_s", "rounds_wall_s",
                 "round_length", "row_ln_gain_max", "row_gain_steps_per_cycle", "row_log10_gain_rounding",
                 "faithful_code")
STATUS = ("converged", "regular", "capped", "elsewhere")
#: The arithmetics a row's lambda_1 could be computed in, cheapest first (costs per time unit:
#: benchmarks/precision_cost.yaml, benchmarks/ddbatch.yaml); a row's faithful_code indexes it (len: none).
LADDER = (Precision.DOUBLE, Precision.LONG_DOUBLE, Precision.DOUBLE_DOUBLE, Precision.QUAD)
#: Written into the dataset (attribute gauge_rule).
GAUGE_RULE = ("per row, the faithfulness gauge along its settled orbit (chaos.faithfulness.spike_cycle_gains in "
              "double over T_gain x s, re-orthonormalised every tau_gain x s, s = reference_eps / eps): ln G of every "
              "spike cycle; an arithmetic follows the row's orbit when G_max x steps per cycle x its unit roundoff "
              "< FAITHFUL_MAX; faithful_arithmetic is the cheapest of LADDER that does, lambda_1_follows whether "
              "lambda_1's own arithmetic does (unknown: no complete spike cycle within T_gain)")


def axes(cfg: dict) -> tuple[np.ndarray, np.ndarray]:
    """The log-spaced eps and b values of the grid."""
    return np.geomspace(*cfg["eps_range"], cfg["n_eps"]), np.geomspace(*cfg["b_range"], cfg["n_b"])


def reference_row(cfg: dict) -> int:
    """Index of the eps row nearest reference_eps (in log eps)."""
    return int(np.argmin(np.abs(np.log(axes(cfg)[0] / cfg["reference_eps"]))))


def elsewhere(cfg: dict) -> np.ndarray:
    """Mask of the eps rows the block leaves to another config (``elsewhere.eps``, e.g. the long
    small-eps rows kept for config/cluster.yaml); ValueError for a listed eps not on the axis or
    for the reference row."""
    eps_all, listed = axes(cfg)[0], cfg.get("elsewhere", {}).get("eps", [])
    mask = np.zeros(eps_all.size, bool)
    for e in listed:
        hit = np.isclose(eps_all, e, rtol=1e-3)
        if not hit.any():
            raise ValueError(f"elsewhere.eps: {e:g} is not a row of the grid ({np.round(eps_all, 4).tolist()})")
        mask |= hit
    if mask[reference_row(cfg)]:
        raise ValueError(f"elsewhere.eps: the reference row (eps {cfg['reference_eps']:g}) must be computed here")
    return mask


def slow_time(cfg: dict, eps: float) -> float:
    """The slow time unit at eps relative to reference_eps: the spike cycle grows like 1 / eps
    (measured: interval ~ eps^-1.03), so horizons and replica spacings scale by eps_ref / eps."""
    return cfg["reference_eps"] / eps


def pre_run(cfg: dict, eps: float) -> float:
    """Pre-run length at eps: t_pre (eps_ref / eps)^2 (transients grow like 1/eps^2), at least t_pre_min."""
    return max(cfg["t_pre_min"], cfg["t_pre"] * (cfg["reference_eps"] / eps) ** 2)


def _row_transient(cfg: dict, t_pre: float) -> dict:
    """The transient block (given for the pre-run t_pre at reference_eps) for a row whose pre-run is
    ``t_pre``: sampling interval, window and t_min scale with the pre-run length."""
    tc = cfg["transient"]
    scaled = {k: tc[k] / cfg["t_pre"] * t_pre for k in ("dt", "window", "t_min")}
    return dict(tc, **scaled)


def _replicas(params, y, cfg, s, label):
    """``replicas`` states along the settled orbit, replica_spacing (slow time units) apart (in the
    block's steady-state arithmetic), and the steady spike interval of that stretch (mean and
    standard deviation; the stretch sampled every ``spike_dt`` time units at most, unscaled)."""
    spacing = cfg["replica_spacing"] * s
    per_spacing = max(400, math.ceil(spacing / cfg["spike_dt"]))
    states, run = orbit_samples(params, y, cfg["replicas"], spacing, **steady_arithmetic(cfg),
                                samples_per_spacing=per_spacing, scene=label)
    try:
        spikes = transient.spike_times(run.time.values, run.Omega.values, factor=cfg["transient"]["spike_factor"])
    except ValueError:  # a record shorter than two spike-detection blocks
        spikes = np.array([])
    return (states, *transient.interval_stats(spikes))


def _steadiness(states, n_blocks: int, rtol: float) -> tuple[float, bool]:
    """Largest relative drift of omega's block means (over n_blocks blocks of each replica's record)."""
    om = states[:, 2, :]
    m = (om.shape[0] // n_blocks) * n_blocks
    means = om[:m].reshape(n_blocks, -1, om.shape[1]).mean(axis=1)
    drift = float(np.max(np.abs(means / means.mean(axis=0) - 1.0)))
    return drift, drift <= rtol


def row(cfg: dict, eps: float, label: str = "", check_b: bool = False) -> dict:
    """One eps row at b = 1: pre-run from y0 at the label (transient checked), replicas along the
    settled orbit, the replica estimate of lambda_1 (benettin.replica_exponents), steadiness of each
    replica, the steady spike interval, and (poincare_span > 0) the P_2pi rotation number and curve
    thickness; with ``check_b``, lambda_1 again at the b_check values from the replicas mapped by the
    symmetry (one round). The rounds' wall time (s) and round length (time units) price a longer horizon."""
    start = time.perf_counter()
    s, t_pre = slow_time(cfg, eps), pre_run(cfg, eps)
    tau = cfg["tau"] * s
    p = Params.paper(eps=eps, b=1.0)
    y, pre = settle(p, state_at_label(cfg["y0"], p, cfg["energy_label"]), t_pre, **_row_transient(cfg, t_pre),
                    tol=cfg["tol"], label=label, progress=1)
    replicas, interval, interval_std = _replicas(p, y, cfg, s, label)
    B, arith = cfg["replicas"], steady_arithmetic(cfg)
    gauge = row_gauge(p, y, cfg, s, arith["precision"])
    ta, _ = benettin.sleigh_tangent_lanes(B, arith["tol"], cfg["compact_mode"], precision=arith["precision"])
    integrators.set_pars(ta, p)
    kw = dict(T_round=cfg["T_round"] * s, max_rounds=cfg["max_rounds"], target_rel=cfg["target_rel"],
              regular_floor=cfg["regular_floor"] / s, t_align=cfg["t_align"] * s, sigma=cfg["sigma"], label=label)
    t_rounds = time.perf_counter()
    r = benettin.replica_exponents(ta, 4, 1, replicas, tau, **kw)
    rounds_wall = time.perf_counter() - t_rounds
    drift, steady = _steadiness(r["states"], cfg["steady_blocks"], cfg["transient"]["rtol"])
    out = {"lambda_1": float(r["exponents"][0]), "stderr": float(r["stderr"][0]), "T": r["T"], "tau": tau,
           "status_code": STATUS.index(r["status"]), "transient_over": pre["transient_over"],
           "omega_block_drift": drift, "steady": int(steady), "settling_time": pre["transient_settling_time"],
           "t_pre": t_pre, "spike_interval": interval, "spike_interval_std": interval_std,
           "rotation_number": math.nan, "curve_thickness": math.nan, "b_check_max_diff": math.nan,
           "b_check_bound": math.nan, "rounds_wall_s": rounds_wall, "round_length": kw["T_round"], "settled": y,
           "rule": r["rule"], **gauge}
    if cfg["poincare_span"] > 0:
        c = poincare.crossings(p, replicas[0], 0.0, cfg["poincare_span"] * s, **arith, scene=label)
        pts = np.c_[c["u"], c["Omega"], c["omega"]][c["k"] == 0]
        if len(pts) > 10:
            out["rotation_number"] = poincare.rotation_number(pts)["rotation_number"]
            out["curve_thickness"] = poincare.curve_thickness(pts)
    if check_b and cfg["b_check"]:
        diffs, bounds = [], []
        for b in cfg["b_check"]:
            pb = Params.paper(eps=eps, b=b)
            integrators.set_pars(ta, pb)
            rb = benettin.replica_exponents(ta, 4, 1, np.array([b_image(x, 1.0, b) for x in replicas]),
                                            tau, **dict(kw, max_rounds=1, label=f"{label}[b={b:g}]"))
            T1, first = r["history"][0][0], r["history"][0][1]  # the b = 1 estimate after the same single round
            diffs.append(abs(rb["exponents"][0] - first))
            # the same orbit in other coordinates (u scaled by b): the tangent norms differ by at most a
            # factor b at both ends, so the finite-time exponents may differ by up to 2 |ln b| / T
            bounds.append(2 * abs(math.log(b)) / T1)
            log.info("%s: b = %g gives lambda_1 %.6g after one round (b = 1: %.6g; allowed difference %.2g)", label, b,
                     rb["exponents"][0], first, bounds[-1])
        out["b_check_max_diff"] = float(max(diffs))
        out["b_check_bound"] = float(max(bounds))
    out["wall_time_s"] = time.perf_counter() - start
    log.info("%s: lambda_1 = %.4g +- %.2g (%s, T = %.4g per replica), omega drift %.2g, interval %.4g, %.1f s",
             label, out["lambda_1"], out["stderr"], r["status"], r["T"], drift, interval, out["wall_time_s"])
    return out


def row_gauge(p: Params, y, cfg: dict, s: float, arithmetic: Precision) -> dict:
    """The row's faithfulness gauge (:data:`GAUGE_RULE`): row_ln_gain_max, row_gain_steps_per_cycle,
    row_log10_gain_rounding (G_max x steps x unit roundoff of ``arithmetic``, log10) and faithful_code (the
    index in LADDER of the cheapest arithmetic that follows; len(LADDER): none; NaN: unknown)."""
    g = settled_gains(p, y, tol=cfg["tol"], compact_mode=cfg["compact_mode"], T=cfg["T_gain"] * s,
                      tau=cfg["tau_gain"] * s, spike_factor=cfg["transient"]["spike_factor"])
    follows = [g["follows"][a] for a in LADDER]
    code = math.nan if UNKNOWN in follows else next((i for i, f in enumerate(follows) if f == FOLLOWS), len(LADDER))
    return {"row_ln_gain_max": g["ln_gain_max"], "row_gain_steps_per_cycle": g["steps_per_cycle"],
            "row_log10_gain_rounding": g["log10_gain_rounding"][arithmetic], "faithful_code": float(code)}


def faithful_words(codes, arithmetic: Precision) -> tuple[list[str], list[str]]:
    """Per row (its faithful_code): the cheapest arithmetic that follows its orbit (or "none of ..." /
    "unknown (...)"), and whether ``arithmetic`` (lambda_1's) does: follows, does not follow or unknown."""
    names, verdicts = [], []
    for c in codes:
        if not np.isfinite(c):
            names.append("unknown (no complete spike cycle within T_gain)")
            verdicts.append(UNKNOWN)
            continue
        c = int(c)
        names.append(LADDER[c].value if c < len(LADDER) else "none of " + ", ".join(a.value for a in LADDER))
        verdicts.append(FOLLOWS if c <= LADDER.index(arithmetic) else DOES_NOT_FOLLOW)
    return names, verdicts


def chunk(cfg: dict, index: int, scene: str = "", inputs: dict | None = None) -> xr.Dataset:
    """The eps rows index, index + n_chunks, ... (see :func:`row`), each with its verdict (:func:`judged`; the
    judge-power record ``inputs["power"]``)."""
    eps_all, _ = axes(cfg)
    ref, away = eps_all[reference_row(cfg)], set(eps_all[elsewhere(cfg)])
    record = read_yaml(inputs["power"])
    rows = {}
    for e in eps_all[index::cfg["n_chunks"]]:
        label = f"{scene}[eps={e:.4g}]"
        rows[e] = _not_here(cfg) if e in away else judged(cfg, row(cfg, e, label=label, check_b=e == ref), e,
                                                          record, label)
    eps = np.array(list(rows), float)
    ds = xr.Dataset({v: ("eps", np.array([rows[e][v] for e in eps], float)) for v in ROW_VARIABLES + FLOATS},
                    coords={"eps": eps})
    for v in TEXTS:
        ds[v] = ("eps", np.array([rows[e][v] for e in eps], dtype=object))
    ds["realization_row_verdict"] = (("eps", "realization"),
                                     np.array([rows[e]["realization_verdicts"] for e in eps], dtype=object))
    ds["row_settled_state"] = (("eps", "component"), np.array([rows[e]["settled"] for e in eps], float),
                           cf.attrs("the row's settled state (u, Omega, omega, delta) in model units (double "
                                    "pre-run; its steady part starts here)"))
    computed = [r["rule"] for r in rows.values() if r["rule"]]
    ds.attrs.update(chunk=index, n_chunks=cfg["n_chunks"], rule=computed[0] if computed else "")
    return ds


def judged(cfg: dict, out: dict, eps: float, record: dict, label: str) -> dict:
    """A computed row with its verdict (``grid_verdict.judge_row``: the decisive judges in the cheapest arithmetic
    its gauge accepts for them, over realizations). A ladder's finer rung runs the same rows again for lambda_1
    only: the verdict, whose arithmetic is its own, is the double dataset's."""
    if Precision.parse(steady_arithmetic(cfg)["precision"]) is not Precision.DOUBLE:
        return {**out, **not_judged("judged in the grid's double dataset (the verdict chooses its own arithmetic)",
                                    realizations=cfg["verdict"]["realizations"])}
    return {**out, **judge_row(Params.paper(eps=eps, b=1.0), out["settled"], eps, cfg["verdict"], record, out,
                               out["spike_interval"], cfg["transient"]["spike_factor"], label)}


def _not_here(cfg: dict) -> dict:
    """A row left to another config: every variable NaN, status "elsewhere", not judged here."""
    out = dict.fromkeys(ROW_VARIABLES, math.nan)
    out.update(status_code=STATUS.index("elsewhere"), wall_time_s=0.0, rule="", settled=np.full(4, math.nan))
    where = cfg.get("elsewhere", {}).get("config", "another config")
    return {**out, **not_judged(f"computed with {where}", realizations=cfg["verdict"]["realizations"])}


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """The rows of every chunk, in eps order, with lambda_1 on the (eps, b) grid filled by the
    symmetry and each row's flags: a row is flagged when its transient was not shown over, a
    replica's omega block means drift by more than transient.rtol, or lambda_1 is not resolved
    (status other than converged)."""
    chunks = [read_dataset(p) for p in paths]
    parts = xr.concat(chunks, dim="eps", combine_attrs="drop").sortby("eps")
    eps, bs = axes(cfg)
    if not np.allclose(parts.eps.values, eps, rtol=1e-12):
        raise ValueError(f"chunks hold eps {parts.eps.values.tolist()}, expected {eps.tolist()}")
    ds = parts.assign_coords(eps=eps, b=bs)
    flagged = (ds.transient_over.values == 0) | (ds.steady.values == 0) | (ds.status_code.values != 0)
    ds["flagged"] = ("eps", flagged.astype(np.int8))
    ds["lambda_1_grid"] = (("eps", "b"), np.repeat(ds.lambda_1.values[:, None], bs.size, axis=1),
                           cf.attrs("lambda_1(eps, b) = lambda_1(eps, 1) by the length-scale symmetry", "rate"))
    ds["status"] = ("eps", np.array([STATUS[int(c)] for c in ds.status_code.values], dtype=object))
    arithmetic = Precision.parse(steady_arithmetic(cfg)["precision"])
    names, follow = faithful_words(ds.faithful_code.values, arithmetic)
    ds["faithful_arithmetic"] = ("eps", np.array(names, dtype=object))
    ds["lambda_1_follows"] = ("eps", np.array(follow, dtype=object))
    ds["row_verdict_flag"] = cf.flags("eps", ds.row_verdict.values, ROW_VERDICT_FLAGS, "the row's verdict as a CF flag")
    ref = reference_row(cfg)
    ok = ~flagged
    ds.attrs.update(
        rule=next(c.attrs["rule"] for c in chunks if c.attrs["rule"]), reference_eps=float(eps[ref]),
        eps_elsewhere=eps[elsewhere(cfg)], elsewhere_config=cfg.get("elsewhere", {}).get("config", ""),
        reference_rel_err=float(ds.stderr.values[ref] / abs(ds.lambda_1.values[ref])),
        b_check=np.asarray(cfg["b_check"], float), b_check_max_diff=float(ds.b_check_max_diff.values[ref]),
        b_check_bound=float(ds.b_check_bound.values[ref]),
        b_check_consistent=int(ds.b_check_max_diff.values[ref] <= ds.b_check_bound.values[ref]),
        uncertainty="standard error of the mean over independent replicas (points along the settled orbit, "
                    f"{cfg['replica_spacing']:g} slow time units apart)",
        horizon_rule=f"pre-run max(t_pre_min, t_pre (eps_ref / eps)^2), t_pre = {cfg['t_pre']:g}; replica spacing, "
                     "T_round, t_align and tau scaled by eps_ref / eps (the spike cycle)",
        flag_rule="transient not over, or a replica's omega block means drift by more than transient.rtol, or "
                  "lambda_1 not resolved (status regular or capped), or the row left to another config (elsewhere)",
        n_rows=int(eps.size), n_points=int(eps.size * bs.size), fraction_flagged=float(flagged.mean()),
        gauge_rule=GAUGE_RULE, n_rows_followed=int(sum(f == FOLLOWS for f in follow)),
        row_verdict_rule=ROW_VERDICT_RULE, vote_record=cfg["vote_record"],
        **{f"verdict_{k}": v for k, v in cfg["verdict"].items()},
        min_lambda_1=float(np.nanmin(ds.lambda_1.values)), max_lambda_1=float(np.nanmax(ds.lambda_1.values)),
        min_lambda_1_unflagged=float(np.nanmin(ds.lambda_1.values[ok])) if ok.any() else math.nan,
        cost_total_s=float(np.nansum(ds.wall_time_s.values)), transient_tol=cfg["tol"],
        transient_precision=Precision.DOUBLE,
        resolve_budget_s=float(cfg.get("resolve_budget_s", math.nan)),
        **steady_arithmetic(cfg), energy_label=cfg["energy_label"], scene=scene,
        settled_state=ds.row_settled_state.values.ravel(), **_observed(ds, ref),
    )
    return ds


def _observed(ds: xr.Dataset, ref: int) -> dict:
    """The grid's ladder observables (1/time): lambda_1 at the reference row and at the row where it
    is smallest (over the rows computed), each with its row's standard error over replicas."""
    lam = ds.lambda_1.values
    low = int(np.nanargmin(lam))
    return {"lambda_1_reference": float(lam[ref]), "lambda_1_reference_uncertainty": float(ds.stderr.values[ref]),
            "lambda_1_smallest": float(lam[low]), "lambda_1_smallest_uncertainty": float(ds.stderr.values[low]),
            "lambda_1_smallest_eps": float(ds.eps.values[low])}


#: Keys the lyapunov_grid work model reads (everything else of such a block is outside the model).
WORK_KEYS = ("eps_range", "n_eps", "n_chunks", "reference_eps", "t_pre", "t_pre_min", "replicas",
             "replica_spacing", "t_align", "T_round", "max_rounds", "poincare_span", "b_check", "eps", "T_gain",
             "eps_min", "realizations", "T")


def grid_rows(cfg: dict, *, verdict: bool = True) -> list[tuple[float, float]]:
    """(eps, work) of every row of a lyapunov_grid block, following :func:`row`, in time units
    integrated at slow time s = reference_eps / eps:

    - pre-run: max(t_pre_min, t_pre s^2) (one trajectory);
    - replica sampling: replicas x replica_spacing x s (one trajectory through the replicas' states);
    - tangent batch: (t_align + T_round x max_rounds) x s, counted once: the replicas are the SIMD
      lanes of one batch (the brief's n_b / batch_size), and max_rounds is the cap (rows that converge
      earlier cost less; target_rel is not modelled);
    - Poincare crossings: poincare_span x s;
    - the faithfulness gauge: T_gain x s (one orbit with its 4 x 4 tangent map);
    - the reference row also runs one round per b_check value: len(b_check) x (t_align + T_round) x s;
    - the row's verdict from verdict.eps_min on: verdict.realizations x verdict.T x MARGIN x s, the row's spike
      period taken as s times the record's (``grid_verdict``; the lanes run double-double where the gauge asks,
      which the model does not know before the run).

    n_b costs nothing: b is an exact symmetry and every row is computed once at b = 1; a row left to
    another config (``elsewhere``) costs nothing here. ``verdict=False`` leaves the verdict's term out (the cost
    estimate prices it by the row's steps per cycle instead: ``sleighsim.ops.rowprices``)."""
    eps_all, _ = axes(cfg)
    ref, away = reference_row(cfg), elsewhere(cfg)
    rows = []
    for i, eps in enumerate(eps_all):
        if away[i]:  # left to another config: no work here
            rows.append((float(eps), 0.0))
            continue
        s = slow_time(cfg, eps)
        w = pre_run(cfg, eps) + cfg["replicas"] * cfg["replica_spacing"] * s
        w += (cfg["t_align"] + cfg["T_round"] * cfg["max_rounds"]) * s + cfg.get("poincare_span", 0.0) * s
        w += cfg.get("T_gain", 0.0) * s
        if i == ref:
            w += len(cfg.get("b_check") or ()) * (cfg["t_align"] + cfg["T_round"]) * s
        judged = cfg.get("verdict")  # a measured run's config from before row verdicts has none
        if verdict and judged and eps >= judged["eps_min"]:
            w += judged["realizations"] * judged["T"] * MARGIN * s
        rows.append((float(eps), float(w)))
    return rows


def chunk_work(cfg: dict) -> list[float]:
    """Work of each chunk job: chunk k computes rows k, k + n_chunks, ... (:func:`grid_rows`)."""
    rows, n = grid_rows(cfg), cfg["n_chunks"]
    return [sum(w for _, w in rows[k::n]) for k in range(n)]


def _checks(w, cfg):
    increasing(f"{w}.eps_range", cfg["eps_range"], strict=False)
    increasing(f"{w}.b_range", cfg["b_range"], strict=False)
    if cfg["n_chunks"] > cfg["n_eps"]:
        raise ConfigError(f"{w}.n_chunks = {cfg['n_chunks']} must lie in [1, n_eps = {cfg['n_eps']}] "
                          "(a chunk holds whole eps rows)")
    lo, hi = cfg["eps_range"]
    if not lo <= cfg["reference_eps"] <= hi:
        raise ConfigError(f"{w}.reference_eps = {cfg['reference_eps']} must lie in eps_range [{lo}, {hi}]")
    try:
        elsewhere(cfg)
    except ValueError as bad:
        raise ConfigError(f"{w}.{bad}") from None


def _replica_stretch(cfg: dict) -> memory.Span:
    """The record of the stretch through a row's replicas (:func:`_replicas`), at the slowest row: replicas x
    replica_spacing x reference_eps / min(eps) sampled every spike_dt (or 400 samples per spacing)."""
    horizon = cfg["replicas"] * cfg["replica_spacing"] * cfg["reference_eps"] / min(cfg["eps_range"])
    step = min(cfg.get("spike_dt", 0.5), horizon / cfg["replicas"] / 400)
    return memory.span(cfg, ("replicas x replica_spacing x reference_eps / min(eps_range)", horizon),
                       ("spike_dt", step), 5)


LYAPUNOV_GRID = SceneKind(
    name="lyapunov_grid",
    title="the largest Lyapunov exponent over a grid of (eps, b) rows at one energy label",
    chunk=chunk, gather=gather, observables=("lambda_1_reference", "lambda_1_smallest"), inputs=("power",),
    records=lambda c: [*memory.pre_run(c, "t_pre"), *memory.benettin(c, 5),
                       memory.span(c, ("n_eps x n_b", c["n_eps"] * c["n_b"]), None, 20), _replica_stretch(c),
                       # a row's verdict lanes (T / dt samples whatever the row's scale): as the decisive stage's
                       memory.span(c, "verdict.T", "verdict.dt", 40, ("verdict.realizations",
                                                                      c["verdict"]["realizations"]))],
    work=lambda cfg: sum(w for _, w in grid_rows(cfg)), chunk_work=chunk_work, modelled=lambda leaf: leaf in WORK_KEYS,
    chunk_holds=lambda cfg, k: [e for e, _ in grid_rows(cfg)[k::cfg["n_chunks"]]],
    checks=_checks, pre_run="t_pre")
