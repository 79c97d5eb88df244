"""The paper-setup inference's decision rules on small synthetic arrays (sleighsim.scenes.paper_setup)."""

import math

import numpy as np
import pytest
import xarray as xr

from sleighsim.scenes import paper_setup as ps
from sleighsim.scenes import setup_predictions as sp


@pytest.mark.parametrize("text, sigma", [("0.241", 5e-4), ("2.9e-4", 5e-6), ("8700", 50.0), ("1", 0.5),
                                         ("-2.2e-4", 5e-6), ("0.02", 5e-3)])
def test_sigma_is_half_the_last_significant_digit(text, sigma):
    assert ps.spelling_sigma(text) == pytest.approx(sigma)


def test_interpolation_never_extrapolates_nor_crosses_an_undetermined_value():
    out = sp.interp_inside([1.0, 2.0, 3.0], [10.0, 20.0, np.nan], [0.5, 1.5, 2.0, 2.5, 3.5])
    assert math.isnan(out[0]) and out[1] == 15.0 and out[2] == 20.0
    assert math.isnan(out[3]) and math.isnan(out[4])


def test_psd_map_converts_units_and_folds_about_nyquist():
    assert sp.psd_map([0.5], 2 * math.pi, math.nan)[0] == pytest.approx(math.pi)
    assert sp.psd_map([0.9], 1.0, 1.0)[0] == pytest.approx(0.1)  # fs = 1: 0.9 aliases to 0.1


def test_no_sampling_interval_leaves_the_two_units_unsampled_and_each_interval_adds_both():
    none = sp.psd_conventions(np.geomspace(1e-3, 1e-3, 0))
    assert [c[:2] for c in none] == [("cycles/time", 1.0), ("rad/time", 2 * math.pi)]
    assert all(math.isnan(c[2]) for c in none) and len(sp.psd_conventions([0.5, 1.0])) == 6


def _blocks():
    """Deviance blocks: K2 (2) x integrator (2), K2 x psd (2), energy (2), lyapunov (1)."""
    A = np.array([[5.0, np.inf], [1.0, 3.0]])
    P = np.array([[0.0, 2.0], [4.0, 2.5]])
    return A, P, np.array([1.0, 0.0]), np.array([0.0])


def test_best_setup_is_the_least_total_deviance_and_undetermined_setups_are_not_ranked():
    A, P, E, L = _blocks()
    top = ps.top_setups(A, P, E, L, n=20)
    assert top[0] == (3.5, (1, 0, 1, 1, 0))  # 1 + 2.5 + 0 + 0
    assert all(math.isfinite(v) for v, _ in top)
    assert ps.n_ranked(A, P, E, L) == len(top) == 12  # K2 0: 1 x 2; K2 1: 2 x 2; times 2 energies


def test_profiles_give_each_candidates_best_completion_and_the_gap_to_the_runner_up():
    A, P, E, L = _blocks()
    prof = ps.profiles(A, P, E, L)
    assert prof["K2"].tolist() == [5.0, 3.5]
    assert prof["integrator"].tolist() == [3.5, 5.5]
    coords = {"K2": [1.1, 1.2], "integrator": ["heyoka", "rk"], "psd": ["c", "r"], "energy": ["a", "b"],
              "lyapunov": ["x"]}
    gaps = ps.element_gaps(prof, coords, {"K2": 1, "integrator": 0, "psd": 1, "energy": 1, "lyapunov": 0})
    assert gaps["best_K2"] == 1.2 and gaps["gap_K2"] == 1.5 and gaps["runner_up_integrator"] == "rk"
    assert gaps["runner_up_lyapunov"] == "none ranked" and math.isnan(gaps["gap_lyapunov"])


def test_the_k2_interval_widens_with_the_misfit_and_never_narrows_below_a_deviance_of_1():
    K2, prof = [1.0, 1.1, 1.2, 1.3, 1.4], [50.0, 9.0, 5.0, 5.5, 30.0]
    fit = ps.misfit_interval(prof, K2, [0.5, -0.5, 0.2, 0.1, 0.3, -0.2])  # chi-square 0.68 on 1 dof: scale 1
    assert fit == {"misfit_scale": 1.0, "best_K2_low_scaled": 1.2, "best_K2_high_scaled": 1.3}
    bad = ps.misfit_interval(prof, K2, [3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])  # chi-square 9 on 2 dof: scale 4.5
    assert bad == {"misfit_scale": 4.5, "best_K2_low_scaled": 1.1, "best_K2_high_scaled": 1.3}


def test_a_number_swept_against_k2_and_integrator_adds_the_solvers_shift_at_the_baseline():
    k2 = xr.Dataset({"first_spike": ("K2", [100.0, 80.0])}, coords={"K2": [1.0, 1.2]})
    err = xr.Dataset({"first_spike": ("rtol", [70.0, np.nan])}, coords={"rtol": [1e-6, 1e-3]},
                     attrs={"param_K2": 1.1})
    pred = sp.spike_observable(k2, err, "first_spike", [1.0, 1.2])
    assert pred.values[:, 0].tolist() == [100.0, 80.0]  # heyoka: the sweep
    assert pred.values[:, 1].tolist() == pytest.approx([80.0, 60.0])  # + (70 - 90)
    assert np.isnan(pred.values[:, 2]).all()  # no spike at rtol 1e-3: not determined


def _start_inputs(T1_paper):
    paper = {"D5": {"label": 0.1}, "C08": {"T1": T1_paper, "_text": {"T1": f"{T1_paper:.3f}"}}}
    d = {"model": xr.Dataset(attrs={"d5_normalisation_names": "a | b", "d5_normalisation_values": [0.025, 0.4]}),
         "hierarchy": xr.Dataset(attrs={"T1_u2": 6.0, "T1_u2_uncertainty": 1e-6})}
    return paper, d


def test_the_start_is_the_stated_state_when_t1_is_its_own_and_a_rescaled_one_when_t1_scales():
    paper, d = _start_inputs(6.0)
    out = ps.start_test(paper, d)
    assert out["start"] == ps.STATED and out["start_T1"].tolist() == [6.0, 3.0, 12.0]  # sqrt(0.25), sqrt(4)
    assert out["start_T1_residual"][0] == 0.0 and abs(out["start_T1_residual"][1]) > 1e3
    paper, d = _start_inputs(12.0)  # the paper's T1 is what a start rescaled under "b" gives
    assert ps.start_test(paper, d)["start"] == "rescaled to E = 0.1 under b"
