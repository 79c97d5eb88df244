"""The chaos verdict's decisive stage: a state whose orbit double and long double do not follow (the
faithfulness gauge), run again from its settled state in an arithmetic that does, one chunk job per
realization (:mod:`sleighsim.scenes.verdict` cuts the jobs and reads the first stage's dataset in).

From one orbit in the decisive arithmetic: MEGNO and the return map's MEGNO (tangent-based; only
when one of them votes at the stage's horizon, ``needs_tangent``, else the orbit alone, about a
third of the work), and without tangent dynamics the frequency analysis of the velocity
frequency.component sampled every dt, the weighted Birkhoff averages and the spike train (the torus
the realization is on: its spike intervals). The state's verdict is then decided again
(``chaos.rule.decide``) from these and the first stage's indicators, every one gated by its own
limit of G x rounding (``chaos.faithfulness.indicator_limit``). Times in the flow's time unit."""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.analysis.path import path, shape
from sleighsim.analysis.volume import CYCLE_MEAN_RULE, cycle_mean, hermite_integrals
from sleighsim.chaos import decisive
from sleighsim.chaos.birkhoff import observables
from sleighsim.chaos.bounds import BOUND_RULE, regular_bound
from sleighsim.chaos.faithfulness import FOLLOWS, indicator_follows, injected_rounding
from sleighsim.chaos.indicators import DECISIVE as DECISIVE_STAGE
from sleighsim.chaos.indicators import record_names
from sleighsim.chaos.rule import TANGENT_BASED, classify, consistent, decide, faithful_gate, vote_gate
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED
from sleighsim.engine import transient
from sleighsim.io import cf
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.precision import Precision
from sleighsim.scenes.verdict_decisive_orbits import lane_orbits

log = logging.getLogger("sleighsim")

#: The indicators the decisive stage judges (again), in its arithmetic (the others keep the first stage's).
DECISIVE = ("megno", "section_megno", "frequency", "birkhoff")
#: The variables of the mean divergence over the decisive orbit's whole cycles and of its path's shape (each
#: realization's kept by the gather).
REALIZED_VARS = ("decisive_mean_divergence", "decisive_mean_divergence_stderr",
                 "decisive_mean_divergence_quadrature", "decisive_divergence_cycles", "decisive_path_growth",
                 "decisive_path_reach", "decisive_path_recurrence")
#: Those of them that read the tangent vector.
TANGENT_JUDGED = ("megno", "section_megno")


def needs_tangent(voters) -> bool:
    """Whether the stage integrates a tangent vector: only when one of its tangent-based judges
    (TANGENT_JUDGED) votes at its horizon; otherwise their verdicts could not count (``vote_gate``)."""
    return any(k in voters for k in TANGENT_JUDGED)


def section_megno_judged(orbit: dict, dc: dict, sigma: float) -> dict:
    """The return map's MEGNO at the spike section (``chaos.decisive.section_megno_judged`` at the spikes of
    Omega, ``spike_train``'s section); value: the exponent it implies (1/time) and its error."""
    spikes = transient.spike_times(orbit["t"], orbit["Y"][:, 1], factor=dc["spike_factor"])
    return decisive.section_megno_judged(orbit["t"], orbit["log_norm"], spikes, dc["T"], sigma)


def not_run(name: str, dc: dict) -> dict:
    """A tangent-based indicator the stage did not compute: it does not vote at the stage's horizon."""
    return {"run": None, "value": math.nan, "error": math.nan,
            "verdict": (UNDECIDED, f"not run: {name} does not vote at vote_horizon {dc['vote_horizon']:g} (the "
                                   "judge-power record), so the stage integrates no tangent vector")}


def megno_judged(orbit: dict, dc: dict, sigma: float) -> dict:
    """The MEGNO indicator from the decisive orbit's tangent log-norm over dc["T"]
    (``chaos.decisive.megno_judged``: the trapezoid rule on the log-norm, dc["megno_samples"] points)."""
    return decisive.megno_judged(orbit["t"], orbit["log_norm"], dc["megno_samples"], dc["T"], sigma)


def frequency_stage(orbit: dict, dc: dict, sigma: float) -> dict:
    """The frequency analysis (``chaos.decisive.frequency_judged``) of the orbit's component dc["component"]
    over windows dc["T"] / K, K in dc["splits"]."""
    x = orbit["Y"][:-1, equations.STATE_NAMES.index(dc["component"])]
    return decisive.frequency_judged(x, dc["dt"], dc["splits"], dc["min_cycles"], dc["precision"], sigma)


def birkhoff_stage(orbit: dict, dc: dict, gain_rounding: float) -> dict:
    """The weighted Birkhoff averages (``chaos.decisive.birkhoff_judged``) of the orbit's smooth observables
    (u, Omega, omega, cos delta, sin delta) over windows dc["T"] / K, K in dc["splits"], with the decisive
    arithmetic's G x injected rounding."""
    obs = observables(orbit["Y"][:-1], angles=[equations.DELTA])
    return decisive.birkhoff_judged(obs, dc["dt"], dc["splits"], gain_rounding)


def spike_train(orbit: dict, dc: dict) -> np.ndarray:
    """The spike intervals of the orbit (Omega's spikes, ``engine.transient.spike_times`` with
    dc["spike_factor"]): which torus the realization is on, one interval per cycle."""
    t, Omega = orbit["t"], orbit["Y"][:, 1]
    spikes = transient.spike_times(t, Omega, factor=dc["spike_factor"])
    return np.diff(spikes)


def derivatives(orbit: dict, params: Params) -> tuple[np.ndarray, np.ndarray]:
    """The first and second time derivatives of the decisive orbit at its samples (f, J f)."""
    f = equations.rhs(orbit["Y"], params)
    return f, equations.second_derivative(orbit["Y"], params, f)


def divergence_stage(orbit: dict, dc: dict, params: Params, derivs=None) -> dict:
    """The mean divergence of the flow (trace J; the sum of the Lyapunov exponents) over the decisive orbit's
    whole spike cycles (``analysis.volume``: quintic Hermite quadrature between samples, delta unwrapped; spikes
    as ``spike_train``'s; windows the finest split). ``derivs``: ``derivatives`` of the orbit, if known."""
    t, Y = orbit["t"], orbit["Y"]
    dY, d2Y = derivs or derivatives(orbit, params)
    spikes = transient.spike_times(t, Y[:, 1], factor=dc["spike_factor"])
    smooth = Y.copy()
    smooth[:, equations.DELTA] = np.unwrap(Y[:, equations.DELTA])
    fine, coarse = hermite_integrals(t, smooth, dY, d2Y, lambda y: equations.divergence(y, params))
    return cycle_mean(t, fine, spikes, max(dc["splits"]), coarse=coarse)


def path_stage(orbit: dict, params: Params, derivs=None) -> dict:
    """The shape of the sleigh's path along the decisive orbit (``analysis.path``: growth of its reach over the
    second half, reach, size, recurrence). ``derivs``: ``derivatives`` of the orbit, if known."""
    _, x, y = path(orbit["t"], orbit["Y"], *(derivs or derivatives(orbit, params)), params.b)
    return shape(orbit["t"], x, y)


def stage_one_verdicts(stage1: xr.Dataset) -> dict:
    """{indicator: (verdict, reason)} of the first stage's one state, as it judged them (gated there)."""
    return {str(k): (str(v), str(r)) for k, v, r in zip(stage1.indicator.values, stage1.indicator_verdict.values[0],
                                                       stage1.indicator_reason.values[0])}


#: Written into the chaos_verdict dataset (attribute decisive_rule).
DECIDE_AGAIN_RULE = (
    "The state's verdict with the decisive stage: the first stage's indicator verdicts (each already set aside "
    "there where its arithmetic did not follow closely enough for it), those of DECISIVE replaced by the "
    "decisive stage's (``judged``: name -> dict with verdict and resolved), each of which is set aside unless "
    "the decisive arithmetic follows the orbit closely enough for it (the first stage's ln G per cycle, "
    "``faithfulness.indicator_limit``), and set aside unless it votes (``voters``, ``chaos.rule.vote_gate``); "
    "then ``chaos.rule.decide`` and ``consistent``. Returns (verdict, reason, the verdicts decided from)."
)


def decide_again(stage1: xr.Dataset, judged: dict, precision: str, sigma: float,
                 voters: frozenset) -> tuple[str, str, dict]:
    """Applies :data:`DECIDE_AGAIN_RULE`, the rule as the datasets record it (just above)."""
    verdicts = stage_one_verdicts(stage1)
    verdicts.update({k: judged[k]["verdict"] for k in judged})
    ln_gain = float(stage1.ln_gain_max.values[0])
    follows = indicator_follows(ln_gain, dict.fromkeys(judged, precision),
                                {k: judged[k].get("resolved", math.nan) for k in judged},
                                steps_per_cycle=_steps_per_cycle(stage1))
    first = dict.fromkeys((k for k in verdicts if k not in judged), FOLLOWS)  # gated by the first stage's gauge
    faithful_gate(verdicts, {**dict.fromkeys(verdicts, Precision.DOUBLE), **dict.fromkeys(judged, precision)},
                  {**first, **follows})
    vote_gate(verdicts, voters)
    verdict, reason, _ = decide(verdicts, TANGENT_BASED)
    values = dict(zip(map(str, stage1.indicator.values), stage1.indicator_value.values[0]))
    errors = dict(zip(map(str, stage1.indicator.values), stage1.indicator_uncertainty.values[0]))
    others = {k: (values[k], errors[k]) for k in verdicts
              if k not in TANGENT_BASED and k not in judged and verdicts[k][0] == CHAOTIC}
    verdict, reason = consistent(verdict, reason, float(values["benettin"]), float(errors["benettin"]), others, sigma)
    return verdict, f"decided with the {precision} stage: {reason}", verdicts


def state_class(stage1: xr.Dataset, verdict: str, sigma: float) -> str:
    """The state's class (``chaos.rule.classify``) from the new verdict and the first stage's exponents,
    their sum and the R-image test."""
    lam = stage1.exponent.values[0]
    return classify(verdict, float(stage1.sum_exponents.values[0]), float(stage1.sum_exponents_stderr.values[0]),
                    float(lam[0]), float(lam[3]), str(stage1.R_image.values[0]), sigma)


def decisive_config(cfg: dict) -> dict:
    """The decisive stage's settings: the block's ``decisive`` entries, with the frequency analysis'
    component and min_cycles, the spike rule's factor and the MEGNO renormalisation interval tau."""
    fc = cfg["frequency"]
    return {"component": fc["component"], "min_cycles": fc["min_cycles"],
            "spike_factor": cfg["transient"]["spike_factor"], "tau": cfg["tau"], **cfg["decisive"]}


def decisive_lanes(cfg: dict, lanes: list, scenes: list) -> list[xr.Dataset]:
    """The decisive stage of the first stage's states ``lanes`` (each (its chunk dataset, its voters, its
    vote_horizon, vote_why and cycle_scale)), one lane each of one integration (``lane_orbits``, with a
    tangent vector when any lane's voters need one) over T and dt times the largest cycle_scale (1 unless a
    state's spike period exceeds the audit's): per lane the indicators judged again and the state's verdict
    and class decided again (``judged_lane``). Each lane's wall time is its share of the stage's."""
    start = time.perf_counter()
    scale = max(vote.get("cycle_scale", 1.0) for _, _, vote in lanes)
    params, dc = Params.from_config(cfg["params"]), decisive_config(cfg)
    dc.update(T=dc["T"] * scale, dt=dc["dt"] * scale)
    tangent = any(needs_tangent(voters) for _, voters, _ in lanes)
    log.info("%s: decisive stage: %d lanes in %s over T = %g%s%s", scenes[0].split("#")[0], len(lanes),
             dc["precision"], dc["T"], " with a tangent vector" if tangent else "",
             f" (T and dt x {scale:.4g}: the audited spike cycles of a longer spike period)" if scale != 1 else "")
    orbits = lane_orbits(params, [s.settled_state.values[0] for s, _, _ in lanes], dc, tangent=tangent)
    share = (time.perf_counter() - start) / len(lanes)
    return [judged_lane({**cfg, "decisive": {**cfg["decisive"], **vote, "T": dc["T"], "dt": dc["dt"]}}, stage1,
                        orbit, scene, voters=voters, tangent=tangent, orbit_s=share)
            for (stage1, voters, vote), orbit, scene in zip(lanes, orbits, scenes)]


def four_judges(orbit: dict, dc: dict, sigma: float, gain_rounding: float, *, tangent: bool) -> dict:
    """The decisive judges (DECISIVE) on one orbit: MEGNO and the return map's MEGNO (``not_run`` without a
    tangent vector), the frequency analysis and the Birkhoff averages with the arithmetic's G x rounding."""
    return {"megno": megno_judged(orbit, dc, sigma) if tangent else not_run("megno", dc),
            "section_megno": section_megno_judged(orbit, dc, sigma) if tangent else not_run("section_megno", dc),
            "frequency": frequency_stage(orbit, dc, sigma), "birkhoff": birkhoff_stage(orbit, dc, gain_rounding)}


def judged_lane(cfg: dict, stage1: xr.Dataset, orbit: dict, scene: str, *, voters: frozenset, tangent: bool,
                orbit_s: float) -> xr.Dataset:
    """One lane's dataset: the indicators judged again on its decisive ``orbit``, the state's verdict and class
    decided again (``decide_again``, ``state_class``); ``orbit_s`` its share of the integration's wall time."""
    start = time.perf_counter()
    dc, sigma = decisive_config(cfg), cfg["sigma"]
    gain_rounding = math.exp(float(stage1.ln_gain_max.values[0])) * injected_rounding(
        dc["precision"].rounding, _steps_per_cycle(stage1))
    judged = four_judges(orbit, dc, sigma, gain_rounding, tangent=tangent)
    verdict, reason, gated = decide_again(stage1, judged, dc["precision"], sigma, voters)
    bound = what_regular_bounds(judged, gated, sigma)
    if verdict == REGULAR:
        reason = f"{reason}; {bound['text']}"
    klass = state_class(stage1, verdict, sigma)
    log.info("%s: decisive stage in %s: %s (%s); %s", scene, dc["precision"], verdict, klass, reason)
    variables = _decisive_vars(stage1, judged, orbit, dc, verdict, reason, klass)
    params = Params.from_config(cfg["params"])
    derivs = derivatives(orbit, params)
    variables.update(_divergence_vars(divergence_stage(orbit, dc, params, derivs)))
    variables.update(_path_vars(path_stage(orbit, params, derivs)))
    variables.update(_bound_vars(bound, [k in voters for k in judged]))
    wall = orbit_s + time.perf_counter() - start
    variables["decisive_wall_time_s"] = ("state", [wall], {
        "long_name": "wall-clock time of the decisive stage for this state: its share of the lanes' integration "
                     "and its own judging", "units": "s"})
    ds = xr.Dataset(variables,
                    coords={"state": stage1.state.values, "decisive_indicator": list(judged),
                            "decisive_megno_sample": np.arange(variables["decisive_megno_t"][1][0].size),
                            "decisive_split": np.asarray(dc["splits"], int)})
    ds.attrs.update(decisive_precision=dc["precision"], decisive_tol=dc["tol"], decisive_T=dc["T"],
                    decisive_dt=dc["dt"], decisive_megno_samples=dc["megno_samples"], decisive_steps=orbit["steps"],
                    decisive_splits=list(dc["splits"]), decisive_vote_horizon=float(dc["vote_horizon"]),
                    decisive_vote_why=dc.get("vote_why", ""),
                    decisive_voters=sorted(voters), decisive_tangent=int(tangent),
                    decisive_rule=DECIDE_AGAIN_RULE, decisive_bound_rule=BOUND_RULE,
                    decisive_divergence_rule=CYCLE_MEAN_RULE, backend=_backend(dc["precision"]),
                    wall_time_s=wall, stage="decisive")
    return ds


def what_regular_bounds(judged: dict, gated: dict, sigma: float) -> dict:
    """``chaos.bounds.regular_bound`` of the decisive stage's judges, each with its verdict after the gates
    (``gated``: a judge that does not vote or whose arithmetic does not follow closely enough bounds nothing)
    and the numbers it rests on, under its registry name (``chaos.indicators``)."""
    names = record_names(DECISIVE_STAGE)
    return regular_bound({names[k]: {"verdict": gated[k], "numbers": judged[k].get("numbers", {})} for k in judged},
                         sigma)


def _bound_vars(bound: dict, voting: list) -> dict:
    """The variables of what a regular verdict bounds and of which decisive judges vote."""
    return {
        "decisive_lambda_max": ("state", [bound["lambda_max"]],
                                cf.attrs("the largest lambda_1 the regular tangent-based judges leave room for "
                                         "(NaN: none said regular)", "rate")),
        "decisive_bound_T": ("state", [bound["T"]], cf.attrs("the horizon that bound holds over", "time")),
        "decisive_bound_text": ("state", np.array([bound["text"]], dtype=object),
                                {"long_name": "what a regular verdict bounds (decisive_bound_rule)"}),
        "decisive_voting": (("state", "decisive_indicator"), [np.asarray(voting, int)],
                            {"long_name": "does the judge vote at the stage's horizon (the judge-power record)",
                             "units": "1"}),
    }


def _divergence_vars(div: dict) -> dict:
    """The variables of the mean divergence over the decisive orbit's whole cycles (``divergence_stage``)."""
    return {
        "decisive_mean_divergence": ("state", [div["mean"]], cf.attrs(
            "mean divergence (trace J) over the decisive orbit's whole spike cycles: the sum of its Lyapunov "
            "exponents", "rate")),
        "decisive_mean_divergence_stderr": ("state", [div["stderr"]], cf.attrs(
            "standard error of the mean divergence over the finest split's windows of whole cycles", "rate")),
        "decisive_mean_divergence_quadrature": ("state", [div["quadrature"]], cf.attrs(
            "quadrature error of the mean divergence (its difference from the cubic Hermite rule's)", "rate")),
        "decisive_divergence_cycles": ("state", [div["cycles"]], cf.attrs(
            "whole spike cycles the mean divergence runs over")),
    }


def _path_vars(p: dict) -> dict:
    """The variables of the shape of the sleigh's path along the decisive orbit (``path_stage``)."""
    return {
        "decisive_path_growth": ("state", [p["growth"]], cf.attrs(
            "the path's farthest distance from its start at the end over that at half the decisive orbit (about 1 "
            "bounded, 1.41 diffusive, 2 straight)")),
        "decisive_path_reach": ("state", [p["reach"]], cf.attrs(
            "the path's farthest distance from its start along the decisive orbit", "length")),
        "decisive_path_recurrence": ("state", [p["recurrence"]], cf.attrs(
            "the smallest RMS distance between the path and its copy shifted by 50 time units to a third of the "
            "orbit, over the path's size (0: periodic)")),
    }


def _section_curve(judged: dict) -> np.ndarray:
    """The map's <Y> per return (one NaN when the section gave no map)."""
    return np.full(1, math.nan) if judged["run"] is None else np.asarray(judged["run"]["Y_mean"], float)


def _per_split(run: dict, key: str, dc: dict) -> np.ndarray:
    """run[key] (one value per split the run kept, run["splits"]) on dc["splits"], NaN where left out."""
    out = np.full(len(dc["splits"]), math.nan)
    for k, v in zip(run["splits"], run[key]):
        out[list(dc["splits"]).index(int(k))] = v
    return out


def _decisive_vars(stage1, judged: dict, orbit: dict, dc: dict, verdict: str, reason: str, klass: str) -> dict:
    """The decisive stage's variables for its one state (names prefixed decisive_)."""
    names = list(judged)
    ln_gain = float(stage1.ln_gain_max.values[0])
    steps = _steps_per_cycle(stage1)
    log10_gr = math.log10(math.exp(ln_gain) * injected_rounding(dc["precision"].rounding, steps))
    follows = indicator_follows(ln_gain, dict.fromkeys(names, dc["precision"]),
                                {k: judged[k].get("resolved", math.nan) for k in names}, steps_per_cycle=steps)
    m = judged["megno"]["run"] or {"t": np.full(1, math.nan), "Y_mean": np.full(1, math.nan)}
    return {
        "decisive_verdict": ("state", np.array([verdict], dtype=object)),
        "decisive_reason": ("state", np.array([reason], dtype=object)),
        "decisive_class": ("state", np.array([klass], dtype=object)),
        "decisive_indicator_verdict": (("state", "decisive_indicator"),
                                       np.array([[judged[k]["verdict"][0] for k in names]], dtype=object)),
        "decisive_indicator_reason": (("state", "decisive_indicator"),
                                      np.array([[judged[k]["verdict"][1] for k in names]], dtype=object)),
        "decisive_indicator_value": (("state", "decisive_indicator"), [[judged[k]["value"] for k in names]],
                                     cf.attrs("MEGNO: 2 x slope of <Y> (rate); frequency: the spread D at the "
                                              "longest window (relative); birkhoff: digits at the longest window")),
        "decisive_indicator_uncertainty": (("state", "decisive_indicator"), [[judged[k]["error"] for k in names]],
                                           cf.attrs("MEGNO: least-squares error; frequency: D x its ln-error; "
                                                    "birkhoff: spread of the digits over the observables")),
        "decisive_follows": (("state", "decisive_indicator"), np.array([[follows[k] for k in names]], dtype=object),
                             {"long_name": "does the decisive arithmetic follow the orbit closely enough for the "
                                           "indicator (faithfulness.indicator_limit)"}),
        "decisive_log10_gain_rounding": ("state", [log10_gr],
                                         cf.attrs("log10(G_max x unit roundoff of the decisive arithmetic)")),
        "decisive_spike_interval": (("state", "decisive_spike"), [spike_train(orbit, dc)],
                                    cf.attrs("intervals between successive Omega spikes of the decisive orbit",
                                             "time")),
        "decisive_megno_t": (("state", "decisive_megno_sample"), [m["t"]],
                             cf.attrs("time of the MEGNO sample", "time")),
        "decisive_megno_Y_mean": (("state", "decisive_megno_sample"), [m["Y_mean"]],
                                  cf.attrs("MEGNO <Y> in the decisive arithmetic")),
        "decisive_birkhoff_digits": (("state", "decisive_split"), [_per_split(judged["birkhoff"]["run"], "dig", dc)],
                                     cf.attrs("digits of agreement of consecutive windows' weighted Birkhoff averages "
                                              "(the worst observable's)")),
        "decisive_frequency_D": (("state", "decisive_split"), [_per_split(judged["frequency"]["run"], "D", dc)],
                                 cf.attrs("spread D of the window frequencies over their mean (NaN: split left out)")),
        "decisive_section_Y_mean": (("state", "decisive_return"), [_section_curve(judged["section_megno"])],
                                    cf.attrs("the return map's MEGNO <Y> after each return to the spike section")),
        "decisive_energy_max_rel_drift": ("state", [orbit["drift"]],
                                          cf.attrs("max |E/E0 - 1| along the decisive orbit")),
    }


def with_decisive(ds: xr.Dataset, parts: list) -> xr.Dataset:
    """One realization's dataset (all its states) with its decisive-stage datasets ``parts`` (one per
    state of the stage): their variables (NaN for the states without the stage) and, for those states,
    the verdict, reason and class they decided. Unchanged without parts."""
    if not parts:
        return ds
    for dim in ("decisive_spike", "decisive_return"):
        width = max(p.sizes.get(dim, 0) for p in parts)
        parts = [p.pad({dim: (0, width - p.sizes[dim])}) if dim in p.dims else p for p in parts]
    dec = xr.concat(parts, dim="state", data_vars="minimal", coords="minimal", compat="override",
                    combine_attrs="override")
    dec = dec.reindex(state=ds.state.values)
    done = np.array([isinstance(v, str) for v in dec.decisive_verdict.values])
    out = ds.copy()
    for name in dec.data_vars:
        v = dec[name]
        if v.dtype == object:  # text: "not run" for the states without the stage (netCDF holds no NaN text)
            v = v.copy(data=np.vectorize(lambda x: x if isinstance(x, str) else "not run", otypes=[object])(v.values))
        out[name] = v
    for var, source in (("verdict", "decisive_verdict"), ("reason", "decisive_reason"),
                        ("state_class", "decisive_class")):
        out[var] = ("state", np.where(done, dec[source].values, out[var].values).astype(object))
    out.attrs.update({k: v for k, v in parts[0].attrs.items() if k.startswith("decisive_")})
    out.attrs["wall_time_s"] = float(ds.attrs["wall_time_s"] + sum(p.attrs["wall_time_s"] for p in parts))
    return out


def decisive_spike_period(ds: xr.Dataset) -> np.ndarray:
    """Per state of a realization's dataset, the median spike interval of its decisive orbit (which
    torus the realization is on, in the decisive arithmetic; NaN without the stage or two spikes)."""
    x = np.asarray(ds.decisive_spike_interval.values, float)
    return np.array([np.nanmedian(row) if np.isfinite(row).any() else math.nan for row in x])


def _steps_per_cycle(stage1: xr.Dataset) -> float:
    """The gauge's Taylor steps per spike cycle of the first stage's state (NaN when not stored)."""
    return float(stage1.gain_steps_per_cycle.values[0]) if "gain_steps_per_cycle" in stage1 else math.nan


def _backend(precision: str) -> str:
    """The integrator of the decisive arithmetic."""
    return "heyoka" if precision.heyoka else "sleighsim.engine.ddbatch"
