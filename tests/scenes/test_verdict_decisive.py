"""The chaos verdict's decisive stage (sleighsim.scenes.verdict_decisive and its jobs in
sleighsim.scenes.verdict): which first-stage chunk each decisive job reads, how the state's verdict is
decided again (each branch), how a realization's dataset takes the stage in, and MEGNO from a sampled
log-norm (chaos.megno.megno_from_log_norm) on growth laws whose MEGNO is known."""

import math

import numpy as np
import pytest
import xarray as xr

from sleighsim.chaos.megno import megno_from_log_norm
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED
from sleighsim.engine import transient
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.precision import parsed
from sleighsim.scenes import verdict, verdict_decisive, verdict_decisive_orbits, verdict_lanes
from sleighsim.scenes.checks import ConfigError

C, G, U = CHAOTIC, REGULAR, UNDECIDED
INDICATORS = ("benettin", "ftle", "megno", "two_trajectory", "loschmidt", "frequency")
ALL = frozenset(INDICATORS) | {"section_megno", "birkhoff"}  # every indicator votes


def _cfg(states=("main", "rotor_a", "rotor_b"), decisive=("main",), n_chunks=3):
    return {"states": dict.fromkeys(states, [0.0, 0.1, 1.0, 0.0]), "n_chunks": n_chunks,
            "decisive": {"states": list(decisive)}}


def test_the_decisive_job_reads_every_realizations_first_stage_job_of_each_decisive_state():
    """3 realizations x 3 states = 9 first-stage jobs (reading nothing), then one decisive job whose
    lanes are (realization, state), realizations outer: it reads job r * 3 + index of the state."""
    cfg = _cfg(decisive=("main", "rotor_b"))
    assert verdict._chunk_count(cfg) == 9 + 1
    assert all(verdict._chunk_reads(cfg, k) == [] for k in range(9))
    assert verdict._chunk_reads(cfg, 9) == [0, 2, 3, 5, 6, 8]
    assert verdict._decisive_lanes(cfg) == [(0, "main"), (0, "rotor_b"), (1, "main"), (1, "rotor_b"),
                                             (2, "main"), (2, "rotor_b")]
    assert verdict._chunk_count(_cfg(decisive=())) == 9


def test_lanes_packed_into_one_job_unpack_to_the_datasets_they_were():
    """Two lanes with spike trains of different lengths (the pack NaN-pads them) and their own attributes
    come back exactly: the same variables, lengths and attributes, each with its realization."""
    a = _decisive_part("main", n_spikes=3).assign_attrs(decisive_voters=["birkhoff"], decisive_steps=12,
                                                        decisive_vote_horizon=math.nan)
    b = _decisive_part("rotor_a", n_spikes=5).assign_attrs(decisive_voters=[], decisive_steps=7,
                                                           decisive_vote_horizon=5.0)
    packed = verdict_lanes.pack([a, b], [2, 0])
    assert packed.sizes["decisive_spike"] == 5 and packed.attrs["wall_time_s"] == 10.0
    back = verdict_lanes.unpack(packed)
    assert [r for r, _ in back] == [2, 0]
    for want, (_, got) in zip((a, b), back):
        assert got.drop_attrs().identical(want.drop_attrs())
        assert {k: v for k, v in got.attrs.items() if k != "decisive_vote_horizon"} == \
            {k: v for k, v in want.attrs.items() if k != "decisive_vote_horizon"}
        assert got.attrs["decisive_vote_horizon"] == want.attrs["decisive_vote_horizon"] or (
            math.isnan(got.attrs["decisive_vote_horizon"]) and math.isnan(want.attrs["decisive_vote_horizon"]))
    with pytest.raises(ValueError, match="lanes for"):
        verdict_lanes.pack([a], [0, 1])


def test_lanes_integrated_together_are_each_the_scalar_engines_orbit():
    """The decisive stage's double-double lanes (engine.ddbatch) with a tangent vector: each lane's orbit,
    steps and log-norm are bit for bit DDFlow's from the same start and unit tangent vector."""
    from sleighsim.engine.ddtaylor import DDFlow
    from sleighsim.model.params import Params

    dc = {**_decisive_cfg()["decisive"], "T": 50.0}
    params = Params.from_config({"eps": 0.1, "b": 1.0, "K2": 1.1})
    ys = [[0.02, 0.02, 3.3, 2.5], [0.021, 0.019, 3.31, 2.4], [0.0, 0.1, 1.0, 0.0]]
    lanes = verdict_decisive_orbits.lane_orbits(params, ys, dc, tangent=True)
    grid = np.arange(101) * 0.5
    for y, lane in zip(ys, lanes):
        flow = DDFlow(params, dc["tol"])
        hi, _, log_norm, _ = flow.propagate_tangent_grid(np.asarray(y), verdict_decisive_orbits._unit_tangent(), grid)
        assert np.array_equal(lane["Y"], hi) and np.array_equal(lane["log_norm"], log_norm)
        assert lane["steps"] == flow.steps


@pytest.mark.parametrize("decisive", [("nowhere",), ("main", "main")])
def test_a_decisive_state_must_be_a_state_of_the_block_named_once(decisive):
    with pytest.raises(ConfigError, match="decisive.states"):
        verdict._checks("scenes.chaos_verdict", _cfg(decisive=decisive))
    verdict._checks("scenes.chaos_verdict", _cfg())  # a valid block passes


def test_the_decisive_lanes_must_fit_one_batch():
    verdict._checks("scenes.chaos_verdict", _cfg(decisive=("main", "rotor_a", "rotor_b"), n_chunks=341))  # 1023
    one = _cfg(decisive=("main", "rotor_a"), n_chunks=513)
    one["decisive"]["jobs"] = 1
    with pytest.raises(ConfigError, match="would make 1026 lanes of a decisive job .decisive.jobs = 1.; at most 1024"):
        verdict._checks("scenes.chaos_verdict", one)
    two = _cfg(decisive=("main", "rotor_a"), n_chunks=513)
    two["decisive"]["jobs"] = 2  # 513 lanes each
    verdict._checks("scenes.chaos_verdict", two)


def test_the_decisive_lanes_cut_into_jobs_contiguously_and_as_even_as_they_go():
    """decisive.jobs = 2 over 3 realizations x 3 states: jobs 9 and 10 take lanes 0-4 and 5-8, each reading its
    lanes' first-stage jobs; their work is their lanes' share; more jobs than lanes is refused."""
    cfg = _cfg(decisive=("main", "rotor_a", "rotor_b"))
    cfg["decisive"]["jobs"] = 2
    assert verdict._chunk_count(cfg) == 9 + 2
    assert verdict._job_lanes(cfg, 0) + verdict._job_lanes(cfg, 1) == verdict._decisive_lanes(cfg)
    assert [len(verdict._job_lanes(cfg, j)) for j in (0, 1)] == [5, 4]
    assert verdict._chunk_reads(cfg, 9) == [0, 1, 2, 3, 4] and verdict._chunk_reads(cfg, 10) == [5, 6, 7, 8]
    cfg["decisive"]["T"] = 100.0
    assert verdict._chunk_work(cfg)[-2:] == [500.0, 400.0]
    cfg["decisive"]["jobs"] = 10
    with pytest.raises(ConfigError, match="decisive.jobs = 10: more jobs than the 9 lanes"):
        verdict._checks("scenes.chaos_verdict", cfg)


@pytest.mark.parametrize("width, jobs, lanes", [(16, 1, [9]), (8, 2, [5, 4]), (4, 3, [3, 3, 3])])
def test_unset_decisive_jobs_make_one_job_per_block_of_the_hosts_widest_vector(monkeypatch, width, jobs, lanes):
    """decisive.jobs unset: 9 lanes make ceil(9 / MAX_WIDTH) jobs (AVX-512's 16: one; AVX2's 8: two), cut as even
    as they go; a set decisive.jobs wins."""
    monkeypatch.setattr(verdict, "MAX_WIDTH", width)
    cfg = _cfg(decisive=("main", "rotor_a", "rotor_b"))
    assert verdict._chunk_count(cfg) == 9 + jobs
    assert [len(verdict._job_lanes(cfg, j)) for j in range(jobs)] == lanes
    cfg["decisive"]["jobs"] = 1
    assert verdict._chunk_count(cfg) == 9 + 1


def _stage1(verdicts: dict, ln_gain=36.0):
    """A first-stage chunk dataset of one state with these indicator verdicts (the others undecided)."""
    v = [verdicts.get(k, U) for k in INDICATORS]
    return xr.Dataset({
        "indicator_verdict": (("state", "indicator"), np.array([v], dtype=object)),
        "indicator_reason": (("state", "indicator"), np.array([[f"{k} said {x}" for k, x in zip(INDICATORS, v)]],
                                                              dtype=object)),
        "indicator_value": (("state", "indicator"), [[7e-4, 7e-4, 1.0, 1e-2, 1e-3, 1e-5]]),
        "indicator_uncertainty": (("state", "indicator"), [[5e-5, 5e-5, 0.1, 1e-3, 1e-4, 1e-6]]),
        "ln_gain_max": ("state", [ln_gain]), "gain_steps_per_cycle": ("state", [1.8e4]),
        "exponent": (("state", "i"), [[7e-4, 0.0, -1e-4, -6e-4]]),
        "sum_exponents": ("state", [0.0]), "sum_exponents_stderr": ("state", [1e-5]),
        "R_image": ("state", np.array(["stays"], dtype=object)),
    }, coords={"state": ["main"], "indicator": list(INDICATORS)})


def _judged(megno=U, frequency=U, birkhoff=U, digits=8.0, D=1e-8):
    return {"megno": {"verdict": (megno, "m")}, "frequency": {"verdict": (frequency, "f"), "resolved": D},
            "birkhoff": {"verdict": (birkhoff, "b"), "resolved": 10.0**-digits}}


def test_the_decisive_stage_decides_regular_from_a_tangent_and_a_non_tangent_indicator_that_follow():
    """MEGNO and the weighted Birkhoff averages regular in double-double (G x rounding = e^36 x 2^-106 =
    5e-17, below both limits): regular; the first stage's chaotic double verdicts were set aside there
    already (undecided in its dataset), so they do not vote."""
    v, reason, used = verdict_decisive.decide_again(_stage1({}), _judged(megno=G, birkhoff=G), "double-double",
                                                    3.0, ALL)
    assert v == G and reason.startswith("decided with the double-double stage: regular")
    assert used["megno"] == (G, "m") and used["birkhoff"] == (G, "b")
    assert verdict_decisive.state_class(_stage1({}), v, 3.0) == "regular"


def test_an_indicator_that_does_not_vote_cannot_decide():
    """The same decisive verdicts with the weighted Birkhoff average outside the voters (its measured
    wrong rate too high): no indicator without tangent dynamics says regular, so undecided."""
    v, reason, used = verdict_decisive.decide_again(_stage1({}), _judged(megno=G, birkhoff=G), "double-double", 3.0,
                                                    ALL - {"birkhoff"})
    assert v == U and used["birkhoff"][1].startswith("does not vote")


def test_a_regular_verdict_needs_both_kinds_of_indicator():
    v, reason, _ = verdict_decisive.decide_again(_stage1({}), _judged(birkhoff=G), "double-double", 3.0, ALL)
    assert v == U and "missing: a tangent-based indicator" in reason


def test_an_indicator_judged_in_an_arithmetic_that_does_not_follow_closely_enough_is_set_aside():
    """In long double the rounding injected over a cycle of 1.8e4 steps, amplified by G, is e^36 x 1.8e4 x
    2^-64 = 4: neither MEGNO nor the Birkhoff average follows (limits 1e-3 and 1e-10): both set aside, so no
    regular verdict; in double-double (9e-13) both follow."""
    v, _, used = verdict_decisive.decide_again(_stage1({}), _judged(megno=G, birkhoff=G), "long double", 3.0, ALL)
    assert v == U and all(used[k][0] == U and used[k][1].startswith("set aside: judged in long double")
                          for k in ("megno", "birkhoff"))
    v, _, _ = verdict_decisive.decide_again(_stage1({}), _judged(megno=G, birkhoff=G), "double-double", 3.0, ALL)
    assert v == G


def test_indicators_that_disagree_leave_the_state_undecided():
    """The first stage's Loschmidt test (kept: it is not judged again) says chaotic, the decisive
    MEGNO and Birkhoff average regular: undecided, naming both sides."""
    v, reason, _ = verdict_decisive.decide_again(_stage1({"loschmidt": C}), _judged(megno=G, birkhoff=G),
                                                 "double-double", 3.0, ALL)
    assert v == U and "indicators disagree" in reason and "loschmidt" in reason


def test_a_chaotic_decision_is_checked_for_consistent_rates():
    """Chaotic from the decisive MEGNO and the first stage's two nearby orbits, whose rate (1e-2) is far
    from Benettin's lambda_1 (7e-4 +- 5e-5): undecided (``consistent``)."""
    v, reason, _ = verdict_decisive.decide_again(_stage1({"two_trajectory": C}), _judged(megno=C),
                                                 "double-double", 3.0, ALL)
    assert v == U and "disagree on the rate" in reason


def _realization(states=("main", "rotor_a")):
    n = len(states)
    return xr.Dataset({"verdict": ("state", np.array([U] * n, dtype=object)),
                       "reason": ("state", np.array(["first"] * n, dtype=object)),
                       "state_class": ("state", np.array(["undetermined"] * n, dtype=object))},
                      coords={"state": list(states)}, attrs={"wall_time_s": 10.0})


def _decisive_part(state="main", n_spikes=3):
    return xr.Dataset({"decisive_verdict": ("state", np.array([G], dtype=object)),
                       "decisive_reason": ("state", np.array(["second"], dtype=object)),
                       "decisive_class": ("state", np.array(["regular"], dtype=object)),
                       "decisive_spike_interval": (("state", "decisive_spike"), [np.full(n_spikes, 2337.5)])},
                      coords={"state": [state]}, attrs={"wall_time_s": 5.0, "decisive_precision": "double-double"})


def test_a_realization_takes_the_decisive_verdict_of_its_decisive_states_only():
    ds = verdict_decisive.with_decisive(_realization(), [_decisive_part()])
    assert list(ds.verdict.values) == [G, U] and list(ds.reason.values) == ["second", "first"]
    assert list(ds.state_class.values) == ["regular", "undetermined"]
    assert list(ds.decisive_verdict.values) == [G, "not run"]
    assert np.isnan(ds.decisive_spike_interval.values[1]).all() and ds.attrs["wall_time_s"] == 15.0
    assert ds.attrs["decisive_precision"] == "double-double"
    assert list(verdict_decisive.decisive_spike_period(ds)[:1]) == [2337.5]
    assert math.isnan(verdict_decisive.decisive_spike_period(ds)[1])
    assert verdict_decisive.with_decisive(_realization(), []).identical(_realization())


def test_megno_from_a_log_norm_on_known_growth_laws():
    """l = lambda t (exponential growth): <Y> = lambda t / 2; l = ln(1 + t) (linear growth, a sheared
    torus): Y = 2 - 2 ln(1 + t) / t, so <Y>(T) = 2 - (2 / T) int_0^T ln(1 + t) / t dt -> 2; a bounded
    periodic l (isochronous): <Y> -> 0. Refused: too few samples, a non-finite log-norm, samples not
    from t = 0."""
    from scipy.integrate import quad

    t = np.linspace(0.0, 2000.0, 40001)
    lam = 0.01
    m = megno_from_log_norm(t, lam * t, 50)
    assert m["final"] == pytest.approx(lam * 2000.0 / 2, rel=1e-3)
    assert 2 * m["slope"] == pytest.approx(lam, rel=1e-3)
    sheared = 2.0 - 2.0 / 2000.0 * quad(lambda s: np.log1p(s) / s, 0.0, 2000.0, limit=200)[0]
    assert megno_from_log_norm(t, np.log1p(t), 50)["final"] == pytest.approx(sheared, abs=1e-4)
    assert abs(megno_from_log_norm(t, np.sin(t), 50)["final"]) < 0.01
    with pytest.raises(ValueError, match="at least"):
        megno_from_log_norm(t[:50], t[:50], 50)
    with pytest.raises(ValueError, match="finite"):
        megno_from_log_norm(t, np.where(t > 5, np.nan, t), 50)
    with pytest.raises(ValueError, match="from t = 0"):
        megno_from_log_norm(t + 1.0, t, 50)


def test_the_stage_integrates_a_tangent_vector_only_when_a_tangent_based_judge_of_it_votes():
    assert verdict_decisive.needs_tangent({"megno", "birkhoff"})
    assert verdict_decisive.needs_tangent({"section_megno"})
    assert not verdict_decisive.needs_tangent({"birkhoff", "ftle", "two_trajectory"})  # the audit's factor-1 voters


def _decisive_cfg():
    return parsed({"params": {"eps": 0.1, "b": 1.0, "K2": 1.1}, "sigma": 3.0, "tau": 10.0,
            "frequency": {"component": "omega", "min_cycles": 2.0}, "transient": {"spike_factor": 1.8},
            "decisive": {"states": ["main"], "precision": "double-double", "tol": 1e-20, "T": 200.0, "dt": 0.5,
                         "splits": [2, 4], "megno_samples": 4}})


@pytest.mark.parametrize("voters", [ALL, frozenset({"birkhoff", "ftle", "two_trajectory"})])
def test_without_a_voting_tangent_judge_the_stage_runs_the_orbit_alone(voters):
    """The stage over T = 200 in double-double: with MEGNO among the voters it integrates the tangent
    vector and judges MEGNO; with the audit's factor-1 voters it does not (MEGNO and the return map's
    MEGNO "not run", NaN) and the orbit's own judges still run on the same orbit."""
    stage1 = _stage1({}).assign(settled_state=(("state", "var"), [[0.02, 0.02, 3.3, 2.5]]))
    ds, = verdict_decisive.decisive_lanes(_decisive_cfg(), [(stage1, voters, {"vote_horizon": 1.0})], ["one"])
    reasons = dict(zip(ds.decisive_indicator.values, ds.decisive_indicator_reason.values[0]))
    tangent = "megno" in voters
    assert ds.attrs["decisive_tangent"] == int(tangent)
    for k in ("megno", "section_megno"):
        assert reasons[k].startswith("not run") != tangent
    assert np.isfinite(ds.decisive_megno_Y_mean.values[0]).all() == tangent
    assert ds.decisive_energy_max_rel_drift.values[0] < 1e-18  # NaN fails too
    assert not reasons["birkhoff"].startswith("not run")
    assert int(ds.decisive_divergence_cycles.values[0]) == 0 and np.isnan(ds.decisive_mean_divergence.values[0])


def test_the_mean_divergence_runs_over_the_decisive_orbits_whole_cycles():
    """From the settled state at eps = 0.1 over T = 5000 in double-double (two spikes, about 2340 apart): the mean
    of trace J over that whole cycle (the divergence ranges over +-0.1 within it) agrees with the trapezoid rule on
    the same orbit sampled every 0.025 within the quoted quadrature error, which is far below the mean's size on
    this torus' cycles (about 1e-6); one window of the two holds a cycle, so no standard error."""
    params = Params.paper(eps=0.1, b=1.0, K2=1.1)
    y0 = [[0.026915490034010996, 0.0237695612672332, 3.299243512952921, 2.5060573896810956]]
    dc = {**verdict_decisive.decisive_config(_decisive_cfg()), "T": 5000.0}
    orbit, = verdict_decisive_orbits.lane_orbits(params, y0, dc, tangent=False)
    div = verdict_decisive.divergence_stage(orbit, dc, params)
    assert div["cycles"] == 1 and np.isnan(div["stderr"]) and div["quadrature"] < 1e-7
    a, b = transient.spike_times(orbit["t"], orbit["Y"][:, 1], factor=dc["spike_factor"])
    fine, = verdict_decisive_orbits.lane_orbits(params, y0, {**dc, "T": b, "dt": 0.025}, tangent=False)
    inside = fine["t"] >= a
    ref = np.trapezoid(equations.divergence(fine["Y"][inside], params), fine["t"][inside]) / (b - a)
    assert abs(div["mean"] - ref) <= div["quadrature"]
    shape = verdict_decisive.path_stage(orbit, params)
    assert shape["reach"] > 0 and np.isfinite([shape["growth"], shape["recurrence"]]).all()


def test_a_regular_verdict_states_the_exponent_bound_of_the_judges_that_voted_it():
    """MEGNO regular after the gates bounds lambda_1 by 2 (<Y> + sigma resid) / T; Birkhoff regular confirms the
    torus; a MEGNO set aside by the gates (not voting) bounds nothing, whatever it said before."""
    judged = {"megno": {"verdict": (G, "y"), "numbers": {"Y_mean": 2.0, "Y_resid": 0.1, "T": 5e5}},
              "section_megno": {"verdict": (U, "n"), "numbers": {}},
              "frequency": {"verdict": (G, "f"), "numbers": {}}, "birkhoff": {"verdict": (G, "b"), "numbers": {}}}
    gated = {k: v["verdict"] for k, v in judged.items()}
    b = verdict_decisive.what_regular_bounds(judged, gated, 3.0)
    assert b["lambda_max"] == pytest.approx(2 * 2.3 / 5e5) and b["T"] == 5e5 and b["by"] == "megno_log_norm"
    assert "confirmed by a torus-specific judge (birkhoff, frequency_orbit)" in b["text"]
    gated.update(megno=(U, "does not vote"), birkhoff=(U, "does not vote"), frequency=(U, "does not vote"))
    b = verdict_decisive.what_regular_bounds(judged, gated, 3.0)
    assert math.isnan(b["lambda_max"]) and b["text"].startswith("no tangent-based judge bounds lambda_1; not confirmed")


def _vote_cfg():
    """A chaos_verdict block whose decisive settings are the audited ones of ``_power_record``."""
    return {"sigma": 3.0, "frequency": {"min_cycles": 8.0},
            "decisive": {"T": 100000.0, "dt": 0.5, "splits": [2, 4, 8], "megno_samples": 100}}


def _power_record():
    """A record of one audited horizon (factor 1) at spike period 2400 in which every decisive judge votes."""
    from sleighsim.chaos.indicators import DECISIVE, REGISTRY

    counts = {i.name: {c: {"N": 301, "correct": 301, "wrong": 0, "undecided": 0} for c in ("chaotic", "tori")}
              for i in REGISTRY.values() if i.stage == DECISIVE}
    return {"stage": "decisive", "spike_period": 2400.0,
            "settings": {"T": 100000.0, "dt": 0.5, "splits": [2, 4, 8], "min_cycles": 8.0, "sigma": 3.0},
            "horizons": {1.0: {"megno_samples": 100}}, "counts": {1.0: counts}}


def test_a_state_of_a_longer_spike_period_runs_the_audited_cycles_and_is_voted_on():
    """Spike period 3600 above the audit's 2400: the lane is voted on at the block's own settings and runs T and
    dt x 1.1 x 3600 / 2400 (as F11's rows); at 2000 it keeps T and is voted on at its spike period; the stage
    integrates every lane over the largest scale and judges each with it."""
    from sleighsim.scenes.grid_verdict import MARGIN

    long = _stage1({}).assign(spike_period=("state", [3600.0]))
    _, voters, vote = verdict._lane_vote(_power_record(), _vote_cfg(), long)
    assert vote["cycle_scale"] == pytest.approx(MARGIN * 1.5) and voters and vote["vote_why"] == ""
    _, short_voters, short = verdict._lane_vote(_power_record(), _vote_cfg(), long.assign(spike_period=("state",
                                                                                                       [2000.0])))
    assert short["cycle_scale"] == 1.0 and short_voters == voters
    stage1 = _stage1({}).assign(settled_state=(("state", "var"), [[0.02, 0.02, 3.3, 2.5]]))
    lanes = [(stage1, frozenset({"birkhoff"}), {"vote_horizon": 1.0, "cycle_scale": 1.5}),
             (stage1, frozenset({"birkhoff"}), {"vote_horizon": 1.0, "cycle_scale": 1.0})]
    parts = verdict_decisive.decisive_lanes(_decisive_cfg(), lanes, ["a", "b"])
    assert [p.attrs["decisive_T"] for p in parts] == [300.0, 300.0]
    assert [p.attrs["decisive_dt"] for p in parts] == [0.75, 0.75]
