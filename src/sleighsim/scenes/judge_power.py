"""The judges' power and false rates on independent orbits of known class (``sleighsim.chaos.power_audit``),
as chunk jobs gathered into one dataset: every realization's verdicts (raw, the gauge's answer, gated),
the numbers behind them, its confirmation and gauge; the verdict counts per judge, class, system and
horizon; the voters per horizon (on the bound) and the decision rule's own counts with them.

Work units: a chaotic base orbit (its WINDOWS_PER_BASE disjoint windows: the base orbit and its
confirmation are computed once) or one torus realization, every horizon of the block each; chunk k
takes units k, k + n_chunks, ... (the systems cycle fastest)."""

from __future__ import annotations

import json
import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.chaos import indicators, power, power_audit
from sleighsim.chaos.audit_orbits import WINDOWS_PER_BASE
from sleighsim.chaos.decision import SEQUENCE
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, SYSTEMS
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")
TEXT = ("system", "judge", "raw", "follows", "verdict", "reason", "numbers", "context")
RUN_ATTRS = {"system": cf.attrs("system of the realization", "text"),
             "index": cf.attrs("realization index in its stream"),
             "horizon": cf.attrs("horizon factor on the audited decisive settings"),
             "judge": cf.attrs("judge (chaos.indicators.REGISTRY)", "text"),
             "raw": cf.attrs("the judge's verdict before the gauge", "text"),
             "follows": cf.attrs("the faithfulness gauge's answer for the judge in the system's arithmetic", "text"),
             "verdict": cf.attrs("the verdict after the gauge (what counts)", "text"),
             "reason": cf.attrs("the judge's reason", "text"),
             "numbers": cf.attrs("the numbers the verdict rests on (JSON)", "text"),
             "context": cf.attrs("the realization's confirmation and gauge (JSON)", "text"),
             "wall_s": cf.attrs("wall time of the realization's runs at every horizon", "s")}


def units(cfg: dict) -> list[tuple]:
    """(system, first realization, count) work units: a chaotic system's base orbits (WINDOWS_PER_BASE
    windows each, the last one cut to ``samples``), a torus system's realizations one by one; the systems
    cycling fastest."""
    per = {}
    for s in cfg["systems"]:
        step = WINDOWS_PER_BASE if SYSTEMS[s].cls == CHAOTIC_ORBITS else 1
        per[s] = [(s, k, min(step, cfg["samples"] - k)) for k in range(0, cfg["samples"], step)]
    longest = max(len(v) for v in per.values())
    return [per[s][i] for i in range(longest) for s in cfg["systems"] if i < len(per[s])]


def _rows(cfg: dict, unit: tuple) -> list[dict]:
    system, first, count = unit
    rows = []
    for k in range(first, first + count):
        start = time.perf_counter()
        mine = power_audit.realization_rows(cfg, system, cfg["stream"], k)
        wall = time.perf_counter() - start
        rows += [{**r, "wall_s": wall / len(mine)} for r in mine]
        log.info("judge_power: %s #%d in %.1f s", system, k, wall)
    return rows


def chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
    """Work units index, index + n_chunks, ... of :func:`units`: the run table (dim run)."""
    rows = [r for u in units(cfg)[index::cfg["n_chunks"]] for r in _rows(cfg, u)]
    ds = _table(rows)
    ds.attrs.update(chunk=index, n_chunks=cfg["n_chunks"], scene=scene)
    return ds


def _table(rows: list[dict]) -> xr.Dataset:
    return xr.Dataset({f"run_{k}": ("run", np.array([r[k] for r in rows], dtype=object if k in TEXT else float), a)
                       for k, a in RUN_ATTRS.items()})


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """Every chunk's runs, the gated verdict counts per judge (``power.counts``), the voters per horizon
    (``power.voting`` on the bound), the decision rule's counts with them (``power_audit.rule_counts``) and
    the rates per judge and class."""
    parts = [read_dataset(p) for p in paths]
    rows = [{k: p[f"run_{k}"].values[i] for k in RUN_ATTRS} for p in parts for i in range(p.sizes.get("run", 0))]
    factors = [float(e["factor"]) for e in cfg["decisive"]["horizons"]]
    judges = [i.name for i in indicators.audited(indicators.DECISIVE)]
    ds = power.counts([(r["judge"], r["system"], float(r["horizon"]), r["verdict"]) for r in rows], judges,
                      cfg["systems"], factors)
    voters = {h: power.voting(ds.sel(horizon=[h])) for h in factors}
    rule = power.counts([("rule", s, h, v) for s, h, v in power_audit.rule_counts(rows, voters)], ["rule"],
                        cfg["systems"], factors)
    ds["rule_counts"] = rule.counts.isel(judge=0, drop=True).assign_attrs(
        long_name="realizations the decision rule (with each horizon's voters) gave each verdict", units="1")
    ds = xr.merge([ds, _table(rows)])
    ds["votes"] = (("judge", "horizon"), np.array([[int(j in voters[h]) for h in factors] for j in judges]),
                   cf.attrs("the judge votes at that horizon (its wrong rate's 95% bound at most 5% on each class)"))
    ds["system_class"] = ("system", [SYSTEMS[s].cls for s in cfg["systems"]], cf.attrs("orbit class", "text"))
    ds["period"] = ("system", [SYSTEMS[s].period for s in cfg["systems"]], cf.attrs("characteristic period P", "time"))
    ds["arithmetic"] = ("system", [SYSTEMS[s].arithmetic for s in cfg["systems"]],
                        cf.attrs("the arithmetic the audit follows the system in", "text"))
    ds.attrs.update(scene=scene, vote_rule=power.VOTE_RULE, sequence=SEQUENCE, spike_period=float(cfg["spike_period"]),
                    stream=int(cfg["stream"]), samples=int(cfg["samples"]), settings=json.dumps(cfg["decisive"]),
                    estimators=json.dumps({j: indicators.REGISTRY[j].estimator for j in judges}),
                    cost_total_s=float(np.sum([r["wall_s"] for r in rows])))
    return ds


def work(cfg: dict) -> float:
    """Time units integrated, in the sleigh's time unit before the scaling by P / spike_period (which a
    system's step size undoes, roughly): per realization the sum of the horizons (decisive T x factor);
    the chaotic base orbits and torus references (2000 periods each) are not modelled."""
    d = cfg["decisive"]
    return len(cfg["systems"]) * cfg["samples"] * d["T"] * sum(float(e["factor"]) for e in d["horizons"])


def chunk_work(cfg: dict) -> list[float]:
    """Work of each chunk job: the total shared equally."""
    return [work(cfg) / cfg["n_chunks"]] * cfg["n_chunks"]


def _checks(w: str, cfg: dict) -> None:
    unknown = [s for s in cfg["systems"] if s not in SYSTEMS]
    if unknown:
        raise ConfigError(f"{w}.systems: unknown {unknown}; known: {list(SYSTEMS)}")
    classes = {SYSTEMS[s].cls for s in cfg["systems"]}
    if classes != set(power.CLASSES):
        raise ConfigError(f"{w}.systems: {cfg['systems']} must hold chaotic systems and tori alike")
    factors = [float(e["factor"]) for e in cfg["decisive"]["horizons"]]
    if len(set(factors)) != len(factors) or not all(math.isfinite(f) and f > 0 for f in factors):
        raise ConfigError(f"{w}.decisive.horizons: factors {factors} must be distinct and positive")
    n_units = len(units(cfg))
    if not 1 <= cfg["n_chunks"] <= n_units:
        raise ConfigError(f"{w}.n_chunks = {cfg['n_chunks']} must lie in [1, {n_units}] (the work units: chaotic "
                          f"base orbits of {WINDOWS_PER_BASE} windows and torus realizations)")


#: Keys (leaves) the work model reads.
WORK_KEYS = ("T", "factor", "systems", "samples", "n_chunks")

def _records(c: dict) -> list:
    """One realization's orbit at the longest horizon: T x factor / dt samples of about 16 values (states,
    tangent, observables and their long-double copies)."""
    from sleighsim.scenes.memory import Span

    d = c["decisive"]
    longest = d["T"] * max(float(e["factor"]) for e in d["horizons"])
    return [Span(("decisive.T x the largest factor", longest), ("decisive.dt", d["dt"]), 16)]


JUDGE_POWER = SceneKind(
    name="judge_power",
    title=("the chaos judges' power and false rates on independent orbits of known class (sticky chaos, slow-fast "
           "and spiked tori, textbook orbits) and the judges that vote"),
    chunk=chunk, gather=gather, integrates=False, records=_records,
    work=work, chunk_work=chunk_work, modelled=lambda leaf: leaf in WORK_KEYS, checks=_checks)
