"""Is the steady state chaotic? A verdict per steady state from independent indicators, and the
class of each state in the reversible system (the report's first answer).

The indicators, their judges and the decision rule are in ``sleighsim.chaos``; this module runs
the sleigh's integrations for them and assembles the dataset."""

from __future__ import annotations

import inspect
import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.io import cf
from sleighsim.chaos import naff as frequencies
from sleighsim.engine import integrators
from sleighsim.chaos import benettin
from sleighsim.model import equations
from sleighsim.chaos.frequency import frequency_drift, frequency_log_ratio, judge_frequency, judged_run
from sleighsim.chaos.orbits import (
    LOSCHMIDT_GAIN_ROUNDING_MAX,
    d0_independent,
    judge_loschmidt,
    judge_loschmidt_run,
    loschmidt,
    loschmidt_fit,
    loschmidt_indicator,
    two_trajectory,
    two_trajectory_indicator,
)
from sleighsim.chaos.rule import (
    DECISION_RULE,
    agree,
    INDICATORS,
    TANGENT_BASED,
    classify,
    consistent,
    decide,
    faithful_gate,
    precision_gate,
)
from sleighsim.chaos.tangent import (
    finite_time_exponents,
    growth_confirmed,
    judge_benettin,
    judge_ftle,
    judge_megno,
    judge_megno_run,
    megno,
    megno_in_long_double,
)
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR
from sleighsim.chaos.faithfulness import FAITHFUL_MAX, cycle_gains, follows, spike_cycle_gains
from sleighsim.engine.precision import Precision
from sleighsim.engine.integrate import integrate, orbit_samples, sample_grid
from sleighsim.io.netcdf import read_dataset
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.engine.transient import settle
from sleighsim.scenes.common import nan_padded, realization_states

log = logging.getLogger("sleighsim")

N_BLOCKS = 10  # consecutive blocks of the long-double run for its standard error
R = np.array([-1.0, -1.0, -1.0, 1.0])  # the reversing involution: (u, Omega, omega, delta) -> (-u, -Omega, -omega, delta)


# the docstring is written into the chaos_verdict dataset (attribute R_rule)
def r_image(params, y, ref_mean, *, T: float, tol: float, rtol: float, scene: str) -> tuple[str, float]:
    """Where R sends a point of the state: integrate R y forward over T and compare the time means of
    (u, omega) over the second half with R applied to the state's own means. "stays" when within rtol
    of the scale of the means, else "leaves" (the image of the state is not visited: a repeller)."""
    run = integrate(params, R * np.asarray(y), sample_grid(0.0, T, T / 2000), tol=tol, scene=f"{scene}.R", progress=1)
    half = run.time.values >= T / 2
    got = np.array([run.u.values[half].mean(), run.omega.values[half].mean()])
    want = -np.asarray(ref_mean)
    dist = float(np.max(np.abs(got - want)) / max(np.max(np.abs(ref_mean)), 1e-12))
    return ("stays" if dist <= rtol else "leaves"), dist


def one_state(params, y0, cfg: dict, scene: str) -> dict:
    """Every indicator, the classification and the settling facts for the state reached from y0."""
    tol, tau, sigma = cfg["tol"], cfg["tau"], cfg["sigma"]
    y, pre = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=tol, label=scene, progress=1)
    replicas, record = orbit_samples(params, y, cfg["replicas"], cfg["replica_spacing"], tol=tol, scene=scene)
    mean_u_omega = np.array([record.u.values.mean(), record.omega.values.mean()])
    res = replica_run(params, replicas, cfg, scene)
    gain = gain_run(params, replicas[0], cfg)
    values, errors, verdicts = {}, {}, {}
    m, ld, megno_double, megno_precision = _tangent_indicators(params, replicas, res, cfg, scene, values, errors, verdicts)
    freq = frequency_indicator(params, replicas[0], cfg, sigma)
    values["frequency"], errors["frequency"], verdicts["frequency"] = freq["value"], freq["error"], freq["verdict"]
    L = loschmidt_run(params, replicas[0], cfg)
    L_ld = loschmidt_run(params, replicas[0], cfg, precision=Precision.LONG_DOUBLE)
    los = loschmidt_indicator(L, L_ld, sigma)
    values["loschmidt"], errors["loschmidt"], verdicts["loschmidt"] = los["value"], los["error"], los["verdict"]
    flow, tts = two_trajectory_runs(params, replicas[-1], cfg)
    two = two_trajectory_indicator(tts, cfg["d0"], tau, sigma)
    values["two_trajectory"], errors["two_trajectory"], verdicts["two_trajectory"] = two["value"], two["error"], two["verdict"]
    arithmetic = {"benettin": "double", "ftle": "double", "megno": megno_precision, "two_trajectory": "double",
                  "loschmidt": "long double", "frequency": list(freq["runs"])[-1]}
    faithful_gate(verdicts, arithmetic, indicator_follows(gain["ln_gain_max"], arithmetic))
    verdict, reason, _ = decide(verdicts, TANGENT_BASED)
    others = {k: (values[k], errors[k]) for k in INDICATORS if k not in TANGENT_BASED and verdicts[k][0] == CHAOTIC}
    verdict, reason = consistent(verdict, reason, values["benettin"], errors["benettin"], others, sigma)
    klass, s, s_err, image, image_dist = _class_facts(params, replicas[0], mean_u_omega, res, verdict, cfg, scene)
    lam, tt = res["exponents"], tts[len(tts) // 2]
    return {"verdict": verdict, "reason": reason, "klass": klass, "values": values, "errors": errors, "verdicts": verdicts,
            "two_rates": [t["rate"] for t in tts], "two_stderrs": [t["stderr"] for t in tts],
            "megno_t": m["t"], "megno_Y_mean": m["Y_mean"], "megno_final": m["final"],
            "megno_t_ld": _or_nan(ld["megno"], "t", m["t"].size), "megno_Y_mean_ld": _or_nan(ld["megno"], "Y_mean", m["t"].size),
            "megno_rate_double": 2 * m["slope"], "megno_rate_double_err": 2 * m["slope_err"],
            "megno_verdict_double": megno_double[0], "megno_precision": megno_precision,
            "loschmidt_error": L["rel_error"], "loschmidt_error_ld": L_ld["rel_error"],
            "loschmidt_power": L_ld["pow_exponent"], "loschmidt_power_err": L_ld["pow_exponent_err"],
            "loschmidt_tail_power": L_ld["tail_pow_exponent"], "loschmidt_tail_power_err": L_ld["tail_pow_exponent_err"],
            "loschmidt_n_used": [L["n_used"], L_ld["n_used"]], "loschmidt_tail_n": [L["tail_n"], L_ld["tail_n"]],
            "loschmidt_floor": [L["floor"] / L["scale"], L_ld["floor"] / L_ld["scale"]],
            "loschmidt_verdict_double": los["verdict_double"], "frequency": freq, "ld_lambda_1": ld["lambda_1"],
            "ld_stderr": ld["stderr"], "ld_check": ld["check"],
            "exponents": lam, "stderr": res["stderr"], "T": float(res["T"]), "status": res["status"], "sum_all": s,
            "sum_err": s_err, "r_image": image, "r_image_distance": image_dist, "mean_u": float(mean_u_omega[0]),
            "mean_omega": float(mean_u_omega[1]), "transient_over": int(pre["transient_over"]), "T_two": float(tt["T"]),
            "gain": gain,
            "drift": float(abs(equations.energy(integrators.read(flow, 4), params) / equations.energy(y0, params) - 1))}


def gain_run(params, y, cfg: dict) -> dict:
    """The faithfulness gauge along the settled orbit from y: ln G of each spike cycle (the largest
    singular value of the one-period tangent map, ``faithfulness.spike_cycle_gains``) over T_gain, in
    double at tol, and G x rounding per arithmetic."""
    ta, _ = integrators.sleigh_tangent(4, cfg["tol"], cfg["compact_mode"])
    integrators.set_pars(ta, params)
    return spike_cycle_gains(ta, y, T=cfg["T_gain"], tau=cfg["tau_gain"], spike_factor=cfg["transient"]["spike_factor"])


def replica_run(params, replicas, cfg: dict, scene: str) -> dict:
    """Benettin over the replicas (one SIMD lane each, 4 tangent vectors), ``benettin.replica_exponents``
    at tol with tau, T_round, max_rounds, target_rel, t_align, regular_floor and sigma from cfg."""
    ta, _ = integrators.sleigh_tangent_batch(cfg["replicas"], cfg["tol"], cfg["compact_mode"], k=4)
    integrators.set_pars(ta, params)
    return benettin.replica_exponents(ta, 4, 4, replicas, cfg["tau"], T_round=cfg["T_round"], max_rounds=cfg["max_rounds"],
                                      target_rel=cfg["target_rel"], t_align=cfg["t_align"],
                                      regular_floor=cfg["regular_floor"], sigma=cfg["sigma"], label=scene)


def _tangent_indicators(params, replicas, res: dict, cfg: dict, scene: str, values: dict, errors: dict,
                        verdicts: dict) -> tuple:
    """The tangent-based indicators into values, errors and verdicts: Benettin from the replica run
    res, the finite-time exponents of its first vector, MEGNO from the first replica; when one of
    them says chaotic in double, the long-double precision check, which gates them and whose MEGNO
    run is judged instead. Returns the double MEGNO run, the check (``precision_check``; "not run"
    and no MEGNO run when not made), the double run's MEGNO verdict and the precision judged."""
    tau, sigma = cfg["tau"], cfg["sigma"]
    values["benettin"], errors["benettin"] = float(res["exponents"][0]), float(res["stderr"][0])
    verdicts["benettin"] = judge_benettin(res, tau, sigma)
    g = res["log_growth"][:, 0, 0]
    windows = [w for w in cfg["ftle_windows"] if g.size * tau / w >= 2]
    f = finite_time_exponents(g, tau, windows)
    values["ftle"], errors["ftle"] = f["rate"], f["rate_err"]
    verdicts["ftle"] = judge_ftle(f["rate"], f["rate_err"], f["T"], tau, f["spread_slope"], f["spread_slope_err"],
                                  sigma=sigma)
    m = megno_run(params, replicas[0], cfg)
    values["megno"], errors["megno"] = 2 * m["slope"], 2 * m["slope_err"]
    verdicts["megno"] = megno_double = judge_megno_run(m, cfg["T_megno"], sigma)
    megno_precision = "double"
    ld = {"lambda_1": math.nan, "stderr": math.nan, "check": "not run", "megno": None}
    if any(verdicts[k][0] == CHAOTIC for k in TANGENT_BASED):
        ld = precision_check(params, replicas[0], cfg, scene)
        precision_gate(verdicts, ld)
        values["megno"], errors["megno"] = 2 * ld["megno"]["slope"], 2 * ld["megno"]["slope_err"]
        megno_precision = "long double"
        verdicts["megno"] = megno_in_long_double(judge_megno_run(ld["megno"], cfg["T_long_double"], sigma), ld,
                                                 megno_double, cfg["T_long_double"], cfg["T_megno"])
    return m, ld, megno_double, megno_precision


def two_trajectory_runs(params, y, cfg: dict) -> tuple:
    """``chaos.orbits.two_trajectory`` from y (model variables) at each separation d0, in double at
    tol over T_two (renormalised every tau, after t_align), the partner kept on the reference's
    energy level. Returns (the flow integrator, the runs)."""
    flow, _ = integrators.flow(False, cfg["tol"])
    integrators.set_pars(flow, params)
    y_int = _stored(y)
    tts = [two_trajectory(flow, y_int, d0=d0, tau=cfg["tau"], T=cfg["T_two"], t_align=cfg["t_align"],
                          callback=integrators.bounded(flow), difference=equations.state_difference,
                          project=lambda ref, p: _on_level(ref, p, params)) for d0 in cfg["d0"]]
    return flow, tts


def _class_facts(params, y, mean_u_omega, res: dict, verdict: str, cfg: dict, scene: str) -> tuple:
    """The class of the state (``chaos.rule.classify``) from the verdict, the replicas' sum of
    exponents (mean and standard error) and where R sends y (``r_image``). Returns (class, sum,
    its stderr, R-image, its distance)."""
    sums = res["per_replica"].sum(axis=1)
    s, s_err = float(sums.mean()), float(sums.std(ddof=1) / math.sqrt(cfg["replicas"]))
    image, image_dist = r_image(params, y, mean_u_omega, T=cfg["T_R"], tol=cfg["tol"], rtol=cfg["R_rtol"], scene=scene)
    lam = res["exponents"]
    return classify(verdict, s, s_err, float(lam[0]), float(lam[3]), image, cfg["sigma"]), s, s_err, image, image_dist


def indicator_follows(ln_gain_max: float, arithmetic: dict) -> dict:
    """{indicator: does its arithmetic follow the orbit (``faithfulness.follows``)}: G x rounding
    below 1e-3, or below LOSCHMIDT_GAIN_ROUNDING_MAX for the Loschmidt test."""
    limit = {"loschmidt": LOSCHMIDT_GAIN_ROUNDING_MAX}
    return {name: follows(ln_gain_max, Precision.parse(a).rounding, limit.get(name, FAITHFUL_MAX)) for name, a in arithmetic.items()}


def loschmidt_run(params, y, cfg: dict, *, precision: Precision = Precision.DOUBLE) -> dict:
    """``chaos.orbits.loschmidt`` from y (model variables) with the involution R at loschmidt_n
    log-spaced T in loschmidt_T, relative to max |velocity|: in double at tol, or in long double at
    tol_long_double (rounding 2^11 smaller: the rounding floor is 3.3 decades lower)."""
    tol = cfg["tol_long_double"] if precision is Precision.LONG_DOUBLE else cfg["tol"]
    flow, _ = integrators.flow(False, tol, precision)
    integrators.set_pars(flow, params)
    return loschmidt(flow, _stored(y), loschmidt_T(cfg), lambda z: R * z, callback=integrators.bounded(flow),
                     difference=equations.state_difference, scale=float(np.max(np.abs(np.asarray(y)[:3]))))


PRECISIONS = tuple(Precision)  # the frequency indicator's runs, in order


def _frequency_tol(cfg: dict, precision: Precision) -> float:
    """The Taylor tolerance of the frequency run in ``precision`` (one of PRECISIONS)."""
    return {"double": cfg["tol"], "long double": cfg["tol_long_double"], "quad": cfg["frequency"]["tol_quad"]}[precision]


def frequency_run(params, y, cfg: dict, precision: Precision = Precision.DOUBLE) -> dict:
    """``chaos.frequency.frequency_drift`` of the velocity frequency.component (u, Omega or omega) from y,
    sampled every frequency.dt: in double at tol over frequency.T, in long double at
    tol_long_double over frequency.T, or in quad at frequency.tol_quad over frequency.quad_T."""
    fc = cfg["frequency"]
    T = fc["quad_T"] if precision is Precision.QUAD else fc["T"]
    flow, _ = integrators.flow(False, _frequency_tol(cfg, precision), precision)
    integrators.set_pars(flow, params)
    return frequency_drift(flow, _stored(y), T=T, dt=fc["dt"], component=equations.STATE_NAMES.index(fc["component"]),
                           splits=fc["splits"], min_cycles=fc["min_cycles"], callback=integrators.bounded(flow))


# the docstring is written into the chaos_verdict dataset (attribute frequency_rule)
def frequency_indicator(params, y, cfg: dict, sigma: float) -> dict:
    """The frequency-analysis indicator (``chaos.frequency.judge_frequency``): the double run first; while
    the leading frequency has not converged (and the last run had at least two usable splits),
    the next precision: long double, then quad when frequency.quad_T > 0 (costs per time unit in
    benchmarks/precision_cost.yaml; the cluster config makes it). Each run's drift is compared with
    the previous one's against the ratio of their tolerances. Value: the relative frequency drift
    per unit time, D / W at the longest window of the last run (1/time); error: that times D's
    ln-error. Returns value, error, verdict ((verdict, reason)) and runs (precision -> run, for
    the runs made)."""
    made, judged, judgement = {}, [], None  # judgement: set by the double run, which is always made
    for prev, precision in zip((None, *PRECISIONS[:-1]), PRECISIONS):
        if prev is not None and (judgement[0] == REGULAR or made[prev]["splits"].size < 2):
            break
        if precision is Precision.QUAD and cfg["frequency"]["quad_T"] <= 0:
            judgement = (judgement[0], judgement[1] + "; quad run not made (frequency.quad_T = 0; config/cluster.yaml makes it)")
            break
        run = made[precision] = frequency_run(params, y, cfg, precision)
        ratio = {}
        if prev is not None:
            log_ratio, log_ratio_err = frequency_log_ratio(made[prev], run)
            ratio = {"log_ratio": log_ratio, "log_ratio_err": log_ratio_err,
                     "rounding_ratio": _frequency_tol(cfg, prev) / _frequency_tol(cfg, precision)}
        judged.append(judged_run(precision, run, **ratio))
        judgement = judge_frequency(judged, sigma=sigma)
    last = made[list(made)[-1]]
    if last["D"].size:
        value = float(last["D"][0] / last["W"][0])
        error = value * float(last["D_log_err"][0])
    else:
        value = error = math.nan
    return {"value": value, "error": error, "verdict": judgement, "runs": made}


def frequency_table(runs: list, splits) -> dict:
    """Per state and precision (PRECISIONS), the window lengths and the spread D of the window
    frequencies at each configured split (NaN where the split was left out or the run not made),
    the convergence slope and its error, and the mean frequency."""
    splits = list(splits)
    D, W = (np.full((len(runs), len(PRECISIONS), len(splits)), math.nan) for _ in range(2))
    slope, slope_err, f = (np.full((len(runs), len(PRECISIONS)), math.nan) for _ in range(3))
    for i, fr in enumerate(runs):
        for j, precision in enumerate(PRECISIONS):
            run = fr["runs"].get(precision)
            if run is None:
                continue
            W[i, j] = run["T"] / np.asarray(splits, float)
            for k, d in zip(run["splits"], run["D"]):
                D[i, j, splits.index(int(k))] = d
            slope[i, j], slope_err[i, j], f[i, j] = run["slope"], run["slope_err"], run["f"]
    return {"D": D, "W": W, "slope": slope, "slope_err": slope_err, "f": f}


def _loschmidt_settings() -> dict:
    """The Loschmidt engine's fixed settings (its defaults), as dataset attributes."""
    run = inspect.signature(loschmidt).parameters
    fit = inspect.signature(loschmidt_fit).parameters
    return {"loschmidt_floor_factor": run["floor_factor"].default, "loschmidt_saturation": run["saturation"].default,
            "loschmidt_tail_fraction": fit["tail"].default, "loschmidt_tail_min": fit["tail_min"].default}


def loschmidt_T(cfg: dict) -> np.ndarray:
    """The Loschmidt horizons: loschmidt_n log-spaced in loschmidt_T."""
    return np.geomspace(*cfg["loschmidt_T"], cfg["loschmidt_n"])


def megno_run(params, y, cfg: dict, *, precision: Precision = Precision.DOUBLE) -> dict:
    """MEGNO from y (model variables), renormalised every tau, <Y> recorded at megno_samples times
    (``chaos.tangent.megno``): over T_megno in double, or over T_long_double at tol_long_double in long
    double."""
    long_double = precision is Precision.LONG_DOUBLE
    tol, T = (cfg["tol_long_double"], cfg["T_long_double"]) if long_double else (cfg["tol"], cfg["T_megno"])
    ta, _ = integrators.sleigh_megno(tol, precision, cfg["compact_mode"])
    integrators.set_pars(ta, params)
    return megno(ta, 4, _stored(y), T=T, n_samples=cfg["megno_samples"], tau=cfg["tau"], callback=integrators.bounded(ta))


# the docstring is written into the chaos_verdict dataset (attribute precision_rule)
def precision_check(params, y, cfg: dict, scene: str) -> dict:
    """One replica (from y, model variables) in long double over T_long_double, with MEGNO: a
    tangent-based chaotic verdict stands only if its tangent vector, too, grows exponentially:
    lambda_1 (log growth after t_align / its time) - sigma stderr (N_BLOCKS consecutive blocks) >
    2 ln(T / tau) / T.
    On the sleigh, rounding noise off the leading direction is amplified by many orders at every
    spike, which inflates double-precision exponents and MEGNO. The run's MEGNO replaces the
    double-precision one as the MEGNO indicator. The check runs only when a tangent-based indicator
    says chaotic in double (it costs about 4 min), so MEGNO's precision depends on the other
    tangent-based verdicts: the one place where a larger uncertainty elsewhere (a Benettin rate
    no longer resolved) can change which MEGNO run is judged. Returns lambda_1, stderr, check
    ("confirmed" | "not confirmed"), the reason and the run (``megno``)."""
    tau, sigma, T = cfg["tau"], cfg["sigma"], cfg["T_long_double"]
    m = megno_run(params, y, cfg, precision=Precision.LONG_DOUBLE)
    g = m["log_growth"][math.ceil(cfg["t_align"] / tau):]  # the alignment of the vector left out
    lam, err, bound, ok = growth_confirmed(g, tau, T, sigma, N_BLOCKS)
    text = (f"long double (tol {cfg['tol_long_double']:.2g}): lambda_1 = {lam:.3g} +- {err:.2g} over T = {T:.3g}, "
            f"bound {bound:.2g}")
    log.info("%s: precision check: %s", scene, text)
    return {"lambda_1": lam, "stderr": err, "check": "confirmed" if ok else "not confirmed",
            "reason": ("confirmed in " if ok else "not confirmed in ") + text, "megno": m}


def _stored(y) -> np.ndarray:
    """A state in the model's variables as the compiled sleigh integrators store it (the engines
    of ``sleighsim.chaos`` take stored states): delta + DELTA_SHIFT in [0, 2 pi)."""
    out = np.array(y, float)
    out[3] = (out[3] + integrators.DELTA_SHIFT) % (2 * math.pi)
    return out


def _or_nan(run, key, n):
    """run[key], or n NaNs when the run was not made."""
    return np.full(n, math.nan) if run is None else run[key]


def _on_level(ref, partner, params):
    """The partner (integrator variables) scaled back onto the reference's energy level: the
    velocities scale, delta is kept (E is quadratic in the velocities at fixed delta)."""
    shift = np.array([0.0, 0.0, 0.0, integrators.DELTA_SHIFT])
    out = np.array(partner, float)
    out[:3] *= math.sqrt(equations.energy(ref - shift, params) / equations.energy(out - shift, params))
    return out


def verdict(cfg: dict, scene: str = "") -> xr.Dataset:
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
        out.append(one_state(params, y0, cfg, f"{scene}[{name}]"))
        log.info("%s: %s: %s (%s); %s", scene, name, out[-1]["verdict"], out[-1]["klass"], out[-1]["reason"])
    ind = list(INDICATORS)
    fc = cfg["frequency"]
    ft = frequency_table([o["frequency"] for o in out], fc["splits"])

    def per_state(key):
        return np.array([o[key] for o in out])

    ds = xr.Dataset(
        {**_verdict_vars(per_state, out, ind), **_state_vars(per_state), **_megno_vars(per_state),
         **_loschmidt_vars(per_state), **_frequency_vars(ft), **_long_double_vars(per_state),
         **_gain_vars(out)},
        coords={"state": names, "indicator": ind, "i": np.arange(1, 5), "d0": np.asarray(cfg["d0"], float),
                "T_loschmidt": loschmidt_T(cfg), "precision": ["double", "long double"],
                "split": np.asarray(fc["splits"], int), "frequency_precision": list(PRECISIONS), "arithmetic": [p.value for p in Precision],
                "tangent_based": ("indicator", [int(i in TANGENT_BASED) for i in ind])},
    )
    _set_attrs(ds, cfg, params, per_state, start)
    return ds


def _verdict_vars(per_state, out: list, ind: list) -> dict:
    """The dataset's verdict, reason and class per state and value, uncertainty, verdict and reason per indicator."""
    return {
        "verdict": ("state", per_state("verdict").astype(object)),
        "reason": ("state", per_state("reason").astype(object)),
        "state_class": ("state", per_state("klass").astype(object)),
        "indicator_value": (("state", "indicator"), [[o["values"][i] for i in ind] for o in out],
                            cf.attrs("value of the chaos indicator (an exponent, a growth rate or a slope)", "rate")),
        "indicator_uncertainty": (("state", "indicator"), [[o["errors"][i] for i in ind] for o in out],
                                  cf.attrs("standard error (replicas or blocks)", "rate")),
        "indicator_verdict": (("state", "indicator"), np.array([[o["verdicts"][i][0] for i in ind] for o in out],
                                                                dtype=object)),
        "indicator_reason": (("state", "indicator"), np.array([[o["verdicts"][i][1] for i in ind] for o in out],
                                                               dtype=object)),
    }


def _state_vars(per_state) -> dict:
    """The dataset's Lyapunov exponents, class facts and settling facts per state, and the two-trajectory rates."""
    return {
        "exponent": (("state", "i"), per_state("exponents"), cf.attrs("Lyapunov exponent lambda_i (Benettin)", "rate")),
        "stderr": (("state", "i"), per_state("stderr"), cf.attrs("standard error over independent replicas", "rate")),
        "sum_exponents": ("state", per_state("sum_all"), cf.attrs("sum of the four Lyapunov exponents", "rate")),
        "sum_exponents_stderr": ("state", per_state("sum_err"), cf.attrs("standard error of the sum", "rate")),
        "R_image": ("state", per_state("r_image").astype(object)),
        "R_image_distance": ("state", per_state("r_image_distance")),
        "mean_u": ("state", per_state("mean_u")), "mean_omega": ("state", per_state("mean_omega")),
        "transient_over": ("state", per_state("transient_over")),
        "T": ("state", per_state("T"), cf.attrs("Benettin horizon per replica", "time")),
        "energy_max_rel_drift": ("state", per_state("drift")),
        "two_trajectory_rate": (("state", "d0"), per_state("two_rates"),
                                cf.attrs("growth rate of the two trajectories' separation", "rate")),
        "two_trajectory_stderr": (("state", "d0"), per_state("two_stderrs"),
                                  cf.attrs("standard error of the growth rate (consecutive blocks)", "rate")),
    }


def _megno_vars(per_state) -> dict:
    """The dataset's MEGNO runs per state."""
    return {
        "megno_Y_mean": (("state", "megno_sample"), per_state("megno_Y_mean"),
                         cf.attrs("MEGNO running mean <Y> (2: torus with shear, 0: periodic, ~lambda t / 2: chaos)")),
        "megno_t": (("state", "megno_sample"), per_state("megno_t"), cf.attrs("time of the MEGNO sample", "time")),
        "megno_final": ("state", per_state("megno_final"), cf.attrs("MEGNO <Y> at T_megno, double run")),
        "megno_rate_double": ("state", per_state("megno_rate_double"),
                              cf.attrs("2 x slope of <Y>, double run (~ lambda_1)", "rate")),
        "megno_rate_double_stderr": ("state", per_state("megno_rate_double_err"),
                                     cf.attrs("least-squares error of 2 x slope of <Y>, double run", "rate")),
        "megno_verdict_double": ("state", per_state("megno_verdict_double").astype(object)),
        "megno_precision": ("state", per_state("megno_precision").astype(object),
                            {"long_name": "precision of the run the MEGNO indicator is judged from"}),
        "megno_Y_mean_long_double": (("state", "megno_sample"), per_state("megno_Y_mean_ld"),
                                     cf.attrs("MEGNO <Y> of the long-double precision check (NaN: not run)")),
        "megno_t_long_double": (("state", "megno_sample"), per_state("megno_t_ld"),
                                cf.attrs("time of the long-double MEGNO sample", "time")),
    }


def _loschmidt_vars(per_state) -> dict:
    """The dataset's Loschmidt return errors and fits per state."""
    return {
        "loschmidt_rel_error": (("state", "T_loschmidt"), per_state("loschmidt_error"),
                                cf.attrs("return error (forward T, R, forward T) / max |velocity|, double at tol")),
        "loschmidt_rel_error_long_double": (("state", "T_loschmidt"), per_state("loschmidt_error_ld"),
                                            cf.attrs("the same in long double at tol_long_double (judged)")),
        "loschmidt_verdict_double": ("state", per_state("loschmidt_verdict_double").astype(object),
                                     {"long_name": "the Loschmidt verdict of the double run (reported, not judged)"}),
        "loschmidt_power": ("state", per_state("loschmidt_power"),
                            cf.attrs("exponent p of the power fit error ~ T^p over all usable points, long double")),
        "loschmidt_power_stderr": ("state", per_state("loschmidt_power_err"),
                                   cf.attrs("least-squares error of that exponent")),
        "loschmidt_tail_power": ("state", per_state("loschmidt_tail_power"),
                                 cf.attrs("the same over the tail (the last half of the usable points)")),
        "loschmidt_tail_power_stderr": ("state", per_state("loschmidt_tail_power_err"),
                                        cf.attrs("least-squares error of the tail's exponent")),
        "loschmidt_n_used": (("state", "precision"), per_state("loschmidt_n_used"),
                             cf.attrs("return errors between rounding floor and saturation")),
        "loschmidt_tail_n": (("state", "precision"), per_state("loschmidt_tail_n"),
                             cf.attrs("of which in the tail")),
        "loschmidt_floor": (("state", "precision"), per_state("loschmidt_floor"),
                            cf.attrs("rounding floor (relative): floor_factor x machine epsilon")),
    }


def _frequency_vars(ft: dict) -> dict:
    """The dataset's frequency analysis per state and precision (``frequency_table``)."""
    return {
        "frequency_drift": (("state", "frequency_precision", "split"), ft["D"],
                            cf.attrs("spread of the leading frequency over the windows T / split, relative to its "
                                     "mean (NaN: split left out, or run not made)")),
        "frequency_window": (("state", "frequency_precision", "split"), ft["W"],
                             cf.attrs("window length W = T / split", "time")),
        "frequency_slope": (("state", "frequency_precision"), ft["slope"],
                            cf.attrs("convergence exponent of that spread, D ~ W^slope, longest to shortest window")),
        "frequency_slope_stderr": (("state", "frequency_precision"), ft["slope_err"],
                                   cf.attrs("least-squares error of that exponent")),
        "frequency_leading": (("state", "frequency_precision"), ft["f"], cf.attrs("leading frequency", "frequency")),
    }


def _long_double_vars(per_state) -> dict:
    """The dataset's long-double precision check per state."""
    return {
        "lambda_1_long_double": ("state", per_state("ld_lambda_1"),
                                 cf.attrs("largest Lyapunov exponent lambda_1 of the long-double check", "rate")),
        "lambda_1_long_double_stderr": ("state", per_state("ld_stderr"),
                                        cf.attrs("standard error of that lambda_1 (consecutive blocks)", "rate")),
        "precision_check": ("state", per_state("ld_check").astype(object),
                            cf.attrs("long-double check of tangent-based chaotic verdicts (precision_rule)", "text")),
    }


def spike_period(spike_times) -> float:
    """The median interval between spikes (NaN with fewer than two)."""
    t = np.asarray(spike_times, float)
    return float(np.median(np.diff(t))) if t.size >= 2 else math.nan


def _gain_vars(out: list) -> dict:
    """The dataset's faithfulness gauge per state: ln G per spike cycle (NaN-padded), its maximum, and
    per arithmetic log10(G_max x rounding) and whether that arithmetic follows the orbit."""
    gains = [o["gain"] for o in out]
    return {
        "ln_gain": (("state", "cycle"), nan_padded([g["ln_gain"] for g in gains], min_width=1),
                    cf.attrs("ln G: largest singular value of the one-period tangent map, maximised over its start "
                             "in the cycle (double run)")),
        "ln_gain_max": ("state", [g["ln_gain_max"] for g in gains], cf.attrs("largest ln G over the cycles")),
        "spike_period": ("state", [spike_period(g["spike_times"]) for g in gains],
                         cf.attrs("median interval between the spikes of the gauge's run: which torus of the family "
                                  "the state reached (to about tau_gain)", "time")),
        "log10_gain_rounding": (("state", "arithmetic"), [[g["log10_gain_rounding"][a] for a in Precision] for g in gains],
                                cf.attrs("log10(G_max x unit roundoff of the arithmetic)")),
        "follows_orbit": (("state", "arithmetic"), np.array([[g["follows"][a] for a in Precision] for g in gains],
                                                            dtype=object),
                          {"long_name": "does the arithmetic follow the exact orbit (G x rounding below "
                                        "faithfulness.FAITHFUL_MAX; unknown without a complete cycle)"}),
    }


def _set_attrs(ds: xr.Dataset, cfg: dict, params, per_state, start: float) -> None:
    """The dataset's attributes: the rules (from the judges' docstrings), the settings and the wall time since start."""
    fc = cfg["frequency"]
    ds.attrs.update(
        rule=DECISION_RULE + "; then " + " ".join(consistent.__doc__.split()), class_rule=" ".join(classify.__doc__.split()),
        faithful_rule=" ".join(faithful_gate.__doc__.split()),
        precision_rule=" ".join(precision_check.__doc__.split()),
        d0_rule=" ".join(d0_independent.__doc__.split()), T_long_double=cfg["T_long_double"],
        tol_long_double=cfg["tol_long_double"], compact_mode=int(cfg["compact_mode"]),
        benettin_rule=" ".join(judge_benettin.__doc__.split()), R_rule=" ".join(r_image.__doc__.split()),
        uncertainty="Benettin: standard error over independent replicas along the settled orbit; FTLE: window "
                    "standard error; MEGNO: 2 x (slope of <Y> over the second half, least-squares error, "
                    "correlated residuals: understated); two-trajectory: consecutive blocks (value at the middle d0); "
                    "Loschmidt: least-squares error of the exponential fit over the long-double run's tail; frequency: D's "
                    "ln-error 1/sqrt(2 (K - 1)) for K windows (sample standard deviation of K values); long double: "
                    "consecutive blocks of one replica's MEGNO run",
        megno_rule=" ".join(judge_megno.__doc__.split()),
        frequency_rule=" ".join((frequency_indicator.__doc__ + " " + judge_frequency.__doc__ + " "
                                 + frequency_log_ratio.__doc__).split()),
        frequency_method=" ".join(frequencies.drift.__doc__.split()), frequency_T=fc["T"], frequency_dt=fc["dt"],
        frequency_component=fc["component"], frequency_min_cycles=fc["min_cycles"], frequency_quad_T=fc["quad_T"],
        frequency_tol_quad=fc["tol_quad"],
        loschmidt_rule=" ".join((loschmidt_indicator.__doc__ + " " + judge_loschmidt_run.__doc__ + " "
                                 + judge_loschmidt.__doc__).split()),
        loschmidt_fit=" ".join(loschmidt_fit.__doc__.split()), **_loschmidt_settings(), T_megno=cfg["T_megno"],
        loschmidt_T=list(cfg["loschmidt_T"]), loschmidt_n=cfg["loschmidt_n"], T_gain=cfg["T_gain"],
        tau_gain=cfg["tau_gain"], gain_rule=" ".join((cycle_gains.__doc__ + " " + follows.__doc__).split()),
        param_eps=params.eps, param_b=params.b, param_K2=params.K2, energy_label=cfg["energy_label"], tol=cfg["tol"],
        tau=cfg["tau"], replicas=cfg["replicas"], replica_spacing=cfg["replica_spacing"],
        T_two=cfg["T_two"], T_R=cfg["T_R"], backend="heyoka", wall_time_s=time.perf_counter() - start,
        transient_over=int(np.all(per_state("transient_over") == 1)),
    )


def chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
    """Job ``index`` of the verdict (one chunk job each): state index % n_states of realization
    index // n_states, :func:`verdict` from that state of :func:`realization_states` at
    realization_rel (the states of a realization are perturbed together, in order, so a state's
    start does not depend on how the jobs are cut)."""
    names = list(cfg["states"])
    r, k = divmod(index, len(names))
    start = realization_states(cfg["states"], cfg["realization_rel"], r)[names[k]]
    ds = verdict({**cfg, "states": {names[k]: start}}, scene=f"{scene}#{r}")
    ds.attrs.update(chunk=r, n_chunks=cfg["n_chunks"])
    return ds


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


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """The verdict over realizations (each gathered from its per-state jobs): realization 0's dataset
    (its indicators, runs and gauge), with
    each realization's verdict and class, and per state the answer they agree on
    (``chaos.rule.agree``: "fragile" when they do not) and how many give the most common one."""
    by_realization = {}
    for d in (read_dataset(p) for p in paths):
        by_realization.setdefault(int(d.attrs["chunk"]), []).append(d)
    if sorted(by_realization) != list(range(cfg["n_chunks"])):
        raise ValueError(f"realizations {sorted(by_realization)}, expected 0 ... {cfg['n_chunks'] - 1}")
    names = list(cfg["states"])
    chunks = [_states_together(by_realization[r], names) for r in range(cfg["n_chunks"])]
    ds = chunks[0].copy()
    for var, out in (("verdict", "realization_verdict"), ("reason", "realization_reason"),
                     ("state_class", "realization_class")):
        ds[out] = (("realization", "state"), np.array([c[var].values for c in chunks], dtype=object))
    if all("spike_period" in c for c in chunks):
        ds["realization_spike_period"] = (("realization", "state"), [c.spike_period.values for c in chunks],
                                          cf.attrs("the torus each realization reached: its median spike interval",
                                                   "time"))
    verdicts = [agree(ds.realization_verdict.values[:, i]) for i in range(ds.sizes["state"])]
    classes = [agree(ds.realization_class.values[:, i]) for i in range(ds.sizes["state"])]
    ds["verdict"] = ("state", np.array([v for v, _, _ in verdicts], dtype=object))
    ds["reason"] = ("state", np.array([f"{why}; realization 0: {r}" for (_, _, why), r in
                                       zip(verdicts, chunks[0].reason.values)], dtype=object))
    ds["state_class"] = ("state", np.array([v for v, _, _ in classes], dtype=object))
    ds["n_realizations_agreeing"] = ("state", [n for _, n, _ in verdicts],
                                     cf.attrs("realizations that give the most common verdict"))
    ds = ds.assign_coords(realization=np.arange(len(chunks)))
    ds.attrs.pop("chunk", None)
    ds.attrs.update(n_realizations=len(chunks), realization_rel=cfg["realization_rel"],
                    realization_rule=" ".join((realization_states.__doc__ + " " + agree.__doc__).split()),
                    wall_time_s=float(sum(c.attrs["wall_time_s"] for c in chunks)))
    return ds
