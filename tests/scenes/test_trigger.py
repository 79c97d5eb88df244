"""The trigger law (sleighsim.scenes.trigger) and C04's cause test built on it: the fit on each
branch, the level that reproduces a given first spike, and the cause verdict on each branch."""

import math

import numpy as np
import pytest
import xarray as xr

from sleighsim.claims import causes
from sleighsim.precision import Precision, parsed
from sleighsim.scenes import trigger

D, LD, Q = Precision.DOUBLE, Precision.LONG_DOUBLE, Precision.QUAD


def test_fit_recovers_a_known_law_and_needs_three_runs():
    x = np.array([-8.0, -10.0, -12.0, -14.0, -16.0])
    law = trigger.fit(x, 5000.0 - 30.0 * x + np.array([1.0, -1.0, 0.5, -0.5, 0.0]))
    assert law["slope"] == pytest.approx(-30.0, abs=0.3) and law["n_fit"] == 5
    assert 0 < law["slope_stderr"] < 1
    assert trigger.level_for(5000.0 + 30.0 * 20, law) == pytest.approx(-20.0, abs=0.5)
    short = trigger.fit(x[:3], [5240.0, math.nan, 5360.0])
    assert short["n_fit"] == 2 and math.isnan(short["slope"]) and math.isnan(trigger.level_for(8700.0, short))


def _law(slope, intercept, n=6):
    return xr.Dataset({"tol": ("run", [1e-8, 1e-12, 1e-16]), "in_fit": ("run", [1, 1, 1])},
                      attrs=dict(law_slope=slope, law_slope_stderr=1.0, law_intercept=intercept, law_n_fit=n))


@pytest.mark.parametrize("slope, intercept, explained", [
    (-28.0, 5100.0, False),   # 8700 needs 10^-129: no arithmetic injects so small an error
    (-300.0, 5100.0, True),   # 8700 at 10^-12: within reach
    (math.nan, math.nan, False),
])
def test_the_injected_error_explains_a_first_spike_only_at_a_reachable_level(slope, intercept, explained):
    name, ok, text = causes._trigger(_law(slope, intercept), 8700.0)
    assert name.startswith("the injected error") and ok is explained
    assert ("10^" in text) == math.isfinite(slope)


def test_trigger_scene_on_a_short_run():
    """eps = 0.2 (transients 4x shorter than at 0.1): both arithmetics reach the first spike; the
    same tolerance in double and long double gives the same first spike, fitted once (in long
    double); the machine-epsilon run is kept outside the fit."""
    cfg = dict(params={"eps": 0.2, "b": 1.0, "K2": 1.2}, y0=[0.0, 0.1, 1.0, 0.0], t_end=2000.0, dt=1.0, t_min=250.0,
               spike_factor=1.8, tols={"double": [1e-8, 1e-10, 1e-12, 2.0**-52], "long double": [1e-12]})
    ds = trigger.trigger_law(parsed(cfg), "t")
    assert ds.in_fit.values.tolist() == [1, 1, 0, 0, 1]
    assert np.all(np.isfinite(ds.first_spike.values))
    assert ds.first_spike.values[2] == ds.first_spike.values[4]  # tol 1e-12 in both arithmetics
    assert ds.attrs["law_n_fit"] == 3 and ds.attrs["energy_max_rel_drift"] < 1e-6


@pytest.mark.parametrize("runs, want", [
    ([(D, 1e-12), (LD, 1e-12), (D, 1e-10)], [0, 1, 1]),
    ([(LD, 1e-12), (D, 1e-12), (Q, 1e-12)], [0, 0, 1]),  # the finest, in any order
    ([(D, 1e-15), (LD, 1e-15)], [0, 1]),  # 1e-15 is within 100x of double's rounding
    ([(D, 2.0**-52), (LD, 1e-19)], [0, 0]),  # each at its own rounding
])
def test_a_tolerance_run_in_several_arithmetics_is_fitted_once_in_the_finest(runs, want):
    assert trigger.fitted(runs).astype(int).tolist() == want


def test_the_law_counts_each_tolerance_once(monkeypatch):
    """The paper config's tolerances (1e-12 in double and in long double) with a made-up first spike
    5000 - 30 log10(tol) in long double and 200 later in double: the law is exact, from 9 distinct
    tolerances, and its fit rule says how the runs were chosen."""
    def spikes(params, y0, precision, tol, cfg, scene):
        first = 5000.0 - 30.0 * math.log10(tol) + (200.0 if precision == "double" and tol == 1e-12 else 0.0)
        return first, first + 100.0, 0.0, 0.0

    monkeypatch.setattr(trigger, "spikes_after", spikes)
    cfg = {"params": {"eps": 0.1, "b": 1.0, "K2": 1.1}, "y0": [0.0, 0.1, 1.0, 0.0], "t_end": 1.0, "dt": 1.0,
           "t_min": 0.0, "spike_factor": 1.8, "tols": {"double": [1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 2.0**-52],
                                                      "long double": [1e-12, 1e-13, 1e-14, 1e-15, 1e-16, 2.0**-63]}}
    ds = trigger.trigger_law(parsed(cfg), "t")
    assert ds.attrs["law_n_fit"] == 9 == int(ds.in_fit.sum())
    assert ds.attrs["law_slope"] == pytest.approx(-30.0) and ds.attrs["law_intercept"] == pytest.approx(5000.0)
    assert "one per distinct tolerance" in ds.attrs["fit_rule"] and "least squares" in ds.attrs["fit_rule"].lower()
