"""The trigger law as measured (sleighsim.analysis.trigger_law): the saturation test on each branch, the ranges
of adjacent levels (per arithmetic, split by span, bridged), and the local slopes with their pooled error."""

import math

import numpy as np
import pytest

from sleighsim.analysis import trigger_law as tl

D, LD = "double", "long double"


@pytest.mark.parametrize("first, drift, want", [
    ([5638.1, 5638.3], [6.8e-15, 5.7e-15], [1, 1]),    # same spike, same drift: both saturated
    ([5397.7, 5394.7], [1.7e-9, 9.6e-10], [0, 0]),     # drifts alike, spikes 3 apart: not the same spike
    ([5580.4, 5580.6], [8.3e-14, 6.8e-15], [0, 0]),    # same spike, drift cut twelvefold: the tolerance acts
    ([math.nan, 5580.6], [6.8e-15, 6.8e-15], [0, 0]),  # no first spike is the same as none
])
def test_a_pair_is_saturated_only_when_spike_and_drift_both_agree(first, drift, want):
    got = tl.saturated([LD, LD], [1e-15, 1e-16], first, drift, spike=1.0, drift_factor=2.0)
    assert got.astype(int).tolist() == want


def test_saturation_compares_adjacent_tolerances_of_one_arithmetic_only():
    """Runs given in any order; the same first spike and drift in another arithmetic, or two tolerances apart
    within one, is no pair."""
    arith = [LD, D, LD, LD]
    tol = [1e-16, 1e-16, 1e-14, 1e-15]
    first = [100.0, 100.0, 100.2, 300.0]
    drift = [1e-15, 1e-15, 1e-15, 1e-13]
    assert not tl.saturated(arith, tol, first, drift, spike=1.0, drift_factor=2.0).any()
    first[3] = 100.1  # now 1e-14, 1e-15 and 1e-16 of long double agree pairwise
    drift[3] = 1e-15
    assert tl.saturated(arith, tol, first, drift, spike=1.0, drift_factor=2.0).astype(int).tolist() == [1, 0, 1, 1]


@pytest.mark.parametrize("arith, x, decades, want", [
    ([D, D, D, LD, LD], [-8, -9, -10, -12, -14], 4.0,
     [(D, [0, 1, 2]), (f"{D} -> {LD}", [2, 3]), (LD, [3, 4])]),
    (["quad"] * 5, [-18, -20, -22, -24, -26], 4.0,  # split by span, bridged within the arithmetic
     [("quad", [0, 1, 2]), ("quad", [2, 3]), ("quad", [3, 4])]),
    (["quad"] * 7, [-18, -20, -22, -24, -26, -28, -30], 4.0,  # a lone last level joins its neighbour
     [("quad", [0, 1, 2]), ("quad", [2, 3]), ("quad", [3, 4, 5, 6])]),
    ([D, LD, LD], [-8, -12, -14], 4.0,  # an arithmetic with one run: only the bridge reaches it
     [(D, [0]), (f"{D} -> {LD}", [0, 1]), (LD, [1, 2])]),
])
def test_ranges_hold_adjacent_levels_per_arithmetic_and_bridge_them(arith, x, decades, want):
    got = [(label, pos.tolist()) for label, pos in tl.ranges(arith, x, decades)]
    assert got == want


def test_slopes_recover_local_laws_with_the_pooled_scatter():
    """Two arithmetics with different exact slopes plus a known zero-mean wiggle: each range's slope, the bridge
    between them, and the standard error from the scatter pooled over the ranges with residuals."""
    x = np.array([-8.0, -9.0, -10.0, -11.0, -12.0, -13.0, -14.0])
    y = np.where(x >= -11, 5000 - 40 * (x + 8), 5120 - 80 * (x + 11)) + np.array([3, -3, -3, 3, 2, -4, 2])
    out = tl.slopes([D] * 4 + [LD] * 3, x, y, 4.0)
    r = {o["label"]: o for o in out["ranges"]}
    assert r[D]["slope"] == pytest.approx(-40.0, abs=4) and r[LD]["slope"] == pytest.approx(-80.0, abs=4)
    assert r[f"{D} -> {LD}"]["n"] == 2 and r[D]["tol_max"] == pytest.approx(1e-8)
    assert out["dof"] == 3 and out["scatter"] > 0
    assert r[D]["slope_stderr"] == pytest.approx(out["scatter"] / math.sqrt(5.0))


def test_slopes_without_a_residual_have_no_error():
    out = tl.slopes([D, D], [-8.0, -9.0], [5000.0, 5040.0], 4.0)
    assert out["ranges"][0]["slope"] == pytest.approx(-40.0) and math.isnan(out["ranges"][0]["slope_stderr"])
    assert out["dof"] == 0 and math.isnan(out["scatter"])
    assert tl.slopes([D], [-8.0], [5000.0], 4.0)["ranges"] == []
