"""The faithfulness gauge (sleighsim.chaos.faithfulness): the one-period gain on synthetic tangent maps,
each branch of the follows-the-orbit rule, and the gain on the sleigh's main state."""

import math

import numpy as np
import pytest

from sleighsim.chaos import faithfulness as fa
from sleighsim.precision import Precision


def _diag(*d):
    return np.diag(np.array(d, float))


def test_gain_of_a_uniform_stretch_is_its_product_over_the_cycle():
    R = np.array([_diag(2.0, 1.0, 1.0, 0.5)] * 39)
    got = fa.cycle_gains(R, [0, 10, 20, 30])
    assert got == pytest.approx([10 * math.log(2.0)] * 2)  # the third cycle's last window would end past the run


def test_gain_is_maximised_over_where_the_period_starts():
    """Against brute force on random non-normal maps: the largest one-period singular value over
    every start in the cycle, which exceeds the spike-to-spike map's."""
    rng = np.random.default_rng(7)
    R = np.triu(rng.normal(size=(40, 4, 4)))
    R[:, range(4), range(4)] = np.exp(rng.normal(scale=1.5, size=(40, 4)))

    def sigma_1(i, m):
        return math.log(np.linalg.svd(np.linalg.multi_dot(R[i + 1: i + m + 1][::-1]), compute_uv=False)[0])

    got = fa.cycle_gains(R, [0, 12, 24])
    assert got == pytest.approx([max(sigma_1(i, 12) for i in range(a, a + 12)) for a in (0, 12)], rel=1e-12)
    assert got[0] > sigma_1(0, 12) + 1.0


def test_gain_stays_finite_beyond_the_range_of_double():
    R = np.array([_diag(1e30, 1, 1, 1e-30)] * 60)
    assert fa.cycle_gains(R, [0, 20])[0] == pytest.approx(20 * 30 * math.log(10))


def test_window_gain_is_the_largest_map_between_any_two_times_of_the_window():
    """Against brute force on random non-normal maps: the largest singular value of R_j ... R_i over every
    pair i <= j, which exceeds the whole window's map and every one-step map."""
    rng = np.random.default_rng(11)
    R = np.triu(rng.normal(size=(25, 4, 4)))
    R[:, range(4), range(4)] = np.exp(rng.normal(scale=1.5, size=(25, 4)))

    def sigma_1(i, j):
        return math.log(np.linalg.svd(np.linalg.multi_dot([np.eye(4), *R[i:j + 1][::-1]]), compute_uv=False)[0])

    brute = max(sigma_1(i, j) for i in range(25) for j in range(i, 25))
    assert fa.window_gain(R) == pytest.approx(brute, rel=1e-12)
    assert fa.window_gain(R) > sigma_1(0, 24) + 1.0


def test_window_gain_finds_the_growth_inside_a_window_that_ends_contracted():
    """Growth by e^30 over 10 steps, then contraction by e^-40: the window's end-to-end map is small, its gain
    is the growth; it stays finite beyond the range of double."""
    R = np.array([_diag(math.exp(3.0), 1, 1, 1)] * 10 + [_diag(math.exp(-4.0), 1, 1, 1)] * 10)
    assert fa.window_gain(R) == pytest.approx(30.0)
    assert fa.window_gain(np.array([_diag(1e30, 1, 1, 1e-30)] * 60)) == pytest.approx(60 * 30 * math.log(10))
    with pytest.raises(ValueError, match="one step"):
        fa.window_gain(np.zeros((0, 4, 4)))


def test_spike_steps_must_increase():
    with pytest.raises(ValueError, match="increase"):
        fa.cycle_gains(np.array([np.eye(4)] * 10), [5, 2])


@pytest.mark.parametrize("ln_gain, rounding, steps, want", [
    (36.0, Precision.DOUBLE.rounding, 1.8e4, fa.DOES_NOT_FOLLOW),        # G n r = 8e3
    (36.0, Precision.LONG_DOUBLE.rounding, 1.0, fa.FOLLOWS),             # one rounding: G r = 2.3e-4
    (36.0, Precision.LONG_DOUBLE.rounding, 1.8e4, fa.DOES_NOT_FOLLOW),   # counted per step: 4
    (36.0, Precision.DOUBLE_DOUBLE.rounding, 1.8e4, fa.FOLLOWS),          # 9e-13
    (math.log(1.001e-3 / 2.0**-53 / 10), Precision.DOUBLE.rounding, 10.0, fa.DOES_NOT_FOLLOW),  # just above the bound
    (math.log(0.999e-3 / 2.0**-53 / 10), Precision.DOUBLE.rounding, 10.0, fa.FOLLOWS),  # just below
    (math.nan, Precision.QUAD.rounding, 100.0, fa.UNKNOWN),              # no complete cycle
    (20.0, Precision.QUAD.rounding, math.nan, fa.UNKNOWN),               # no step count: never counted as following
])
def test_follows_on_each_branch(ln_gain, rounding, steps, want):
    assert fa.follows(ln_gain, rounding, steps_per_cycle=steps) == want


def test_the_injected_rounding_is_counted_per_step():
    assert fa.injected_rounding(2.0**-53, 1.8e4) == pytest.approx(1.8e4 * 2.0**-53)
    assert math.isnan(fa.injected_rounding(2.0**-53, math.nan)) and math.isnan(fa.injected_rounding(2.0**-53, 0.5))
    assert fa.log10_gain_rounding(36.0, 2.0**-64, 1.8e4) == pytest.approx(
        (36.0 + math.log(1.8e4 * 2.0**-64)) / math.log(10))


def test_tangent_run_refuses_a_horizon_shorter_than_two_steps():
    with pytest.raises(ValueError, match="tau"):
        fa.tangent_run(None, np.zeros(4), T=1.0, tau=1.0)


def test_the_main_state_amplifies_rounding_beyond_double_precision(hy):
    """The settled main state (eps = 0.1, label 0.1127): ln G of about 33-46 per spike cycle, so
    double precision does not follow its orbit and quad does."""
    from sleighsim.engine import integrators
    from sleighsim.model.params import Params

    p = Params.paper(eps=0.1, K2=1.1)
    flow, _ = integrators.flow(False, 2.0**-52)
    integrators.set_pars(flow, p)
    flow.time = 0.0
    integrators.load(flow, np.array([0.0, 0.1, 1.0, 0.0]))
    flow.propagate_until(2.0e4, callback=integrators.bounded(flow))
    ta, _ = integrators.sleigh_tangent(4, 2.0**-52, True)
    integrators.set_pars(ta, p)
    g = fa.spike_cycle_gains(ta, integrators.read(flow, 4), T=1.2e4)
    assert 3 <= g["ln_gain"].size <= 4 and np.all((g["ln_gain"] > 25) & (g["ln_gain"] < 50))
    assert g["follows"]["double"] == fa.DOES_NOT_FOLLOW and g["follows"]["quad"] == fa.FOLLOWS
    assert g["log10_gain_rounding"]["double"] - g["log10_gain_rounding"]["quad"] == pytest.approx(60 * math.log10(2))
    assert 5e3 < g["steps_per_cycle"] < 5e4  # a spike cycle takes about 1.8e4 Taylor steps
    assert g["log10_gain_rounding"]["double"] - g["log10_gain_unit_rounding"]["double"] == pytest.approx(
        math.log10(g["steps_per_cycle"]))


def test_the_report_names_the_arithmetic_that_follows_each_orbit(tmp_path):
    import xarray as xr

    from sleighsim.io.netcdf import write_dataset
    from sleighsim.report.chaos_answers import chaos_answers

    ds = xr.Dataset({"verdict": ("state", np.array(["undecided", "regular"], dtype=object)),
                     "reason": ("state", np.array(["r0", "r1"], dtype=object)),
                     "ln_gain_max": ("state", [36.2, math.nan]),
                     "log10_gain_rounding": (("state", "arithmetic"), [[-0.2, -3.5, -16.3, -18.3], [math.nan] * 4]),
                     "follows_orbit": (("state", "arithmetic"),
                                       np.array([["does not follow", "follows", "follows", "follows"],
                                                 ["unknown"] * 4], dtype=object))},
                    coords={"state": ["main", "rotor"], "arithmetic": [p.value for p in Precision]})
    write_dataset(ds, tmp_path / "v.nc")
    first, second = chaos_answers({"chaos_verdict": tmp_path / "v.nc"})
    main, v0, why0, decided, why1 = first.state, first.verdict, first.why, first.arithmetic, second.why
    assert main == "main" and decided == "follows the orbit: long double, double-double, quad"
    assert v0 == "undecided" and why0.startswith("r0. Rounding amplified by ln G = 36.2")
    assert "double: does not follow (G x rounding = 10^-0.2); long double: follows" in why0
    assert why1 == ("r1. Faithfulness gauge: no complete spike cycle within T_gain, so which arithmetic follows "
                    "the orbit is unknown")


def _decisive_dataset(verdicts, decisive, indicator_verdicts, decisive_verdicts):
    """A verdict dataset of states with these verdicts, the decisive stage's verdict per state ("not run"
    where it did not run), the first stage's indicator verdicts (benettin, megno, frequency) and the
    decisive stage's (megno, frequency, birkhoff), every decisive judge voting."""
    import xarray as xr

    n = len(verdicts)
    return xr.Dataset({"verdict": ("state", np.array(verdicts, dtype=object)),
                       "reason": ("state", np.array(["r"] * n, dtype=object)),
                       "state_class": ("state", np.array(["regular"] * n, dtype=object)),
                       "indicator_verdict": (("state", "indicator"), np.array(indicator_verdicts, dtype=object)),
                       "decisive_verdict": ("state", np.array(decisive, dtype=object)),
                       "decisive_indicator_verdict": (("state", "decisive_indicator"),
                                                      np.array(decisive_verdicts, dtype=object)),
                       "decisive_voting": (("state", "decisive_indicator"), [[1, 1, 1]] * n),
                       "decisive_log10_gain_rounding": ("state", [-16.3] * n),
                       "decisive_wall_time_s": ("state", [61.0] * n)},
                      coords={"state": [f"s{i}" for i in range(n)], "indicator": ["benettin", "megno", "frequency"],
                              "decisive_indicator": ["megno", "frequency", "birkhoff"]},
                      attrs={"decisive_precision": "double-double", "decisive_T": 1e5})


def test_the_first_screen_says_who_decided_and_what_would_decide_the_rest():
    """_decided_by: the indicators that say the state's verdict, with the arithmetic each was judged in
    (the decisive stage's for those it judged again); _to_decide: nothing for a decided state; for an
    undecided one the decisive stage's measured cost and how it scales, or that no stage ran."""
    from sleighsim.report.chaos_answers import _decided_by, _decided_in, _to_decide

    R, U = "regular", "undecided"
    ds = _decisive_dataset([R, U, U], [R, U, "not run"], [[U, "chaotic", U], [U, U, U], [U, U, U]],
                           [[R, U, R], [U, U, U], ["not run"] * 3])
    assert _decided_by(ds, 0) == "birkhoff (double-double), megno (double-double)"
    assert _decided_by(ds, 1) == ""
    assert _to_decide(ds, 0, R) == ""
    assert "(double-double, T = 100000, 61 s per realization" in _to_decide(ds, 1, U)
    assert "200000 would take about 122 s per realization" in _to_decide(ds, 1, U)
    assert _to_decide(ds, 2, U).startswith("no decisive stage ran for this state")
    assert _to_decide(ds, 1, "fragile").startswith("the decisive stage")
    from sleighsim.report.chaos_answers import _settle_note

    unsettled = ds.assign(transient_over=("state", [1, 0, 1]))  # sleighsim judge at eps 0.05 from the paper's start
    assert _settle_note(unsettled, 1) == (". Its transient was not over at the end of the pre-run: a longer "
                                          "pre-run (t_transient, in a --configfile overlay) comes before any "
                                          "longer horizon")
    assert _settle_note(unsettled, 0) == "" and _settle_note(ds, 1) == ""  # over, or not recorded
    assert _decided_in(ds, 0) == "double-double (G x rounding = 10^-16.3; decisive stage over T = 100000)"
    power = {"counts": {h: {j: {"chaotic": {"N": 60, "correct": 59, "wrong": int(h == 1.0 and j == "section_megno"),
                                            "undecided": 1 - int(h == 1.0 and j == "section_megno")},
                                "tori": {"N": 60, "correct": 60, "wrong": 0, "undecided": 0}}
                            for j in ("birkhoff", "section_megno")} for h in (1.0, 4.0)}}
    ds.attrs["decisive_vote_horizon"] = 1.0
    text = _to_decide(ds, 1, U, power)
    assert "at 4 times the horizon the judge-power audit lets section_megno vote as well" in text
    assert "T = 400000 (vote_horizon 4; config/cluster.yaml) would take about 244 s" in text
    assert text.endswith("244 s per realization")  # this stage had the tangent vector (no attribute: it did)
    ds.attrs["decisive_tangent"] = 0  # the orbit alone: the cost scaled from it leaves the tangent vector out
    assert _to_decide(ds, 1, U, power).endswith("244 s per realization for the orbit alone, more with the tangent "
                                                "vector MEGNO needs (not integrated at this horizon, where no "
                                                "tangent-based judge of the stage votes)")
    ds.attrs["decisive_vote_horizon"] = 4.0
    assert _to_decide(ds, 1, U, power).endswith("its cost grows linearly with T: 200000 would take about 122 s "
                                                 "per realization")  # no longer audited horizon
    ds_plain = ds.drop_vars([v for v in ds.data_vars if str(v).startswith("decisive_")])
    assert _decided_by(ds_plain, 0) == ""  # no indicator says regular in the first stage
    ds_plain["verdict"] = ("state", np.array(["chaotic", U, U], dtype=object))
    assert _decided_by(ds_plain, 0) == "megno (double)"


def test_the_first_screen_names_only_voters_with_their_power_at_the_horizon_voted_and_what_a_verdict_rests_on():
    """_decided_by names a judge only where it votes (decisive_voting), with its counts at the audited factor
    the stage voted at, under its record name (megno: megno_log_norm); _rests_on gives the regular judges'
    exponent bound and the decision rule's own counts there, nothing for a state not decided."""
    from sleighsim.report.chaos_answers import _decided_by, _rests_on

    R, U = "regular", "undecided"
    ds = _decisive_dataset([R, U], [R, U], [[U, U, U], [U, U, U]], [[R, R, R], [U, U, U]])
    ds["decisive_voting"] = (("state", "decisive_indicator"), [[1, 0, 1], [1, 0, 1]])
    ds["decisive_bound_text"] = ("state", np.array(["lambda_1 <= 9.2e-06 over T = 5e+05 (megno_log_norm)", ""],
                                                   dtype=object))
    ds.attrs["decisive_vote_horizon"] = 5.0
    tori = {"N": 301, "correct": 142, "wrong": 0, "undecided": 159}
    chaotic = {"N": 301, "correct": 0, "wrong": 0, "undecided": 301}
    power = {"counts": {5.0: {j: {"chaotic": chaotic, "tori": {**tori, "correct": 200, "undecided": 101}}
                              for j in ("birkhoff", "megno_log_norm")}},
             "rule": {1.0: {"tori": {**tori, "correct": 0, "undecided": 301}, "chaotic": chaotic},
                      5.0: {"tori": tori, "chaotic": chaotic}}}
    decided = _decided_by(ds, 0, power)
    assert decided.startswith("birkhoff (double-double; says regular on 200 of 301 tori, wrongly on 0 of 301 chaotic")
    assert "megno (double-double; says regular on 200 of 301 tori" in decided and "frequency" not in decided
    rests = _rests_on(ds, 0, R, power)
    assert rests.startswith("lambda_1 <= 9.2e-06 over T = 5e+05 (megno_log_norm); the decision rule at audited "
                            "factor 5 says regular on 142 of 301 tori and wrongly on 0 of 301 chaotic (95% bound")
    assert _rests_on(ds, 1, U, power) == "" and _rests_on(ds, 0, R) == "lambda_1 <= 9.2e-06 over T = 5e+05 " \
                                                                          "(megno_log_norm)"
    assert _rests_on(ds.drop_vars("decisive_bound_text"), 0, R) == ""
    assert _decided_by(ds.drop_vars("decisive_voting"), 0) == ""  # who voted unrecorded: nobody named


def test_the_first_screen_names_the_arithmetic_each_state_was_decided_in():
    """report._decided_in: MEGNO's precision, the frequency analysis' precisions, and which arithmetic
    follows the orbit (some, none, or unknown when the gauge saw no complete cycle)."""
    import xarray as xr

    from sleighsim.report.chaos_answers import _decided_in

    follows = np.array([["does not follow", "follows", "follows", "follows"], ["does not follow"] * 4,
                        ["unknown"] * 4], dtype=object)
    ds = xr.Dataset({"megno_precision": ("state", np.array(["long double", "double", "double"], dtype=object)),
                     "follows_orbit": (("state", "arithmetic"), follows)},
                    coords={"state": ["a", "b", "c"], "arithmetic": [p.value for p in Precision],
                            "frequency_precision": ["double", "long double"]})
    assert _decided_in(ds, 0) == ("MEGNO: long double; frequency analysis: double, long double; "
                                  "follows the orbit: long double, double-double, quad")
    assert _decided_in(ds, 1).endswith("follows the orbit: none")
    assert _decided_in(ds, 2).endswith("follows the orbit: unknown")
    assert _decided_in(xr.Dataset(coords={"state": ["a"]}), 0) == ""


def test_the_first_screen_cites_a_verdict_measured_with_another_config():
    """elsewhere: per state of the record, how many realizations gave each verdict, the indicators that said
    it, G x rounding, the tori, the wall times and the commit; nothing without a record."""
    from sleighsim.report.chaos_answers import elsewhere

    def row(k, v, period):
        return {"realization": k, "state": "main", "verdict": v, "indicators": {"megno": v, "birkhoff": "regular"},
                "log10_gain_rounding": -16.2, "spike_period": period, "wall_time_s": 600.0,
                "precision": "double-double", "T": 5e5, "git_commit": "abcdef1234567890",
                "created_utc": "2026-11-26T18:00"}

    rows = [row(0, "regular", 2337.5), row(1, "undecided", 2335.5)]
    (line,) = elsewhere({"config": "config/cluster.yaml", "realizations": rows})
    assert line.startswith("main, with config/cluster.yaml (decisive stage in double-double over T = 500000): "
                           "regular in 1 of 2 realizations, undecided in 1 of 2 realizations")
    assert "indicators saying so: birkhoff, megno" in line
    assert "tori reached (median spike interval) 2337.5, 2335.5" in line
    assert "commit abcdef123456, 2026-11-26" in line
    assert elsewhere(None) == []


def test_a_state_settled_in_an_arithmetic_that_does_not_follow_is_named_a_torus_its_rounding_selected():
    text = fa.state_origin(Precision.DOUBLE, fa.DOES_NOT_FOLLOW, 2337.4)
    assert text.startswith("a torus that double's rounding selected (spike interval 2337)")
    assert "does not follow" in text


def test_a_state_settled_in_an_arithmetic_that_follows_is_its_starts_own_steady_state():
    text = fa.state_origin(Precision.LONG_DOUBLE, fa.FOLLOWS, 1234.0)
    assert text.startswith("the steady state of its start's orbit (spike interval 1234)")
    assert "long double, which settled it, follows" in text


def test_a_state_whose_gauge_is_unknown_is_not_named_either_way():
    text = fa.state_origin(Precision.DOUBLE, fa.UNKNOWN, math.nan)
    assert text.startswith("unknown") and "torus" not in text and "interval" not in text


def test_a_state_no_audit_covers_is_told_that_a_longer_horizon_decides_nothing():
    """_to_decide when no judge votes at any horizon (the decisive stage's vote horizon NaN, with why): it names
    the reason instead of pricing a longer horizon; without the reason it prices one as before."""
    from sleighsim.report.chaos_answers import _to_decide

    U = "undecided"
    ds = _decisive_dataset([U], [U], [[U, U, U]], [[U, U, U]])
    ds.attrs["decisive_vote_horizon"] = math.nan
    ds.attrs["decisive_vote_why"] = "spike period 3530 above the audit's 2400"
    text = _to_decide(ds, 0, U, {"counts": {1.0: {}, 5.0: {}}})
    assert "no judge votes here at any horizon (spike period 3530 above the audit's 2400)" in text
    assert "would take" not in text
    ds.attrs["decisive_vote_why"] = ""
    assert "would take about" in _to_decide(ds, 0, U, {"counts": {1.0: {}, 5.0: {}}})


def test_the_window_gauge_follows_a_spikeless_orbit_over_a_short_window_and_not_over_a_long_one(hy):
    """eps = 0.01 with the rotor carrying the energy (fig9_eps001's start): no spike cycle; over 200 time units the
    window's gain is small and double follows it; the window gauge counts the window's steps as its one span."""
    from sleighsim.engine import integrators
    from sleighsim.model.params import Params

    ta, _ = integrators.sleigh_tangent(4, 2.0**-52, True)
    integrators.set_pars(ta, Params.paper(eps=0.01, K2=1.01))
    g = fa.window_gains(ta, np.array([1.05784728e-02, 5.03551489e-04, 1.00102322e+02, 4.66151657e+00]), T=200.0,
                        tau=20.0)
    assert g["ln_gain"].size == 1 and g["spike_times"].size == 0 and 0 < g["ln_gain_max"] < 15
    assert 1e4 < g["steps_per_cycle"] < 1e5  # about 130 Taylor steps per time unit at omega = 100
    assert g["follows"]["double"] == fa.FOLLOWS
    assert g["log10_gain_rounding"]["double"] == pytest.approx(
        (g["ln_gain_max"] + math.log(g["steps_per_cycle"] * 2.0**-53)) / math.log(10))
