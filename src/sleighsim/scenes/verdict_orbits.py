"""The chaos verdict's orbit indicators (no tangent dynamics): where the reversing involution R sends a
state, two nearby trajectories and the Loschmidt return error, run on the sleigh for
:mod:`sleighsim.scenes.verdict`."""

from __future__ import annotations

import inspect
import math

import numpy as np

from sleighsim.chaos.loschmidt import (
    judge_loschmidt_run,
    loschmidt,
    loschmidt_fit,
)
from sleighsim.chaos.two_trajectory import two_trajectory
from sleighsim.chaos.verdicts import UNDECIDED
from sleighsim.engine import integrators
from sleighsim.engine.integrate import integrate, sample_grid
from sleighsim.model import equations
from sleighsim.precision import Precision
from sleighsim.scenes.common import stored_state, tolerance

# the reversing involution: (u, Omega, omega, delta) -> (-u, -Omega, -omega, delta)
R = np.array([-1.0, -1.0, -1.0, 1.0])


#: Written into the chaos_verdict dataset (attribute R_rule).
R_IMAGE_RULE = (
    "Where R sends a point of the state: integrate R y forward over T and compare the time means of (u, omega) "
    "over the second half with R applied to the state's own means. \"stays\" when within rtol of the scale of the"
    " means, else \"leaves\" (the image of the state is not visited: a repeller)."
)


def r_image(params, y, ref_mean, *, T: float, tol: float, rtol: float, scene: str) -> tuple[str, float]:
    """Applies :data:`R_IMAGE_RULE`, the rule as the datasets record it (just above)."""
    run = integrate(params, R * np.asarray(y), sample_grid(0.0, T, T / 2000), tol=tol, scene=f"{scene}.R", progress=1)
    half = run.time.values >= T / 2
    got = np.array([run.u.values[half].mean(), run.omega.values[half].mean()])
    want = -np.asarray(ref_mean)
    dist = float(np.max(np.abs(got - want)) / max(np.max(np.abs(ref_mean)), 1e-12))
    return ("stays" if dist <= rtol else "leaves"), dist


def two_trajectory_runs(params, y, cfg: dict) -> tuple:
    """``chaos.two_trajectory.two_trajectory`` from y (model variables) at each separation d0, in double at
    tol over T_two (renormalised every tau, after t_align), the partner kept on the reference's
    energy level. Returns (the flow integrator, the runs)."""
    flow, _ = integrators.flow(False, cfg["tol"])
    integrators.set_pars(flow, params)
    y_int = stored_state(y)
    tts = [two_trajectory(flow, y_int, d0=d0, tau=cfg["tau"], T=cfg["T_two"], t_align=cfg["t_align"],
                          callback=integrators.bounded(flow), difference=equations.state_difference,
                          project=lambda ref, p: _on_level(ref, p, params)) for d0 in cfg["d0"]]
    return flow, tts


def loschmidt_run(params, y, cfg: dict, *, precision: Precision = Precision.DOUBLE) -> dict:
    """``chaos.loschmidt.loschmidt`` from y (model variables) with the involution R at loschmidt_n
    log-spaced T in loschmidt_T, relative to max |velocity|: in double at tol, or in long double at its
    machine epsilon (rounding 2^11 smaller: the rounding floor is 3.3 decades lower)."""
    flow, _ = integrators.flow(False, tolerance(cfg, precision), precision)
    integrators.set_pars(flow, params)
    return loschmidt(flow, stored_state(y), loschmidt_T(cfg), lambda z: R * z, callback=integrators.bounded(flow),
                     difference=equations.state_difference, scale=float(np.max(np.abs(np.asarray(y)[:3]))))


def loschmidt_not_run(L: dict, sigma: float) -> tuple[dict, dict]:
    """For a state the decisive stage judges again: the long-double Loschmidt run's fields, not made (NaN,
    none used), and the indicator undecided for that reason with the double run's verdict named (as
    ``chaos.loschmidt.loschmidt_indicator`` names it). Returns (that run, the indicator)."""
    double = judge_loschmidt_run(L, sigma=sigma)
    run = {"rel_error": np.full_like(np.asarray(L["rel_error"], float), math.nan), "n_used": 0, "tail_n": 0,
           "floor": math.nan, "scale": 1.0, **dict.fromkeys(("pow_exponent", "pow_exponent_err", "tail_pow_exponent",
                                                             "tail_pow_exponent_err"), math.nan)}
    why = "long-double run not made: the decisive stage judges this state"
    return run, {"value": math.nan, "error": math.nan, "verdict": (UNDECIDED, f"{why}; in double: {double[0]}"),
                 "verdict_double": double[0]}


def loschmidt_settings() -> dict:
    """The Loschmidt engine's fixed settings (its defaults), as dataset attributes."""
    run = inspect.signature(loschmidt).parameters
    fit = inspect.signature(loschmidt_fit).parameters
    return {"loschmidt_floor_factor": run["floor_factor"].default, "loschmidt_saturation": run["saturation"].default,
            "loschmidt_tail_fraction": fit["tail"].default, "loschmidt_tail_min": fit["tail_min"].default}


def loschmidt_T(cfg: dict) -> np.ndarray:
    """The Loschmidt horizons: loschmidt_n log-spaced in loschmidt_T."""
    return np.geomspace(*cfg["loschmidt_T"], cfg["loschmidt_n"])


def _on_level(ref, partner, params):
    """The partner (integrator variables) scaled back onto the reference's energy level: the
    velocities scale, delta is kept (E is quadratic in the velocities at fixed delta)."""
    shift = np.array([0.0, 0.0, 0.0, integrators.DELTA_SHIFT])
    out = np.array(partner, float)
    out[:3] *= math.sqrt(equations.energy(ref - shift, params) / equations.energy(out - shift, params))
    return out
