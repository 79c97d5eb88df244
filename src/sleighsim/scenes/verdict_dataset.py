"""The chaos verdict's dataset: its variables per state, indicator and arithmetic, and its attributes (the
rules, from the judges' docstrings, and the settings)."""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from sleighsim.chaos.faithfulness import GAIN_RULE, state_origin
from sleighsim.chaos.frequency import DRIFT_RULE, FREQUENCY_LOG_RATIO_RULE, JUDGE_FREQUENCY_RULE
from sleighsim.chaos.loschmidt import (
    JUDGE_LOSCHMIDT_RULE,
    JUDGE_LOSCHMIDT_RUN_RULE,
    LOSCHMIDT_FIT_RULE,
    LOSCHMIDT_INDICATOR_RULE,
)
from sleighsim.chaos.megno import JUDGE_MEGNO_RULE
from sleighsim.chaos.rule import (
    CLASS_RULE,
    CONSISTENCY_RULE,
    DECISION_RULE,
    FAITHFUL_RULE,
)
from sleighsim.chaos.tangent import JUDGE_BENETTIN_RULE
from sleighsim.chaos.two_trajectory import D0_INDEPENDENT_RULE
from sleighsim.io import cf
from sleighsim.precision import Precision
from sleighsim.scenes.common import nan_padded
from sleighsim.scenes.verdict_frequency import FREQUENCY_INDICATOR_RULE
from sleighsim.scenes.verdict_orbits import R_IMAGE_RULE, loschmidt_settings
from sleighsim.scenes.verdict_tangent import PRECISION_CHECK_RULE


def variables(per_state, out: list, ind: list, ft: dict) -> dict:
    """The dataset's variables from the states' results ``out`` (``per_state(key)``: one value per state),
    the indicators ``ind`` and the frequency table ``ft``, in the dataset's order."""
    return {**_verdict_vars(per_state, out, ind), **_state_vars(per_state), **_megno_vars(per_state),
            **_loschmidt_vars(per_state), **_frequency_vars(ft), **_long_double_vars(per_state), **_gain_vars(out)}


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
        "settled_state": (("state", "component"), per_state("settled")),
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


#: The arithmetic in which the chaos verdict settles its states (engine.transient.settle, heyoka's double).
SETTLED_BY = Precision.DOUBLE


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
        "gain_steps_per_cycle": ("state", [g["steps_per_cycle"] for g in gains],
                                 cf.attrs("Taylor steps per spike cycle of the gauge's run (the count of roundings "
                                          "injected per cycle)")),
        "log10_gain_rounding": (("state", "arithmetic"),
                                [[g["log10_gain_rounding"][a] for a in Precision] for g in gains],
                                cf.attrs("log10(G_max x steps per cycle x unit roundoff of the arithmetic)")),
        "follows_orbit": (("state", "arithmetic"), np.array([[g["follows"][a] for a in Precision] for g in gains],
                                                            dtype=object),
                          {"long_name": "does the arithmetic follow the exact orbit (G x steps x rounding below "
                                        "faithfulness.FAITHFUL_MAX; unknown without a complete cycle)"}),
        "state_origin": ("state", np.array([state_origin(SETTLED_BY, g["follows"][SETTLED_BY],
                                                         spike_period(g["spike_times"])) for g in gains], dtype=object),
                         {"long_name": "what the settled state is: its start's own steady state, or a torus the "
                                       "settling arithmetic's rounding selected (chaos.faithfulness.state_origin)"}),
    }


def set_attrs(ds: xr.Dataset, cfg: dict, params, per_state, start: float) -> None:
    """The dataset's attributes: the rules (from the judges' docstrings), the settings and the wall time since start."""
    fc = cfg["frequency"]
    ds.attrs.update(
        rule=DECISION_RULE + "; then " + CONSISTENCY_RULE,
        class_rule=CLASS_RULE,
        faithful_rule=FAITHFUL_RULE,
        precision_rule=PRECISION_CHECK_RULE, d0_rule=D0_INDEPENDENT_RULE, T_long_double=cfg["T_long_double"],
        tol_long_double=Precision.LONG_DOUBLE.epsilon, compact_mode=int(cfg["compact_mode"]),
        benettin_rule=JUDGE_BENETTIN_RULE, R_rule=R_IMAGE_RULE,
        uncertainty="Benettin: standard error over independent replicas along the settled orbit; FTLE: window "
                    "standard error; MEGNO: 2 x (slope of <Y> over the second half, least-squares error, "
                    "correlated residuals: understated); two-trajectory: consecutive blocks (value at the middle d0); "
                    "Loschmidt: least-squares error of the exponential fit over the long-double run's tail; "
                    "frequency: D's "
                    "ln-error 1/sqrt(2 (K - 1)) for K windows (sample standard deviation of K values); long double: "
                    "consecutive blocks of one replica's MEGNO run",
        megno_rule=JUDGE_MEGNO_RULE,
        frequency_rule=" ".join((FREQUENCY_INDICATOR_RULE, JUDGE_FREQUENCY_RULE, FREQUENCY_LOG_RATIO_RULE)),
        frequency_method=DRIFT_RULE, frequency_T=fc["T"], frequency_dt=fc["dt"],
        frequency_component=fc["component"], frequency_min_cycles=fc["min_cycles"], frequency_quad_T=fc["quad_T"],
        frequency_tol_quad=Precision.QUAD.epsilon,
        loschmidt_rule=" ".join((LOSCHMIDT_INDICATOR_RULE, JUDGE_LOSCHMIDT_RUN_RULE, JUDGE_LOSCHMIDT_RULE)),
        loschmidt_fit=LOSCHMIDT_FIT_RULE, **loschmidt_settings(), T_megno=cfg["T_megno"],
        loschmidt_T=list(cfg["loschmidt_T"]), loschmidt_n=cfg["loschmidt_n"], T_gain=cfg["T_gain"],
        tau_gain=cfg["tau_gain"], gain_rule=GAIN_RULE,
        param_eps=params.eps, param_b=params.b, param_K2=params.K2, energy_label=cfg["energy_label"], tol=cfg["tol"],
        tau=cfg["tau"], replicas=cfg["replicas"], replica_spacing=cfg["replica_spacing"],
        T_two=cfg["T_two"], T_R=cfg["T_R"], backend="heyoka", wall_time_s=time.perf_counter() - start,
        transient_over=int(np.all(per_state("transient_over") == 1)),
    )
