"""The judges' power and false rates on orbits of known class, their bounds and the vote.

Counts (:func:`counts`): a dataset ``counts(judge, orbit_class, system, horizon, verdict)``; :func:`rates`
gives per judge and class (or system) N, correct, wrong, undecided, their shares, the one-sided 95%
Clopper-Pearson upper bound on the wrong rate and the lower bound on the correct rate. The vote is on
the bound, not the point estimate: a judge votes at a horizon when its wrong rate's 95% upper bound is
at most :data:`VOTE_BOUND` (5%) on tori and on chaotic orbits alike (0 wrong in at least 59, 1 in 93,
...). The decision rule's own wrong rate is what a state's verdict rests on: its bound is reported per
class beside the target :data:`RULE_BOUND` (1%: 0 wrong in at least 299).

The record (``ops.powerrecord`` writes it from the audit, ``benchmarks/judge_power.yaml``) holds per
stage the audited settings at factor 1 (in the sleigh's time unit), the horizon factors with their
own settings, each judge's estimator text, and per factor, judge and class the counts. A run votes by it
(:func:`stage_vote`) only with the same estimator and settings, at the largest audited horizon no
longer than its own, measured in spike cycles of at most the record's spike period; a config the record
did not audit votes by nothing. :func:`check_record` lists what makes a record unusable (refused at plan
time).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from sleighsim.chaos.indicators import DECISIVE, REGISTRY
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, SYSTEMS, TORI
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED, VERDICTS
from sleighsim.io.netcdf import full_clean_commit

CLASSES = (CHAOTIC_ORBITS, TORI)
RIGHT = {CHAOTIC_ORBITS: CHAOTIC, TORI: REGULAR}  # the correct verdict on each class
WRONG = {CHAOTIC_ORBITS: REGULAR, TORI: CHAOTIC}
LEVEL = 0.95
VOTE_BOUND = 0.05  # a judge votes when its wrong rate's 95% upper bound is at most this on every class
RULE_BOUND = 0.01  # the bound the decision rule's own wrong rate should meet on every class
SCHEMA = "sleighsim.judge_power/2"
KEEP = ("N", "correct", "wrong", "undecided")
#: What a judge's vote rests on (the text a record and a dataset keep).
VOTE_RULE = (f"a judge votes at a horizon when the one-sided {LEVEL:.0%} Clopper-Pearson upper bound on its wrong-"
             f"verdict rate is at most {VOTE_BOUND:g} on tori and on chaotic orbits alike (independent orbits of "
             "known class, the same estimator and settings, an audited horizon no longer than the run's)")


def upper_bound(wrong: int, N: int, level: float = LEVEL) -> float:
    """One-sided Clopper-Pearson upper confidence bound on a rate seen ``wrong`` times in N (1 at N = 0;
    about 3 / N when none is seen, the rule of three)."""
    from scipy.stats import beta

    return 1.0 if N == 0 or wrong >= N else float(beta.ppf(level, wrong + 1, N - wrong))


def lower_bound(k: int, N: int, level: float = LEVEL) -> float:
    """One-sided Clopper-Pearson lower confidence bound on a rate seen k times in N (0 at k = 0)."""
    from scipy.stats import beta

    return 0.0 if k == 0 or N == 0 else float(beta.ppf(1.0 - level, k, N - k + 1))


def row(c: dict, cls: str) -> dict:
    """Rates from verdict counts c (verdict -> count) on one class: N, correct, wrong, undecided, their shares,
    wrong_upper95 and correct_lower95."""
    N = int(sum(c.values()))
    right, wrong, und = int(c.get(RIGHT[cls], 0)), int(c.get(WRONG[cls], 0)), int(c.get(UNDECIDED, 0))
    p = (lambda k: k / N) if N else (lambda k: math.nan)
    return {"N": N, "correct": right, "wrong": wrong, "undecided": und, "p_correct": p(right), "p_wrong": p(wrong),
            "p_undecided": p(und), "wrong_upper95": upper_bound(wrong, N), "correct_lower95": lower_bound(right, N)}


def from_counts(c: dict) -> dict:
    """Rates from recorded counts (N, correct, wrong, undecided)."""
    N, right, wrong = int(c["N"]), int(c["correct"]), int(c["wrong"])
    p = (lambda k: k / N) if N else (lambda k: math.nan)
    return {**{k: int(c[k]) for k in KEEP}, "p_correct": p(right), "p_wrong": p(wrong),
            "p_undecided": p(int(c["undecided"])), "wrong_upper95": upper_bound(wrong, N),
            "correct_lower95": lower_bound(right, N)}


def votes(by_class: dict, bound: float = VOTE_BOUND) -> bool:
    """Whether a judge with these per-class counts votes: measured on every class, each wrong rate's 95% upper
    bound at most ``bound``."""
    return set(by_class) >= set(CLASSES) and all(
        int(by_class[c]["N"]) > 0 and upper_bound(int(by_class[c]["wrong"]), int(by_class[c]["N"])) <= bound
        for c in CLASSES)


# ----------------------------------------------------------------------------- counts from runs

def counts(rows, judges, systems, factors) -> xr.Dataset:
    """``counts(judge, orbit_class, system, horizon, verdict)`` (int) from rows (judge, system, factor,
    verdict); a system's counts sit under its own class only."""
    n = np.zeros((len(judges), len(CLASSES), len(systems), len(factors), len(VERDICTS)), int)
    for judge, system, factor, verdict in rows:
        n[list(judges).index(judge), CLASSES.index(SYSTEMS[system].cls), list(systems).index(system),
          list(factors).index(factor), VERDICTS.index(verdict)] += 1
    return xr.Dataset(
        {"counts": (("judge", "orbit_class", "system", "horizon", "verdict"), n,
                    {"long_name": "number of realizations given each verdict", "units": "1"})},
        coords={"judge": ("judge", list(judges), {"long_name": "judge (chaos.indicators.REGISTRY, or rule)"}),
                "orbit_class": ("orbit_class", list(CLASSES), {"long_name": "known class of the orbits"}),
                "system": ("system", list(systems), {"long_name": "system (chaos.known_orbits.SYSTEMS)"}),
                "horizon": ("horizon", np.asarray(factors, float),
                            {"long_name": "horizon factor on the audited settings", "units": "1"}),
                "verdict": ("verdict", list(VERDICTS), {"long_name": "verdict"})})


def rates(ds: xr.Dataset, by: str = "orbit_class") -> list[dict]:
    """Per judge and class (``by="orbit_class"``) or per judge and system (``by="system"``, with its class):
    ``row`` summed over the dataset's horizons (and systems)."""
    c = ds.counts.sum("horizon")
    out = []
    for judge in ds.judge.values:
        for key in ds[by].values:
            cls = str(key) if by == "orbit_class" else SYSTEMS[str(key)].cls
            sel = c.sel(judge=judge, orbit_class=cls)
            sel = sel.sum("system") if by == "orbit_class" else sel.sel(system=key)
            r = {"judge": str(judge), "class": cls, **row(dict(zip(VERDICTS, sel.values.tolist())), cls)}
            out.append(r if by == "orbit_class" else {**r, "system": str(key)})
    return out


def by_class(ds: xr.Dataset, judge: str) -> dict:
    """{class: row} of one judge over the dataset's horizons."""
    return {r["class"]: r for r in rates(ds) if r["judge"] == judge}


def voting(ds: xr.Dataset, bound: float = VOTE_BOUND) -> set[str]:
    """The judges of a one-horizon counts dataset that vote (``votes``)."""
    return {str(j) for j in ds.judge.values if votes(by_class(ds, str(j)), bound)}


# ----------------------------------------------------------------------------- the record

def record_rates(rec: dict, horizon: float | None = None) -> list[dict]:
    """Per judge and class of a record: counts, shares and bounds (``from_counts``), at the audited horizon
    factor ``horizon`` or summed over the record's horizons (None)."""
    total = {}
    for h, judges in rec.get("counts", {}).items():
        if horizon is not None and float(h) != float(horizon):
            continue
        for judge, classes in judges.items():
            for cls, c in classes.items():
                t = total.setdefault((judge, cls), dict.fromkeys(KEEP, 0))
                for k in KEEP:
                    t[k] += int(c[k])
    return [{"judge": j, "class": c, **from_counts(v)} for (j, c), v in sorted(total.items())]


def record_voting(rec: dict, horizon: float) -> set[str]:
    """The judges (record names) that vote at the largest audited factor not above ``horizon`` (none below
    every audited factor), by their counts there (``votes``)."""
    below = [float(h) for h in rec.get("counts", {}) if float(h) <= horizon * (1 + 1e-12)]
    if not below:
        return set()
    h = max(below)
    counts_h = next(v for k, v in rec["counts"].items() if float(k) == h)
    return {j for j, classes in counts_h.items() if votes(classes)}


def _run_settings(block: dict) -> dict:
    """A chaos_verdict block's decisive-stage settings, in the keys the audit records."""
    d = block["decisive"]
    return {"T": float(d["T"]), "dt": float(d["dt"]), "megno_samples": int(d["megno_samples"]),
            "splits": [int(k) for k in d["splits"]], "min_cycles": float(block["frequency"]["min_cycles"]),
            "sigma": float(block["sigma"])}


def audited_settings(rec: dict, factor: float) -> dict:
    """The record's decisive settings at horizon ``factor`` (T scaled, its own overrides applied)."""
    s = dict(rec["settings"])
    over = next(v for k, v in rec["horizons"].items() if float(k) == float(factor))
    return {**s, **over, "T": float(s["T"]) * float(factor)}


def stage_vote(rec: dict, block: dict, stage: str, spike_period: float = math.nan) -> dict:
    """Who votes in a chaos_verdict block's ``stage`` by the record: per audited judge of that stage, the
    largest audited horizon no longer than the run's with every setting the estimator reads equal to the
    run's; it votes when its counts there pass ``votes``. A state whose spike period exceeds the record's
    runs fewer cycles than audited: nobody votes. Returns voters (the stage's verdict names), factor (per
    judge, NaN when none applies), why (per registry judge of the stage) and covered (False when no horizon
    of the record could let any judge vote: the stage not audited, or the spike period above the audit's)."""
    why, factor, voters = {}, {}, set()
    stage_judges = [i for i in REGISTRY.values() if i.stage == stage]
    if stage != DECISIVE or rec.get("stage") != DECISIVE:
        return {"voters": set(), "factor": {}, "covered": False,
                "why": {i.name: f"no audit of the {stage} stage's estimators in the record" for i in stage_judges}}
    if math.isfinite(spike_period) and spike_period > float(rec["spike_period"]):
        return {"voters": set(), "factor": {}, "covered": False,
                "why": {i.name: f"spike period {spike_period:g} above the audit's {float(rec['spike_period']):g}"
                        for i in stage_judges}}
    run = _run_settings(block)
    for ind in stage_judges:
        ok = [float(h) for h in rec["horizons"] if ind.name in rec["counts"].get(h, {})
              and audited_settings(rec, h)["T"] <= run["T"] * (1 + 1e-12)
              and all(audited_settings(rec, h)[k] == run[k] for k in ind.settings)]
        if not ok:
            why[ind.name] = "no audited horizon at most the run's with the run's settings " + str(
                {k: run[k] for k in ("T", *ind.settings)})
            continue
        h = max(ok)
        factor[ind.name] = h
        if votes(next(v for k, v in rec["counts"].items() if float(k) == h)[ind.name]):
            voters.add(ind.verdict_name)
            why[ind.name] = f"votes at audited factor {h:g}"
        else:
            why[ind.name] = f"its wrong rate's 95% bound exceeds {VOTE_BOUND:g} on a class at factor {h:g}"
    return {"voters": voters, "factor": factor, "why": why, "covered": True}


def check_record(rec) -> list[str]:
    """What makes a judge-power record unusable (empty: none): not a mapping of this schema; a judge not in
    the registry; an estimator text other than the registry's (the record audited another estimator); a
    horizon without settings; a source that is not a full clean commit."""
    if not isinstance(rec, dict) or rec.get("schema") != SCHEMA:
        return [f"not a record of schema {SCHEMA}"]
    out = []
    for h, judges in rec.get("counts", {}).items():
        if h not in rec.get("horizons", {}):
            out.append(f"horizon {h} has counts but no settings")
        for j in judges:
            if j not in REGISTRY:
                out.append(f"unknown judge {j!r}")
            elif rec.get("estimators", {}).get(j) != REGISTRY[j].estimator:
                out.append(f"judge {j!r} was audited with another estimator: {rec.get('estimators', {}).get(j)!r}")
    for s in rec.get("sources", []):
        commit = str(s.get("git_commit", ""))
        if not full_clean_commit(commit):
            out.append(f"source {commit!r} is not a full clean commit")
    return out
