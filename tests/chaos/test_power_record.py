"""The judge-power record (sleighsim.ops.powerrecord writes it from the audit's dataset; chaos.power reads the
vote from it): its counts, voters and rule counts from a gathered run table, what it refuses, and the
committed record itself: complete, from a clean commit, its counts and votes the tally of its own runs,
and two of its realizations judged again to the same verdicts and numbers."""

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from sleighsim.chaos import indicators, power, power_audit
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, TORI
from sleighsim.io.netcdf import write_dataset
from sleighsim.ops import powerrecord
from sleighsim.scenes import judge_power

ROOT = Path(__file__).resolve().parents[2]
RECORD = ROOT / "benchmarks" / "judge_power.yaml"
JUDGES = [i.name for i in indicators.audited(indicators.DECISIVE)]
BLOCK = {"stream": 0, "spike_period": 2400.0, "samples": 60,
         "decisive": {"T": 1e5, "dt": 0.5, "splits": [2, 4, 8], "min_cycles": 8.0, "sigma": 3.0,
                      "horizons": [{"factor": 1.0, "megno_samples": 100}]},
         "systems": ["henon-heiles E=1/6", "quartic oscillators"]}


def _rows(n=60, megno_wrong=0):
    """n realizations per system: on chaos MEGNO and section MEGNO say chaotic (MEGNO regular on the first
    ``megno_wrong``), frequency undecided, Birkhoff undecided; on tori all four regular."""
    rows = []
    for system, cls in (("henon-heiles E=1/6", CHAOTIC_ORBITS), ("quartic oscillators", TORI)):
        for k in range(n):
            for j in JUDGES:
                v = ("chaotic" if j in ("megno_log_norm", "section_megno") else "undecided") if cls == CHAOTIC_ORBITS \
                    else "regular"
                if cls == CHAOTIC_ORBITS and j == "megno_log_norm" and k < megno_wrong:
                    v = "regular"
                rows.append({"system": system, "index": k, "horizon": 1.0, "judge": j, "raw": v, "follows": "follows",
                             "verdict": v, "reason": "r", "numbers": json.dumps({"value": 1.0}),
                             "context": json.dumps({"confirmed": 1.0}), "wall_s": 0.5})
    return rows


def _gathered(tmp_path, rows, commit="0123456789" * 4):
    path = write_dataset(judge_power._table(rows).assign_attrs(chunk=0), tmp_path / "c0.nc")
    ds = judge_power.gather([path], BLOCK)
    ds.attrs["git_commit"] = commit
    return ds


def test_the_record_holds_counts_voters_rule_and_every_run(tmp_path):
    """60 chaotic orbits and 60 tori, every judge right or undecided: each votes (0 of 60, bound 4.9%); the
    rule says chaotic on every chaotic orbit (MEGNO and section MEGNO; no non-tangent voter says chaotic:
    undecided) and regular on every torus; with MEGNO wrong once on chaos it no longer votes, and the rule
    rests on the section MEGNO."""
    rec = powerrecord.record(_gathered(tmp_path, _rows()))
    assert rec["voting"][1.0] == sorted(JUDGES)
    assert rec["counts"][1.0]["megno_log_norm"][CHAOTIC_ORBITS] == {"N": 60, "correct": 60, "wrong": 0, "undecided": 0}
    assert rec["rule"][1.0][TORI] == {"N": 60, "correct": 60, "wrong": 0, "undecided": 0}
    assert rec["rule"][1.0][CHAOTIC_ORBITS]["undecided"] == 60  # chaos needs a non-tangent voter saying so
    assert len(rec["runs"][1.0]) == 120 and rec["runs"][1.0][0]["judges"]["birkhoff"]["value"] == 1.0
    assert rec["estimators"] == {j: indicators.REGISTRY[j].estimator for j in JUDGES}
    assert power.check_record(yaml.safe_load(yaml.safe_dump(rec))) == []
    rec = powerrecord.record(_gathered(tmp_path, _rows(megno_wrong=1)))
    assert rec["voting"][1.0] == sorted(set(JUDGES) - {"megno_log_norm"})
    assert rec["rule"][1.0][TORI]["correct"] == 60
    assert "| x1 | megno_log_norm | chaotic | 60 | 59 (0.98, >= " in powerrecord.markdown(rec)


def test_a_dirty_or_unnamed_commit_makes_no_record(tmp_path):
    with pytest.raises(ValueError, match="full clean commit"):
        powerrecord.record(_gathered(tmp_path, _rows(2), commit="0123456789" * 4 + "-dirty"))
    with pytest.raises(ValueError, match="full clean commit"):
        powerrecord.record(_gathered(tmp_path, _rows(2), commit="unknown"))


def test_a_missing_unreadable_or_empty_record(tmp_path):
    assert "no such file" in powerrecord.problems(tmp_path / "none.yaml")[0]
    (tmp_path / "bad.yaml").write_text("a: [")
    assert powerrecord.problems(tmp_path / "bad.yaml")[0].startswith("not YAML")
    (tmp_path / "empty.yaml").write_text(yaml.safe_dump(powerrecord.empty()))
    assert powerrecord.problems(tmp_path / "empty.yaml") == []
    block = {"sigma": 3.0, "frequency": {"min_cycles": 8.0},
             "decisive": {"T": 1e5, "dt": 0.5, "megno_samples": 100, "splits": [2, 4, 8]}}
    assert power.stage_vote(powerrecord.empty(), block, "decisive")["voters"] == set()


# ----------------------------------------------------------------------------- the committed record

@pytest.fixture(scope="module")
def record():
    return yaml.safe_load(RECORD.read_text())


def test_the_committed_record_is_complete_and_from_a_clean_commit(record):
    assert power.check_record(record) == [] and record["sources"], "the record must name its clean source"
    assert record["stream"] == 0 and set(record["counts"]) == set(record["horizons"]) == set(record["runs"])
    assert record["estimators"] == {j: indicators.REGISTRY[j].estimator for j in JUDGES}


def test_the_committed_counts_votes_and_rule_are_the_tally_of_its_runs(record):
    for h, runs in record["runs"].items():
        tally = {}
        for r in runs:
            cls = power.SYSTEMS[r["system"]].cls
            for j, v in r["judges"].items():
                c = tally.setdefault(j, {}).setdefault(cls, dict.fromkeys(power.KEEP, 0))
                c["N"] += 1
                c["correct" if v["verdict"] == power.RIGHT[cls] else "wrong" if v["verdict"] == power.WRONG[cls]
                  else "undecided"] += 1
        assert tally == record["counts"][h]
        assert sorted(j for j, by in tally.items() if power.votes(by)) == record["voting"][h]
        rows = [{"system": r["system"], "index": r["index"], "horizon": h, "judge": j, "verdict": v["verdict"]}
                for r in runs for j, v in r["judges"].items()]
        rule = {}
        for system, _, v in power_audit.rule_counts(rows, {h: set(record["voting"][h])}):
            cls = power.SYSTEMS[system].cls
            c = rule.setdefault(cls, dict.fromkeys(power.KEEP, 0))
            c["N"] += 1
            c["correct" if v == power.RIGHT[cls] else "wrong" if v == power.WRONG[cls] else "undecided"] += 1
        assert rule == record["rule"][h]


@pytest.mark.parametrize("system", ["henon-heiles E=1/6", "quartic oscillators"])
def test_two_recorded_realizations_judged_again_give_the_same_verdicts_and_numbers(hy, record, system):
    """Realization 0 of a chaotic and of a torus system at the record's horizons, from its settings: every
    judge's gated verdict as recorded, its value to 1e-9 (relative)."""
    settings = dict(record["settings"])
    block = {"spike_period": record["spike_period"],
             "decisive": {**settings, "horizons": [{"factor": h, **o} for h, o in record["horizons"].items()]}}
    rows = power_audit.realization_rows(block, system, record["stream"], 0)
    for r in rows:
        want = next(x for x in record["runs"][r["horizon"]] if x["system"] == system and x["index"] == 0)
        w = want["judges"][r["judge"]]
        assert r["verdict"] == w["verdict"], (r["horizon"], r["judge"], r["reason"])
        got = json.loads(r["numbers"])["value"]
        assert (got is None and w["value"] is None) or np.isclose(got, w["value"], rtol=1e-9, atol=0)
