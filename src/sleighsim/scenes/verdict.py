"""Is the steady state chaotic? A verdict per steady state from independent indicators, and the
class of each state in the reversible system (the report's first answer).

The indicators, their judges and the decision rule are in ``sleighsim.chaos``; the sleigh's runs for
them are in :mod:`~sleighsim.scenes.verdict_tangent`, :mod:`~sleighsim.scenes.verdict_orbits` and
:mod:`~sleighsim.scenes.verdict_frequency`, the dataset's variables in
:mod:`~sleighsim.scenes.verdict_dataset`. This module runs each state, cuts the scene into chunk
jobs, gathers them and declares the kind."""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.chaos.faithfulness import indicator_follows
from sleighsim.chaos.loschmidt import loschmidt_indicator
from sleighsim.chaos.megno import megno_rate
from sleighsim.chaos.power import stage_vote
from sleighsim.chaos.rule import (
    AGREE_RULE,
    FRAGILE,
    INDICATORS,
    TANGENT_BASED,
    VOTE_RULE,
    agree,
    classify,
    consistent,
    decide,
    faithful_gate,
    vote_gate,
)
from sleighsim.chaos.two_trajectory import two_trajectory_indicator
from sleighsim.chaos.verdicts import CHAOTIC, VERDICTS
from sleighsim.engine import integrators
from sleighsim.engine.ddbatch import MAX_LANES, MAX_WIDTH
from sleighsim.engine.integrate import orbit_samples
from sleighsim.engine.transient import settle
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset
from sleighsim.io.yamlfile import read_yaml
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.common import REALIZATION_STATES_RULE, realization_states
from sleighsim.scenes.grid_verdict import cycle_scale
from sleighsim.scenes.kind import SceneKind
from sleighsim.scenes.verdict_dataset import set_attrs, variables
from sleighsim.scenes.verdict_decisive import REALIZED_VARS, decisive_lanes, decisive_spike_period, with_decisive
from sleighsim.scenes.verdict_frequency import (
    PRECISIONS,
    frequency_indicator,
    frequency_resolved,
    frequency_table,
)
from sleighsim.scenes.verdict_lanes import pack, unpack
from sleighsim.scenes.verdict_orbits import (
    loschmidt_not_run,
    loschmidt_run,
    loschmidt_T,
    r_image,
    two_trajectory_runs,
)
from sleighsim.scenes.verdict_tangent import (
    gain_run,
    replica_run,
    tangent_indicators,
)
from sleighsim.scenes.workload import HORIZON_KEYS, horizon_work

log = logging.getLogger("sleighsim")


def one_state(params, y0, cfg: dict, scene: str, voters: set, *, decisive: bool) -> dict:
    """Every indicator, the classification and the settling facts for the state reached from y0; only
    the indicators in ``voters`` (``chaos.rule.vote_gate``) vote. A state the decisive stage judges
    again (``decisive``) gets no long-double runs (the precision check, the frequency and Loschmidt
    runs): where that stage runs, the gauge has shown that long double does not follow the orbit
    closely enough for them (``verdict_decisive``), so they would decide nothing."""
    tol, tau, sigma = cfg["tol"], cfg["tau"], cfg["sigma"]
    y, pre = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=tol, label=scene, progress=1)
    replicas, record = orbit_samples(params, y, cfg["replicas"], cfg["replica_spacing"], tol=tol, scene=scene)
    mean_u_omega = np.array([record.u.values.mean(), record.omega.values.mean()])
    res = replica_run(params, replicas, cfg, scene)
    gain = gain_run(params, replicas[0], cfg)
    values, errors, verdicts = {}, {}, {}
    m, ld, megno_double, megno_precision = tangent_indicators(params, replicas, res, cfg, scene,
                                                              values, errors, verdicts, long_double=not decisive)
    freq = frequency_indicator(params, replicas[0], cfg, sigma, long_double=not decisive)
    values["frequency"], errors["frequency"], verdicts["frequency"] = freq["value"], freq["error"], freq["verdict"]
    L = loschmidt_run(params, replicas[0], cfg)
    if decisive:
        L_ld, los = loschmidt_not_run(L, sigma)
    else:
        L_ld = loschmidt_run(params, replicas[0], cfg, precision=Precision.LONG_DOUBLE)
        los = loschmidt_indicator(L, L_ld, sigma)
    values["loschmidt"], errors["loschmidt"], verdicts["loschmidt"] = los["value"], los["error"], los["verdict"]
    flow, tts = two_trajectory_runs(params, replicas[-1], cfg)
    two = two_trajectory_indicator(tts, cfg["d0"], tau, sigma)
    values["two_trajectory"], errors["two_trajectory"] = two["value"], two["error"]
    verdicts["two_trajectory"] = two["verdict"]
    D = Precision.DOUBLE
    arithmetic = {"benettin": D, "ftle": D, "megno": megno_precision, "two_trajectory": D,
                  "loschmidt": Precision.LONG_DOUBLE, "frequency": list(freq["runs"])[-1]}
    faithful_gate(verdicts, arithmetic, indicator_follows(gain["ln_gain_max"], arithmetic,
                                                          {"frequency": frequency_resolved(freq)},
                                                          steps_per_cycle=gain["steps_per_cycle"]))
    vote_gate(verdicts, voters)
    verdict, reason, _ = decide(verdicts, TANGENT_BASED)
    others = {k: (values[k], errors[k]) for k in INDICATORS if k not in TANGENT_BASED and verdicts[k][0] == CHAOTIC}
    verdict, reason = consistent(verdict, reason, values["benettin"], errors["benettin"], others, sigma)
    klass, s, s_err, image, image_dist = _class_facts(params, replicas[0], mean_u_omega, res, verdict, cfg, scene)
    lam, tt = res["exponents"], tts[len(tts) // 2]
    return {"verdict": verdict, "reason": reason, "klass": klass, "values": values, "errors": errors,
            "settled": np.asarray(replicas[0], float),
            "verdicts": verdicts,
            "two_rates": [t["rate"] for t in tts], "two_stderrs": [t["stderr"] for t in tts],
            "megno_t": m["t"], "megno_Y_mean": m["Y_mean"], "megno_final": m["final"],
            "megno_t_ld": _or_nan(ld["megno"], "t", m["t"].size),
            "megno_Y_mean_ld": _or_nan(ld["megno"], "Y_mean", m["t"].size),
            "megno_rate_double": megno_rate(m)[0], "megno_rate_double_err": megno_rate(m)[1],
            "megno_verdict_double": megno_double[0], "megno_precision": megno_precision,
            "loschmidt_error": L["rel_error"], "loschmidt_error_ld": L_ld["rel_error"],
            "loschmidt_power": L_ld["pow_exponent"], "loschmidt_power_err": L_ld["pow_exponent_err"],
            "loschmidt_tail_power": L_ld["tail_pow_exponent"],
            "loschmidt_tail_power_err": L_ld["tail_pow_exponent_err"],
            "loschmidt_n_used": [L["n_used"], L_ld["n_used"]], "loschmidt_tail_n": [L["tail_n"], L_ld["tail_n"]],
            "loschmidt_floor": [L["floor"] / L["scale"], L_ld["floor"] / L_ld["scale"]],
            "loschmidt_verdict_double": los["verdict_double"], "frequency": freq, "ld_lambda_1": ld["lambda_1"],
            "ld_stderr": ld["stderr"], "ld_check": ld["check"],
            "exponents": lam, "stderr": res["stderr"], "T": float(res["T"]), "status": res["status"], "sum_all": s,
            "sum_err": s_err, "r_image": image, "r_image_distance": image_dist, "mean_u": float(mean_u_omega[0]),
            "mean_omega": float(mean_u_omega[1]), "transient_over": int(pre["transient_over"]), "T_two": float(tt["T"]),
            "gain": gain,
            "drift": float(abs(equations.energy(integrators.read(flow, 4), params) / equations.energy(y0, params) - 1))}


def _class_facts(params, y, mean_u_omega, res: dict, verdict: str, cfg: dict, scene: str) -> tuple:
    """The class of the state (``chaos.rule.classify``) from the verdict, the replicas' sum of
    exponents (mean and standard error) and where R sends y (``r_image``). Returns (class, sum,
    its stderr, R-image, its distance)."""
    sums = res["per_replica"].sum(axis=1)
    s, s_err = float(sums.mean()), float(sums.std(ddof=1) / math.sqrt(cfg["replicas"]))
    image, image_dist = r_image(params, y, mean_u_omega, T=cfg["T_R"], tol=cfg["tol"], rtol=cfg["R_rtol"], scene=scene)
    lam = res["exponents"]
    return classify(verdict, s, s_err, float(lam[0]), float(lam[3]), image, cfg["sigma"]), s, s_err, image, image_dist


def _or_nan(run, key, n):
    """run[key], or n NaNs when the run was not made."""
    return np.full(n, math.nan) if run is None else run[key]


def verdict(cfg: dict, scene: str = "", *, voters: frozenset) -> xr.Dataset:
    """The chaos verdict per steady state of cfg["states"] (name -> start state, scaled to the
    energy label): indicators (Benettin over independent replicas, the finite-time-exponent
    spread, MEGNO; two nearby orbits, the Loschmidt return error and frequency analysis without
    tangent dynamics), combined by chaos.rule.DECISION_RULE;
    the sum of exponents over replicas and the R-image test give the class."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    names = list(cfg["states"])
    out = []
    for name in names:
        y0 = state_at_label(cfg["states"][name], params, cfg["energy_label"])
        out.append(one_state(params, y0, cfg, f"{scene}[{name}]", set(voters),
                             decisive=name in cfg["decisive"]["states"]))
        log.info("%s: %s: %s (%s); %s", scene, name, out[-1]["verdict"], out[-1]["klass"], out[-1]["reason"])
    ind = list(INDICATORS)
    fc = cfg["frequency"]
    ft = frequency_table([o["frequency"] for o in out], fc["splits"])

    def per_state(key):
        return np.array([o[key] for o in out])

    ds = xr.Dataset(
        variables(per_state, out, ind, ft),
        coords={"state": names, "indicator": ind, "i": np.arange(1, 5), "d0": np.asarray(cfg["d0"], float),
                "T_loschmidt": loschmidt_T(cfg), "precision": [Precision.DOUBLE, Precision.LONG_DOUBLE],
                "split": np.asarray(fc["splits"], int), "frequency_precision": list(PRECISIONS),
                "arithmetic": [p.value for p in Precision], "component": list(equations.STATE_NAMES),
                "tangent_based": ("indicator", [int(i in TANGENT_BASED) for i in ind])},
    )
    set_attrs(ds, cfg, params, per_state, start)
    return ds


def chunk(cfg: dict, index: int, scene: str = "", reads=(), inputs=None) -> xr.Dataset:
    """Job ``index`` of the verdict (one chunk job each). The first stage, index < n_chunks x n_states:
    state index % n_states of realization index // n_states, :func:`verdict` from that state of
    :func:`realization_states` at realization_rel (the states of a realization are perturbed together,
    in order, so a state's start does not depend on how the jobs are cut). The decisive stage, one job
    after those: every realization's first-stage dataset of every state of decisive.states (``reads``,
    :func:`_chunk_reads`) as the lanes of one integration (``verdict_decisive.decisive_lanes``), packed
    into one dataset (``verdict_lanes.pack``). In both, the indicators that vote are those the judge-power
    audit's record (``inputs["power"]``, the block's vote_record) lets vote with the stage's settings at its
    horizon (``chaos.power.stage_vote``; the decisive stage's states no longer in spike cycles than audited)."""
    names, base = list(cfg["states"]), _stage_one_count(cfg)
    record = read_yaml(inputs["power"])
    if index >= base:
        lanes = [_lane_vote(record, cfg, read_dataset(path)) for path in reads]
        order = _job_lanes(cfg, index - base)
        parts = decisive_lanes(cfg, lanes, [f"{scene}#{r}[{name}]" for r, name in order])
        ds = pack(parts, [r for r, _ in order])
        ds.attrs.update(n_chunks=cfg["n_chunks"], vote_rule=VOTE_RULE)
        return ds
    voters = frozenset(stage_vote(record, cfg, "first")["voters"])
    r, k = divmod(index, len(names))
    start = realization_states(cfg["states"], cfg["realization_rel"], r)[names[k]]
    ds = verdict({**cfg, "states": {names[k]: start}}, scene=f"{scene}#{r}", voters=voters)
    ds.attrs.update(chunk=r, n_chunks=cfg["n_chunks"], voters=sorted(voters), vote_rule=VOTE_RULE)
    return ds


def _lane_vote(record: dict, cfg: dict, stage1: xr.Dataset) -> tuple:
    """One decisive lane: (the first stage's dataset of its state, its voters, its vote horizon, why and its
    cycle_scale) by the record (``chaos.power.stage_vote``). A state whose spike period P exceeds the record's
    P_a is run over the audited cycles instead, T and dt times MARGIN x P / P_a (as F11's rows,
    ``grid_verdict``), and voted by the record at the block's own settings; else at its spike period."""
    period = float(stage1.spike_period.values[0])
    scale = cycle_scale(period, record) if period > float(record.get("spike_period", math.nan)) else 1.0
    vote = stage_vote(record, cfg, "decisive", period if scale == 1.0 else math.nan)
    factor = max(vote["factor"].values(), default=math.nan)  # the audited horizon voted at (NaN: none)
    why = "" if vote["covered"] else "; ".join(dict.fromkeys(vote["why"].values()))  # no horizon would vote
    return stage1, frozenset(vote["voters"]), {"vote_horizon": factor, "vote_why": why, "cycle_scale": scale}


def _stage_one_count(cfg: dict) -> int:
    """The first stage's chunk jobs: one per realization and state."""
    return cfg["n_chunks"] * len(cfg["states"])


def _decisive_lanes(cfg: dict) -> list[tuple[int, str]]:
    """The decisive stage's lanes, (realization, state): realizations outer, decisive.states inner."""
    return [(r, name) for r in range(cfg["n_chunks"]) for name in cfg["decisive"]["states"]]


def _decisive_jobs(cfg: dict) -> int:
    """The decisive stage's jobs: decisive.jobs or, when unset, one per block of the host's widest vector
    (``ddbatch.MAX_WIDTH`` lanes), so that its blocks run side by side rather than one after another; none
    without decisive states."""
    if not cfg["decisive"]["states"]:
        return 0
    return int(cfg["decisive"].get("jobs") or math.ceil(len(_decisive_lanes(cfg)) / MAX_WIDTH))


def _job_lanes(cfg: dict, job: int) -> list[tuple[int, str]]:
    """The lanes of decisive job ``job``: ``_decisive_lanes`` cut into _decisive_jobs contiguous parts, as even as
    they go (the first ones one longer)."""
    lanes = _decisive_lanes(cfg)
    n, k = divmod(len(lanes), _decisive_jobs(cfg))
    start = job * n + min(job, k)
    return lanes[start:start + n + (job < k)]


def _chunk_reads(cfg: dict, index: int) -> list[int]:
    """The first-stage chunks a decisive job reads (each of its lanes' realization's job of its state, in
    ``_decisive_lanes`` order); none for a first-stage chunk."""
    base = _stage_one_count(cfg)
    if index < base:
        return []
    names = list(cfg["states"])
    return [r * len(names) + names.index(name) for r, name in _job_lanes(cfg, index - base)]


def _states_together(parts: list, names: list) -> xr.Dataset:
    """One realization's dataset from its per-state jobs, in the config's state order (ln G per cycle
    NaN-padded to the longest); its transient is over when every state's is, its wall time is their sum."""
    parts = sorted(parts, key=lambda d: names.index(str(d.state.values[0])))
    if [str(d.state.values[0]) for d in parts] != names:
        raise ValueError(f"realization {parts[0].attrs['chunk']}: states {[str(d.state.values[0]) for d in parts]}, "
                         f"expected {names}")
    width = max(d.sizes.get("cycle", 0) for d in parts)
    parts = [d.pad(cycle=(0, width - d.sizes["cycle"])) if "cycle" in d.dims else d for d in parts]
    ds = xr.concat(parts, dim="state", data_vars="minimal", coords="minimal", compat="override",
                   combine_attrs="override")
    ds.attrs.update(transient_over=int(all(d.attrs["transient_over"] == 1 for d in parts)),
                    wall_time_s=float(sum(d.attrs["wall_time_s"] for d in parts)))
    return ds


#: The verdicts a state can have over its realizations, in the order of their CF flag values.
VERDICT_FLAGS = (*VERDICTS, FRAGILE)


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """The verdict over realizations (each gathered from its per-state jobs): realization 0's dataset
    (its indicators, runs and gauge), with
    each realization's verdict and class, and per state the answer they agree on
    (``chaos.rule.agree``: "fragile" when they do not) and how many give the most common one."""
    by_realization, decisive = {}, {}
    for d in (read_dataset(p) for p in paths):
        if d.attrs.get("stage") == "decisive":
            for r, lane in unpack(d):
                decisive.setdefault(r, []).append(lane)
        else:
            by_realization.setdefault(int(d.attrs["chunk"]), []).append(d)
    if sorted(by_realization) != list(range(cfg["n_chunks"])):
        raise ValueError(f"realizations {sorted(by_realization)}, expected 0 ... {cfg['n_chunks'] - 1}")
    names = list(cfg["states"])
    chunks = [with_decisive(_states_together(by_realization[r], names), decisive.get(r, []))
              for r in range(cfg["n_chunks"])]
    ds = chunks[0].copy()
    for var, out in (("verdict", "realization_verdict"), ("reason", "realization_reason"),
                     ("state_class", "realization_class")):
        ds[out] = (("realization", "state"), np.array([c[var].values for c in chunks], dtype=object))
    if all("spike_period" in c for c in chunks):
        ds["realization_spike_period"] = (("realization", "state"), [c.spike_period.values for c in chunks],
                                          cf.attrs("the torus each realization reached: its median spike interval",
                                                   "time"))
    if all("decisive_spike_interval" in c for c in chunks):
        ds["realization_decisive_spike_period"] = (("realization", "state"),
                                                   [decisive_spike_period(c) for c in chunks])
    for name in REALIZED_VARS:
        if all(name in c for c in chunks):
            ds[f"realization_{name}"] = (("realization", "state"), [c[name].values for c in chunks],
                                         chunks[0][name].attrs)
    verdicts = [agree(ds.realization_verdict.values[:, i]) for i in range(ds.sizes["state"])]
    classes = [agree(ds.realization_class.values[:, i]) for i in range(ds.sizes["state"])]
    ds["verdict"] = ("state", np.array([v for v, _, _ in verdicts], dtype=object))
    ds["reason"] = ("state", np.array([f"{why}; realization 0: {r}" for (_, _, why), r in
                                       zip(verdicts, chunks[0].reason.values)], dtype=object))
    ds["state_class"] = ("state", np.array([v for v, _, _ in classes], dtype=object))
    ds["n_realizations_agreeing"] = ("state", [n for _, n, _ in verdicts],
                                     cf.attrs("realizations that give the most common verdict"))
    ds["verdict_flag"] = cf.flags("state", ds.verdict.values, VERDICT_FLAGS, "the verdict as a CF flag")
    ds["realization_verdict_flag"] = cf.flags(("realization", "state"), ds.realization_verdict.values, VERDICT_FLAGS,
                                              "each realization's verdict as a CF flag")
    ds = ds.assign_coords(realization=np.arange(len(chunks)))
    ds.attrs.pop("chunk", None)
    ds.attrs.update(n_realizations=len(chunks), realization_rel=cfg["realization_rel"],
                    realization_rule=" ".join((REALIZATION_STATES_RULE, AGREE_RULE)),
                    wall_time_s=float(sum(c.attrs["wall_time_s"] for c in chunks)))
    return ds


def _chunk_count(cfg: dict) -> int:
    """One chunk job per realization and state (the first stage), then decisive.jobs for the decisive stage when
    it has states (:func:`chunk`)."""
    return _stage_one_count(cfg) + _decisive_jobs(cfg)


def _checks(where: str, cfg: dict) -> None:
    """The decisive stage's states are states of the block, each once, and its lanes (realizations x states)
    fit one batch (``engine.ddbatch.MAX_LANES``)."""
    states, dec = list(cfg["states"]), list(cfg["decisive"]["states"])
    if not set(dec) <= set(states) or len(set(dec)) != len(dec):
        raise ConfigError(f"{where}.decisive.states: {dec} must name states of {where}.states ({states}), each once")
    jobs, lanes = _decisive_jobs(cfg), len(_decisive_lanes(cfg))
    if jobs > lanes:
        raise ConfigError(f"{where}.decisive.jobs = {jobs}: more jobs than the {lanes} lanes (n_chunks x "
                          f"decisive.states)")
    if jobs and len(_job_lanes(cfg, 0)) > MAX_LANES:
        raise ConfigError(f"{where}.decisive.states: {len(dec)} states x n_chunks = {cfg['n_chunks']} realizations "
                          f"would make {len(_job_lanes(cfg, 0))} lanes of a decisive job (decisive.jobs = {jobs}); "
                          f"at most {MAX_LANES}")


def _chunk_work(cfg: dict) -> list[float]:
    """Work of each chunk job: one state of one realization, an equal share of the block's horizons
    outside the decisive stage; then each decisive job, that stage's horizons once per lane of it (an upper
    estimate: lanes share the vector units) (a block without n_chunks or a decisive stage, measured before
    the verdict ran them, has none of those jobs)."""
    n, states = cfg.get("n_chunks", 1), len(cfg["states"])
    decisive = cfg.get("decisive", {"states": []})
    first = {k: v for k, v in cfg.items() if k != "decisive"}
    jobs = [len(_job_lanes(cfg, j)) for j in range(_decisive_jobs(cfg))] if decisive["states"] else []
    return [horizon_work(first) / states] * (n * states) + [horizon_work(decisive) * lanes for lanes in jobs]


CHAOS_VERDICT = SceneKind(
    name="chaos_verdict",
    title="is the steady state chaotic? Indicators, their verdicts and the faithfulness gauge per start state",
    chunk=chunk, gather=gather, chunk_count=_chunk_count, chunk_reads=_chunk_reads,
    inputs=("power",),
    checks=_checks, pre_run="t_transient",
    records=lambda c: [*memory.pre_run(c, "t_transient"), *memory.benettin(c, 8),
                       memory.span(c, "frequency.T", "frequency.dt", 4 * max(c["frequency"]["splits"])),
                       memory.span(c, "megno_samples", None, 2),
                       # the decisive job's lanes: hi, lo, scale, tangent and the kernels' blocks per sample
                       memory.span(c, "decisive.T", "decisive.dt", 40,
                                   ("the lanes of a decisive job", len(_job_lanes(c, 0)) if c["decisive"]["states"]
                                    else 0))],
    work=lambda cfg: sum(_chunk_work(cfg)), chunk_work=_chunk_work,
    modelled=lambda leaf: leaf in HORIZON_KEYS or leaf == "n_chunks")
