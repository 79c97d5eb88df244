"""Does the steady state's slow drift end? One orbit over a long horizon, cut into windows: the
spike interval and the finite-time lambda_1 per window, and the trend rule on each."""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.analysis import windows
from sleighsim.engine import integrators, transient
from sleighsim.engine.transient import settle
from sleighsim.io import cf
from sleighsim.model import equations
from sleighsim.model.attrs import state_attrs
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.checks import multiple
from sleighsim.scenes.common import steady_arithmetic
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def _intervals(t, Omega, spike: dict) -> tuple[float, float, int]:
    """Mean and standard deviation of the intervals between the window's Omega spikes, and their count."""
    s = transient.spike_times(t, Omega, factor=spike["factor"], block=spike["block"],
                              min_separation=spike["min_separation"])
    return (*transient.interval_stats(s), int(s.size))


def _windowed(ta, y, params, cfg: dict, scene: str) -> tuple:
    """The orbit from the settled y in windows: per window (arrays) its start, spike interval mean, sd
    and count, lambda_1 and energy drift; the number of windows; the steps taken."""
    n_windows = int(round(cfg["T"] / cfg["window"]))
    E0 = equations.energy(y, params)
    rows, steps = [], 0
    for w in windows.windowed_orbit(ta, 4, y, n_windows=n_windows, window=cfg["window"], tau=cfg["tau"],
                                    component=1, t_align=cfg["t_align"], label=scene):
        mean, sd, count = _intervals(w["t"], w["x"], cfg["spike"])
        rows.append((w["t_start"], mean, sd, count, w["lambda_1"],
                     float(equations.energy(w["state"], params) / E0 - 1)))
        steps += w["steps"]
    return tuple(np.array(c) for c in zip(*rows)), n_windows, steps


def _notes(cfg: dict) -> dict:
    """The dataset's spike rule, uncertainty and precision note."""
    return {
        "spike_rule": (f"spike: |Omega| (sampled every tau) block maximum ({cfg['spike']['block']:g} time units) above "
                       f"{cfg['spike']['factor']:g} x the median block maximum of the window's second half; spikes "
                       f"closer than {cfg['spike']['min_separation']:g} merged; interval: mean of the window's "
                       "intervals"),
        "uncertainty": "lambda_1_stderr: spread of the per-window values / sqrt(windows) (windows of many spike cycles "
                       "taken as independent); trends: least squares over the windows of the last part of the run",
        "precision_note": ("tangent-based exponents of this system are inflated by rounding amplified at the spikes in "
                           "double (see the chaos verdict's long-double check); long double has 2^11 smaller rounding; "
                           "the spike interval is an orbit statistic"),
    }


def drift_windows(cfg: dict, scene: str = "") -> xr.Dataset:
    """From y0 (scaled to the label), after a checked transient: one orbit over T in windows of
    ``window``, with one tangent vector renormalised every tau (compact or full heyoka mode; in the
    block's ``precision``, ``common.steady_arithmetic``: double at tol, long double at its machine
    epsilon; the transient in double). Per window: the steady spike interval (mean, sd, spikes), lambda_1
    of the window and the energy drift; the trend rule (``windows.trend``) on the spike interval and on
    lambda_1."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    y0 = state_at_label(cfg["y0"], params, cfg["energy_label"])
    y, transient_attrs = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=cfg["tol"], label=scene,
                                progress=1)
    arith = steady_arithmetic(cfg)
    tol = arith["tol"]
    ta, compile_s = integrators.sleigh_tangent(1, tol, cfg["compact_mode"], arith["precision"])
    integrators.set_pars(ta, params)
    precision = (Precision.DOUBLE if ta.state.dtype == np.float64
                 else f"long double (epsilon {float(np.finfo(ta.state.dtype).eps):.2g})")
    (t_start, interval, interval_sd, n_spikes, lam, drift), n_windows, steps = _windowed(ta, y, params, cfg, scene)
    t_mid = t_start + cfg["window"] / 2
    judged = {name: windows.trend(t_mid, x, rel_tol=cfg["rel_tol"][name], sigma=cfg["sigma"],
                                  last_fraction=cfg["last_fraction"])
              for name, x in (("spike_interval", interval), ("lambda_1", lam))}
    ds = xr.Dataset(
        {
            "spike_interval": ("window", interval, cf.attrs("mean interval between Omega spikes", "time")),
            "spike_interval_sd": ("window", interval_sd,
                                  cf.attrs("standard deviation of the intervals between Omega spikes", "time")),
            "n_spikes": ("window", n_spikes),
            "lambda_1": ("window", lam, {"units": "1", "long_name": "finite-time lambda_1 of the window per model "
                                                                    f"time unit (one tangent vector, {precision})"}),
            "energy_rel_drift": ("window", drift, cf.attrs("E / E(settled) - 1 at the window's end")),
        },
        coords={"window": np.arange(n_windows), "t_start": ("window", t_start, cf.attrs("start of the window", "time")),
                "t_mid": ("window", t_mid, cf.attrs("middle of the window", "time"))},
    )
    ds.attrs.update(state_attrs(params, y0))
    ds.attrs.update(transient_attrs)
    for name, j in judged.items():
        ds.attrs.update({f"{name}_trend_{k}": v for k, v in j.items()})
    n = lam.size
    ds.attrs.update(
        scene=scene, backend="heyoka", compact_mode=int(cfg["compact_mode"]), precision=precision, tol=tol,
        tol_transient=cfg["tol"], tau=cfg["tau"],
        T=float(n * cfg["window"]), window=cfg["window"], steps=int(steps), compile_s=compile_s,
        lambda_1_mean=float(lam.mean()), lambda_1_stderr=float(lam.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan,
        spike_interval_overall=float(np.nanmean(interval)),
        energy_max_rel_drift=float(np.max(np.abs(drift))), rel_tol_spike_interval=cfg["rel_tol"]["spike_interval"],
        rel_tol_lambda_1=cfg["rel_tol"]["lambda_1"], last_fraction=cfg["last_fraction"], sigma=cfg["sigma"],
        trend_rule=windows.TREND_RULE, t_align=cfg["t_align"], **_notes(cfg),
        wall_time_s=time.perf_counter() - start,
    )
    log.info("%s: spike interval %s (%s), lambda_1 %s (%s)", scene, judged["spike_interval"]["verdict"],
             judged["spike_interval"]["reason"], judged["lambda_1"]["verdict"], judged["lambda_1"]["reason"])
    return ds


def _drift_windows_checks(w, cfg):
    multiple(f"{w}.window", cfg["window"], "tau", cfg["tau"], least=2)
    multiple(f"{w}.T", cfg["T"], "window", cfg["window"])


#: The variables only this kind writes: name -> (long_name, kind of quantity) (``sleighsim.io.cf``).
VOCABULARY = {
    "t_mid": ("middle of the window", "time"),
}


DRIFT_WINDOWS = SceneKind(
    name="drift_windows",
    title="the main state's slow drift: spike interval and lambda_1 per window of one long run",
    vocabulary=VOCABULARY,
    compute=drift_windows, checks=_drift_windows_checks,
    records=lambda c: [*memory.pre_run(c, "t_transient"), memory.span(c, "window", "tau", 2)])
