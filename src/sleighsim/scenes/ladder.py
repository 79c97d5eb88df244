"""The precision ladder: does the arithmetic decide the steady state? Each state is settled (in
double), then its orbit is run from that one point in every precision of the ladder (double, long
double, and quad where the config asks), and the steady-state observables (the spike intervals of
Omega) and the orbits' separation are compared precision by precision.

Conventions: time in the flow's time unit; a precision's run uses its own Taylor tolerance (its
machine epsilon); the separation of two runs is max |velocity difference| / max |velocity| of the
finer run (delta left out: the orbits' phase along the torus is what separates first).
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.analysis.observables import SEPARATED
from sleighsim.engine.orbits import sleigh_orbit
from sleighsim.engine.transient import settle, spike_times
from sleighsim.io import cf
from sleighsim.model.equations import energy
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.checks import multiple
from sleighsim.scenes.common import nan_padded
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


#: Written into the precision_ladder dataset (attribute agreement_rule).
AGREES_RULE = (
    "Do two precisions' spike trains agree? Both have at least two intervals, the spreads of their intervals "
    "(standard deviations, floored at the sampling dt that resolves a spike time) are within a factor 2 of each"
    " other (the same regularity), and their mean intervals differ by at most the smaller spread (no assumption"
    " of independent intervals is made)."
)


def agrees(coarse: dict, fine: dict, dt: float) -> bool:
    """Applies :data:`AGREES_RULE`, the rule as the datasets record it (just above)."""
    if min(coarse["n_intervals"], fine["n_intervals"]) < 2:
        return False
    sd = sorted(max(r["interval_sd"], dt) for r in (coarse, fine))
    return sd[1] <= 2 * sd[0] and abs(coarse["interval_mean"] - fine["interval_mean"]) <= sd[0]


#: Written into the precision_ladder dataset (attribute converged_rule).
CONVERGED_PRECISION_RULE = (
    "The lowest precision whose spike train agrees (``agrees``) with that of every finer precision run, or \"not"
    " converged\" when the two finest disagree or only one precision ran."
)


def converged_precision(runs: list[dict], names: list[str], dt: float) -> str:
    """Applies :data:`CONVERGED_PRECISION_RULE`, the rule as the datasets record it (just above)."""
    for i in range(len(runs) - 1):
        if all(agrees(runs[i], later, dt) for later in runs[i + 1:]):
            return str(names[i])
    return "not converged"


def run_in(params, y, precision: Precision, *, T: float, dt: float, spike_factor: float) -> dict:
    """The orbit from y (model variables) in ``precision`` over T, sampled every dt: velocities and
    the spike train of Omega (``transient.spike_times``), with the run's wall time."""
    start = time.perf_counter()
    n = int(round(T / dt))
    Y = sleigh_orbit(params, y, precision, precision.epsilon, n + 1, dt).Y
    v = Y[1:, :3]
    t = dt * np.arange(1, n + 1)
    spikes = spike_times(t, v[:, 1], factor=spike_factor)
    intervals = np.diff(spikes)
    return {"velocities": v, "spikes": spikes, "n_intervals": intervals.size,
            "interval_mean": float(intervals.mean()) if intervals.size else math.nan,
            "interval_sd": float(intervals.std(ddof=1)) if intervals.size > 1 else math.nan,
            "energy_max_rel_drift": float(np.max(np.abs(energy(Y, params) / energy(Y[0], params) - 1))),
            "wall_s": time.perf_counter() - start}


def separation(coarse: dict, fine: dict) -> np.ndarray:
    """max |velocity difference| / max |velocity| of the finer run, at every sample."""
    return np.abs(coarse["velocities"] - fine["velocities"]).max(axis=1) / np.abs(fine["velocities"]).max()


def one_state(params, y0, cfg: dict, label: str) -> dict:
    """Settle the state from y0 (double), then run it in every precision of the ladder."""
    y, pre = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=Precision.DOUBLE.epsilon, label=label,
                    progress=1)
    runs = [run_in(params, y, p, T=cfg["T"], dt=cfg["dt"], spike_factor=cfg["transient"]["spike_factor"])
            for p in cfg["precisions"]]
    seps = [separation(a, b) for a, b in zip(runs[:-1], runs[1:])]
    t = cfg["dt"] * np.arange(1, runs[0]["velocities"].shape[0] + 1)
    t_sep = [float(t[np.argmax(s > SEPARATED)]) if np.any(s > SEPARATED) else math.nan for s in seps]
    out = {"runs": runs, "separations": seps, "t_separated": t_sep, "transient_over": int(pre["transient_over"]),
           "converged": converged_precision(runs, list(cfg["precisions"]), cfg["dt"])}
    log.info("%s: intervals %s; converged in %s", label, [round(r["interval_mean"], 2) for r in runs], out["converged"])
    return out


def precision_ladder(cfg: dict, scene: str = "") -> xr.Dataset:
    """Per state and precision: the spike times and interval statistics of the steady state; per
    pair of neighbouring precisions, the orbits' separation (sampled every ``separation_every``)
    and when it first exceeds SEPARATED; per state, the converged precision."""
    start = time.perf_counter()
    params = Params.from_config(cfg["params"])
    names, precs = list(cfg["states"]), cfg["precisions"]
    out = [one_state(params, state_at_label(cfg["states"][n], params, cfg["energy_label"]), cfg, f"{scene}[{n}]")
           for n in names]
    every = int(round(cfg["separation_every"] / cfg["dt"]))
    spikes = nan_padded([r["spikes"] for o in out for r in o["runs"]], min_width=1).reshape(len(names), len(precs), -1)
    ds = xr.Dataset(
        {
            "spike_time": (("state", "precision", "spike"), spikes,
                           cf.attrs("times of the Omega spikes after the settled point", "time")),
            "interval_mean": (("state", "precision"), [[r["interval_mean"] for r in o["runs"]] for o in out],
                              cf.attrs("mean interval between the Omega spikes of the run", "time")),
            "interval_sd": (("state", "precision"), [[r["interval_sd"] for r in o["runs"]] for o in out],
                            cf.attrs("standard deviation of the intervals within the run", "time")),
            "run_wall_s": (("state", "precision"), [[r["wall_s"] for r in o["runs"]] for o in out]),
            "run_energy_max_rel_drift": (("state", "precision"),
                                         [[r["energy_max_rel_drift"] for r in o["runs"]] for o in out]),
            "separation": (("state", "pair", "t_separation"), [[s[every - 1::every] for s in o["separations"]]
                                                              for o in out],
                           cf.attrs("max |velocity difference| / max |velocity| of the finer run, computed in double "
                                    "(resolves differences above about 1e-16)")),
            "t_separated": (("state", "pair"), [o["t_separated"] for o in out],
                            cf.attrs(f"first time the separation exceeds {SEPARATED:g} (NaN: never)", "time")),
            "converged_precision": ("state", np.array([o["converged"] for o in out], dtype=object)),
            "transient_over": ("state", [o["transient_over"] for o in out]),
            "start": (("state", "component"), [cfg["states"][n] for n in names],
                      cf.attrs("configured start state (u, Omega, omega, delta) in model units, before scaling to "
                               "the label")),
        },
        coords={"state": names, "precision": [p.value for p in precs], "component": ["u", "Omega", "omega", "delta"],
                "pair": [f"{a} / {b}" for a, b in zip(precs[:-1], precs[1:])],
                "t_separation": cfg["dt"] * every * np.arange(1, out[0]["separations"][0][every - 1::every].size + 1),
                "rounding": ("precision", [p.rounding for p in precs]),
                "tol": ("precision", [p.epsilon for p in precs])},
    )
    ds.attrs.update(params.attrs())
    ds.attrs.update(scene=scene, energy_label=cfg["energy_label"], T=cfg["T"], dt=cfg["dt"],
                    integrator="heyoka Taylor in each precision, tolerance its machine epsilon (coordinate tol)",
                    energy_max_rel_drift=float(np.nanmax([[r["energy_max_rel_drift"] for r in o["runs"]]
                                                          for o in out])),
                    agreement_rule=AGREES_RULE, converged_rule=CONVERGED_PRECISION_RULE,
                    wall_time_s=time.perf_counter() - start)
    return ds


def _precision_ladder_checks(w, cfg):
    multiple(f"{w}.separation_every", cfg["separation_every"], "dt", cfg["dt"])


PRECISION_LADDER = SceneKind(
    name="precision_ladder",
    title="spike times per arithmetic from one settled point and the orbits' separation",
    compute=precision_ladder, checks=_precision_ladder_checks,
    records=lambda c: [*memory.pre_run(c, "t_transient"), memory.span(c, "T", "dt", 4, memory.count(c, "precisions"))])
