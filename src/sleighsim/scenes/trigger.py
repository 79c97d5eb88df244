"""What triggers the steady state: the first Omega spike against the size of the error the
integration injects (C04's tested cause).

From one start the flow is integrated at a ladder of Taylor tolerances, each in an arithmetic
whose rounding lies far below it (tol >= FAR x machine epsilon), so that the tolerance, not the
rounding, sets the error injected along the second transient. The first spike time is then fitted
against log10(tol), one point per distinct tolerance (:func:`fitted`): its slope (time units per
decade of injected error) and the level at which any given first-spike time would come. Runs at an
arithmetic's own epsilon, and a tolerance's runs in coarser arithmetics than its finest, are kept,
marked outside the fit.

Conventions: time in the flow's time unit; spikes by the scenes' rule (``transient.spike_times``)
on Omega sampled every dt, after t_min.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.engine.integrate import integrate, sample_grid
from sleighsim.engine.transient import spike_times
from sleighsim.io import cf
from sleighsim.model.equations import STATE_NAMES
from sleighsim.model.params import Params
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")

#: A tolerance sets the injected error when the arithmetic's rounding is at least this far below it.
FAR = 100.0


def spikes_after(params, y0, precision: Precision, tol: float, cfg: dict, scene: str) -> tuple:
    """(first spike, second spike, wall seconds, max relative energy drift) of the run from y0 in
    ``precision`` at ``tol`` (NaN for a spike that does not come within t_end)."""
    start = time.perf_counter()
    run = integrate(params, y0, sample_grid(0.0, cfg["t_end"], cfg["dt"]), tol=tol, precision=precision,
                    scene=f"{scene}[{precision} {tol:.0e}]", progress=1)
    s = spike_times(run.time.values, run.Omega.values, factor=cfg["spike_factor"], t_min=cfg["t_min"])
    first, second = (float(s[i]) if s.size > i else math.nan for i in (0, 1))
    log.info("%s: %s at tol %.1e: first spike %.6g, second %.6g", scene, precision, tol, first, second)
    return first, second, time.perf_counter() - start, run.attrs["energy_max_rel_drift"]


#: Written into the trigger_law dataset (attribute fit_rule, before fit's).
FITTED_RULE = (
    "The runs (precision, tol) in the fit, one per distinct tolerance: where the arithmetic's rounding lies at "
    "least FAR times below tol (the tolerance, not the rounding, sets the injected error), and of a tolerance "
    "run in several such arithmetics only the finest (the same injected error is one point of the law, not one "
    "per arithmetic; its rounding lies farthest below it)."
)


def fitted(runs) -> np.ndarray:
    """Applies :data:`FITTED_RULE`, the rule as the datasets record it (just above)."""
    finest = {}
    for i in sorted(range(len(runs)), key=lambda i: -runs[i][0].epsilon):  # coarse to fine: the finest stays
        p, t = runs[i]
        if t >= FAR * p.epsilon:
            finest[t] = i
    return np.isin(np.arange(len(runs)), list(finest.values()))


#: Written into the trigger_law dataset (attribute fit_rule, after fitted's).
FIT_RULE = (
    "Least squares of the first spike time against log10(tol) over the runs in the fit "
    "(scipy.stats.linregress): slope (time units per decade) and intercept with their standard errors from the "
    "residual scatter of the independent runs; NaN with fewer than 3 runs whose first spike came."
)


def fit(log10_tol, first) -> dict:
    """Applies :data:`FIT_RULE`, the rule as the datasets record it (just above)."""
    from scipy import stats  # here: at the top it costs every job start-up (scenes.catalog)

    x, y = np.asarray(log10_tol, float), np.asarray(first, float)
    ok = np.isfinite(y)
    if ok.sum() < 3:
        return dict(slope=math.nan, slope_stderr=math.nan, intercept=math.nan, intercept_stderr=math.nan,
                    rvalue=math.nan, n_fit=int(ok.sum()))
    r = stats.linregress(x[ok], y[ok])
    return dict(slope=float(r.slope), slope_stderr=float(r.stderr), intercept=float(r.intercept),
                intercept_stderr=float(r.intercept_stderr), rvalue=float(r.rvalue), n_fit=int(ok.sum()))


def level_for(first_spike: float, law: dict) -> float:
    """log10 of the injected error (tolerance) at which the fitted law puts the first spike at
    ``first_spike`` (NaN when the law is not determined or flat)."""
    if not (math.isfinite(law["slope"]) and law["slope"] != 0):
        return math.nan
    return (first_spike - law["intercept"]) / law["slope"]


def trigger_law(cfg: dict, scene: str = "") -> xr.Dataset:
    """First and second spike per (precision, tol) of ``cfg["tols"]`` from y0, and the fitted law."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    runs = [(p, float(t)) for p, tols in cfg["tols"].items() for t in tols]
    out = np.array([spikes_after(params, cfg["y0"], p, t, cfg, scene) for p, t in runs])
    tol = np.array([t for _, t in runs])
    in_fit = fitted(runs)
    law = fit(np.log10(tol[in_fit]), out[in_fit, 0])
    ds = xr.Dataset(
        {"precision": ("run", np.array([p.value for p, _ in runs], dtype=object)),
         "tol": ("run", tol, cf.attrs("Taylor tolerance: the size of the injected error where in_fit")),
         "rounding": ("run", [p.epsilon for p, _ in runs], cf.attrs("machine epsilon of the arithmetic")),
         "in_fit": ("run", in_fit.astype(np.int8), cf.attrs(f"1 when tol >= {FAR:g} x rounding (the tolerance sets "
                                                            "the injected error), in the finest such arithmetic that "
                                                            "ran this tol, else 0")),
         "first_spike": ("run", out[:, 0], cf.attrs("time of the first Omega spike", "time")),
         "second_spike": ("run", out[:, 1], cf.attrs("time of the second Omega spike", "time")),
         "run_wall_s": ("run", out[:, 2], cf.attrs("wall-clock time of the run", "s")),
         "run_energy_max_rel_drift": ("run", out[:, 3])},
        coords={"run": np.arange(len(runs))},
    )
    ds.attrs.update(params.attrs())
    ds.attrs.update({f"y0_{n}": float(v) for n, v in zip(STATE_NAMES, cfg["y0"])})
    ds.attrs.update({f"law_{k}": v for k, v in law.items()})
    ds.attrs.update(scene=scene, t_end=cfg["t_end"], dt=cfg["dt"], t_min=cfg["t_min"],
                    spike_factor=cfg["spike_factor"], far=FAR,
                    integrator="heyoka Taylor, tolerance and arithmetic per run",
                    energy_max_rel_drift=float(np.nanmax(out[:, 3])), tol_max=float(tol.max()),
                    fit_rule=f"{FITTED_RULE} {FIT_RULE}",
                    wall_time_s=time.perf_counter() - start)
    return ds


TRIGGER_LAW = SceneKind(
    name="trigger_law",
    title="the first spike against the size of the injected error (tolerance and arithmetic) (claim C04)",
    compute=trigger_law, records=lambda c: [memory.span(c, "t_end", "dt")])
