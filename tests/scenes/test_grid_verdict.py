"""A faithful verdict per eps row of the F11 grid (sleighsim.scenes.grid_verdict): each branch of the row's
choice of arithmetic and of "not judged", and one judged row end to end."""

import math

import pytest

VC = {"eps_min": 0.2, "realizations": 3, "realization_rel": 1e-12, "T": 100000.0, "dt": 0.5, "splits": [2, 4, 8],
      "megno_samples": 100, "min_cycles": 8.0, "tau": 10.0, "tol_dd": 1e-34, "sigma": 3.0}


def _record(spike_period=2400.0, voting=True):
    """A judge-power record of one audited horizon (factor 1, VC's settings): every judge votes (no wrong verdict
    in 301 on either class), or none does (30 wrong of 301)."""
    from sleighsim.chaos.indicators import DECISIVE, REGISTRY

    wrong = 0 if voting else 30
    counts = {i.name: {c: {"N": 301, "correct": 301 - wrong, "wrong": wrong, "undecided": 0}
                       for c in ("chaotic", "tori")} for i in REGISTRY.values() if i.stage == DECISIVE}
    settings = {"T": 100000.0, "dt": 0.5, "splits": [2, 4, 8], "min_cycles": 8.0, "sigma": 3.0}
    return {"stage": "decisive", "spike_period": spike_period, "settings": settings,
            "horizons": {1.0: {"megno_samples": 100}}, "counts": {1.0: counts}}


@pytest.mark.parametrize("ln_gain, voters, want", [
    (5.0, {"megno", "section_megno"}, "double"),  # the tangent-based judges need G x rounding < 1e-3 only
    (20.0, {"megno", "birkhoff"}, "double-double"),  # Birkhoff's 6 digits need 1e-8: double's 1e-4 is not enough
    (80.0, {"megno"}, None),  # e^80 x 1e4 steps x 2^-106 > 1e-3: neither follows
    (math.nan, {"megno"}, None),  # no complete cycle: the gauge is unknown, never a rung
])
def test_a_rows_arithmetic_is_the_cheapest_that_follows_closely_enough_for_every_voter(ln_gain, voters, want):
    from sleighsim.scenes.grid_verdict import row_arithmetic

    got = row_arithmetic({"row_ln_gain_max": ln_gain, "row_gain_steps_per_cycle": 1e4}, voters)
    assert (got.value if got else None) == want


@pytest.mark.parametrize("eps, period, record, gain, why", [
    (0.1, 500.0, _record(), 5.0, "below verdict.eps_min"),
    (0.3, math.nan, _record(), 5.0, "no spike period measured"),
    (0.3, 500.0, _record(voting=False), 5.0, "no judge votes"),
    (0.3, 500.0, _record(), 80.0, "no arithmetic of double, double-double"),
])
def test_a_row_is_not_judged_and_says_why_on_each_branch(eps, period, record, gain, why):
    """Each branch runs nothing (a Params of None would fail any integration) and keeps no bound."""
    from sleighsim.scenes.grid_verdict import NOT_JUDGED, judge_row

    gauge = {"row_ln_gain_max": gain, "row_gain_steps_per_cycle": 1e4}
    out = judge_row(None, [0.0, 0.1, 1.0, 0.0], eps, VC, record, gauge, period, 1.8)
    assert out["row_verdict"] == NOT_JUDGED and why in out["row_verdict_reason"]
    assert out["realization_verdicts"] == [NOT_JUDGED] * 3 and out["row_verdict_agree"] == 0
    assert math.isnan(out["row_lambda_max"])


def test_a_judged_row_runs_the_audited_cycles_in_its_arithmetic_and_agrees_over_realizations(monkeypatch):
    """F11's row eps = 0.292 from its settled state, every judge voting, the record's spike period 40 times the
    period given: the row
    runs T x 1.1 x period / 2400 (here 2750 time units) in double-double, three realizations from starts 1e-12
    apart; the row's verdict is the realizations' common answer, each decided from the four judges."""
    from sleighsim.model.params import Params
    from sleighsim.scenes import grid_verdict as gv

    seen = {}
    real = gv.lane_orbits

    def spy(p, starts, dc, tangent):
        seen.update(starts=starts, dc=dc, tangent=tangent)
        return real(p, starts, dc, tangent=tangent)

    monkeypatch.setattr(gv, "lane_orbits", spy)
    p = Params.paper(eps=0.2924017738212865, b=1.0)
    y = [0.04302031254287423, 0.07876346172227429, 1.3582899100734502, 2.7640231035797154]
    gauge = {"row_ln_gain_max": 18.0, "row_gain_steps_per_cycle": 1700.0}
    out = gv.judge_row(p, y, 0.2924, VC, _record(), gauge, 60.0, 1.8, "row")
    assert seen["dc"]["precision"].value == "double-double" and seen["tangent"]
    assert seen["dc"]["T"] == pytest.approx(1e5 * 1.1 * 60.0 / 2400) and seen["dc"]["dt"] == pytest.approx(0.5 * 0.0275)
    assert len(seen["starts"]) == 3 and seen["starts"][0] == y and seen["starts"][1] != y
    assert max(abs(a / b - 1) for a, b in zip(seen["starts"][1], y)) < 1e-11
    verdicts = out["realization_verdicts"]
    assert out["row_verdict"] == (verdicts[0] if len(set(verdicts)) == 1 else "fragile")
    assert out["row_verdict_agree"] == max(verdicts.count(v) for v in verdicts)
    assert out["row_verdict_arithmetic"] == "double-double" and "realization 0:" in out["row_verdict_reason"]
    assert out["row_verdict_wall_s"] > 0


def test_the_work_model_counts_each_judged_rows_lanes_over_its_cycles():
    """grid.grid_rows adds realizations x T x MARGIN x s to each row from eps_min on (s = reference_eps / eps, the
    row's spike period in the record's), nothing below or without a verdict block."""
    from sleighsim.scenes import grid
    from sleighsim.scenes.grid_verdict import MARGIN

    cfg = {"eps_range": [0.05, 0.2], "n_eps": 3, "b_range": [1.0, 1.0], "n_b": 1, "n_chunks": 3, "reference_eps": 0.1,
           "t_pre": 2e4, "t_pre_min": 2e4, "replicas": 8, "replica_spacing": 2e4, "t_align": 1e3, "T_round": 2e4,
           "max_rounds": 10}
    none = grid.grid_rows({**cfg, "verdict": {"eps_min": 1.0, "realizations": 3, "T": 5e5}})
    some = grid.grid_rows({**cfg, "verdict": {"eps_min": 0.1, "realizations": 3, "T": 5e5}})
    assert grid.grid_rows(cfg) == none  # a measured run's config from before row verdicts: no verdict work
    added = [b - a for (_, a), (_, b) in zip(none, some)]
    assert added[0] == 0.0
    assert added[1:] == pytest.approx([3 * 5e5 * MARGIN * 0.1 / e for e, _ in some[1:]])


def test_a_ladders_finer_rung_leaves_the_verdict_to_the_double_dataset(monkeypatch):
    """grid.judged in a long-double variant runs no verdict (judge_row replaced by a failure) and says where it is."""
    from sleighsim.precision import Precision
    from sleighsim.scenes import grid

    monkeypatch.setattr(grid, "judge_row", lambda *a, **k: pytest.fail("a finer rung ran the verdict again"))
    cfg = {"precision": Precision.LONG_DOUBLE, "verdict": VC, "transient": {"spike_factor": 1.8}}
    out = grid.judged(cfg, {"settled": [0.0] * 4, "spike_interval": 400.0}, 0.3, {}, "row")
    assert out["row_verdict"] == "not judged" and "double dataset" in out["row_verdict_reason"]
