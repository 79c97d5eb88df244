"""The trigger_law dataset (sleighsim.scenes.trigger): per run its escape, saturation and the torus it lands on,
per range the first spike's local slope, each variable with its CF attributes, and the settings it records.

Conventions: time in the flow's time unit; slopes in time units per decade of injected error; text variables
hold words; a run without an escape (or a torus quantity not measured) holds NaN, an empty text or -1 cycles.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from sleighsim.analysis import fate
from sleighsim.io import cf
from sleighsim.model.equations import STATE_NAMES
from sleighsim.scenes import trigger_fate
from sleighsim.scenes.common import nan_padded


def _column(fates, key: str, missing=math.nan) -> list:
    """One quantity of every run's fate row (``missing`` where a run has none)."""
    return [missing if r is None else r[key] for r in fates]


def _dd_gauge(r) -> float:
    """log10 G x steps x rounding double-double's gauge gave on a run's torus (NaN without a row)."""
    return math.nan if r is None else r.get("instead_of", r)["log10_gain_rounding"]


def _fate_variables(fates) -> dict:
    """The landed torus per run."""
    text = lambda values: ("run", np.array(values, dtype=object))  # noqa: E731
    return {
        "landed_arithmetic": (*text(_column(fates, "arithmetic", "")),
                              cf.attrs("arithmetic the landed torus was followed and recorded in", "text")),
        "landed_spike_time": (("run", "spike"), nan_padded([[] if r is None else r["times"] for r in fates], 1),
                              cf.attrs("refined spike times on the torus reached, from the post-escape state", "time")),
        "landed_interval": ("run", _column(fates, "interval"),
                            cf.attrs("mean refined spike interval of the torus reached", "time")),
        "landed_interval_scatter": ("run", _column(fates, "scatter"),
                                    cf.attrs("standard deviation of the torus' refined spike intervals", "time")),
        "landed_interval_resolution": ("run", _column(fates, "resolution"),
                                       cf.attrs("resolution of the refined spike intervals (rms error)", "time")),
        "landed_cycles": ("run", np.array(_column(fates, "cycles", -1), dtype=np.int64),
                          cf.attrs("refined spike intervals measured on the torus reached (past the approach)")),
        "landed_approach": ("run", np.array(_column(fates, "approach", -1), dtype=np.int64),
                            cf.attrs("leading refined intervals of the approach, before the train is periodic")),
        "landed_class": (*text(_column(fates, "class", "")),
                         cf.attrs(f"class of the torus reached: one of {', '.join(fate.CLASSES)}", "text")),
        "landed_ln_gain": ("run", _column(fates, "ln_gain"),
                           cf.attrs("ln G of the torus' spike cycle (largest one-period tangent-map gain)")),
        "landed_steps_per_cycle": ("run", _column(fates, "steps_per_cycle"),
                                   cf.attrs("Taylor steps of one spike cycle in the landed arithmetic")),
        "landed_log10_gain_rounding": ("run", _column(fates, "log10_gain_rounding"),
                                       cf.attrs("log10 of G x steps x rounding in the landed arithmetic")),
        "dd_log10_gain_rounding": ("run", [_dd_gauge(r) for r in fates],
                                   cf.attrs("log10 of G x steps x rounding in double-double on the torus reached")),
        "landed_follows": (*text(_column(fates, "follows", "")),
                           cf.attrs("the gauge's answer for the landed arithmetic on the torus reached", "text")),
        "follows": (*text([trigger_fate.follows_text(r) for r in fates]),
                    cf.attrs("whether the arithmetic follows the torus reached (faithfulness gauge)", "text")),
        "landing_confirmed": ("run", np.array(_column(fates, "confirmed", -1), dtype=np.int8),
                              cf.attrs("1 when triple-double lands on the same torus, 0 when not, -1 unchecked")),
        "landing_check_difference": ("run", _column(fates, "check_difference"),
                                     cf.attrs("largest difference of the first refined spikes, double-double against "
                                              "triple-double", "time")),
        "fate_cpu_s": ("run", _column(fates, "cpu_s"), cf.attrs("CPU time of following the torus (share)", "s")),
        "landing_check_cpu_s": ("run", _column(fates, "check_cpu_s"),
                                cf.attrs("CPU time of the landing check in triple-double (share)", "s")),
    }


def _range_variables(ranges: list[dict]) -> dict:
    """The local slopes per range."""
    col = lambda key: [r[key] for r in ranges]  # noqa: E731
    return {
        "range_label": ("range", np.array(col("label"), dtype=object),
                        cf.attrs("arithmetic of the range (a -> b: the bridge between two ranges)", "text")),
        "range_tol_max": ("range", col("tol_max"), cf.attrs("largest tolerance (injected error) of the range")),
        "range_tol_min": ("range", col("tol_min"), cf.attrs("smallest tolerance (injected error) of the range")),
        "range_n": ("range", np.array(col("n"), dtype=np.int64), cf.attrs("runs in the range")),
        "range_slope": ("range", col("slope"),
                        cf.attrs("local slope of the first spike, per decade of injected error", "time")),
        "range_slope_stderr": ("range", col("slope_stderr"),
                               cf.attrs("standard error of the local slope, per decade", "time")),
    }


def dataset(runs, escapes, found: dict, fates) -> xr.Dataset:
    """The dataset from the runs (precision, tol), their escapes (sleighsim.scenes.trigger.escape), the law
    (sleighsim.scenes.trigger.law) and the fate rows (sleighsim.scenes.trigger_fate.landed)."""
    esc = lambda key: [e[key] for e in escapes]  # noqa: E731
    per_run = {
        "precision": ("run", np.array([p.value for p, _ in runs], dtype=object), cf.attrs("arithmetic", "text")),
        "tol": ("run", [t for _, t in runs], cf.attrs("Taylor tolerance: the size of the injected error")),
        "rounding": ("run", [p.epsilon for p, _ in runs], cf.attrs("machine epsilon of the arithmetic")),
        "saturated": ("run", found["saturated"].astype(np.int8), cf.attrs("1 when saturated (saturation_rule)")),
        "in_slopes": ("run", found["in_slopes"].astype(np.int8),
                      cf.attrs("1 when in the local slopes (chosen_rule, not saturated, a first spike)")),
        "first_spike": ("run", esc("first"), cf.attrs("refined time of the first Omega spike after t_min", "time")),
        "first_spike_err": ("run", esc("first_err"), cf.attrs("error of the refined first spike", "time")),
        "run_energy_max_rel_drift": ("run", esc("drift"),
                                     cf.attrs("maximum relative energy drift of the run (at 200 bits)")),
        "run_cpu_s": ("run", esc("cpu_s"), cf.attrs("CPU time of the run and its refinement", "s")),
    }
    return xr.Dataset({**per_run, **_fate_variables(fates), **_range_variables(found["ranges"])},
                      coords={"run": np.arange(len(runs)),
                              "range": ("range", np.arange(len(found["ranges"])),
                                        cf.attrs("index of a range of adjacent levels (local slopes)"))})


def settings(cfg: dict) -> dict:
    """The global attributes of the block's settings and the fate's rules."""
    f = cfg["fate"]
    return {**{f"y0_{n}": float(v) for n, v in zip(STATE_NAMES, cfg["y0"])},
            **{k: cfg[k] for k in ("t_end", "dt", "t_min", "spike_factor", "half_width", "range_decades",
                                   "price_record")},
            "saturation_spike": cfg["saturation"]["spike"], "saturation_drift": cfg["saturation"]["drift"],
            **{f"fate_{k}": v for k, v in f.items()},
            "peak_rule": fate.PEAK_RULE, "class_rule": fate.TRAIN_RULE, "fate_rule": trigger_fate.FATE_RULE,
            "check_rule": trigger_fate.CHECK_RULE,
            "integrator": "heyoka Taylor per run (tolerance and arithmetic per run); the fate in double-double "
                          "(sleighsim.engine.ddbatch), again in triple-double (sleighsim.engine.tdtaylor) where "
                          "double-double does not follow"}
