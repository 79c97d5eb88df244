"""The long run in windows: its per-window exponent is Benettin's, and the trend rule on each branch."""

import math

import numpy as np
import pytest

from sleighsim.analysis import windows
from sleighsim.chaos import benettin
from sleighsim.engine import integrators
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.precision import Precision

T_WIN = np.arange(10) * 1e5 + 5e4


@pytest.mark.parametrize("x, want", [
    (2000.0 + np.random.default_rng(1).normal(0, 5, 10), windows.SETTLED),             # flat, tight
    (2000.0 - 4e-4 * T_WIN + np.random.default_rng(2).normal(0, 5, 10), windows.DRIFTING),  # -160 over the last half
    (2000.0 + np.random.default_rng(3).normal(0, 80, 10), windows.UNDETERMINED),     # too noisy to tell
    (np.r_[np.full(7, np.nan), 2000.0, 2001.0, 1999.0], windows.UNDETERMINED),         # 3 finite windows
])
def test_trend_on_each_branch(x, want):
    out = windows.trend(T_WIN, x, rel_tol=0.02, sigma=3.0)
    assert out["verdict"] == want, out["reason"]
    assert out["reason"]


def test_trend_measures_the_slope_of_the_last_part_only():
    x = np.r_[np.linspace(3000, 2000, 5), np.full(5, 2000.0)] + np.r_[0, 0, 0, 0, 0, 1, -1, 1, -1, 0]
    out = windows.trend(T_WIN, x, rel_tol=0.02, sigma=3.0)
    assert out["n"] == 5 and abs(out["slope"]) < 1e-5 and out["verdict"] == windows.SETTLED
    assert "goes on" not in out["reason"]
    slow = 2000.0 - 2e-5 * T_WIN + np.r_[0, 0, 0, 0, 0, 0.1, -0.1, 0.1, -0.1, 0]  # -8 over the last half: resolved
    out = windows.trend(T_WIN, slow, rel_tol=0.02, sigma=3.0)
    assert out["verdict"] == windows.SETTLED and "goes on" in out["reason"]
    assert windows.trend(T_WIN, x, rel_tol=0.02, sigma=3.0, last_fraction=1.0)["verdict"] == windows.DRIFTING
    with pytest.raises(ValueError):
        windows.trend(T_WIN, x[:-1], rel_tol=0.02, sigma=3.0)
    with pytest.raises(ValueError):
        windows.trend(T_WIN, x, rel_tol=0.0, sigma=3.0)
    with pytest.raises(ValueError):
        windows.trend(T_WIN, x, rel_tol=0.02, sigma=3.0, min_points=2)


def test_a_drift_above_the_tolerance_must_be_resolved_above_it():
    """|change| above the tolerance but within 3 standard errors of it: undetermined, not drifting."""
    base = 2000.0 - 1.2e-4 * T_WIN  # -48 over the last half, against a tolerance of 0.02 x 1910 = 38.2
    wiggle = np.r_[np.zeros(5), 1.0, -1.0, 0.0, -1.0, 1.0]  # orthogonal to a line: the slope stays exact
    out = windows.trend(T_WIN, base + 10.0 * wiggle, rel_tol=0.02, sigma=3.0)  # change -48 +- 14.6
    assert out["change"] == pytest.approx(-48.0)
    assert abs(out["change"]) > 0.02 * abs(out["mean"]) and out["verdict"] == windows.UNDETERMINED, out["reason"]
    out = windows.trend(T_WIN, base + 0.5 * wiggle, rel_tol=0.02, sigma=3.0)  # change -48 +- 0.73
    assert out["verdict"] == windows.DRIFTING, out["reason"]


def test_windowed_orbit_gives_benettins_exponent_and_the_sampled_component():
    p = Params.paper(eps=0.3)
    y0 = state_at_label([0.0, 0.1, 1.0, 0.0], p, 1.0)
    ta, _ = integrators.sleigh_tangent(1, 1e-14, True)
    integrators.set_pars(ta, p)
    got = list(windows.windowed_orbit(ta, 4, y0, n_windows=4, window=50.0, tau=5.0, component=1, seed=7))
    assert [w["index"] for w in got] == [0, 1, 2, 3] and got[1]["t_start"] == 50.0
    assert all(w["x"].size == 10 and w["x"][-1] == w["state"][1] for w in got)
    assert np.allclose(got[2]["t"], 100.0 + 5.0 * np.arange(1, 11))
    ref = benettin.benettin(ta, 4, 1, y0, t_align=0.0, T=200.0, tau=5.0, n_blocks=4, seed=7)
    lam = np.mean([w["lambda_1"] for w in got])
    assert math.isclose(lam, float(ref["exponents"][0]), rel_tol=1e-8, abs_tol=1e-12)
    # each window's exponent is its own block of the same accumulation
    assert np.allclose([w["lambda_1"] for w in got], ref["block_estimates"][:, 0], rtol=1e-7, atol=1e-12)
    with pytest.raises(ValueError, match="multiple"):
        next(windows.windowed_orbit(ta, 4, y0, n_windows=2, window=12.0, tau=5.0, component=1))


def test_windowed_orbit_in_long_double_matches_double_where_both_are_accurate():
    # a short spike-free stretch: the long-double run (what the drift run uses with long_double)
    # gives the same windows as the double one, its state kept in long double
    p = Params.paper(eps=0.3)
    y0 = state_at_label([0.0, 0.1, 1.0, 0.0], p, 1.0)
    runs = {}
    for ld in (False, True):
        ta, _ = integrators.sleigh_tangent(1, 1.0842021724855044e-19 if ld else 2.0**-52, True,
                                   Precision.LONG_DOUBLE if ld else Precision.DOUBLE)
        integrators.set_pars(ta, p)
        runs[ld] = list(windows.windowed_orbit(ta, 4, y0, n_windows=3, window=50.0, tau=5.0, component=1, seed=7))
        assert ta.state.dtype == (np.longdouble if ld else np.float64)
        assert all(w["state"].dtype == ta.state.dtype for w in runs[ld])  # the windows keep the precision
    lam = {ld: np.array([w["lambda_1"] for w in r]) for ld, r in runs.items()}
    assert np.abs(lam[False]).max() > 1e-3  # the vector changes length: the comparison is not vacuous
    # measured: the window exponents agree to 5e-11 / time (log growth 2.5e-9 over 50: double's rounding)
    np.testing.assert_allclose(lam[True], lam[False], rtol=0, atol=2e-10)
    # and the end states to 5e-9 (double's global error at t = 150)
    np.testing.assert_allclose(np.asarray(runs[True][-1]["state"], float), runs[False][-1]["state"], rtol=5e-8)


@pytest.mark.parametrize("precision", [Precision.DOUBLE, Precision.LONG_DOUBLE])
def test_drift_scene_at_smoke_size_in_each_precision(precision):
    from conftest import smoke_config

    from sleighsim.scenes.catalog import scene_config
    from sleighsim.scenes.drift import drift_windows

    config = smoke_config()
    cfg = {**scene_config(config, "main_drift"), "T": 100.0, "window": 50.0, "precision": precision}
    ds = drift_windows(cfg, "main_drift")
    assert ds.sizes["window"] == 2 and np.all(np.isfinite(ds.lambda_1.values))
    # the precision is read from the integrator's state, not from the config
    long_double = precision is Precision.LONG_DOUBLE
    assert ds.attrs["precision"] == ("long double (epsilon 1.1e-19)" if long_double else "double")
    assert ds.attrs["tol"] == (2.0**-63 if long_double else cfg["tol"])
    assert ds.lambda_1.attrs["long_name"].endswith(f", {ds.attrs['precision']})")
