"""What triggers the steady state, and where it leads: the first Omega spike against the size of the error the
integration injects (C04's tested cause), and the torus each escape lands on.

From one start the flow is integrated at a ladder of Taylor tolerances, each in an arithmetic whose rounding
lies far below it (tol >= FAR x machine epsilon), so that the tolerance, not the rounding, sets the error
injected along the second transient. Per run: the first spike after t_min, refined on the section delta = 0
(sleighsim.analysis.fate.refined_peaks), and the maximum relative energy drift. Runs that two adjacent
tolerances show saturated (sleighsim.analysis.trigger_law.saturated) and runs outside reach (:func:`chosen`)
stay out of the local slopes (sleighsim.analysis.trigger_law.slopes): the first spike's slope per range of
adjacent levels, never one line across them. Then every run's state ``fate.offset`` after its first spike is
followed on to the torus it reaches (sleighsim.scenes.trigger_fate).

Conventions: time in the flow's time unit; levels are log10 tol; spikes by the scenes' rule
(``transient.spike_times``) on Omega sampled every dt, after t_min; CPU seconds of this process.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.analysis import fate
from sleighsim.analysis.trigger_law import SATURATION_RULE, SLOPES_RULE, saturated, slopes
from sleighsim.chaos import faithfulness
from sleighsim.engine import ddsection, ddtaylor, integrators
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.engine.orbits import grid_samples
from sleighsim.engine.transient import spike_times
from sleighsim.model.params import Params
from sleighsim.precision import Precision
from sleighsim.scenes import memory, trigger_data, trigger_fate, trigger_price
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")

#: A tolerance sets the injected error when the arithmetic's rounding is at least this far below it.
FAR = 100.0
#: The energy drift is measured on every DRIFT_EVERY-th sample (at 200 bits: ddtaylor.energy_drift).
DRIFT_EVERY = 20


def _samples(params, y0, precision: Precision, tol: float, n: int, dt: float) -> np.ndarray:
    """The run from y0 in ``precision`` at ``tol`` at t = 0, dt, ..., (n - 1) dt, in its own arithmetic."""
    ta, _ = integrators.flow(False, tol, precision)
    integrators.set_pars(ta, params)
    integrators.load(ta, np.asarray(y0, float))
    return integrators.samples(ta, grid_samples(ta, n, dt, integrators.bounded(ta))[0])


def escape(params, precision: Precision, tol: float, cfg: dict, jets: DDBatch, scene: str) -> dict:
    """The run from y0 in ``precision`` at ``tol`` over t_end: its first spike after t_min refined (NaN without
    one) with the refinement's error, its maximum relative energy drift (every DRIFT_EVERY-th sample), the
    sample ``fate.offset`` after the first spike in the run's own arithmetic (None when the spike or that sample
    does not come within t_end) and its CPU seconds."""
    start = time.process_time()
    n = int(math.floor(cfg["t_end"] / cfg["dt"] + 1e-3)) + 1
    Y = _samples(params, cfg["y0"], precision, tol, n, cfg["dt"])
    hi = Y.astype(float)
    lo = (Y - hi.astype(Y.dtype)).astype(float)
    grid = cfg["dt"] * np.arange(n)
    coarse = spike_times(grid, hi[:, 1], factor=cfg["spike_factor"], t_min=cfg["t_min"])[:1]
    t_sec, x_sec = ddsection.crossings(jets, hi, lo, grid, coarse, 2 * cfg["half_width"])
    times, errors = fate.refined_peaks(t_sec, x_sec, coarse, cfg["half_width"])
    first, err = (float(times[0]), float(errors[0])) if times.size else (math.nan, math.nan)
    row = round((first + cfg["fate"]["offset"]) / cfg["dt"]) if math.isfinite(first) else n
    drift = ddtaylor.energy_drift(params, hi[::DRIFT_EVERY], lo[::DRIFT_EVERY])
    log.info("%s: %s at tol %.1e: first spike %.8g +- %.2g, drift %.3g", scene, precision, tol, first, err, drift)
    return {"first": first, "first_err": err, "drift": drift, "after": Y[row] if row < n else None,
            "cpu_s": time.process_time() - start}


#: Written into the trigger_law dataset (attribute chosen_rule, before the saturation rule).
CHOSEN_RULE = (
    "The runs (precision, tol) within reach of the slopes, one per distinct tolerance: where the arithmetic's "
    "rounding lies at least FAR times below tol (the tolerance, not the rounding, sets the injected error), and of "
    "a tolerance run in several such arithmetics only the finest (the same injected error is one point of the law, "
    "not one per arithmetic; its rounding lies farthest below it)."
)


def chosen(runs) -> np.ndarray:
    """Applies :data:`CHOSEN_RULE`, the rule as the datasets record it (just above)."""
    finest = {}
    for i in sorted(range(len(runs)), key=lambda i: -runs[i][0].epsilon):  # coarse to fine: the finest stays
        p, t = runs[i]
        if t >= FAR * p.epsilon:
            finest[t] = i
    return np.isin(np.arange(len(runs)), list(finest.values()))


def law(runs, escapes, cfg: dict) -> dict:
    """Per run whether it is saturated and in the slopes (chosen, not saturated, a first spike), and the slopes
    per range (sleighsim.analysis.trigger_law)."""
    tol = np.array([t for _, t in runs])
    arithmetic = [p.value for p, _ in runs]
    first = np.array([e["first"] for e in escapes])
    sat = saturated(arithmetic, tol, first, [e["drift"] for e in escapes], spike=cfg["saturation"]["spike"],
                    drift_factor=cfg["saturation"]["drift"])
    in_slopes = chosen(runs) & ~sat & np.isfinite(first)
    order = sorted(np.flatnonzero(in_slopes), key=lambda i: -tol[i])
    found = slopes([arithmetic[i] for i in order], np.log10(tol[order]), first[order], cfg["range_decades"])
    return {"saturated": sat, "in_slopes": in_slopes, **found}


def priced(fates, record: dict) -> None:
    """Adds to each fate row whose arithmetic does not follow its torus the price of the one it would need
    (sleighsim.scenes.trigger_price)."""
    for r in fates:
        if r is not None and r["follows"] == faithfulness.DOES_NOT_FOLLOW:
            needed = trigger_price.log10_needed(r["log10_gain_rounding"], trigger_fate.ROUNDING[r["arithmetic"]],
                                                faithfulness.FAITHFUL_MAX)
            r["price"] = trigger_price.price(record, 10.0**needed, r["interval"])


def trigger_law(cfg: dict, inputs: dict, scene: str = "") -> xr.Dataset:
    """First spike, saturation and the landed torus per (precision, tol) of ``cfg["tols"]`` from y0, and the local
    slopes (:mod:`this module <sleighsim.scenes.trigger>`); ``inputs["price"]``: the price record's path."""
    start, cpu = time.perf_counter(), time.process_time()
    params = Params.from_config(cfg["params"])
    record = trigger_price.load(inputs["price"])
    runs = [(p, float(t)) for p, tols in cfg["tols"].items() for t in tols]
    jets = DDBatch(params, cfg["fate"]["tol"])
    escapes = [escape(params, p, t, cfg, jets, scene) for p, t in runs]
    found = law(runs, escapes, cfg)
    fates = trigger_fate.landed(params, [e["after"] for e in escapes],
                                {**cfg["fate"], "spike_factor": cfg["spike_factor"], "half_width": cfg["half_width"]})
    priced(fates, record)
    ds = trigger_data.dataset(runs, escapes, found, fates)
    ds.attrs.update(params.attrs())
    ds.attrs.update(trigger_data.settings(cfg))
    ds.attrs.update(slopes_scatter=found["scatter"], slopes_dof=found["dof"], far=FAR, drift_every=DRIFT_EVERY,
                    chosen_rule=CHOSEN_RULE, saturation_rule=SATURATION_RULE, slopes_rule=SLOPES_RULE,
                    price_rule=trigger_price.PRICE_RULE, price_record_commit=str(record.get("git_commit", "")),
                    scene=scene, wall_time_s=time.perf_counter() - start, cpu_s=time.process_time() - cpu)
    return ds


TRIGGER_LAW = SceneKind(
    name="trigger_law",
    title="the first spike and the torus reached against the size of the injected error (tolerance and "
          "arithmetic) (claim C04)",
    compute=trigger_law, inputs=("price",),
    records=lambda c: [memory.span(c, "t_end", "dt"),
                       memory.span(c, "fate.T", "fate.dt", 8, ("runs", sum(len(t) for t in c["tols"].values())))])
