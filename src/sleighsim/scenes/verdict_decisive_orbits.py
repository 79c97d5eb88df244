"""The decisive stage's orbits (``scenes.verdict_decisive``): every lane's orbit from its settled state over
T sampled every dt in the decisive arithmetic, with one tangent vector's log-norm when a tangent-based judge
votes. Double-double lanes are one ``engine.ddbatch.DDBatch`` (each lane bit for bit ``DDFlow``'s); heyoka's
arithmetics run one lane after another. Times in the flow's time unit."""

from __future__ import annotations

import numpy as np

from sleighsim.chaos.megno import megno
from sleighsim.engine import ddtaylor, integrators
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.engine.orbits import sleigh_orbit
from sleighsim.model import equations
from sleighsim.precision import Precision
from sleighsim.scenes.common import stored_state


def lane_orbits(params, ys, dc: dict, *, tangent: bool) -> list[dict]:
    """The decisive orbits from the starts ``ys`` (model variables, one per lane) over dc["T"] sampled every
    dc["dt"] in dc["precision"] at dc["tol"]: in double-double the lanes of one ``engine.ddbatch.DDBatch``
    (each lane bit for bit ``DDFlow``'s orbit), in heyoka's arithmetics one orbit after another
    (``heyoka_lane``). Each orbit: t, Y in the model's variables as doubles, drift max |E/E0 - 1|, steps and,
    with ``tangent``, log_norm: the log-norm of one tangent vector on t (started in a random unit
    direction, seed 0, as ``chaos.megno.megno``)."""
    if dc["precision"] is Precision.DOUBLE_DOUBLE:
        return dd_lanes(params, ys, dc, tangent=tangent)
    return [heyoka_lane(params, y, dc, tangent=tangent) for y in ys]


def _samples(dc: dict) -> int:
    """The decisive orbit's number of samples: t = 0, dt, ..., T."""
    return round(dc["T"] / dc["dt"]) + 1


def _dd_drift(params, hi, lo) -> float:
    """The energy drift of a double-double orbit at 200 bits on at most 201 of its samples."""
    every = max(1, hi.shape[0] // 200)
    return ddtaylor.energy_drift(params, hi[::every], lo[::every])


def _unit_tangent() -> np.ndarray:
    """The tangent vector's start: a random unit direction (seed 0, as ``chaos.megno.megno``)."""
    v0 = np.random.default_rng(0).normal(size=4)
    return v0 / np.linalg.norm(v0)


def dd_lanes(params, ys, dc: dict, *, tangent: bool) -> list[dict]:
    """``lane_orbits`` in double-double: every start a lane of one DDBatch (per-lane steps)."""
    batch, grid = DDBatch(params, dc["tol"]), np.arange(_samples(dc)) * dc["dt"]
    ys = np.asarray(ys, float)
    if tangent:
        hi, lo, log_norm, _ = batch.propagate_tangent_grid(ys, np.tile(_unit_tangent(), (len(ys), 1)), grid)
    else:
        (hi, lo), log_norm = batch.propagate_grid(ys, grid), None
    return [{"t": grid, "Y": hi[i], "steps": int(batch.steps[i]), "drift": _dd_drift(params, hi[i], lo[i]),
             **({"log_norm": log_norm[i]} if tangent else {})} for i in range(len(ys))]


def heyoka_lane(params, y, dc: dict, *, tangent: bool) -> dict:
    """``lane_orbits`` in a heyoka arithmetic for one start: the orbit (``heyoka_orbit``) and, with
    ``tangent``, a MEGNO run (``chaos.megno.megno``, renormalised every dc["tau"]) over the same T, its
    log-norm interpolated onto t between renormalisations."""
    orbit = heyoka_orbit(params, y, dc, dc["precision"])
    if tangent:
        ta, _ = integrators.sleigh_megno(dc["tol"], dc["precision"], True)
        integrators.set_pars(ta, params)
        m = megno(ta, 4, stored_state(y), T=dc["T"], n_samples=dc["megno_samples"], tau=dc["tau"],
                  callback=integrators.bounded(ta))
        ell = np.concatenate([[0.0], np.cumsum(m["log_growth"])])
        orbit["log_norm"] = np.interp(orbit["t"], m["tau"] * np.arange(ell.size), ell)
    return orbit


def heyoka_orbit(params, y, dc: dict, precision: Precision) -> dict:
    """The orbit from y in heyoka's ``precision`` at dc["tol"], sampled every dc["dt"] over dc["T"]
    (``engine.orbits.sleigh_orbit``): t, Y (the model's variables, as doubles), drift and steps."""
    orbit = sleigh_orbit(params, y, precision, dc["tol"], _samples(dc), dc["dt"])
    E = equations.energy(orbit.Y, params)
    return {"t": orbit.t, "Y": orbit.Y, "steps": orbit.steps, "drift": float(np.max(np.abs(E / E[0] - 1)))}
