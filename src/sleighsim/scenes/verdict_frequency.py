"""The chaos verdict's frequency-analysis indicator: the drift of the leading frequency over windows, in
double and, while it has not converged, in long double and quad, run on the sleigh for
:mod:`sleighsim.scenes.verdict`."""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.frequency import (
    PRECISION,
    frequency_drift,
    frequency_log_ratio,
    judge_frequency,
    judged_run,
)
from sleighsim.chaos.verdicts import REGULAR
from sleighsim.engine import integrators
from sleighsim.model import equations
from sleighsim.precision import Precision
from sleighsim.scenes.common import stored_state, tolerance

# the frequency indicator's runs, in order (heyoka's arithmetics; double-double runs in the decisive stage)
PRECISIONS = (Precision.DOUBLE, Precision.LONG_DOUBLE, Precision.QUAD)


def frequency_run(params, y, cfg: dict, precision: Precision = Precision.DOUBLE) -> dict:
    """``chaos.frequency.frequency_drift`` of the velocity frequency.component (u, Omega or omega) from y,
    sampled every frequency.dt: in double at tol over frequency.T, in long double over frequency.T, or in
    quad over frequency.quad_T (each finer one at its machine epsilon, ``common.tolerance``)."""
    fc = cfg["frequency"]
    T = fc["quad_T"] if precision is Precision.QUAD else fc["T"]
    flow, _ = integrators.flow(False, tolerance(cfg, precision), precision)
    integrators.set_pars(flow, params)
    return frequency_drift(flow, stored_state(y), T=T, dt=fc["dt"],
                           component=equations.STATE_NAMES.index(fc["component"]),
                           splits=fc["splits"], min_cycles=fc["min_cycles"], callback=integrators.bounded(flow))


#: Written into the chaos_verdict dataset (attribute frequency_rule).
FREQUENCY_INDICATOR_RULE = (
    "The frequency-analysis indicator (``chaos.frequency.judge_frequency``): the double run first; while the "
    "leading frequency has not converged (and the last run had at least two usable splits), the next precision:"
    " long double, then quad when frequency.quad_T > 0 (costs per time unit in benchmarks/precision_cost.yaml; "
    "the cluster config makes it). Each run's drift is compared with the previous one's against the ratio of "
    "their tolerances. Value: the relative frequency drift per unit time, D / W at the longest window of the "
    "last run (1/time); error: that times D's ln-error. Without ``long_double`` (a state the decisive stage "
    "judges again) only the double run is made. Returns value, error, verdict ((verdict, reason)) and runs "
    "(precision -> run, for the runs made)."
)


def frequency_indicator(params, y, cfg: dict, sigma: float, *, long_double: bool = True) -> dict:
    """Applies :data:`FREQUENCY_INDICATOR_RULE`, the rule as the datasets record it (just above)."""
    made, judged, judgement = {}, [], None  # judgement: set by the double run, which is always made
    for prev, precision in zip((None, *PRECISIONS[:-1]), PRECISIONS):
        if prev is not None and (judgement[0] == REGULAR or made[prev]["splits"].size < 2):
            break
        if prev is not None and not long_double:
            judgement = (judgement[0], judgement[1] + "; finer runs not made: the decisive stage judges this state")
            break
        if precision is Precision.QUAD and cfg["frequency"]["quad_T"] <= 0:
            judgement = (judgement[0], judgement[1] + "; quad run not made "
                         "(frequency.quad_T = 0; config/cluster.yaml makes it)")
            break
        run = made[precision] = frequency_run(params, y, cfg, precision)
        ratio = {}
        if prev is not None:
            log_ratio, log_ratio_err = frequency_log_ratio(made[prev], run)
            ratio = {"log_ratio": log_ratio, "log_ratio_err": log_ratio_err,
                     "rounding_ratio": tolerance(cfg, prev) / tolerance(cfg, precision)}
        judged.append(judged_run(precision, run, **ratio))
        judgement = judge_frequency(judged, sigma=sigma)
    last = made[list(made)[-1]]
    if last["D"].size:
        value = float(last["D"][0] / last["W"][0])
        error = value * float(last["D_log_err"][0])
    else:
        value = error = math.nan
    return {"value": value, "error": error, "verdict": judgement, "runs": made}


def frequency_resolved(freq: dict) -> float:
    """The smallest relative quantity the frequency indicator's verdict rests on (for
    ``chaos.faithfulness.indicator_limit``): the spread D at the longest window of its last run, at
    least the refinement's precision (``chaos.frequency.PRECISION``); NaN without a window kept."""
    last = freq["runs"][list(freq["runs"])[-1]]
    return max(float(last["D"][0]), PRECISION) if last["D"].size else math.nan


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
