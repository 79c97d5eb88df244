"""Every judge of the ledger driven to each verdict it can return, with small synthetic datasets.
The paper's values are those parsed from paper/CLAIMS.md."""

import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sleighsim.analysis import torus
from sleighsim.claims import judges
from sleighsim.claims.judges import lyapunov, perturbation, sleigh0, steady_state, transients
from sleighsim.claims.rules import CANNOT, DIFFERS, NOT_YET, REPRODUCED, all_of, digits, number
from sleighsim.io.claims_table import parse_claims
from sleighsim.report.figures.catalog import FIGURES

ROOT = Path(__file__).resolve().parents[2]
PAPER = {c.id: c.values for c in parse_claims(ROOT / "paper" / "CLAIMS.md")}
NAN = math.nan


def A(**attrs):
    return xr.Dataset(attrs=attrs)


def test_number_digits_and_all_of_rules():
    assert number(2200.0, 2080.0) == REPRODUCED and number(8700.0, 5440.0) == DIFFERS
    assert number(1.0, 1.5, 0.3) == REPRODUCED and number(1.0, NAN) == NOT_YET and number(1.0, 1.0, NAN) == NOT_YET
    assert digits("6.276", 6.2765) == REPRODUCED and digits("6.276", 6.2999) == DIFFERS
    assert digits("6.276", 6.2999, 0.02) == REPRODUCED and digits("6.276", NAN) == NOT_YET
    assert all_of([REPRODUCED, NOT_YET, DIFFERS]) == DIFFERS and all_of([REPRODUCED, NOT_YET]) == NOT_YET
    assert all_of([REPRODUCED, CANNOT]) == CANNOT and all_of([REPRODUCED]) == REPRODUCED


def test_every_claim_of_the_list_has_a_judge_or_a_figure():
    figure_ids = {f.paper for f in FIGURES.values() if f.paper}
    for c in parse_claims(ROOT / "paper" / "CLAIMS.md"):
        assert c.id in judges.JUDGES or c.id in figure_ids, c.id


def _fig2(omega_end, turn):
    t = np.linspace(0, 10, 101)
    return xr.Dataset({"Omega_closed": (("k", "t"), np.array([[1.0, omega_end]])),
                       "u_closed": (("k", "t"), np.array([[0.0, 0.5]])),
                       "path_theta": ("s", turn * t / 10)}, attrs={"closed_form_max_abs_error": 1e-14})


@pytest.mark.parametrize("omega_end, turn, want", [(1e-6, 0.0, REPRODUCED), (0.1, 0.0, DIFFERS), (1e-6, 1.0, DIFFERS)])
def test_c01(omega_end, turn, want):
    assert sleigh0.c01(PAPER["C01"], _fig2(omega_end, turn)).verdict == want


def test_c02_both_branches(monkeypatch):
    assert sleigh0.c02(PAPER["C02"]).verdict == REPRODUCED
    monkeypatch.setattr(sleigh0, "rhs", lambda y, p: np.ones_like(y))  # a flow with no fixed points there
    assert sleigh0.c02(PAPER["C02"]).verdict == DIFFERS


@pytest.mark.parametrize("judge, key, values, want", [
    ("c03", "sleigh_phase_end", 80.0, REPRODUCED), ("c03", "sleigh_phase_end", 300.0, DIFFERS),
    ("c03", "sleigh_phase_end", NAN, NOT_YET),
    ("c04", "first_spike", 8650.0, REPRODUCED), ("c04", "first_spike", 5500.0, DIFFERS),
    ("c04", "first_spike", NAN, NOT_YET),
])
def test_c03_c04(monkeypatch, judge, key, values, want):
    monkeypatch.setattr(transients, "_phases", lambda ds: {key: values})
    args = (A(),) if judge == "c03" else (A(), A(first_spike_slope=-2.3))
    assert judges.JUDGES[judge.upper()](PAPER[judge.upper()], *args).verdict == want


@pytest.mark.parametrize("mean, std, n, want", [(2150.0, 30.0, 10, REPRODUCED), (2500.0, 10.0, 10, DIFFERS),
                                                (NAN, NAN, 1, NOT_YET), (2700.0, 400.0, 4, REPRODUCED)])
def test_c05_standard_error_decides(monkeypatch, mean, std, n, want):
    monkeypatch.setattr(transients, "_phases", lambda ds: {"spike_interval_mean": mean, "spike_interval_std": std,
                                                        "n_spikes": n})
    assert transients.c05(PAPER["C05"], A()).verdict == want


def _fig4(n_groups, reached=1):
    ds = xr.Dataset({"level": ("run", [0, 0, 1]), "reached": ("run", [reached] * 3),
                     "group": ("run", [0, n_groups - 1, 0]),
                     "spike_interval_level0_units": ("run", [2000.0, 2100.0, 2000.0]),
                     "group_id": ("g", [0]), "long_spike_time": (("g", "k"), [[100.0, 2100.0, 4200.0, NAN]])})
    ds.attrs.update(level0_n_groups=n_groups, level1_n_groups=1, level0_distance_main_group=0.01,
                    level1_distance_main_group=0.02, group_rel_tol=0.02)
    return ds


def _torus(directions=4, err=3.0):
    """A torus-stability dataset: the reference and three perturbed orbits, two on other tori of the family, one
    not shown to be on a torus; laws fitted over ``directions`` directions (none: not fitted)."""
    return xr.Dataset({"amplitude": ("orbit", [0.0, 1e-6, 1e-3, 1e-3]),
                       "period": ("orbit", [2337.575614, 2311.309838, 2010.833297, 2052.1]),
                       "torus_class": ("orbit", [torus.PERIODIC, torus.PERIODIC, torus.PERIODIC, torus.NOT_SHOWN]),
                       "torus_identity": ("orbit", [torus.REFERENCE, torus.ANOTHER, torus.ANOTHER,
                                                    torus.UNDETERMINED])},
                      attrs=dict(n_perturbed=3, T=2.5e4, T_reference=1e5, reference_class=torus.PERIODIC,
                                 reference_period=2337.575613998, reference_period_err=2.8e-13, reference_n_cycles=42,
                                 law_amplitudes=[1e-6, 1e-3], period_law_slope=-91.5, period_law_slope_err=err,
                                 period_law_slope_residual=8.0, period_law_slope_directions=directions,
                                 offset_law_exponent=0.31, offset_law_exponent_err=err / 100,
                                 offset_law_exponent_residual=0.1, offset_law_exponent_directions=directions))


@pytest.mark.parametrize("n_groups, reached, want", [(1, 1, REPRODUCED), (2, 1, DIFFERS), (1, 0, NOT_YET)])
def test_c06(n_groups, reached, want):
    j = transients.c06(PAPER["C06"], _fig4(n_groups, reached), _torus())
    assert j.verdict == want and (want != DIFFERS or "extra steady state" in j.reason)
    assert "torus (periodic train), period 2337.575614 +- 3e-13 over 42 reversal intervals" in j.measured
    assert "2 torus (periodic train), 1 not shown to be a torus; 2 another torus of the family, 1 undetermined" \
        in j.measured and "periods 2010.833 to 2311.31" in j.measured
    assert "period changes per decade of a by -91.5 +- 3 (standard error over 4 directions" in j.measured
    assert "spike point moves like a to the power 0.31 +- 0.03" in j.measured
    assert "neutrally" not in j.measured and "neighbouring" not in j.measured


@pytest.mark.parametrize("directions, err, want", [
    (1, math.nan, "by -91.5 (standard error over 1 directions"),  # one direction: no spread to take
    (0, math.nan, "period changes per decade of a by: not fitted"),
])
def test_c06_torus_laws_on_each_branch(directions, err, want):
    j = transients.c06(PAPER["C06"], _fig4(1, 1), _torus(directions, err))
    assert want in j.measured


def _fig6(**over):
    a = dict(order1_max_abs=0.0, T1_Omega2=6.2762, T1_u2=6.276, two_pi_over_omega0=6.2771, T1_Omega2_uncertainty=1e-4,
             two_pi_over_omega0_uncertainty=1e-5, Omega2_amplitude=0.89, Omega2_amplitude_uncertainty=1e-3,
             phi1_over_pi=0.47, phi1_uncertainty=1e-3, theory_phi1=0.47 * math.pi, theory_Omega2_amplitude=0.89,
             T2=3.138, T2_uncertainty=1e-3, theory_T2=3.135, B=0.241, B_uncertainty=1e-3, theory_B=0.238,
             omega2_growth=0.0445, omega2_growth_uncertainty=1e-4, theory_omega2_growth=0.0415,
             fit_window_start=20.0, fit_window_end=100.0)
    a.update(over)
    return A(**a)


@pytest.mark.parametrize("judge, over, want", [
    ("c07", {}, REPRODUCED), ("c07", {"order1_max_abs": 1e-9}, DIFFERS),
    ("c08", {}, REPRODUCED), ("c08", {"T1_Omega2": 6.30}, DIFFERS), ("c08", {"T1_Omega2": NAN}, NOT_YET),
    ("c09", {}, REPRODUCED), ("c09", {"phi1_over_pi": -0.47}, DIFFERS), ("c09", {"Omega2_amplitude": NAN}, NOT_YET),
    ("c10", {}, REPRODUCED), ("c10", {"B": 0.2}, DIFFERS), ("c10", {"omega2_growth": NAN}, NOT_YET),
])
def test_hierarchy_judges(judge, over, want):
    j = judges.JUDGES[judge.upper()](PAPER[judge.upper()], _fig6(**over))
    assert j.verdict == want
    if want == DIFFERS and judge == "c10":
        assert "B: 0.2 against 0.241" in j.reason


@pytest.mark.parametrize("err, want", [(0.021, REPRODUCED), (7e-4, DIFFERS), (NAN, NOT_YET)])
def test_c11(err, want):
    j = perturbation.c11(PAPER["C11"], A(omega_rel_error_at_t_end=err, t_end=100.0, u_rel_error_at_t_end=0.01,
                                   Omega_rel_error_at_t_end=0.01))
    assert j.verdict == want and (want != DIFFERS or "smaller than the paper's" in j.reason)


@pytest.mark.parametrize("vanishes, n_secular, want", [(1, 3, REPRODUCED), (0, 3, DIFFERS), (1, 0, DIFFERS)])
def test_c12(vanishes, n_secular, want):
    a = A(order3_forcing_vanishes=vanishes, order3_max_abs_along_solution=0.0, order4_n_secular=n_secular,
          order3_forcing_with_order1_zero="0", order4_n_terms=78, growth_exponent_omega4=1.5,
          growth_exponent_omega2=0.8, order4_secular_rule="a rule")
    assert perturbation.c12(PAPER["C12"], a).verdict == want


def _fig7(back_at, spike_at, turn):
    t = np.arange(9000.0, 11500.0, 0.5)
    u = np.where(np.abs(t - back_at) < 40, -0.05, 0.05)
    Om = 0.01 * np.sin(t) + np.where(np.abs(t - spike_at) < 1, 1.0, 0.0)
    theta = turn * math.pi / (1 + np.exp(-(t - spike_at)))
    return xr.Dataset({"u": ("time", u), "Omega": ("time", Om), "theta": ("time", theta)}, coords={"time": t})


@pytest.mark.parametrize("back, spike, turn, want", [(9800, 10000, 1.0, REPRODUCED), (9800, 10000, 0.3, DIFFERS),
                                                     (10500, 11000, 1.0, DIFFERS)])
def test_c13(back, spike, turn, want):
    assert steady_state.c13(PAPER["C13"], _fig7(back, spike, turn)).verdict == want


def _fig8(kind):
    t = np.arange(0.0, 2000.0, 0.5)
    if kind == "bounded":
        x, y = np.cos(0.0123 * t) + 0.3 * np.cos(0.0377 * t), np.sin(0.0123 * t) + 0.3 * np.sin(0.0377 * t)
    elif kind == "periodic":
        x, y = np.cos(2 * math.pi * t / 100), np.sin(2 * math.pi * t / 100)
    else:  # straight
        x, y = 0.01 * t, 0.0 * t
    return xr.Dataset({"x": ("time", x), "y": ("time", y)}, coords={"time": t})


@pytest.mark.parametrize("kind, want", [("bounded", REPRODUCED), ("periodic", DIFFERS), ("straight", DIFFERS)])
def test_c14_bounded_and_not_periodic(kind, want):
    assert steady_state.c14(PAPER["C14"], _fig8(kind)).verdict == want


def _ref(**over):
    a = dict(p2pi_curve_thickness=0.003, n_p2pi=2000, p2pi_recurrence=0.05, rotation_number=0.12,
             rotation_number_first_half=0.12, rotation_number_second_half=0.12, n_loops=4,
             loops_per_class=np.ones(4), n_components_projected=2, attractor_flatness=0.1, energy_label=0.1127,
             param_eps=0.1, return_time_n_adjacent_pairs_within_tie_tol=0, return_time_min=5.0, return_time_max=6.0,
             return_time_min_pairwise_difference=1e-4)
    a.update(over)
    return A(**a)


@pytest.mark.parametrize("over, want", [({}, REPRODUCED), ({"p2pi_recurrence": 1e-10}, DIFFERS),
                                        ({"p2pi_recurrence": 0.005}, REPRODUCED),
                                        ({"p2pi_curve_thickness": 0.1}, DIFFERS), ({"n_p2pi": 50}, DIFFERS)])
def test_c15(over, want):
    assert steady_state.c15(PAPER["C15"], _ref(**over)).verdict == want


@pytest.mark.parametrize("loops, want", [(4, REPRODUCED), (3, DIFFERS)])
def test_c16(loops, want):
    assert steady_state.c16(PAPER["C16"], _ref(n_loops=loops)).verdict == want


@pytest.mark.parametrize("loops_small, flat_small, want", [(4, 0.3, REPRODUCED), (3, 0.3, DIFFERS), (4, 0.05, DIFFERS)])
def test_c17(loops_small, flat_small, want):
    scaling = A(scale_factor_c=2.7, distance_scaled_median=1e-3, distance_unscaled_median=0.5)
    j = steady_state.c17(PAPER["C17"], _ref(), _ref(energy_label=0.8313), _ref(n_loops=loops_small, param_eps=0.01,
                                                                          attractor_flatness=flat_small), scaling)
    assert j.verdict == want


def _spectrum(div, unc, lam=(3e-4, 1e-6, -1e-6, -3e-4), err=(1e-5,) * 4):
    return xr.Dataset({"exponent": ("i", list(lam)), "stderr": ("i", list(err))},
                      attrs=dict(mean_divergence=div, mean_divergence_stderr=unc, replicas=4, sum_all=div,
                                 sum_all_stderr=unc, sum_lambda_1_4=div, sum_lambda_1_4_stderr=unc, T=1e5))


@pytest.mark.parametrize("div, unc, want, why", [(-1e-3, 1e-4, REPRODUCED, ""), (1e-3, 1e-4, DIFFERS, "expands"),
                                                 (1e-6, 1e-5, DIFFERS, "no contraction resolved")])
def test_c18_judged_by_replica_standard_error(div, unc, want, why):
    j = lyapunov.c18(PAPER["C18"], _spectrum(div, unc))
    assert j.verdict == want and why in j.reason


def _protocol(lam1):
    return xr.Dataset({"exponent": (("state", "i"), [[lam1, 0, 0, -lam1]] * 3)}, attrs=dict(T=4000.0, t_transient=1e4))


@pytest.mark.parametrize("lam, want", [((2.9e-4, 2.2e-4, 2.02e-5, -2.2e-4), REPRODUCED),
                                       ((5.7e-4, 1e-6, -1e-6, -5.6e-4), DIFFERS),
                                       ((NAN, NAN, NAN, NAN), NOT_YET)])
def test_c19_paper_against_our_converged_spectrum_not_the_protocol_spread(lam, want):
    # a noisy protocol whose spread would cover everything must not help
    j = lyapunov.c19(PAPER["C19"], _protocol(1.0), _spectrum(0.0, 1.0, lam, (1e-6,) * 4))
    assert j.verdict == want


def _energy(smallest, low_value, with_low=True):
    labels = [1e-4, 1e-3, 1e-1, 1e1, 1e3] if with_low else [1e-3, 1e-1, 1e1, 1e3]
    lam = ([low_value] if with_low else []) + [smallest, 1e-3, 1e-2, 1e-1]
    # T / tau = 1e4 at every label: polynomial growth fakes 1.84e-4 at T = 1e5, 1.84e-6 at T = 1e7 (the low label)
    T = [1e7 if lab < 1e-3 else 1e5 for lab in labels]
    return xr.Dataset({"lambda_1": ("label", lam), "stderr": ("label", [1e-6] * len(lam)), "T": ("label", T),
                       "tau": ("label", [t / 1e4 for t in T])},
                      coords={"label": labels}, attrs={"fitted_exponent": 0.5})


@pytest.mark.parametrize("smallest, low, with_low, want", [(1.1e-4, 5e-5, True, REPRODUCED),
                                                           (4e-3, 5e-5, True, DIFFERS),
                                                           (1.1e-4, -5e-5, True, DIFFERS),
                                                           (1.1e-4, 1e-7, True, NOT_YET),
                                                           # resolved > 0 but below what polynomial growth fakes
                                                           (1.1e-4, 3.5e-6, True, NOT_YET),
                                                           (1.1e-4, 0, False, NOT_YET)])
def test_c20_judged_at_the_papers_lowest_energy(smallest, low, with_low, want):
    assert lyapunov.c20(PAPER["C20"], _energy(smallest, low, with_low)).verdict == want


def _grid(lam, err, status, steady=1, T=1e5, follows=None):
    # tau = 10: polynomial growth fakes 2 ln(T / tau) / T, 1.84e-4 at T = 1e5, 1.2e-3 at T = 1e4
    n = len(lam)
    follows = ["follows"] * n if follows is None else follows
    return xr.Dataset({"lambda_1": ("eps", lam), "stderr": ("eps", err), "status": ("eps", status),
                       "transient_over": ("eps", [1] * n), "steady": ("eps", [steady] * n), "T": ("eps", [T] * n),
                       "tau": ("eps", [10.0] * n), "lambda_1_follows": ("eps", np.array(follows, dtype=object)),
                       "faithful_arithmetic": ("eps", np.array(["double-double"] * n, dtype=object))},
                      coords={"eps": np.linspace(0.02, 0.5, n)}, attrs={"n_rows": n})


@pytest.mark.parametrize("grid, want", [
    (_grid([1e-3, 2e-3], [1e-5, 1e-5], ["converged", "converged"]), REPRODUCED),
    # the same values over a horizon too short: below the rate polynomial growth fakes, not resolved
    (_grid([1e-3, 2e-3], [1e-5, 1e-5], ["converged", "converged"], T=1e4), CANNOT),
    (_grid([1e-3, 1e-5], [1e-5, 1e-6], ["converged", "converged"]), DIFFERS),
    (_grid([1e-3, 1e-5], [1e-5, 1e-6], ["converged", "regular"]), DIFFERS),
    (_grid([1e-3, 2e-4], [1e-5, 1e-4], ["converged", "capped"]), CANNOT),
    (_grid([1e-3, 2e-3], [1e-5, 1e-5], ["converged", "converged"], steady=0), CANNOT),
])
def test_c21(grid, want):
    assert lyapunov.c21(PAPER["C21"], grid).verdict == want


@pytest.mark.parametrize("follows, want", [(["follows", "does not follow"], CANNOT), (["follows", "unknown"], CANNOT),
                                           (None, CANNOT)])
def test_c21_counts_no_row_whose_orbit_double_does_not_follow(follows, want):
    """A row resolved positive in an arithmetic that does not follow its orbit (or whose gauge is unknown, or
    a grid without the gauge: fail closed) supports nothing: cannot be reproduced, the arithmetic it needs named;
    a row below the paper's floor there is not a difference either."""
    grid = _grid([1e-3, 2e-3], [1e-5, 1e-5], ["converged", "converged"], follows=follows or ["follows"] * 2)
    if follows is None:
        grid = grid.drop_vars(["lambda_1_follows", "faithful_arithmetic"])
    j = lyapunov.c21(PAPER["C21"], grid)
    assert j.verdict == want and "does not follow the orbit at eps " in j.reason and j.reason.endswith("0.5")
    if follows is not None:
        assert "(the arithmetic each needs: eps 0.5: double-double)" in j.measured
    below = _grid([1e-3, 1e-5], [1e-5, 1e-6], ["converged", "converged"], follows=["follows", "does not follow"])
    assert lyapunov.c21(PAPER["C21"], below).verdict == CANNOT


@pytest.mark.parametrize("other, want", [("converged", REPRODUCED), ("regular", DIFFERS)])
def test_c21_judges_the_rows_computed_and_names_those_left_to_another_config(other, want):
    grid = _grid([math.nan, 1e-3, 1e-5 if other == "regular" else 2e-3], [math.nan, 1e-5, 1e-6],
                 ["elsewhere", "converged", other])
    # a row left elsewhere is NaN throughout, as grid.chunk stores it
    for v in ("T", "tau", "transient_over", "steady"):
        grid[v] = grid[v].astype(float)
        grid[v][0] = math.nan
    grid.attrs["elsewhere_config"] = "config/cluster.yaml"
    j = lyapunov.c21(PAPER["C21"], grid)
    assert j.verdict == want  # the row not computed here is neither unresolved nor below
    assert j.measured.endswith("not computed in this run: eps 0.02 (computed by config/cluster.yaml)")
    rows = _regimes(["elsewhere", "regular", "converged", "converged"], [math.nan, 2e-6, 3e-4, 5e-4],
                    [math.nan] + [0.001] * 3)
    rows["T"] = rows["T"].copy(data=[math.nan, 1e5, 1e5, 1e5])
    assert lyapunov.c27(PAPER["C27"], rows).verdict == REPRODUCED  # C27 reads the same rows: the NaN row is skipped


def test_c26_names_the_eps_left_to_another_config():
    ds = _formal([1e-3, 1e-6, 2e-6], [1e-5, 1e-7, 1e-7])
    ds.attrs.update(eps_elsewhere=np.array([50.0]), elsewhere_config="config/cluster.yaml")
    j = lyapunov.c26(PAPER["C26"], ds)
    assert j.verdict == REPRODUCED and j.measured.endswith(
        "not computed in this run: eps 50 (computed by config/cluster.yaml)")
    assert "not computed" not in lyapunov.c26(PAPER["C26"], _formal([1e-3, 1e-6, 2e-6], [1e-5, 1e-7, 1e-7])).measured


@pytest.mark.parametrize("pairs, want", [(0, REPRODUCED), (2, DIFFERS)])
def test_c22(pairs, want):
    assert steady_state.c22(PAPER["C22"], _ref(return_time_n_adjacent_pairs_within_tie_tol=pairs)).verdict == want


def _psd(low, high, segment=200.0):
    return A(Omega_band_low=low, Omega_band_high=high, u_band_low=low, u_band_high=high, psd_segment=segment,
             Omega_n_peaks_near_zero=2)


@pytest.mark.parametrize("judge, band, want", [("c23", (1.46, 1.79), REPRODUCED), ("c23", (0.23, 0.29), DIFFERS),
                                               ("c24", (0.561, 0.599), REPRODUCED), ("c24", (0.56, 0.70), DIFFERS)])
def test_bands_within_a_tenth_of_the_band_width(judge, band, want):
    assert judges.JUDGES[judge.upper()](PAPER[judge.upper()], _psd(*band, segment=1000.0)).verdict == want


def _cost(hours, budget=100.0):
    t = [1e-3, 1e-4, 1e-5]
    return xr.Dataset({"wall_estimate_s": ("target", [1.0, 10.0, hours * 3600]),
                       "transient_estimate": ("target", [1, 2, 3])},
                      coords={"target": t}, attrs={"budget_core_hours": budget})


@pytest.mark.parametrize("hours, want", [(1e4, CANNOT), (5.0, NOT_YET), (NAN, NOT_YET)])
def test_c25_cannot_only_from_a_cost_above_the_budget(hours, want):
    j = lyapunov.c25(PAPER["C25"], _cost(hours))
    assert j.verdict == want and ("above the budget" in j.reason) == (want == CANNOT)


def _formal(lam, err, over=(1, 1, 1)):
    return xr.Dataset({"lambda_1": ("eps", lam), "stderr": ("eps", err), "transient_over": ("eps", list(over))},
                      coords={"eps": [10.0, 30.0, 60.0]})


@pytest.mark.parametrize("lam, err, want", [([1e-3, 1e-6, 2e-6], [1e-5, 1e-7, 1e-7], REPRODUCED),
                                            ([1e-3, 1e-3, 2e-6], [1e-5, 1e-5, 1e-7], DIFFERS),
                                            ([1e-3, 1e-5, 2e-6], [1e-5, 1e-5, 1e-7], NOT_YET)])
def test_c26(lam, err, want):
    assert lyapunov.c26(PAPER["C26"], _formal(lam, err)).verdict == want


@pytest.mark.parametrize("lam, over, want, reason", [
    ([1e-3, 1e-6, 1e-3], (1, 1, 0), NOT_YET, "transient not over at eps 60"),  # the excess is at an unsettled eps
    ([1e-3, 1e-6, 1e-3], (1, 0, 1), DIFFERS,  # a settled eps resolves the excess
     "lambda_1 resolved above 1e-05 at settled eps 60; transient not over at eps 30"),
    ([1e-3, 1e-6, 2e-6], (0, 1, 1), REPRODUCED, ""),  # eps 10 is below the paper's threshold
])
def test_c26_counts_only_rows_whose_transient_is_over(lam, over, want, reason):
    j = lyapunov.c26(PAPER["C26"], _formal(lam, [1e-5, 1e-7, 1e-7], over))
    assert j.verdict == want
    assert j.reason == reason


def test_c26_a_missing_transient_check_counts_as_not_checked():
    ds = _formal([1e-3, 1e-6, 2e-6], [1e-5, 1e-7, 1e-7]).drop_vars("transient_over")
    assert lyapunov.c26(PAPER["C26"], ds).verdict == NOT_YET


def test_c26_without_eps_above_the_threshold():
    ds = xr.Dataset({"lambda_1": ("eps", [1e-3]), "stderr": ("eps", [1e-5])}, coords={"eps": [5.0]})
    assert lyapunov.c26(PAPER["C26"], ds).verdict == NOT_YET


def _formal_fluctuating(lam, over, fluct):
    """_formal with each pre-run's block fluctuation, its wall time and the settling rule's numbers."""
    ds = _formal(lam, [1e-5, 1e-7, 1e-7], over)
    ds["block_fluctuation"] = ("eps", list(fluct))
    ds["pre_run_wall_s"] = ("eps", [1.5, 2.5, 3.5])
    ds.attrs.update(transient_rtol=0.02, transient_window=2500.0, t_transient=2e4)
    return ds


@pytest.mark.parametrize("lam, over, fluct, want", [
    # eps 60 unsettled, its block means scattering by 0.15 >= rtol 0.02: the rule cannot certify it
    ([1e-3, 1e-6, 1e-3], (1, 1, 0), (0.01, 0.01, 0.15), CANNOT),
    # the same row scattering less than rtol: a longer pre-run may certify it
    ([1e-3, 1e-6, 1e-3], (1, 1, 0), (0.01, 0.01, 0.005), NOT_YET),
    # a settled eps resolved above the bound differs whatever the other row
    ([1e-3, 1e-3, 1e-3], (1, 1, 0), (0.01, 0.01, 0.15), DIFFERS),
    # an unsettled row that may still settle outranks one that cannot
    ([1e-3, 1e-6, 1e-3], (1, 0, 0), (0.01, 0.005, 0.15), NOT_YET),
    # every row above the threshold settled and below: the scatter of a settled row does not matter
    ([1e-3, 1e-6, 2e-6], (0, 1, 1), (0.15, 0.15, 0.15), REPRODUCED),
])
def test_c26_cannot_be_reproduced_only_where_the_settling_rule_cannot_certify(lam, over, fluct, want):
    j = lyapunov.c26(PAPER["C26"], _formal_fluctuating(lam, over, fluct))
    assert j.verdict == want
    # the reason names every row the rule cannot certify, with its scatter and its pre-run's wall time (s)
    uncertifiable = over[2] == 0 and fluct[2] >= 0.02
    named = "at eps 60 (scatter 0.15, pre-run 3.5 s) omega's block means over 2500 time units scatter"
    assert (named in j.reason) == uncertifiable


def test_c26_without_a_recorded_fluctuation_an_unsettled_row_is_not_yet_computed():
    ds = _formal_fluctuating([1e-3, 1e-6, 1e-3], (1, 1, 0), (0.01, 0.01, 0.15)).drop_vars("block_fluctuation")
    j = lyapunov.c26(PAPER["C26"], ds)
    assert j.verdict == NOT_YET and j.reason == "transient not over at eps 60"


def _regimes(status, lam, thick, T=1e5):
    n = len(status)
    return xr.Dataset({"lambda_1": ("eps", lam), "stderr": ("eps", [1e-6] * n), "status": ("eps", status),
                       "transient_over": ("eps", [1] * n), "steady": ("eps", [1] * n), "T": ("eps", [T] * n),
                       "tau": ("eps", [10.0] * n), "curve_thickness": ("eps", thick)},
                      coords={"eps": np.geomspace(0.02, 0.5, n)})


@pytest.mark.parametrize("status, lam, thick, want", [
    (["regular", "regular", "converged", "converged"], [1e-6, 2e-6, 3e-4, 5e-4], [0.001] * 4, REPRODUCED),
    (["regular", "regular", "converged", "converged"], [1e-6, 2e-6, 3e-4, 5e-4], [0.05, 0.001, 0.001, 0.001], DIFFERS),
    (["capped", "regular", "converged", "converged"], [1e-4, 2e-6, 3e-4, 5e-4], [0.001] * 4, REPRODUCED),
    (["capped", "capped", "converged", "converged"], [1e-4, 2e-6, 3e-4, 5e-4], [0.001] * 4, NOT_YET),
    (["converged"] * 4, [1e-4, 2e-4, 3e-4, 5e-4], [0.001] * 4, NOT_YET),
    (["regular"] * 4, [1e-6] * 4, [0.001] * 4, NOT_YET),
])
def test_c27_route_to_chaos_near_eps_zero(status, lam, thick, want):
    assert lyapunov.c27(PAPER["C27"], _regimes(status, lam, thick)).verdict == want


def test_c27_counts_as_chaotic_only_rates_above_what_polynomial_growth_fakes():
    # converged rows with lambda_1 - 2 stderr > 0 but below 2 ln(T / tau) / T (1.84e-4 at T = 1e5): not chaotic
    rows = _regimes(["regular", "converged", "converged", "converged"], [1e-6, 1e-4, 1.5e-4, 5e-4], [0.001] * 4)
    j = lyapunov.c27(PAPER["C27"], rows)
    assert j.verdict == REPRODUCED and "chaotic (lambda_1 resolved above the polynomial rate) at eps 0.5;" in j.measured
    # the same rows over T = 1e4 (the fake rate 1.2e-3): none is chaotic
    assert lyapunov.c27(PAPER["C27"], _regimes(["regular", "converged", "converged", "converged"],
                                             [1e-6, 1e-4, 1.5e-4, 5e-4], [0.001] * 4, T=1e4)).verdict == NOT_YET


def _priced(status, lam, budget, wall=10.0):
    """_regimes (T = 1e5, tau = 10) whose rows record their rounds: ``wall`` s for T, rounds of 5e4."""
    rows = _regimes(status, lam, [0.001] * len(status))
    rows["rounds_wall_s"] = ("eps", [wall] * len(status))
    rows["round_length"] = ("eps", [5e4] * len(status))
    rows.attrs["resolve_budget_s"] = budget
    return rows


# rows converged at T = 1e5 but below the polynomial rate (1.84e-4): 1.5e-4 - 2e-6 needs T* = 1.3e5, one more
# round of 5e4 at 10 s per 1e5, 5 s per row
@pytest.mark.parametrize("status, lam, budget, want, text", [
    (["converged"] * 4, [1.5e-4] * 4, 10.0, CANNOT, "about 20 s more of their rounds"),
    (["converged"] * 4, [1.5e-4] * 4, 30.0, NOT_YET, "within the 30 s the run affords, but not run"),
    # eps 0.5 resolved chaotic: only the three rows below it are priced
    (["converged"] * 4, [1.5e-4] * 3 + [5e-4], 10.0, CANNOT, "about 15 s more"),
    # a row whose lambda_1 - 2 stderr is not positive: no horizon resolves it at the measured values
    (["converged"] * 4, [1.5e-4, 1e-6, 1.5e-4, 1.5e-4], 10.0, NOT_YET, "[1.3e+05, inf, 1.3e+05, 1.3e+05]"),
])
def test_c27_cannot_be_reproduced_when_resolving_the_rows_costs_more_than_the_run_affords(status, lam, budget, want,
                                                                                            text):
    j = lyapunov.c27(PAPER["C27"], _priced(status, lam, budget))
    assert j.verdict == want and text in j.reason
    assert ("above the 10 s the run affords (resolve_budget_s)" in j.reason) == (want == CANNOT)


def test_c27_resolving_cost_prices_whole_rounds_by_each_rows_rounds():
    rows = _priced(["converged"] * 4, [1.5e-4] * 4, 10.0)
    need, cost = lyapunov.resolving_cost(rows, np.array([True, True, False, False]))
    assert need == pytest.approx([1.3e5] * 2, rel=0.05) and cost == pytest.approx(2 * 10.0 / 1e5 * 5e4)
    assert math.isnan(lyapunov.resolving_cost(rows.drop_vars("rounds_wall_s"), np.ones(4, bool))[1])


def test_c27_with_chaos_down_to_the_smallest_row_computed_the_route_lies_below():
    rows = _priced(["elsewhere", "converged", "converged", "converged"], [math.nan, 5e-4, 5e-4, 5e-4], 10.0)
    j = lyapunov.c27(PAPER["C27"], rows)
    assert j.verdict == NOT_YET
    assert j.reason == ("no row below the first chaotic eps (0.0585) is computed here: a route, if any, lies below "
                        "the computed range")


def _audit(**over):
    a = dict(printed_max_abs_rel_change=0.9, derived_max_abs_rel_change=1e-12, d2_Omegadot_residual_with_Ic=1e-16,
             d2_Omegadot_residual_with_Ir=0.1, d3_n_differences=4, d3_differences="M[0,0]", d4_dL_dbeta="-a*m_r",
             d5_reference_energy_physical=0.0071, param_eps=0.1, d6_eps=np.array([2.0, 25.0]),
             d6_m_c=np.array([-1.0, -24.0]), d6_min_det_M=np.array([72.0, 1e7]))
    a.update(over)
    return A(**a)


@pytest.mark.parametrize("judge, over, want", [
    ("d1", {}, DIFFERS), ("d1", {"printed_max_abs_rel_change": 1e-9}, REPRODUCED),
    ("d2", {}, DIFFERS), ("d2", {"d2_Omegadot_residual_with_Ir": 1e-16}, REPRODUCED),
    ("d3", {}, DIFFERS), ("d3", {"d3_n_differences": 0}, REPRODUCED),
    ("d4", {}, DIFFERS), ("d4", {"d4_dL_dbeta": "0"}, REPRODUCED),
    ("d5", {}, DIFFERS), ("d5", {"d5_reference_energy_physical": 0.113}, REPRODUCED),
    ("d5", {"d5_reference_energy_physical": NAN}, NOT_YET),
    ("d6", {}, DIFFERS), ("d6", {"d6_m_c": np.array([0.5, 0.2])}, REPRODUCED),
])
def test_model_items(judge, over, want):
    assert judges.JUDGES[judge.upper()](PAPER[judge.upper()], _audit(**over)).verdict == want


def test_rows_are_listed_by_their_eps_and_no_row_never_reads_as_a_value():
    from sleighsim.claims.judges.lyapunov import at_eps

    assert at_eps([0.0, 0.05]) == "at eps 0, 0.05"
    assert at_eps([]) == "at no eps row"
    assert "none" not in at_eps(np.array([]))
