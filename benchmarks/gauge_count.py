"""Does the faithfulness gauge count the error it predicts? On the chaos verdict's states (the main state and
both rotor states, settled as the chaos verdict settles them) and on one orbit of each audit system, the
gauge's prediction of how far an arithmetic's orbit separates from the exact one over a cycle (G x steps x
rounding, the coherent count chaos.faithfulness uses; G x sqrt(steps) x rounding, a random walk; G x
rounding, one rounding) against the separation measured from a finer arithmetic (quad, heyoka's real128)
over two cycles from the same state:

    PYTHONPATH=src python benchmarks/gauge_count.py [--quick] [--out benchmarks/gauge_count.yaml]

Separation: max over the samples of the largest component difference over the largest component (the
sleigh: its velocities; a spiked system: its base coordinates), at the end of the first cycle and over
both. Writes benchmarks/gauge_count.yaml."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from sleighsim.chaos import audit_orbits, faithfulness, known_orbits
from sleighsim.engine import integrators
from sleighsim.engine.transient import settle
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.ops import benchio
from sleighsim.precision import Precision

NAME = "gauge_count"
REPO = Path(__file__).resolve().parents[1]
ARITHMETICS = (Precision.DOUBLE, Precision.LONG_DOUBLE)
LD = np.longdouble  # the runs are compared in long double: a comparison in double would floor at 1e-16
FULL = {"states": ["main", "rotor_a", "rotor_b"], "systems": list(known_orbits.SYSTEMS), "samples": 200}
QUICK = {"states": ["main"], "systems": ["henon-heiles E=1/6", "spiked quartic oscillators"], "samples": 50}


def _ld(Y) -> np.ndarray:
    """Y in long double; a real128 array through its leading and trailing doubles (NumPy has no cast)."""
    Y = np.asarray(Y)
    if Y.dtype in (np.dtype(float), np.dtype(LD)):
        return Y.astype(LD)
    import heyoka as hy

    hi = Y.astype(float)
    return hi.astype(LD) + (Y - hi.astype(hy.real128)).astype(float).astype(LD)


def _base(Y):
    """The base coordinates of spiked states (``known_orbits.unspiked``), in long double."""
    X = Y[:, :-3].copy()
    X[:, 0], X[:, 2] = X[:, 0] / Y[:, -1], X[:, 2] * Y[:, -1]
    return X


def _predicted(ln_gain: float, steps: float, p: Precision) -> dict:
    G = math.exp(ln_gain)
    return {"coherent": G * steps * p.rounding, "random_walk": G * math.sqrt(steps) * p.rounding,
            "one_rounding": G * p.rounding}


def _separation(runs: dict, ref, scale_cols, half: int) -> dict:
    """Per arithmetic: the separation from ``ref`` at the first cycle's end (sample ``half``) and its max."""
    scale = np.max(np.abs(ref[:, scale_cols]))
    out = {}
    for p, Y in runs.items():
        d = (np.max(np.abs(Y[:, scale_cols] - ref[:, scale_cols]), axis=1) / scale).astype(float)
        out[p] = {"after_one_cycle": float(d[half]), "max_over_two": float(d.max())}
    return out


def _sleigh_run(params, y, T: float, n: int, p: Precision, tol: float):
    ta, _ = integrators.flow(False, tol, p)
    integrators.set_pars(ta, params)
    fp = ta.state.dtype.type
    ta.time = fp(0)
    integrators.load(ta, np.asarray(y, float))
    res = ta.propagate_grid(np.linspace(0.0, T, n).astype(ta.state.dtype), callback=integrators.bounded(ta))
    return _ld(integrators.samples(ta, res[-1])), int(res[3])


def sleigh_state(cfg: dict, name: str, samples: int) -> dict:
    """One chaos-verdict state: settled, gauged (spike_cycle_gains in double over T_gain), then two cycles in
    double, long double and quad from the settled state."""
    params = Params.from_config(cfg["params"])
    y0 = state_at_label(cfg["states"][name], params, cfg["energy_label"])
    y, _ = settle(params, y0, cfg["t_transient"], **cfg["transient"], tol=cfg["tol"], label=name, progress=0)
    ta, _ = integrators.sleigh_tangent(4, cfg["tol"], True)
    integrators.set_pars(ta, params)
    g = faithfulness.spike_cycle_gains(ta, y, T=cfg["T_gain"], tau=cfg["tau_gain"],
                                       spike_factor=cfg["transient"]["spike_factor"])
    cycle = float(np.mean(np.diff(g["spike_times"])))
    runs, steps = {}, {}
    for p in (*ARITHMETICS, Precision.QUAD):
        runs[p.value], s = _sleigh_run(params, y, 2 * cycle, 2 * samples + 1, p, p.epsilon)
        steps[p.value] = s / 2
    ref = runs.pop("quad")
    return _entry(g["ln_gain_max"], g["steps_per_cycle"], cycle, steps, _separation(runs, ref, [0, 1, 2], samples))


def _entry(ln_gain, steps_gauge, cycle, steps, sep) -> dict:
    out = {"ln_gain_max": ln_gain, "cycle": cycle, "steps_per_cycle_gauge": steps_gauge, "steps_per_cycle": steps,
           "arithmetics": {}}
    for p in ARITHMETICS:
        pred = _predicted(ln_gain, steps_gauge, p)
        m = sep[p.value]["max_over_two"]
        out["arithmetics"][p.value] = {"predicted": pred, "measured": sep[p.value],
                                       "within_coherent": bool(m <= pred["coherent"]),
                                       "measured_over_one_rounding": m / pred["one_rounding"]}
    return out


def audit_system(system: str, samples: int) -> dict:
    """One realization (stream 2) of an audit system: its gauge, then two cycles of length P in double, long
    double and quad from its start."""
    s = known_orbits.SYSTEMS[system]
    o = audit_orbits.realization(system, 2, 0, window=10 * s.period)
    g = audit_orbits.gauge(system, o.y0)
    runs, steps = {}, {}
    for p in (*ARITHMETICS, Precision.QUAD):
        ta = audit_orbits.flow(system, p.value)
        fp = ta.state.dtype.type
        ta.time = fp(0)
        ta.state[:] = np.array([fp(v) for v in o.y0], dtype=ta.state.dtype)
        grid = np.array([fp(t) for t in np.linspace(0.0, 2 * s.period, 2 * samples + 1)], dtype=ta.state.dtype)
        res = ta.propagate_grid(grid)
        runs[p.value] = _ld(res[-1])
        steps[p.value] = int(res[3]) / 2
    if system.startswith("spiked"):  # compare in the base coordinates: w swings the scale by e^15
        runs = {p: _base(Y) for p, Y in runs.items()}
    ref = runs.pop("quad")
    cols = list(range(ref.shape[1]))
    return {"class": s.cls, "arithmetic_audited": s.arithmetic,
            **_entry(g["ln_gain_max"], g["steps_per_cycle"], s.period, steps, _separation(runs, ref, cols, samples))}


def run(opts: dict) -> dict:
    """Every state and system of ``opts``."""
    from snakemake.common.configfile import load_configfile

    from sleighsim.scenes import catalog

    cfg = catalog.scene_config(load_configfile(str(REPO / "config" / "config.yaml")), "chaos_verdict")
    load = {"start": benchio.loadavg()}
    out = {"states": {}, "systems": {}}
    for name in opts["states"]:
        benchio.say(NAME, f"state {name}")
        out["states"][name] = sleigh_state(cfg, name, opts["samples"])
    for system in opts["systems"]:
        benchio.say(NAME, f"system {system}")
        out["systems"][system] = audit_system(system, opts["samples"])
    load["end"] = benchio.loadavg()
    import heyoka

    return {**benchio.header("sleighsim.gauge_count/1", opts is QUICK, {"heyoka": heyoka.__version__}, load),
            "rule": "predicted: G x steps x rounding (coherent), G x sqrt(steps) x rounding (random walk), G x "
                    "rounding (one); measured: separation from quad over two cycles from the same state", **out}


if __name__ == "__main__":
    raise SystemExit(benchio.main(NAME, __doc__, run, FULL, QUICK, REPO / "benchmarks" / "gauge_count.yaml",
                                  "the main state and two audit systems only"))
