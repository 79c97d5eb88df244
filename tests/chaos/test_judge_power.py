"""The judge-power audit's rules and orbits (sleighsim.chaos.power, indicators, audit_orbits, power_audit,
decision, bounds): the bounds and the vote on each branch, who votes in a stage by a record (settings,
horizon, spike period), what makes a record unusable, the registry, the audit's independent confirmed
realizations and the classes the sleigh needs (tori and chaos with e^30 swings per cycle)."""

import math

import numpy as np
import pytest

from sleighsim.chaos import audit_orbits, bounds, decision, indicators, known_orbits, power, power_audit
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED

C, T = known_orbits.CHAOTIC_ORBITS, known_orbits.TORI


# ----------------------------------------------------------------------------- bounds and the vote

def test_the_bounds_are_clopper_pearson_and_need_59_and_299_clean_orbits_for_5_and_1_percent():
    assert power.upper_bound(0, 300) == pytest.approx(1 - 0.05 ** (1 / 300))  # exact for k = 0
    assert power.upper_bound(0, 59) <= 0.05 < power.upper_bound(0, 58)
    assert power.upper_bound(0, 299) <= 0.01 < power.upper_bound(0, 298)
    assert power.upper_bound(1, 93) <= 0.05 < power.upper_bound(1, 92)
    assert power.upper_bound(0, 0) == 1.0 and power.upper_bound(7, 7) == 1.0
    assert power.lower_bound(0, 10) == 0.0 and power.lower_bound(10, 10) == pytest.approx(0.05 ** (1 / 10))


def _by_class(chaotic, tori):
    """Counts per class from (N, correct, wrong)."""
    return {cls: {"N": n, "correct": r, "wrong": w, "undecided": n - r - w} for cls, (n, r, w) in
            ((C, chaotic), (T, tori)) if n is not None}


@pytest.mark.parametrize("chaotic, tori, votes", [
    ((59, 40, 0), (59, 10, 0), True),      # 0 wrong of 59: bound 4.95%
    ((58, 40, 0), (59, 10, 0), False),     # 0 of 58: 5.03%
    ((100, 40, 1), (93, 10, 1), True),     # 1 of 93: 4.99%
    ((100, 40, 1), (92, 10, 1), False),    # 1 of 92
    ((59, 0, 0), (59, 0, 0), True),        # never decides, never wrong
    ((300, 40, 0), (None, 0, 0), False),   # never measured on tori
])
def test_a_judge_votes_on_the_bound_of_its_wrong_rate(chaotic, tori, votes):
    assert power.votes(_by_class(chaotic, tori)) is votes


def _record(n=300, wrong_megno=0, settings=None, horizons=None, stage="decisive", estimators=None):
    """A record of the decisive judges: every judge right on every orbit of n per class, megno_log_norm wrong
    ``wrong_megno`` times on chaotic orbits at factor 1."""
    horizons = horizons or {1.0: {"megno_samples": 100}, 5.0: {"megno_samples": 200}}
    names = [i.name for i in indicators.audited(indicators.DECISIVE)]
    counts = {h: {j: _by_class((n, n - (w := wrong_megno * (j == "megno_log_norm" and h == 1.0)), w), (n, n, 0))
                  for j in names} for h in horizons}
    return {"schema": power.SCHEMA, "stage": stage, "spike_period": 2400.0,
            "settings": settings or {"T": 1e5, "dt": 0.5, "splits": [2, 4, 8], "min_cycles": 8.0, "sigma": 3.0},
            "horizons": horizons, "counts": counts, "sources": [{"git_commit": "0123456789" * 4}],
            "estimators": estimators or {j: indicators.REGISTRY[j].estimator for j in names}}


def _block(T=1e5, megno_samples=100, dt=0.5, splits=(2, 4, 8)):
    return {"sigma": 3.0, "frequency": {"min_cycles": 8.0},
            "decisive": {"T": T, "dt": dt, "megno_samples": megno_samples, "splits": list(splits)}}


def test_who_votes_in_a_stage_by_its_settings_horizon_and_spike_period():
    """Paper settings: all four vote at factor 1; the cluster's T = 5e5 with 200 samples at factor 5; T = 3e5
    with 150 MEGNO samples: MEGNO's settings were audited at no horizon (it votes by nothing), the others at
    factor 1; a shorter T than audited, other windows, a longer spike period or the first stage: nobody."""
    rec = _record()
    everyone = {"megno", "section_megno", "frequency", "birkhoff"}
    v = power.stage_vote(rec, _block(), "decisive", 2337.6)
    assert v["voters"] == everyone and set(v["factor"].values()) == {1.0}
    assert power.stage_vote(rec, _block(5e5, 200), "decisive")["factor"] == dict.fromkeys(v["factor"], 5.0)
    mixed = power.stage_vote(rec, _block(3e5, 150), "decisive")
    assert mixed["voters"] == everyone - {"megno"} and "megno_log_norm" not in mixed["factor"]
    assert "no audited horizon" in mixed["why"]["megno_log_norm"]
    assert power.stage_vote(rec, _block(5e4), "decisive")["voters"] == set()
    assert power.stage_vote(rec, _block(5e4), "decisive")["covered"]  # a longer horizon would vote: covered
    assert not power.stage_vote(rec, _block(), "decisive", 2500.0)["covered"]  # no horizon would
    assert not power.stage_vote(rec, _block(), "first")["covered"]
    assert power.stage_vote(rec, _block(splits=(2, 4)), "decisive")["voters"] == {"megno", "section_megno"}
    assert power.stage_vote(rec, _block(), "decisive", 2500.0)["voters"] == set()
    assert power.stage_vote(rec, _block(), "first")["voters"] == set()
    assert power.stage_vote(_record(stage="first"), _block(), "decisive")["voters"] == set()
    wrong = power.stage_vote(_record(n=100, wrong_megno=2), _block(), "decisive")
    assert wrong["voters"] == everyone - {"megno"} and "exceeds" in wrong["why"]["megno_log_norm"]


def test_the_report_reads_the_vote_at_the_largest_audited_factor_not_above():
    rec = _record(n=100, wrong_megno=2)
    assert "megno_log_norm" not in power.record_voting(rec, 1.0) and "megno_log_norm" in power.record_voting(rec, 5.0)
    assert power.record_voting(rec, 4.9) == power.record_voting(rec, 1.0) and power.record_voting(rec, 0.5) == set()
    rows = {(r["judge"], r["class"]): r for r in power.record_rates(rec, 1.0)}
    assert rows[("megno_log_norm", C)]["wrong"] == 2 and rows[("megno_log_norm", C)]["wrong_upper95"] > 0.05


def test_a_record_of_another_estimator_an_unknown_judge_or_a_dirty_source_is_refused():
    assert power.check_record(_record()) == []
    other = _record(estimators={**_record()["estimators"], "megno_log_norm": "heyoka's quadrature MEGNO"})
    assert "another estimator" in power.check_record(other)[0]
    unknown = _record()
    unknown["counts"][1.0]["tarot"] = unknown["counts"][1.0]["birkhoff"]
    assert any("unknown judge 'tarot'" in p for p in power.check_record(unknown))
    dirty = {**_record(), "sources": [{"git_commit": "0123456789" * 4 + "-dirty"}]}
    assert "not a full clean commit" in power.check_record(dirty)[0]
    assert power.check_record({"counts": {}}) == [f"not a record of schema {power.SCHEMA}"]


# ----------------------------------------------------------------------------- registry, sequence, bounds

def test_the_registry_names_each_stage_and_what_its_estimators_read():
    dec = indicators.audited(indicators.DECISIVE)
    assert [i.name for i in dec] == ["megno_log_norm", "section_megno", "frequency_orbit", "birkhoff"]
    assert indicators.tangent_based(indicators.DECISIVE) == {"megno", "section_megno"}
    assert indicators.audited(indicators.FIRST) == []  # not yet audited on independent orbits: votes by nothing
    run = power._run_settings({**_block(), "decisive": {**_block()["decisive"]}})
    assert all(k in run for i in dec for k in (i.horizon, *i.settings))
    with pytest.raises(ValueError, match="stage"):
        indicators.of_stage("third")


def test_the_decision_sequence_gates_votes_and_decides():
    verdicts = {"megno": (REGULAR, "m"), "section_megno": (REGULAR, "s"), "birkhoff": (REGULAR, "b"),
                "frequency": (CHAOTIC, "f")}
    arithmetic = dict.fromkeys(verdicts, "double")
    follows = {"megno": "follows", "section_megno": "follows", "birkhoff": "follows", "frequency": "follows"}
    tb = indicators.tangent_based(indicators.DECISIVE)
    out = decision.decide_state(verdicts, tangent_based=tb, arithmetic=arithmetic, follows=follows,
                                voters={"megno", "birkhoff"})
    assert out["verdict"] == REGULAR and out["set_aside_vote"] == ["section_megno", "frequency"]
    out = decision.decide_state(verdicts, tangent_based=tb, arithmetic=arithmetic,
                                follows={**follows, "birkhoff": "unknown"}, voters={"megno", "birkhoff"})
    assert out["verdict"] == UNDECIDED and out["set_aside_gauge"] == ["birkhoff"]
    assert decision.over_realizations([REGULAR, REGULAR])[0] == REGULAR


def test_a_regular_verdict_says_the_exponent_it_bounds_and_whether_a_torus_judge_confirmed_it():
    judged = {"megno_log_norm": {"verdict": (REGULAR, ""), "numbers": {"Y_mean": 2.0, "Y_resid": 0.1, "T": 1e5}},
              "section_megno": {"verdict": (REGULAR, ""),
                                "numbers": {"Y_mean": 1.0, "Y_resid": 0.0, "returns": 200.0, "mean_return": 2500.0}},
              "birkhoff": {"verdict": (REGULAR, ""), "numbers": {}}}
    b = bounds.regular_bound(judged, 3.0)
    assert b["lambda_max"] == pytest.approx(2 * 1.0 / 5e5) and b["by"] == "section_megno" and b["T"] == 5e5
    assert b["text"] == ("lambda_1 <= 4e-06 over T = 5e+05 (section_megno); confirmed by a torus-specific judge "
                         "(birkhoff)")
    judged["birkhoff"]["verdict"] = (UNDECIDED, "")
    judged["section_megno"]["verdict"] = (UNDECIDED, "")
    b = bounds.regular_bound(judged, 3.0)
    assert b["lambda_max"] == pytest.approx(2 * 2.3 / 1e5) and b["text"].endswith("not confirmed by a torus-specific "
                                                                                     "judge")
    assert math.isnan(bounds.regular_bound({}, 3.0)["lambda_max"])


# ----------------------------------------------------------------------------- the audit's orbits

def test_chaotic_windows_are_confirmed_and_drawn_from_independent_base_orbits(hy):
    name = "henon-heiles E=1/6"
    P = known_orbits.SYSTEMS[name].period
    base = audit_orbits.base_orbit(name, 5, 0, window=50 * P)
    other = audit_orbits.base_orbit(name, 5, 1, window=50 * P)
    assert len(base["windows"]) == audit_orbits.WINDOWS_PER_BASE
    assert not np.allclose(base["start"], other["start"])
    for w in base["windows"]:
        assert w["confirmed"] == 1.0 and w["lambda_1"] - 3 * w["stderr"] > w["bound"]
        assert known_orbits.hh_energy(w["y0"]) == pytest.approx(1 / 6, rel=1e-9)
    o = audit_orbits.realization(name, 5, 7, window=50 * P)  # base 1, window 1
    assert o.y0 == tuple(other["windows"][1]["y0"]) and o.confirmation["confirmed"] == 1.0


def test_the_windows_of_a_base_orbit_are_disjoint_and_its_reference_runs_on(hy, monkeypatch):
    """On a linear flow (no divergence, so the states can be compared along the orbit) posing as a chaotic
    system: window w starts BURN + w ceil(W / P + GAP) periods after the base's start; a regular orbit is
    not confirmed chaotic."""
    lin = known_orbits.System("linear test", C, lambda h: known_orbits.oscillators(h, False), 2 * math.pi, 0,
                              base=tuple(known_orbits.OSC0), perturb=known_orbits.perturbed)
    monkeypatch.setitem(known_orbits.SYSTEMS, lin.name, lin)
    audit_orbits.flow.cache_clear()
    P, W = lin.period, 20.5 * lin.period
    base = audit_orbits.base_orbit(lin.name, 5, 0, window=W, n_windows=3)
    step = math.ceil(W / P + audit_orbits.GAP_PERIODS)
    flow = audit_orbits.flow(lin.name, "double")
    for w, win in enumerate(base["windows"]):
        flow.time, flow.state[:] = 0.0, base["start"]
        flow.propagate_for((audit_orbits.BURN_PERIODS + w * step) * P)
        assert np.allclose(flow.state, win["y0"], atol=1e-9)
        assert win["confirmed"] == 0.0
    audit_orbits.flow.cache_clear()


def test_tori_are_independent_starts_confirmed_unless_integrable(hy):
    a = audit_orbits.realization("henon-heiles E=1/12", 5, 0, window=1.0)
    b = audit_orbits.realization("henon-heiles E=1/12", 5, 1, window=1.0)
    assert a.y0 != b.y0 and a.confirmation["confirmed"] == 1.0 and a.confirmation["Y_mean"] < 2.5
    assert known_orbits.hh_energy(a.y0) == pytest.approx(1 / 12, rel=1e-12)
    q = audit_orbits.realization("quartic oscillators", 5, 0, window=1.0)
    assert q.confirmation == {"confirmed": 1.0, "attempts": 1.0}


@pytest.mark.parametrize("name", ["spiked quartic oscillators", "spiked henon-heiles E=1/8"])
def test_the_spiked_systems_swing_by_about_e30_per_cycle_and_long_double_follows_them(hy, name):
    """w = exp(c g(phi)) along the orbit (the change of coordinates is what the builder says); ln G per cycle
    about 30 (29 to 33 on these realizations); G x steps x long double's rounding below 1e-3 on the tori."""
    o = audit_orbits.realization(name, 5, 0, window=10 * known_orbits.SPIKE_PERIOD)
    run = audit_orbits.tangent_orbit(name, o.y0, T=2 * known_orbits.SPIKE_PERIOD, dt=0.05, seed=0, renorm=20)
    cp, w = run["X"][:, -3], run["X"][:, -1]
    g = np.exp(known_orbits.SPIKE_KAPPA * (cp - 1.0))
    assert np.allclose(np.log(w), known_orbits.SPIKE_C * g, atol=1e-12)
    gain = audit_orbits.gauge(name, o.y0)
    assert 29.0 < gain["ln_gain_max"] < 34.0
    if known_orbits.SYSTEMS[name].cls == T:
        assert gain["ln_gain_max"] + math.log(gain["steps_per_cycle"] * 2.0**-64) < math.log(1e-3)


@pytest.mark.parametrize("name", list(known_orbits.SYSTEMS))
def test_the_stated_period_is_the_mean_interval_between_upward_crossings(hy, name):
    """Each system's period within 25% of the mean interval between upward mean crossings of its component
    on one realization (the spread between realizations: quartic oscillators 4.0-5.4, Nose-Hoover 7.8-9.0);
    the forced pendulum's chaotic layer, which alternates rotation and libration (14 to 30 measured), within
    a factor 2."""
    s = known_orbits.SYSTEMS[name]
    o = audit_orbits.realization(name, 6, 0, window=10 * s.period)
    fp = np.longdouble if s.arithmetic == "long double" else float
    ta = audit_orbits.flow(name, s.arithmetic)
    ta.time, ta.state[:] = fp(0), np.array(o.y0, dtype=fp)
    n_periods = 8 if name == "slow-fast" else 100
    dt = s.period / 50
    x = np.asarray(ta.propagate_grid(np.arange(n_periods * 50).astype(fp) * fp(dt))[-1], float)[:, s.component]
    x = x - x.mean()
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    measured = (up[-1] - up[0]) * dt / (up.size - 1)
    if name == "slow-fast":  # this draw's own period, 4 K(k) / W1, to 1%; the stated one lies among the draws'
        kc = math.sqrt(1 - (0.5 * o.y0[2] ** 2 / known_orbits.W1**2 + 1 - math.cos(o.y0[0])) / 2)
        assert measured == pytest.approx(known_orbits.slow_period(kc), rel=0.01)
        assert known_orbits.slow_period(1e-2) < s.period < known_orbits.slow_period(1e-4)
    elif name == "forced pendulum sticky":
        assert s.period / 2 < measured < 2 * s.period
    else:
        assert measured == pytest.approx(s.period, rel=0.25)


def test_one_realization_is_judged_by_every_decisive_estimator_at_every_horizon(hy):
    """The audit's rows: one per horizon and judge, the gauge's answer, the gated verdict (undecided where the
    gauge does not follow) and the numbers; on Lorenz (chaotic, followed by double) MEGNO says chaotic over the
    longer horizon."""
    block = {"spike_period": 2400.0, "decisive": {"T": 2e4, "dt": 0.5, "splits": [2, 4], "min_cycles": 4.0,
                                                  "sigma": 3.0, "horizons": [{"factor": 1.0, "megno_samples": 20},
                                                                             {"factor": 2.0, "megno_samples": 20}]}}
    rows = power_audit.realization_rows(block, "lorenz", 5, 0)
    assert [(r["horizon"], r["judge"]) for r in rows] == [(h, j.name) for h in (1.0, 2.0)
                                                          for j in indicators.audited(indicators.DECISIVE)]
    assert all(r["follows"] == "follows" and (r["raw"] == r["verdict"]) for r in rows)
    megno = [r for r in rows if r["judge"] == "megno_log_norm"]
    assert megno[0]["verdict"] != REGULAR and megno[1]["verdict"] == CHAOTIC
    assert power_audit.numbers_of(megno, "T")[0] == pytest.approx(2e4 * 0.75 / 2400, rel=1e-6)
    assert power_audit.rule_verdict(rows[:4], {"megno_log_norm"}) == UNDECIDED  # no non-tangent voter says chaotic
