"""The decisive stage's estimators, on one orbit sampled every dt with one tangent vector's log-norm: the
functions the sleigh's decisive stage (``scenes.verdict_decisive``) and the judge-power audit
(``chaos.power_audit``) both call, so that the estimator audited is the estimator that votes.

Each returns {"run", "value", "error", "verdict": (verdict, reason), "numbers"} (numbers: the floats the
verdict rests on, as the records keep them), and, for the indicators whose faithfulness limit depends on
what they resolve, "resolved" (``faithfulness.indicator_limit``):

* :func:`megno_judged`: MEGNO by the trapezoid rule on the log-norm (``megno.megno_from_log_norm``, n_samples
  points), ``megno.judge_megno_run`` over T. Value: 2 x slope of <Y> (1/time).
* :func:`section_megno_judged`: the return map's MEGNO at the section crossings (``section_megno``), judged
  over its returns. Value: the exponent it implies (1/time).
* :func:`frequency_judged`: the spread of the leading frequency of one component between windows T / K
  (``frequency.drift``, ``judge_frequency``). Value: D at the longest window kept.
* :func:`birkhoff_judged`: the weighted Birkhoff averages' digits (``birkhoff.digits``, ``judge_birkhoff``)
  with the arithmetic's G x injected rounding. Value: the digits at the longest window.

Times in the flow's own unit, exponents in 1/time. The section (the sleigh's Omega spikes, a system's
component maxima) and the observables are the system's, handed in.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.birkhoff import DIG_MIN, digits, judge_birkhoff
from sleighsim.chaos.frequency import PRECISION, drift, judge_frequency, judged_run
from sleighsim.chaos.megno import judge_megno_run, megno_from_log_norm, megno_rate
from sleighsim.chaos.section_megno import judge_section_megno, section_megno, section_rate
from sleighsim.chaos.verdicts import UNDECIDED

NAN = math.nan


def _not_judged(why: str) -> dict:
    return {"run": None, "value": NAN, "error": NAN, "verdict": (UNDECIDED, why), "numbers": {}}


def megno_judged(t, log_norm, n_samples: int, T: float, sigma: float) -> dict:
    """MEGNO of the sampled log-norm (trapezoid rule, ``megno_from_log_norm``) judged over T."""
    m = megno_from_log_norm(t, log_norm, n_samples)
    value, error = megno_rate(m)
    numbers = {"Y_mean": m["final"], "Y_resid": m["resid"], "slope": m["slope"], "slope_err": m["slope_err"],
               "T": float(T)}
    return {"run": m, "value": value, "error": error, "verdict": judge_megno_run(m, T, sigma), "numbers": numbers}


def section_megno_judged(t, log_norm, crossings, T: float, sigma: float) -> dict:
    """The return map's MEGNO at the section ``crossings`` (times), judged over its returns (undecided with
    fewer than two crossings or too few returns)."""
    crossings = np.asarray(crossings, float)
    if crossings.size < 2:
        return _not_judged(f"{crossings.size} section crossings within T = {T:g}: no return map")
    try:
        m = section_megno(t, log_norm, crossings)
    except ValueError as err:
        return _not_judged(str(err))
    value, error = section_rate(m, crossings)
    numbers = {"returns": float(m["n"][-1]), "Y_mean": m["final"], "Y_resid": m["resid"], "slope": m["slope"],
               "slope_err": m["slope_err"], "mean_return": float(np.mean(np.diff(crossings)))}
    return {"run": m, "value": value, "error": error, "verdict": judge_section_megno(m, sigma), "numbers": numbers}


def frequency_judged(x, dt: float, splits, min_cycles: float, precision: str, sigma: float) -> dict:
    """The frequency analysis of x over windows T / K, K in splits (``drift``, ``judge_frequency`` on one
    run in ``precision``). Value: D at the longest window kept; error: D times its ln-error; resolved: D,
    at least the refinement's precision."""
    run = drift(x, dt, splits, min_cycles=min_cycles)
    verdict = judge_frequency([judged_run(precision, run)], sigma=sigma)
    D = float(run["D"][0]) if run["D"].size else NAN
    numbers = {"slope": run["slope"], "slope_err": run["slope_err"],
               **{f"D_{int(k)}": float(d) for k, d in zip(run["splits"], run["D"])}}
    return {"run": run, "value": D, "error": D * float(run["D_log_err"][0]) if run["D"].size else NAN,
            "verdict": verdict, "resolved": max(D, PRECISION) if math.isfinite(D) else NAN, "numbers": numbers}


def birkhoff_judged(obs, dt: float, splits, gain_rounding: float) -> dict:
    """The weighted Birkhoff averages of the observables ``obs`` (samples x observables) over windows T / K,
    K in splits, judged with the arithmetic's G x rounding. Value: the digits at the longest window (the
    worst observable's); error: their spread over the observables; resolved: 10^-min(digits, DIG_MIN), the
    agreement a regular verdict certifies (more digits than DIG_MIN are not what the verdict rests on)."""
    run = digits(obs, dt, splits)
    dig = float(run["dig"][0])
    numbers = {"gain_rounding": float(gain_rounding),
               **{f"dig_{int(k)}": float(d) for k, d in zip(run["splits"], run["dig"])}}
    return {"run": run, "value": dig, "error": float(run["dig_err"][0]),
            "verdict": judge_birkhoff(run, gain_rounding=gain_rounding), "resolved": 10.0 ** -min(dig, DIG_MIN),
            "numbers": numbers}


def refined_intervals(crossings) -> np.ndarray:
    """The intervals between successive section crossings (time): which torus an orbit is on."""
    return np.diff(np.asarray(crossings, float))
