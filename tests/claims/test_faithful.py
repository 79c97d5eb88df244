"""The ledger's faithful columns (sleighsim.claims.faithful): each rule on each of its branches, on small
datasets built here, and the ledger's use of them (the row's own verdict for OWN, a figure's least favourable,
a missing dataset, a run not at the paper's fidelity)."""

import numpy as np
import pytest
import xarray as xr

from sleighsim.claims import faithful as f
from sleighsim.claims import ledger as claims
from sleighsim.claims.evidence import FAITHFUL
from sleighsim.claims.rules import CANNOT, DIFFERS, DIFFERS_GREATLY, FRAGILE, NOT_A_REPRODUCTION, NOT_YET, REPRODUCED


def verdicts(verdict="regular", lam=8e-6, agreeing=3):
    """A chaos_verdict with one state, main, decided as ``verdict`` with the exponent bound ``lam``."""
    one = lambda v: ("state", [v])  # noqa: E731
    return xr.Dataset(
        {"verdict": one(verdict), "n_realizations_agreeing": one(agreeing), "decisive_lambda_max": one(lam),
         "decisive_bound_T": one(5e5), "decisive_bound_text": one(f"lambda_1 <= {lam} over T = 5e5"),
         "decisive_log10_gain_rounding": one(-11.8), "decisive_wall_time_s": one(125.0),
         "decisive_spike_interval": (("state", "decisive_spike"), [[2337.5, 2337.6, np.nan]])},
        coords={"state": ["main"]},
        attrs={"n_realizations": 3, "decisive_precision": "double-double", "decisive_T": 5e5, "energy_label": 0.1127})


def grid(follows, lam, err=None, status=None):
    """fig11_grid rows at eps 0.05, 0.1, 0.2 (reference eps 0.1) with their gauges ``follows``."""
    n = len(follows)
    eps = np.array([0.05, 0.1, 0.2][:n])
    arith = ["double" if x == "follows" else "double-double" for x in follows]
    return xr.Dataset({"lambda_1": ("eps", lam), "stderr": ("eps", err or [1e-5] * n),
                       "status": ("eps", status or ["converged"] * n), "lambda_1_follows": ("eps", follows),
                       "faithful_arithmetic": ("eps", arith)}, coords={"eps": eps}, attrs={"reference_eps": 0.1})


def test_a_regular_state_makes_a_positive_exponent_differ_by_the_paper_over_the_bound():
    out = f.exponents({"exponents": [2.9e-4, 2.2e-4, -2.2e-4, 2e-5]}, verdicts(lam=8e-6))
    assert out.verdict == DIFFERS_GREATLY and "3 of 3" in out.value and out.arithmetic.startswith("double-double")
    assert f.exponents({"exponents": [1e-5]}, verdicts(lam=8e-6)).verdict == DIFFERS  # bound near the paper's


@pytest.mark.parametrize("state, word", [(FRAGILE, FRAGILE), ("chaotic", NOT_YET), ("undecided", NOT_YET)])
def test_a_state_not_regular_leaves_the_claim_fragile_or_not_computed(state, word):
    assert f.exponents({"exponents": [2.9e-4]}, verdicts(state, agreeing=2)).verdict == word
    assert f.energy_labels({"label_min": 1e-4, "label_max": 1e3, "smallest": 1.1e-4},
                           xr.Dataset(coords={"label": [1e-4, 0.1127]}), verdicts(state)).verdict == word


def test_the_energy_labels_scale_the_bound_by_the_root_of_the_energy():
    paper = {"label_min": 1e-4, "label_max": 1e3, "smallest": 1.1e-4}
    out = f.energy_labels(paper, xr.Dataset(coords={"label": [0.1127 / 100, 0.1127]}), verdicts(lam=8e-6))
    assert "8e-07 at E = 0.00113" in out.value and "8e-06 at E = 0.113" in out.value
    assert out.verdict == DIFFERS_GREATLY
    paper["smallest"] = 9e-7  # the paper's smallest barely above the scaled bound: no size worth more
    assert f.energy_labels(paper, xr.Dataset(coords={"label": [0.1127 / 100]}), verdicts(lam=8e-6)).verdict == DIFFERS


def test_each_row_counts_only_in_the_arithmetic_its_gauge_accepts():
    floor = {"smallest_above": 1e-4}
    assert f.grid_rows(floor, grid(["follows"] * 3, [3e-4, 4e-4, 5e-4]), verdicts()).verdict == REPRODUCED
    low = f.grid_rows(floor, grid(["follows", "does not follow", "follows"], [3e-4, 4e-4, 1e-4]), verdicts())
    assert low.verdict == DIFFERS and "eps 0.2: 0.0001" in low.value
    assert "eps 0.1 needs double-double" in low.value
    part = f.grid_rows(floor, grid(["does not follow", "follows", "follows"], [3e-4, 4e-4, 5e-4]), verdicts())
    assert part.verdict == NOT_YET and "eps 0.05 needs double-double (about 250 s over T = 1e+06" in part.value
    none = f.grid_rows(floor, grid(["unknown"] * 2, [3e-4, 4e-4]), verdicts())
    assert none.verdict == NOT_YET and none.value.startswith("no row's lambda_1")


def with_state(ds, y=(0.027, 0.024, 3.3, 2.5), eps=0.1, K2=1.1):
    """``ds`` with main's settled state ``y`` and its parameters."""
    return ds.assign(settled_state=(("state", "component"), [list(y)])).assign_attrs(param_eps=eps, param_K2=K2)


def test_a_row_whose_orbit_is_a_decided_state_takes_its_bound():
    """The row at eps 0.1 settles to main's very state: main's bound (8e-6, double-double) stands for it, below the
    paper's floor, so C21 differs; a row state off by 1e-9, another K2, or a state not regular does not count."""
    rows = grid(["does not follow"] * 3, [3e-4, 4e-4, 5e-4]).assign(
        row_settled_state=(("eps", "component"), [[0.01, 0.02, 1.0, 1.0], [0.027, 0.024, 3.3, 2.5],
                                                  [0.0, 0.1, 1.0, 2.0]]))
    out = f.grid_rows({"smallest_above": 1e-4}, rows, with_state(verdicts()))
    assert out.verdict == DIFFERS and "eps 0.1: the state main (main is regular in double-double" in out.value
    assert "double-double" in out.arithmetic and "eps 0.1 needs" not in out.value
    assert f.decided_rows(rows, with_state(verdicts(), y=(0.027, 0.024, 3.3, 2.5 + 1e-9))) == {}
    assert f.decided_rows(rows, with_state(verdicts(), K2=1.2)) == {}
    assert f.grid_rows({"smallest_above": 1e-4}, rows, with_state(verdicts("undecided"))).verdict == NOT_YET


def with_row_verdicts(ds, words, lam):
    """``ds`` with each row's own verdict (scenes.grid_verdict) ``words`` and regular bounds ``lam``."""
    n = ds.eps.size
    return ds.assign(row_verdict=("eps", words), row_lambda_max=("eps", lam),
                     row_verdict_arithmetic=("eps", ["double-double"] * n),
                     row_verdict_reason=("eps", [f"why {i}" for i in range(n)]))


def test_a_rows_own_regular_verdict_replaces_doubles_lambda_1_and_a_judged_undecided_row_is_named():
    """Row 0.2, which double follows at 5e-4, judged regular in double-double with lambda_1 <= 2e-5: its bound
    stands, below the floor, so C21 differs; row 0.1 judged undecided is named with its reason and stays not
    followed; a row not judged changes nothing."""
    nan = float("nan")
    rows = with_row_verdicts(grid(["follows", "does not follow", "follows"], [3e-4, 4e-4, 5e-4]),
                             ["not judged", "undecided", "regular"], [nan, nan, 2e-5])
    out = f.grid_rows({"smallest_above": 1e-4}, rows, verdicts())
    assert out.verdict == DIFFERS and "eps 0.2: regular in double-double (why 2)" in out.value
    assert "eps 0.2: 0.0005" not in out.value and "eps 0.1: undecided in double-double (why 1)" in out.value
    assert "eps 0.1 needs double-double" in out.value and "eps 0.05: 0.0003" in out.value
    assert list(f.row_verdicts(rows)) == ["", "undecided", "regular"]
    assert list(f.row_verdicts(grid(["follows"], [3e-4]))) == [""]  # a grid without row verdicts
    same = with_row_verdicts(grid(["follows"] * 3, [3e-4, 4e-4, 5e-4]), ["not judged"] * 3, [nan] * 3)
    assert f.grid_rows({"smallest_above": 1e-4}, same, verdicts()).verdict == REPRODUCED


def test_a_row_not_judged_is_priced_by_the_judged_rows_cost_per_step_of_a_cycle():
    """Row 0.2 judged in 60 s at 2000 steps per cycle (0.03 s per step of a cycle); row 0.05, not judged, takes
    10000 steps per cycle: its verdict would cost about 300 s. A row without steps per cycle has no price; a
    grid that judged no row prices by the decisive stage's cost as before."""
    nan = float("nan")
    rows = with_row_verdicts(grid(["does not follow", "does not follow", "follows"], [3e-4, 4e-4, 5e-4]),
                             ["not judged", "not judged", "regular"], [nan, nan, 2e-5]).assign(
        row_verdict_wall_s=("eps", [0.0, 0.0, 60.0]), row_gain_steps_per_cycle=("eps", [1e4, nan, 2e3]))
    assert f.row_verdict_cost(rows) == pytest.approx(0.03)
    out = f.grid_rows({"smallest_above": 1e-4}, rows, verdicts())
    assert "eps 0.05 needs double-double (about 300 s for its verdict)" in out.value
    assert "judged rows' measured wall time" in out.value and "decisive stage's" not in out.value
    assert "eps 0.1 needs double-double" in out.value and "eps 0.1 needs double-double (about" not in out.value
    assert np.isnan(f.row_verdict_cost(rows.assign(row_verdict=("eps", ["not judged"] * 3))))
    assert np.isnan(f.row_verdict_cost(grid(["follows"], [3e-4])))


def test_a_price_runs_over_the_stages_horizon_also_for_a_state_without_a_bound():
    """An undecided state has no exponent bound (its T NaN): what it needs is priced over the decisive stage's
    horizon (5e5 at 125 s), as a regular one's is (the smoke ledger read 'about not computed s')."""
    loose = verdicts("undecided").assign(decisive_bound_T=("state", [float("nan")]))
    for v in (verdicts(), loose):
        assert "(about 125 s over T = 5e+05;" in f.needs(f.decided(v), "something").value


def test_the_route_near_zero_needs_the_row_nearest_zero_followed():
    near = f.route({}, grid(["does not follow", "follows", "follows"], [3e-4, 4e-4, 5e-4]), verdicts())
    assert near.verdict == NOT_YET and "nearest eps = 0 (eps 0.05)" in near.value
    assert f.route({}, grid(["follows"] * 3, [3e-4, 4e-4, 5e-4]), verdicts()).verdict == f.OWN
    some = f.route({}, grid(["follows", "does not follow", "follows"], [3e-4, 4e-4, 5e-4]), verdicts())
    assert some.verdict == NOT_YET


def trigger(slope, err):
    return xr.Dataset({"first_spike": ("run", [5282.0, 5400.0, 5638.0]), "tol": ("run", [1e-8, 1e-12, 1e-16]),
                       "saturated": ("run", [0, 0, 1]), "range_slope": ("range", [-40.0, slope]),
                       "range_slope_stderr": ("range", [8.0, err]),
                       "range_label": ("range", ["double", "long double"])})


def test_a_transient_time_that_still_moves_with_the_error_cannot_be_reproduced():
    moving = f.spike_time({}, trigger(-86.0, 13.0))
    assert moving.verdict == CANNOT and "5282 to 5400" in moving.value and "(2 unsaturated runs)" in moving.value
    assert f.spike_time({}, trigger(-10.0, 13.0)).verdict == NOT_YET


def with_divergence(ds, mean, sigma=(1e-8, 1e-8, 1e-8), quad=(0.0, 0.0, 0.0)):
    """``ds`` with three realizations' mean divergence over whole cycles of main's decisive orbit."""
    per = lambda v: (("realization", "state"), np.asarray(v, float)[:, None])  # noqa: E731
    return ds.assign(realization_decisive_mean_divergence=per(mean),
                     realization_decisive_mean_divergence_stderr=per(sigma),
                     realization_decisive_mean_divergence_quadrature=per(quad),
                     realization_decisive_divergence_cycles=per([210, 210, 210]))


@pytest.mark.parametrize("mean, word, says", [
    ((-1e-6, -2e-6, -1e-6), REPRODUCED, "every realization contracts"),
    ((-1e-6, 1e-9, -1e-6), FRAGILE, "2 of 3 realizations contract"),
    ((1e-9, -1e-9, 2e-9), DIFFERS, "no contraction resolved: |mean divergence| <= 6.4e-08"),
    ((1e-6, 1e-9, 2e-9), DIFFERS, "expands on average in 1 of 3"),
])
def test_the_volume_contracts_when_every_realization_resolves_a_negative_mean_divergence(mean, word, says):
    out = f.volume({}, with_divergence(verdicts(), mean, quad=(3e-8, 0.0, 0.0)))
    assert out.verdict == word and says in out.value and out.arithmetic.startswith("double-double")
    assert "realization 0: " in out.value and "over 210 cycles" in out.value


def test_the_volume_sigma_adds_the_quadrature_error_in_quadrature():
    """-1e-7 with a windows' error 3e-8 and a quadrature error 4e-8: sigma 5e-8, so 2 sigma reaches 0 exactly:
    not resolved; a smaller quadrature error resolves it."""
    assert f.volume({}, with_divergence(verdicts(), [-1.01e-7] * 3, [3e-8] * 3, [4e-8] * 3)).verdict == REPRODUCED
    assert f.volume({}, with_divergence(verdicts(), [-0.99e-7] * 3, [3e-8] * 3, [4e-8] * 3)).verdict == DIFFERS


def test_the_volume_without_the_divergence_or_with_too_few_spikes_is_not_computed():
    assert f.volume({}, verdicts()).verdict == NOT_YET
    out = f.volume({}, with_divergence(verdicts(), [-1e-6, np.nan, -1e-6]))
    assert out.verdict == NOT_YET and "too few spikes" in out.value


def with_path(ds, growth, recurrence=(0.2, 0.2, 0.2)):
    """``ds`` with three realizations' path shapes along main's decisive orbit."""
    per = lambda v: (("realization", "state"), np.asarray(v, float)[:, None])  # noqa: E731
    return ds.assign(realization_decisive_path_growth=per(growth), realization_decisive_path_reach=per([50.0] * 3),
                     realization_decisive_path_recurrence=per(recurrence))


@pytest.mark.parametrize("growth, recurrence, word", [
    ((1.0, 1.01, 1.0), (0.2, 0.2, 0.2), REPRODUCED),
    ((1.0, 1.5, 1.0), (0.2, 0.2, 0.2), FRAGILE),
    ((1.0, 1.0, 1.0), (0.2, 0.001, 0.2), FRAGILE),
    ((1.41, 1.5, 2.0), (0.2, 0.2, 0.2), DIFFERS),
])
def test_the_path_is_judged_by_the_double_judges_rule_on_each_realization(growth, recurrence, word):
    out = f.plane_path({}, with_path(verdicts(), growth, recurrence))
    assert out.verdict == word and "realization 2: its reach grows by" in out.value and "T = 5e+05" in out.value
    assert out.arithmetic.startswith("double-double")


def test_a_path_without_its_shape_is_not_computed():
    assert f.plane_path({}, verdicts()).verdict == NOT_YET
    assert f.plane_path({}, with_path(verdicts(), (1.0, 1.0, 1.0), (0.2, np.nan, 0.2))).verdict == NOT_YET


def test_a_quantity_not_computed_names_the_arithmetic_and_its_price():
    out = f.FAITHFUL_JUDGES["C14"]({}, verdicts())
    assert out.verdict == NOT_YET and out.arithmetic == "double-double" and "about 125 s over T = 5e+05" in out.value


def formal(eps, lam, T=2e4):
    return xr.Dataset({"lambda_1": ("eps", lam), "T": ("eps", [T] * len(eps))}, coords={"eps": eps})


def test_c26s_rows_are_priced_in_the_digits_an_arithmetic_needs_to_follow_them():
    """lambda_1 T / ln 10 + 3 digits (G >= e^(lambda_1 T), G x rounding < 1e-3); a row not positive is named
    without a price; no row above the threshold, nothing to price."""
    assert f.digits_to_follow(0.059, 2e4) == pytest.approx(0.059 * 2e4 / np.log(10) + 3)
    out = f.FAITHFUL_JUDGES["C26"]({"eps_above": 20}, formal([10.0, 25.0, 50.0], [0.08, 0.059, -1e-6]))
    assert out.verdict == NOT_YET and "eps 25: lambda_1 = 0.059 in double over T = 2e+04" in out.value
    assert "at least 515 decimal digits" in out.value and "eps 10" not in out.value
    assert "eps 50: lambda_1 = -1e-06 in double over T = 2e+04 (not gauged)" in out.value
    assert out.arithmetic == "none affordable (at least 515 digits over T)"
    none = f.FAITHFUL_JUDGES["C26"]({"eps_above": 20}, formal([2.0, 5.0], [0.08, 0.1]))
    assert none.verdict == NOT_YET and "no eps above" in none.value
    flat = f.FAITHFUL_JUDGES["C26"]({"eps_above": 20}, formal([25.0], [-1e-6]))
    assert flat.arithmetic == "unknown (not gauged)"


def gauged(eps, lam, arithmetic, need=None, price=None, ln_gain=None):
    n = len(eps)
    return formal(eps, lam).assign(
        faithful_arithmetic=("eps", np.array(arithmetic, object)),
        gauge_needed_log10_rounding=("eps", need or [np.nan] * n),
        faithful_price=("eps", np.array(price or [""] * n, object)),
        row_ln_gain_max=("eps", ln_gain or [np.nan] * n))


def test_c26s_gauged_rows_name_the_arithmetic_that_follows_or_the_rounding_they_need_and_its_price():
    """Double following every row above the threshold keeps the row's own verdict; a finer arithmetic of the
    ladder, not computed in it, names it; none of the ladder: the rounding needed and the price record's answer."""
    judge = f.FAITHFUL_JUDGES["C26"]
    own = judge({"eps_above": 20}, gauged([10.0, 25.0], [0.1, 2e-6], ["", "double"], ln_gain=[np.nan, 3.0]))
    assert own.verdict == f.OWN and own.arithmetic == "double"
    assert "eps 25: lambda_1 = 2e-06 in double over T = 2e+04; its gauge: double follows it" in own.value
    finer = judge({"eps_above": 20}, gauged([25.0, 50.0], [2e-6, 1e-3], ["double", "double-double"]))
    assert finer.verdict == NOT_YET and finer.arithmetic == "double; double-double"
    none = "none of double, long double, double-double, quad (G x steps x rounding 10^6.7 in quad)"
    priced = judge({"eps_above": 20}, gauged([25.0], [4e-3], [none], need=[-41.2],
                                             price=["real 192 (rounding 1.6e-58) would: 0.02 CPU-s per time unit"],
                                             ln_gain=[83.4]))
    assert priced.verdict == NOT_YET and priced.arithmetic == none
    assert ("ln G up to 83.4 per spike cycle, followed by none of double" in priced.value
            and "needs unit roundoff below 1e-41 to follow it: real 192" in priced.value)


def test_every_faithful_judge_has_its_datasets_declared():
    assert set(FAITHFUL) == set(f.FAITHFUL_JUDGES)


class Load:
    """A stand-in for the ledger's datasets: ``have`` {name: dataset}; a name not there is missing."""

    def __init__(self, have):
        self.have = have

    def __call__(self, names):
        for n in names:
            if n not in self.have:
                raise claims.MissingDataset(n)
        return [self.have[n] for n in names]


def test_the_ledger_fills_the_columns_from_the_judge_or_says_what_is_missing():
    claim = type("C", (), {"id": "C27", "values": {}})()
    row = claims.Row("C27", "", "", verdict=DIFFERS)
    claims.judge_faithful(row, claim, Load({"fig11_grid": grid(["follows"] * 2, [1e-4, 2e-4]),
                                            "chaos_verdict": verdicts()}))
    assert row.faithful_verdict == DIFFERS and row.faithful_arithmetic == "per row: double"  # OWN: the row's own
    row = claims.Row("C27", "", "")
    claims.judge_faithful(row, claim, Load({}))
    assert row.faithful_verdict == NOT_YET and "fig11_grid not built" in row.faithful_value


def test_a_figure_takes_the_least_favourable_faithful_verdict_and_a_smoke_run_judges_nothing():
    row = claims.Row
    judged = {"C15": row("C15", "", "", faithful_verdict=REPRODUCED, faithful_value="a", faithful_arithmetic="x"),
              "C16": row("C16", "", "", faithful_verdict=NOT_YET, faithful_value="b", faithful_arithmetic="x"),
              "C01": claims.Row("C01", "", "")}
    fig = claims.Row("F9", "", "")
    claims.faithful_figure(fig, judged, ("C15", "C16", "C01"))
    assert fig.faithful_verdict == NOT_YET and fig.faithful_value == "C15: a; C16: b"
    assert fig.faithful_arithmetic == "x"
    bare = claims.Row("F1", "", "")
    claims.faithful_figure(bare, judged, ("C01",))
    assert bare.faithful_verdict == ""
    rows = [claims.Row("C15", "", "", verdict=REPRODUCED, faithful_verdict=REPRODUCED), claims.Row("C01", "", "")]
    claims.for_run(rows, {"label": "smoke"})
    assert rows[0].faithful_verdict == NOT_A_REPRODUCTION and rows[1].faithful_verdict == ""


class LadderLoad(Load):
    """Load with one scene laddered in double and double-double (its ladder's gauge ``follows`` for the finer)."""

    def __init__(self, follows, laddered=True):
        from sleighsim.io import layout

        gauge = xr.Dataset({"follows_orbit": ("precision", ["does not follow", follows]),
                            "log10_gain_rounding": ("precision", [4.1, -11.8])},
                           coords={"precision": ["double", "double-double"]})
        finer = layout.variant("scene", "double-double")
        super().__init__({"scene": "double's", finer: "double-double's", layout.ladder("scene"): gauge})
        self.ladders = {"scene": ["double", "double-double"]} if laddered else {}
        self.finer = finer

    def finest(self, names):
        return "double-double" if all(n in self.ladders for n in names) else "double"

    def variants(self, names, precision):
        return [self.finer if precision == "double-double" and n in self.ladders else n for n in names]


def test_a_laddered_claim_is_judged_again_by_its_own_judge_where_the_finest_arithmetic_follows(monkeypatch):
    from sleighsim.claims.rules import Judgement

    seen = []

    def judge(values, data):
        seen.append(data)
        return Judgement(DIFFERS, difference=0.6, measured=f"measured on {data}", rule="a rule")

    monkeypatch.setitem(claims.JUDGES, "CX", judge)
    monkeypatch.setitem(claims.EVIDENCE, "CX", ("scene",))
    claim = type("C", (), {"id": "CX", "values": {}})()
    row = claims.Row("CX", "", "")
    claims.faithful_in_ladder(row, claim, LadderLoad("follows"))
    assert seen == ["double-double's"] and row.faithful_verdict == DIFFERS_GREATLY
    assert row.faithful_value == "measured on double-double's" and row.faithful_arithmetic.startswith(
        "double-double (G x rounding 10^-11.8)")
    for load in (LadderLoad("does not follow"), LadderLoad("unknown"), LadderLoad("follows", laddered=False)):
        row = claims.Row("CX", "", "")
        claims.faithful_in_ladder(row, claim, load)
        assert row.faithful_verdict == NOT_YET and row.faithful_value.startswith("not computed")
    assert len(seen) == 1


def test_a_laddered_claim_with_a_dataset_derived_in_double_is_judged_without_it(monkeypatch):
    """A claim whose evidence also holds a dataset that is not laddered (derived from others in double, as
    fig9_scaling): the judge gets None in its place, the text says so, the verdict is the judge's."""
    from sleighsim.claims.rules import Judgement

    seen = []

    def judge(values, data, derived):
        seen.append((data, derived))
        return Judgement(REPRODUCED, measured=f"measured on {data}", rule="a rule")

    monkeypatch.setitem(claims.JUDGES, "CX", judge)
    monkeypatch.setitem(claims.EVIDENCE, "CX", ("scene", "derived"))
    claim = type("C", (), {"id": "CX", "values": {}})()
    row = claims.Row("CX", "", "")
    claims.faithful_in_ladder(row, claim, LadderLoad("follows"))
    assert seen == [("double-double's", None)] and row.faithful_verdict == REPRODUCED
    assert row.faithful_value == "measured on double-double's (judged without derived, which is not laddered)"


def test_c17_without_its_scaling_dataset_judges_the_same_and_leaves_the_comparison_out():
    from sleighsim.claims.judges.steady_state import c17

    def scene(loops, flat, **extra):
        return xr.Dataset(attrs={"n_loops": loops, "attractor_flatness": flat, "energy_label": 0.8313,
                                 "param_eps": 0.1, **extra})

    scaling = xr.Dataset(attrs={"scale_factor_c": 2.716, "distance_scaled_median": 0.01,
                                "distance_unscaled_median": 0.6})
    for small_flat, want in ((0.2, REPRODUCED), (0.1, DIFFERS)):
        args = ({}, scene(4, 0.18), scene(4, 0.17), scene(4, small_flat, param_eps=0.01))
        full, bare = c17(*args, scaling), c17(*args)
        assert full.verdict == bare.verdict == want
        assert "divided by c = 2.716" in full.measured and "divided by" not in bare.measured
        assert full.measured.startswith(bare.measured)
