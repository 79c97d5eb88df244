"""Where an escape lands (sleighsim.analysis.fate): spike peaks refined on section data to far below the
crossings' spacing, with an error that bounds the truth, and the landed train's class on each branch."""

import math

import numpy as np
import pytest

from sleighsim.analysis import fate

PERIOD, TURN = 2063.1388, 1.98  # a slow spike period and the section's crossing spacing (time units)


def section_data(peaks, drift=0.0):
    """Crossings every TURN (their phase against the peaks drifting) of an envelope |Omega| with a smooth peak
    of width 12 at each of ``peaks``; Omega negative, as on some of the sleigh's tori."""
    t = np.arange(0.37, peaks[-1] + 200.0, TURN) + drift * np.sin(np.arange(0.37, peaks[-1] + 200.0, TURN))
    env = 0.01 + sum(0.07 / np.cosh(np.clip((t - p) / 12.0, -50, 50)) ** 2 for p in peaks)
    return t, np.stack([0.01 * np.ones_like(t), -env, 3.1 * np.ones_like(t)], axis=1)


def test_refined_peaks_find_the_envelope_peak_far_below_the_crossing_spacing():
    peaks = 300.0 + PERIOD * np.arange(5) + np.array([0.0, 0.3, 0.7, 1.1, 1.6])
    t, X = section_data(peaks)
    coarse = peaks + np.array([1.0, -0.8, 0.4, 0.9, -1.0])  # the transient rule's, off by a sample or so
    times, errors = fate.refined_peaks(t, X, coarse, 25.0)
    assert times.size == 5
    assert np.max(np.abs(times - peaks)) < 1e-3 < TURN
    assert np.all(np.abs(times - peaks) <= errors + 1e-9)  # the coarser stencil's difference bounds the error


def test_a_spike_whose_stencil_runs_off_the_record_or_across_a_gap_is_dropped():
    peaks = np.array([300.0, 300.0 + PERIOD])
    t, X = section_data(peaks)
    keep = (t < 300.0 + 4 * TURN) | (t > 340.0)  # a gap of 30 (> half_width) inside the first peak's stencil
    times, _ = fate.refined_peaks(t[keep], X[keep], peaks, 25.0)
    assert times.size == 1 and times[0] == pytest.approx(peaks[1], abs=1e-3)
    times, _ = fate.refined_peaks(t[t < peaks[1] + 3 * TURN], X[t < peaks[1] + 3 * TURN], peaks, 25.0)
    assert times.size == 1 and times[0] == pytest.approx(peaks[0], abs=1e-3)
    assert fate.refined_peaks(t, X, [peaks[1] + 1000.0], 25.0)[0].size == 0  # no crossing near it


@pytest.mark.parametrize("offsets, want, approach", [
    ([0, 0, 0, 0, 0, 0, 0], fate.PERIODIC, 0),            # a strict train: intervals agree within their resolution
    ([0, 0.05, -0.05, 0.05, -0.05, 0.05, -0.05], fate.NOT_PERIODIC, 0),  # 0.05 apart, resolved to 1e-5
    ([40.0, 0, 0, 0, 0, 0, 0], fate.PERIODIC, 1),          # one interval of approach, then strict
    ([60.0, 20.0, 0, 0, 0, 0, 0], fate.PERIODIC, 2),       # two
    ([0, 0, 0, 0, 0, 0, 30.0], fate.NOT_PERIODIC, 0),      # a late change is no approach
    ([0, 0, 0], fate.UNDETERMINED, 0),                     # too few intervals to say
])
def test_the_train_class_and_its_approach_on_each_branch(offsets, want, approach):
    n = len(offsets) - 1
    times = 500.0 + PERIOD * np.arange(n + 1) + np.array(offsets)
    got = fate.train(times, np.full(n + 1, 1e-5), min_intervals=3, factor=3.0)
    assert got["class"] == want and got["approach"] == approach and got["cycles"] == n - approach
    assert got["interval"] == pytest.approx(PERIOD, abs=0.1 if want == fate.PERIODIC else 10)
    assert got["resolution"] == pytest.approx(math.sqrt(2) * 1e-5)


def test_a_train_without_intervals_is_undetermined():
    got = fate.train([700.0], [1e-5], min_intervals=3, factor=3.0)
    assert got["class"] == fate.UNDETERMINED and got["cycles"] == 0 and math.isnan(got["interval"])
