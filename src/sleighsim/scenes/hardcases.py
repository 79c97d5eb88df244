"""Hard cases: where the numerics get difficult, and what happens there.

Each case records energy drift, steps, step-size range, heyoka-vs-SciPy agreement
and wall time, and gets an outcome: "reliable" (its measured error is below the
stated bound), "degraded" (how), or "refused" (the documented ValueError).
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.engine import poincare
from sleighsim.engine.integrate import final_state, integrate, sample_grid
from sleighsim.model.equations import state_difference
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_LABEL, REFERENCE_STATE, state_at_label
from sleighsim.scenes import memory
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")
REF = np.array(REFERENCE_STATE)


def _agreement(params, y0, T, tol, rtol):
    """Max |heyoka - DOP853| over the state at T, relative to the velocity scale."""
    a = integrate(params, y0, [0.0, T], tol=tol, progress=1)
    b = integrate(params, y0, [0.0, T], backend="scipy", rtol=rtol, atol=rtol * 1e-3, progress=1)
    scale = max(np.max(np.abs(y0[:3])), 1e-300)
    return a, float(np.max(np.abs(state_difference(final_state(a), final_state(b)))) / scale)


def case_params(name, params, y0, T, cfg):
    """Integrate with both backends; reliable if drift and disagreement are below the bounds."""
    a, disagree = _agreement(params, np.asarray(y0, float), T, cfg["tol"], cfg["scipy_rtol"])
    ok = a.attrs["energy_max_rel_drift"] < cfg["max_drift"] and disagree < cfg["max_disagreement"]
    how = "" if ok else (f"drift {a.attrs['energy_max_rel_drift']:.2g}" if a.attrs["energy_max_rel_drift"]
                         >= cfg["max_drift"] else f"backends differ by {disagree:.2g}")
    return dict(case=name, outcome="reliable" if ok else "degraded",
                error=max(a.attrs["energy_max_rel_drift"], disagree),
                drift=a.attrs["energy_max_rel_drift"], disagreement=disagree, steps=a.attrs["steps"],
                min_step=a.attrs["min_step"], max_step=a.attrs["max_step"], wall_s=a.attrs["wall_time_s"],
                detail=how or f"T = {T:g}")


def case_scaling(name, label, cfg):
    """The time-scaling law at an extreme label: the run at `label` over T/c against c x the reference run."""
    p = Params.paper(eps=0.1)
    c = math.sqrt(label / REFERENCE_LABEL)
    T = cfg["T_scaling"]
    base = integrate(p, REF, [0.0, T], tol=cfg["tol"], progress=1)
    y = state_at_label(REF, p, label)
    scaled = integrate(p, y, [0.0, T / c], tol=cfg["tol"], progress=1)
    pred = np.r_[c * final_state(base)[:3], final_state(base)[3]]
    err = float(np.max(np.abs(state_difference(np.r_[final_state(scaled)[:3] / c, final_state(scaled)[3]],
                                                np.r_[pred[:3] / c, pred[3]]))))
    ok = err < cfg["max_scaling_error"]
    return dict(case=name, outcome="reliable" if ok else "degraded", error=err,
                drift=scaled.attrs["energy_max_rel_drift"], disagreement=np.nan, steps=scaled.attrs["steps"],
                min_step=scaled.attrs["min_step"], max_step=scaled.attrs["max_step"],
                wall_s=scaled.attrs["wall_time_s"],
                detail=f"time-scaling law, c = {c:.3g}: max error {err:.2g} (velocities / c, delta)")


def case_long(name, cfg):
    """A long horizon at the default tolerance: energy drift over T_long."""
    p = Params.paper(eps=0.1)
    T = cfg["T_long"]
    a = integrate(p, REF, sample_grid(0.0, T, T / 100), tol=cfg["tol"], progress=10, scene=name)
    ok = a.attrs["energy_max_rel_drift"] < cfg["max_drift_long"]
    return dict(case=name, outcome="reliable" if ok else "degraded", error=a.attrs["energy_max_rel_drift"],
                drift=a.attrs["energy_max_rel_drift"], disagreement=np.nan, steps=a.attrs["steps"],
                min_step=a.attrs["min_step"], max_step=a.attrs["max_step"], wall_s=a.attrs["wall_time_s"],
                detail=f"T = {T:g}: drift {a.attrs['energy_max_rel_drift']:.2g} over {a.attrs['steps']} steps "
                       f"(bound {cfg['max_drift_long']:g})")


def case_at_rest(name, cfg):
    """Zero velocity: an equilibrium; the state must not move."""
    p = Params.paper(eps=0.1)
    y0 = np.array([0.0, 0.0, 0.0, 0.7])
    a = integrate(p, y0, [0.0, 100.0], tol=cfg["tol"], progress=1)
    err = float(np.max(np.abs(state_difference(final_state(a), y0))))
    return dict(case=name, outcome="reliable" if err == 0 else "degraded", error=err, drift=np.nan,
                disagreement=np.nan, steps=a.attrs["steps"], min_step=a.attrs["min_step"], max_step=a.attrs["max_step"],
                wall_s=a.attrs["wall_time_s"], detail="state unchanged after 100 time units")


def case_on_section(name, cfg):
    """Starting exactly on a section (delta = pi/2): crossings are not double-counted and stay on it."""
    p = Params.sleigh0(b=1.0, K2=1.1)
    omega0 = 1.3
    c = poincare.crossings(p, [0.2, 0.0, omega0, math.pi / 2], 0.0, 50.0, tol=cfg["tol"])
    expected = int(math.floor(50.0 * omega0 / (math.pi / 2)))
    err = float(np.max(np.abs(c["time"] - (np.arange(1, len(c["time"]) + 1) * (math.pi / 2) / omega0))))
    ok = len(c["time"]) == expected and err < 1e-10 and np.max(c["residual"]) < 1e-12
    return dict(case=name, outcome="reliable" if ok else "degraded", error=err, drift=np.nan, disagreement=np.nan,
                steps=c["steps"], min_step=np.nan, max_step=np.nan, wall_s=c["wall_time_s"],
                detail=f"{len(c['time'])} crossings (expected {expected}), max residual {np.max(c['residual']):.1e}")


def case_refused(name, build):
    """An inadmissible input: ``build()`` must raise ValueError (outcome "refused", its message the detail),
    else the row is "degraded"."""
    try:
        build()
    except ValueError as err:
        return dict(case=name, outcome="refused", error=np.nan, drift=np.nan, disagreement=np.nan, steps=0,
                    min_step=np.nan, max_step=np.nan, wall_s=0.0, detail=str(err))
    return dict(case=name, outcome="degraded", error=np.nan, drift=np.nan, disagreement=np.nan, steps=0,
                min_step=np.nan, max_step=np.nan, wall_s=0.0, detail="accepted although inadmissible")


def hardcases(cfg: dict, scene: str = "") -> xr.Dataset:
    """Every hard case of the config block, one row each."""
    start = time.perf_counter()
    rows = []
    for eps in cfg["small_eps"] + cfg["large_eps"]:
        p = Params.paper(eps=eps)
        rows.append(case_params(f"eps = {eps:g}", p, REF, cfg["T_eps"], cfg))
    p = Params.paper(eps=0.1)
    rows.append(case_params("rotor carries all the energy", p, state_at_label([0, 0, 1, 0], p, 0.1127),
                            cfg["T_eps"], cfg))
    for label in cfg["labels"]:
        rows.append(case_scaling(f"energy label {label:g}", label, cfg))
    rows.append(case_long(f"horizon {cfg['T_long']:g}", cfg))
    rows.append(case_at_rest("velocity exactly zero", cfg))
    rows.append(case_on_section("delta exactly pi/2 (on a section)", cfg))
    rows.append(case_refused("eps = 1.5", lambda: Params.paper(eps=1.5)))
    rows.append(case_refused("eps = 0", lambda: Params.paper(eps=0.0)))
    rows.append(case_refused("energy label 0", lambda: state_at_label(REF, p, 0.0)))
    for r in rows:
        log.info("hard case %-32s %-9s %s", r["case"], r["outcome"], r["detail"])
    ds = xr.Dataset({k: ("case", np.array([r[k] for r in rows])) for k in rows[0] if k != "case"},
                    coords={"case": [r["case"] for r in rows]})
    ds.attrs.update({k: v for k, v in cfg.items() if not isinstance(v, list)})
    ds.attrs.update(n_reliable=int(np.sum(ds.outcome.values == "reliable")),
                    n_degraded=int(np.sum(ds.outcome.values == "degraded")),
                    n_refused=int(np.sum(ds.outcome.values == "refused")), wall_time_s=time.perf_counter() - start)
    ds.attrs["scene"] = scene
    return ds


#: The variables only this kind writes: name -> (long_name, kind of quantity) (``sleighsim.io.cf``).
VOCABULARY = {
    "case": ("hard case", "text"),
    "outcome": ("outcome: reliable, degraded or refused", "text"),
    "disagreement": ("max |heyoka - DOP853| of the end state over the velocity scale", "1"),
    "min_step": ("smallest integrator step", "time"),
    "max_step": ("largest integrator step", "time"),
    "detail": ("detail of the outcome", "text"),
}


HARDCASES = SceneKind(
    name="hardcases",
    title=("hard cases of the integrator: extreme parameters, energies and horizons, states at rest and on a "
           "section"),
    vocabulary=VOCABULARY,
    compute=hardcases,
                      records=lambda c: [memory.span(c, "T_long", ("T_long / 100", c["T_long"] / 100))])
