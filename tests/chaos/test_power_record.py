"""The judge-power record the chaos verdict votes by (sleighsim.chaos.power.record, merged_records,
record_rates, record_voting; sleighsim.ops.powerrecord writes it): counts per horizon, judge and class
from an audit dataset, records of separate audits side by side, and the vote on each branch."""

import numpy as np
import pytest
import yaml

from sleighsim.chaos import power
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, TORI


def _dataset(judges=("megno", "two-trajectory")):
    """Counts: megno right on every chaotic orbit and torus but once wrong on a torus at horizon 4;
    two-trajectory right always (named as the first audits named it)."""
    rows = []
    for h in (1.0, 4.0):
        for _ in range(50):
            rows += [(j, "henon-heiles E=1/6", h, "chaotic") for j in judges]
            rows += [(j, "henon-heiles E=1/12", h, "regular") for j in judges]
    if "megno" in judges:
        rows[-len(judges)] = ("megno", "henon-heiles E=1/12", 4.0, "chaotic")
    return power.counts(rows, list(judges), ["henon-heiles E=1/6", "henon-heiles E=1/12"], [1.0, 4.0])


def test_the_record_counts_per_horizon_judge_and_class():
    rec = power.record(_dataset())
    assert set(rec["counts"]) == {1.0, 4.0} and set(rec["counts"][1.0]) == {"megno", "two_trajectory"}
    assert rec["counts"][4.0]["megno"][TORI] == {"N": 50, "correct": 49, "wrong": 1, "undecided": 0}
    assert rec["counts"][1.0]["megno"][CHAOTIC_ORBITS]["correct"] == 50
    assert set(rec["source"]) == {"git_commit", "created_utc", "cost_total_s"}


def test_the_vote_by_a_record_on_each_branch():
    """The vote at a run's horizon factor uses the counts at the largest audited factor not above it:
    megno, 1 wrong in 50 tori at factor 4 (over 1 in 100), votes at factors 1 to 3.99 but not from 4 on;
    below every audited factor no judge votes; a judge measured on one class only does not vote; records
    of the same judge cannot be merged."""
    rec = power.merged_records([power.record(_dataset())])
    rows = {(r["judge"], r["class"]): r for r in power.record_rates(rec)}
    assert rows[("megno", TORI)]["wrong"] == 1 and rows[("megno", TORI)]["N"] == 100
    assert rows[("megno", TORI)]["wrong_upper95"] == pytest.approx(0.0466, abs=1e-3)
    assert power.record_voting(rec, 1.0) == power.record_voting(rec, 3.99) == {"megno", "two_trajectory"}
    assert power.record_voting(rec, 4.0) == power.record_voting(rec, 10.0) == {"two_trajectory"}
    assert power.record_voting(rec, 0.5) == set()
    one_class = yaml.safe_load(yaml.safe_dump(rec))
    for h in one_class["counts"]:
        one_class["counts"][h]["megno"].pop(TORI)
    assert power.record_voting(one_class, 1.0) == {"two_trajectory"}
    with pytest.raises(ValueError, match="in two records"):
        power.merged_records([power.record(_dataset()), power.record(_dataset(("megno",)))])
    both = power.merged_records([power.record(_dataset(("megno",))), power.record(_dataset(("birkhoff",)))])
    assert set(both["counts"][4.0]) == {"megno", "birkhoff"} and len(both["sources"]) == 2


def test_the_record_writer(tmp_path):
    from sleighsim.io.netcdf import write_dataset
    from sleighsim.ops import powerrecord

    ds = _dataset()
    ds.attrs.update(cost_total_s=1.0)
    write_dataset(ds, tmp_path / "a.nc")
    out = tmp_path / "rec.yaml"
    assert powerrecord.main([str(tmp_path / "a.nc"), "--out", str(out)]) == 0
    rec = yaml.safe_load(out.read_text())
    assert rec["voting"] == {1.0: ["megno", "two_trajectory"], 4.0: ["two_trajectory"]}
    assert np.isclose(rec["sources"][0]["cost_total_s"], 1.0)
    assert "| x4 | megno | tori | 50 | 49 (0.98) | 1 (0.020" in powerrecord.markdown(rec)
