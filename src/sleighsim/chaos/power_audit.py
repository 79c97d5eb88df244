"""One realization of the judge-power audit: its gauge, its orbit at each audited horizon and the decisive
stage's registry estimators on it (``chaos.indicators``), each gated by the gauge as the stage gates it.

Settings (``settings``): the judge_power block's ``decisive`` entries in the sleigh's time unit (T at
factor 1, dt, splits, min_cycles, sigma) with each horizon's factor and megno_samples; for a system every
time is multiplied by s = P / spike_period (its period over the sleigh's spike period, the record's
``spike_period``), so that the system is judged over as many of its periods as the sleigh over spike
periods. The tangent vector is renormalised RENORM_PER_PERIOD times per period P (its log-norm continued).
Times in each system's own unit.
"""

from __future__ import annotations

import json
import math

import numpy as np

from sleighsim.chaos import audit_orbits, faithfulness, indicators
from sleighsim.chaos.birkhoff import observables
from sleighsim.chaos.known_orbits import SYSTEMS
from sleighsim.chaos.rule import faithful_gate
from sleighsim.chaos.section_megno import section_times
from sleighsim.precision import Precision

RENORM_PER_PERIOD = 50


def settings(block: dict, factor: float) -> dict:
    """The decisive settings of the audit at horizon ``factor`` (sleigh time unit)."""
    d = block["decisive"]
    h = next(e for e in d["horizons"] if float(e["factor"]) == float(factor))
    return {"T": float(d["T"]) * float(factor), "dt": float(d["dt"]), "splits": [int(k) for k in d["splits"]],
            "min_cycles": float(d["min_cycles"]), "sigma": float(d["sigma"]), "megno_samples": int(h["megno_samples"])}


def scale(block: dict, system: str) -> float:
    """s = the system's period P over the block's spike period."""
    return SYSTEMS[system].period / float(block["spike_period"])


def window(block: dict, system: str) -> float:
    """The chaotic windows' length: the longest audited horizon in the system's time unit."""
    return max(settings(block, e["factor"])["T"] for e in block["decisive"]["horizons"]) * scale(block, system)


def orbit_record(system: str, y0, st: dict, s: float, seed: int, gain: dict) -> dict:
    """The decisive stage's orbit record (``chaos.indicators``) of the orbit from y0 over T x s sampled every
    dt x s: the section at the maxima of the system's component (``section_megno.section_times``), the
    observables with its angles, and G x steps x rounding of its arithmetic."""
    sys_ = SYSTEMS[system]
    dt = st["dt"] * s
    renorm = max(1, round(sys_.period / RENORM_PER_PERIOD / dt))
    run = audit_orbits.tangent_orbit(system, y0, T=st["T"] * s, dt=dt, seed=seed, renorm=renorm)
    x = run["X"][:, sys_.component]
    rounding = Precision.parse(sys_.arithmetic).rounding
    return {"t": run["t"], "log_norm": run["log_norm"], "x": x[:-1], "crossings": section_times(run["t"], x),
            "obs": observables(run["X"][:-1], sys_.angles), "dt": dt, "T": float(run["t"][-1]),
            "precision": sys_.arithmetic,
            "gain_rounding": math.exp(gain["ln_gain_max"]) * faithfulness.injected_rounding(
                rounding, gain["steps_per_cycle"])}


def gated(judged: dict, system: str, gain: dict) -> tuple[dict, dict]:
    """The registry verdicts (by verdict name) after the gauge (``rule.faithful_gate`` with
    ``faithfulness.indicator_follows`` in the system's arithmetic), and the gauge's answer per verdict name."""
    names = {indicators.REGISTRY[k].verdict_name: k for k in judged}
    arithmetic = dict.fromkeys(names, SYSTEMS[system].arithmetic)
    follows = faithfulness.indicator_follows(gain["ln_gain_max"], arithmetic,
                                             {v: judged[k].get("resolved", math.nan) for v, k in names.items()},
                                             steps_per_cycle=gain["steps_per_cycle"])
    verdicts = {v: judged[k]["verdict"] for v, k in names.items()}
    faithful_gate(verdicts, arithmetic, follows)
    return verdicts, follows


def _clean(numbers: dict) -> str:
    """The numbers as JSON text (NaN and infinities as null and strings)."""
    out = {k: float(v) for k, v in numbers.items()}
    return json.dumps({k: None if math.isnan(v) else v if math.isfinite(v) else str(v) for k, v in out.items()},
                      sort_keys=True)


def judge_realization(block: dict, orbit: audit_orbits.Orbit) -> list[dict]:
    """Every audited decisive judge on one realization at every horizon of the block: one row per horizon
    and judge with the raw verdict, the gauge's answer, the gated verdict, value, error, the numbers behind
    it (JSON) and the realization's confirmation and gauge (JSON)."""
    system, s = orbit.system, scale(block, orbit.system)
    gain = audit_orbits.gauge(system, orbit.y0)
    context = _clean({**orbit.confirmation, "ln_gain_max": gain["ln_gain_max"],
                      "steps_per_cycle": gain["steps_per_cycle"]})
    rows = []
    for e in block["decisive"]["horizons"]:
        st = settings(block, e["factor"])
        rec = orbit_record(system, orbit.y0, st, s, orbit.index, gain)
        judged = indicators.judge_orbit(rec, st)
        verdicts, follows = gated(judged, system, gain)
        for name, j in judged.items():
            v = indicators.REGISTRY[name].verdict_name
            numbers = {**j["numbers"], "value": j["value"], "error": j["error"]}
            rows.append({"system": system, "index": orbit.index, "horizon": float(e["factor"]), "judge": name,
                         "raw": j["verdict"][0], "follows": follows[v], "verdict": verdicts[v][0],
                         "reason": j["verdict"][1], "numbers": _clean(numbers), "context": context})
    return rows


def rule_verdict(rows: list[dict], voters) -> str:
    """The decision rule on one realization at one horizon: ``rule.decide`` over the gated verdicts of the
    judges in ``voters`` (record names; the others set aside)."""
    from sleighsim.chaos.rule import decide, vote_gate

    verdicts = {indicators.REGISTRY[r["judge"]].verdict_name: (r["verdict"], "") for r in rows}
    vote_gate(verdicts, {indicators.REGISTRY[j].verdict_name for j in voters})
    return decide(verdicts, indicators.tangent_based(indicators.DECISIVE))[0]


def rule_counts(rows: list[dict], voters_at: dict) -> list[tuple]:
    """(system, factor, verdict) of the rule per realization and horizon, with the voters of each horizon
    (``voters_at``: factor -> record names)."""
    groups = {}
    for r in rows:
        groups.setdefault((r["system"], r["index"], float(r["horizon"])), []).append(r)
    return [(system, h, rule_verdict(g, voters_at.get(h, set()))) for (system, _, h), g in sorted(groups.items())]


def realization_rows(block: dict, system: str, stream: int, index: int) -> list[dict]:
    """The rows of realization ``index`` of ``system`` in ``stream`` (``judge_realization``)."""
    orbit = audit_orbits.realization(system, stream, index, window=window(block, system))
    return judge_realization(block, orbit)


def numbers_of(rows: list[dict], key: str) -> np.ndarray:
    """The number ``key`` of each row (NaN where absent)."""
    out = [json.loads(r["numbers"]).get(key) for r in rows]
    return np.array([math.nan if v is None else float(v) for v in out])
