"""The trigger law (sleighsim.scenes.trigger) and C04's cause test built on it: the fit on each
branch, the level that reproduces a given first spike, and the cause verdict on each branch."""

import math

import numpy as np
import pytest
import xarray as xr

from sleighsim.outputs import causes
from sleighsim.scenes import trigger


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
    same tolerance in double and long double gives the same first spike; the machine-epsilon run
    is kept outside the fit."""
    cfg = dict(params={"eps": 0.2, "b": 1.0, "K2": 1.2}, y0=[0.0, 0.1, 1.0, 0.0], t_end=2000.0, dt=1.0, t_min=250.0,
               spike_factor=1.8, tols={"double": [1e-10, 1e-12, 2.0**-52], "long double": [1e-12]})
    ds = trigger.trigger_law(cfg, "t")
    assert ds.in_fit.values.tolist() == [1, 1, 0, 1]
    assert np.all(np.isfinite(ds.first_spike.values))
    assert ds.first_spike.values[1] == ds.first_spike.values[3]  # tol 1e-12 in both arithmetics
    assert ds.attrs["law_n_fit"] == 3 and ds.attrs["energy_max_rel_drift"] < 1e-6
