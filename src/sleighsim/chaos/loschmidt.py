"""The Loschmidt (time-reversal) test: a chaos indicator without tangent dynamics, and its judges.

Engine (times in the flow's own time unit, rates in 1/time, natural logs): ``loschmidt``: forward
T, apply the involution R, forward T again, compare with R y0 (``loschmidt_fit`` classifies the
return errors as exponential or power-law in T). Judges: ``judge_loschmidt`` (``judge_loschmidt_run``
on a run, ``loschmidt_indicator`` on a double and a long-double run); ``LOSCHMIDT_GAIN_ROUNDING_MAX``:
the faithfulness gauge's limit for this test. States that contain angles reduced by a callback should
be compared with a ``difference(a, b)`` that wraps angle differences (default: ``a - b``). Engine
conventions: ``propagate``; verdict conventions: ``verdicts``.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.common import _state, linfit
from sleighsim.chaos.propagate import _propagate, _propagate_until
from sleighsim.chaos.verdicts import (
    CHAOTIC,
    REGULAR,
    UNDECIDED,
    _check_judge,
    _g,
    _is_finite,
)
from sleighsim.model.params import positive

_EPS = float(np.finfo(float).eps)

_FIT_KEYS = ("exp_rate", "exp_rate_err", "exp_rms", "pow_exponent", "pow_exponent_err", "pow_rms")


def _growth_fits(T, e) -> dict:
    """Least-squares fits of log(e) = a + rate T and log(e) = a + p log T: slope, stderr and rms
    residual (log units) of each; NaN with fewer than 2 points."""
    out = dict.fromkeys(_FIT_KEYS, math.nan)
    if T.size >= 2:
        le = np.log(e)
        out["exp_rate"], out["exp_rate_err"], out["exp_rms"], _ = linfit(T, le)
        out["pow_exponent"], out["pow_exponent_err"], out["pow_rms"], _ = linfit(np.log(T), le)
    return out


#: The largest G x rounding (the most one spike cycle amplifies the rounding, ``sleighsim.chaos.faithfulness``)
#: at which a Loschmidt run can still tell exponential from power-law growth: its return error starts
#: near G x rounding after the first spike and saturates at 1e-2 (``loschmidt_fit``'s saturation), and
#: the fits need two decades between.
LOSCHMIDT_GAIN_ROUNDING_MAX = 1e-4


#: Written into the chaos_verdict dataset (attribute loschmidt_fit).
LOSCHMIDT_FIT_RULE = (
    "Classify return errors: exponential in T (chaos) or a power of T (regular). Uses the points with "
    "floor_factor * rounding * scale < error < saturation * scale (rounding: the integrator's machine epsilon) "
    "before the first horizon whose error reached saturation, fits log(error) = a + rate T and log(error) = a +"
    " p log T by least squares over all of them and again over the tail (the last ``tail`` fraction of them in "
    "T, at least tail_min: the longest horizons before saturation) and reports both (slope, stderr, rms "
    "residual in log units; the tail's under ``tail_``). ``better`` is \"exponential\" or \"power\" (smaller rms "
    "over all points), \"undetermined\" with fewer than 3 usable points."
)


def loschmidt_fit(T_values, errors, scale, *, floor_factor=1e3, saturation=1e-2, rounding=_EPS, tail=0.5,
                  tail_min=4):
    """Applies :data:`LOSCHMIDT_FIT_RULE`, the rule as the datasets record it (just above)."""
    T = np.asarray(T_values, float).ravel()
    e = np.asarray(errors, float).ravel()
    if T.size == 0:
        raise ValueError("T_values is empty")
    if e.size != T.size:
        raise ValueError(f"errors has {e.size} entries, T_values {T.size}")
    scale = positive("scale", scale)
    if not 0 < tail <= 1:
        raise ValueError(f"tail must be in (0, 1], got {tail!r}")
    if not (isinstance(tail_min, int) and tail_min >= 2):
        raise ValueError(f"tail_min must be an integer >= 2, got {tail_min!r}")
    floor = floor_factor * positive("rounding", rounding) * scale
    sat = saturation * scale
    saturated = np.isfinite(e) & (e >= sat)
    before = T < (T[saturated].min() if saturated.any() else np.inf)
    use = np.isfinite(e) & (e > floor) & (e < sat) & np.isfinite(T) & (T > 0) & before
    out = {"floor": floor, "saturation": sat, "used": use, "n_used": int(use.sum()), "better": "undetermined"}
    out.update(_growth_fits(T[use], e[use]))
    idx = np.flatnonzero(use)[np.argsort(T[use], kind="stable")]
    in_tail = np.zeros_like(use)
    in_tail[idx[-max(tail_min, math.ceil(tail * idx.size)):]] = True
    out["tail_used"], out["tail_n"] = in_tail, int(in_tail.sum())
    out.update({f"tail_{k}": v for k, v in _growth_fits(T[in_tail], e[in_tail]).items()})
    if use.sum() >= 3:
        out["better"] = "exponential" if out["exp_rms"] < out["pow_rms"] else "power"
    return out


def loschmidt(ta, y0, T_values, involution, callback=None, *, difference=None, scale=None,
              floor_factor=1e3, saturation=1e-2):
    """Loschmidt (time-reversal) test for a reversible flow with involution R.

    R maps a state to a state, and if y(t) solves the ODE so does R y(-t). For each T in
    ``T_values``: take y(T) on one forward run from y0, apply R, propagate forward T and compare
    with R(y0). In exact arithmetic the return is exact; numerically the return error grows like
    exp(lambda T) times the rounding level on a chaotic orbit and only like a power of T on a
    regular one. ``difference(a, b)`` (default a - b) compares states. Runs in the integrator's
    precision (double or long double; ``involution`` must keep the state's dtype, else ValueError);
    the rounding floor uses its machine epsilon.

    Returns dict: ``T``, ``error`` (infinity norm), ``rel_error`` (error / scale, scale =
    max|y0| unless given) and the classification of ``loschmidt_fit`` (floor
    floor_factor * eps * scale with eps the integrator's machine epsilon, saturation
    saturation * scale).
    """
    dim = len(ta.state)
    y0 = _state("y0", y0, dim)
    T_arr = np.atleast_1d(np.asarray(T_values, float)).ravel()
    if T_arr.size == 0:
        raise ValueError("T_values is empty")
    for Tk in T_arr:
        positive("T_values entry", Tk)
    if not callable(involution):
        raise ValueError("involution must be callable")  # noqa: TRY004
    if scale is None:
        scale = float(np.max(np.abs(y0)))
        if scale == 0:
            raise ValueError("y0 is the zero state: pass scale explicitly")
    scale = positive("scale", scale)
    diff = difference if difference is not None else (lambda a, b: a - b)
    target = np.asarray(involution(y0.copy()), float)
    fp = ta.state.dtype.type  # float, or np.longdouble for an extended-precision integrator
    order = np.argsort(T_arr, kind="stable")
    ahead = []  # y(T) for T in increasing order, from one forward run
    ta.time = fp(0)
    ta.state[:] = y0
    for i in order:
        if T_arr[i] > ta.time:
            _propagate_until(ta, fp(T_arr[i]), callback)  # the absolute time: each leg ends exactly at T
        ahead.append(ta.state.copy())
    err = np.empty(T_arr.size)
    for i, y_T in zip(order, ahead):
        ta.time = fp(0)
        back = np.asarray(involution(y_T.copy()))
        if back.dtype != y_T.dtype:
            raise ValueError(f"involution changed the state's precision ({y_T.dtype} -> {back.dtype})")
        ta.state[:] = back
        _propagate(ta, T_arr[i], callback, T_arr[i])
        err[i] = float(np.max(np.abs(np.asarray(diff(ta.state.copy(), target), float))))
    out = {"T": T_arr, "error": err, "rel_error": err / scale, "scale": scale}
    out.update(loschmidt_fit(T_arr, err, scale, floor_factor=floor_factor, saturation=saturation,
                             rounding=float(np.finfo(ta.state.dtype).eps)))
    return out


#: Written into the chaos_verdict dataset (attribute loschmidt_rule).
JUDGE_LOSCHMIDT_RULE = (
    "Verdict from ``loschmidt`` / ``loschmidt_fit`` (fits over the n_used points between the rounding floor and"
    " saturation; rms residuals are goodness of fit in log units, the stderr's are the uncertainties). chaotic:"
    " n_used >= min_points, exp_rate - sigma * exp_rate_err > 0 and either the exponential fit is better by "
    "fit_ratio (exp_rms * fit_ratio <= pow_rms) or the error grows faster than any plausible power "
    "(pow_exponent - sigma * pow_exponent_err > p_max); regular: n_used >= min_points, the exponential fit is "
    "not better by fit_ratio (pow_rms < exp_rms * fit_ratio) and the error grows at most like T^p_max "
    "(pow_exponent + sigma * pow_exponent_err < p_max; rounding on a torus gives about T^1 to T^1.5, Brouwer's "
    "law). Otherwise undecided. The chaotic return errors scatter by about a factor e around the exponential, "
    "so use many T values (tens) across the window between floor and saturation, which spans about ln(1e-2 / "
    "1e-13) / lambda = 25 / lambda in double (32 / lambda in long double)."
)


def judge_loschmidt(n_used, exp_rate, exp_rate_err, exp_rms, pow_exponent, pow_exponent_err, pow_rms, *,
                    sigma=3.0, fit_ratio=1.5, p_max=3.0, min_points=3):
    """Applies :data:`JUDGE_LOSCHMIDT_RULE`, the rule as the datasets record it (just above)."""
    if not _is_finite(n_used):
        return UNDECIDED, "not finite: n_used"
    if int(n_used) < min_points:
        return UNDECIDED, f"only {int(n_used)} return errors between rounding floor and saturation (need {min_points})"
    chk = _check_judge([("exp_rate", exp_rate), ("exp_rate_err", exp_rate_err), ("exp_rms", exp_rms),
                        ("pow_exponent", pow_exponent), ("pow_exponent_err", pow_exponent_err), ("pow_rms", pow_rms)],
                       [("exp_rate_err", exp_rate_err), ("pow_exponent_err", pow_exponent_err),
                        ("exp_rms", exp_rms), ("pow_rms", pow_rms)], sigma)
    if chk:
        return chk
    nums = (f"{int(n_used)} points; exp fit rate {_g(exp_rate)} +- {_g(exp_rate_err)} /time, rms {_g(exp_rms)}; "
            f"power fit T^{_g(pow_exponent)} +- {_g(pow_exponent_err)}, rms {_g(pow_rms)}; sigma {_g(sigma)}")
    if exp_rate - sigma * exp_rate_err > 0:
        if exp_rms * fit_ratio <= pow_rms:
            return CHAOTIC, f"return error grows exponentially (exp fit better by >= {_g(fit_ratio)}x); {nums}"
        if pow_exponent - sigma * pow_exponent_err > p_max:
            return CHAOTIC, f"return error grows faster than T^{_g(p_max)} (exponential amplification); {nums}"
    if pow_rms < exp_rms * fit_ratio and pow_exponent + sigma * pow_exponent_err < p_max:
        return REGULAR, f"return error grows at most like T^{_g(p_max)}; {nums}"
    return UNDECIDED, f"return error neither clearly exponential nor bounded by T^{_g(p_max)}; {nums}"


#: Written into the chaos_verdict dataset (attribute loschmidt_rule).
JUDGE_LOSCHMIDT_RUN_RULE = (
    "``judge_loschmidt`` on a ``loschmidt`` run, over all usable points and over their tail (the longest "
    "horizons before saturation, ``loschmidt_fit``'s tail_ fits). chaotic: chaotic over all points and in the "
    "tail (the growth is still exponential, or faster than T^3, where the error approaches saturation: a few "
    "early jumps of the error followed by power-law growth are not chaos); regular: regular in the tail (early "
    "transient amplification does not hide the power-law growth that follows); otherwise undecided, with both "
    "reasons."
)


def judge_loschmidt_run(L: dict, *, sigma=3.0) -> tuple[str, str]:
    """Applies :data:`JUDGE_LOSCHMIDT_RUN_RULE`, the rule as the datasets record it (just above)."""
    whole = judge_loschmidt(*(L[k] for k in ("n_used",) + _FIT_KEYS), sigma=sigma)
    tail = judge_loschmidt(L["tail_n"], *(L[f"tail_{k}"] for k in _FIT_KEYS), sigma=sigma)
    both = f"over all usable points: {whole[0]}: {whole[1]}; in the tail: {tail[0]}: {tail[1]}"
    if whole[0] == CHAOTIC and tail[0] == CHAOTIC:
        return CHAOTIC, f"exponential growth sustained into the tail; {both}"
    if tail[0] == REGULAR:
        return REGULAR, f"power-law growth in the tail; {both}"
    if whole[0] == CHAOTIC:
        return UNDECIDED, f"exponential growth not sustained into the tail; {both}"
    return UNDECIDED, f"neither sustained exponential growth nor power-law growth in the tail; {both}"


#: Written into the chaos_verdict dataset (attribute loschmidt_rule).
LOSCHMIDT_INDICATOR_RULE = (
    "The Loschmidt indicator, judged (``chaos.loschmidt.judge_loschmidt_run``) from the long-double run L_ld, "
    "whose rounding floor is 2^11 lower, so its error stays unsaturated up to longer T; the double run L's "
    "verdict is named in the reason and kept. Value and error: the long-double tail's exponential rate and its "
    "least-squares error. Returns value, error, verdict ((verdict, reason)) and verdict_double."
)


def loschmidt_indicator(L: dict, L_ld: dict, sigma: float) -> dict:
    """Applies :data:`LOSCHMIDT_INDICATOR_RULE`, the rule as the datasets record it (just above)."""
    double = judge_loschmidt_run(L, sigma=sigma)
    v, r = judge_loschmidt_run(L_ld, sigma=sigma)
    return {"value": L_ld["tail_exp_rate"], "error": L_ld["tail_exp_rate_err"],
            "verdict": (v, f"in long double: {r}; in double: {double[0]}"), "verdict_double": double[0]}
