"""Frequency analysis (sleighsim.chaos.frequency: leading_frequency, window_frequencies, drift) on
synthetic signals. Its use as a chaos indicator: test_chaos_frequency.py; in the chaos verdict:
test_verdict.py."""

import math

import numpy as np
import pytest

from sleighsim.chaos import frequency as fq


def _torus(T, dt):
    """Three lines at 0.1, 0.1 sqrt(2) and their sum: a 2-torus."""
    f1, f2 = 0.1, 0.1 * math.sqrt(2)
    t = np.arange(0.0, T, dt)
    return (np.cos(2 * math.pi * f1 * t) + 0.4 * np.cos(2 * math.pi * f2 * t + 0.3)
            + 0.1 * np.cos(2 * math.pi * (f1 + f2) * t))


def test_leading_frequency_recovers_a_quasi_periodic_line_and_follows_the_band():
    x = _torus(4000.0, 0.25)
    assert fq.leading_frequency(x, 0.25) == pytest.approx(0.1, rel=1e-9)
    assert fq.leading_frequency(x, 0.25, band=(0.12, 0.2)) == pytest.approx(0.1 * math.sqrt(2), rel=1e-8)
    # a band that holds only the flank of a line: no local maximum inside, no frequency
    assert math.isnan(fq.leading_frequency(x, 0.25, band=(0.101, 0.12)))
    with pytest.raises(ValueError, match="no DFT bin"):
        fq.leading_frequency(x, 0.25, band=(0.1001, 0.10011))
    # a line below the first bin is not resolved from zero frequency
    t = np.arange(4000) * 0.25
    assert math.isnan(fq.leading_frequency(np.cos(2 * math.pi * 0.3 / 1000.0 * t), 0.25))
    with pytest.raises(ValueError, match="non-finite"):
        fq.leading_frequency(np.r_[x[:100], np.nan], 0.25)
    with pytest.raises(ValueError, match="dt"):
        fq.leading_frequency(x, 0.0)
    for bad in (0, 2.5):
        with pytest.raises(ValueError, match="n_windows"):
            fq.window_frequencies(x, 0.25, bad)


def test_refined_frequency_reaches_the_stated_precision():
    f = 0.1 * math.sqrt(2)
    for T in (2000.0, 32000.0):
        t = np.arange(0.0, T, 0.25)
        assert abs(fq.leading_frequency(np.cos(2 * math.pi * f * t + 0.3), 0.25) / f - 1) < fq.PRECISION


def test_drift_converges_on_a_torus_and_not_on_a_wandering_frequency():
    rng = np.random.default_rng(3)
    torus = fq.drift(_torus(16000.0, 0.25), 0.25)
    assert list(torus["splits"]) == [2, 4, 8, 16] and torus["slope"] + 3 * torus["slope_err"] < -2.0
    assert torus["f_ref"] == pytest.approx(0.1, rel=1e-6)
    # a phase diffusing like a random walk: the window frequency scatters like W^-1/2
    dt, T = 0.25, 16000.0
    n = int(T / dt)
    phase = 2 * math.pi * 0.1 * dt * np.arange(n) + np.cumsum(rng.normal(scale=0.02, size=n))
    wander = fq.drift(np.cos(phase), dt)
    assert wander["slope"] + 3 * wander["slope_err"] > -1.0
    assert -1.2 < wander["slope"] < 0.2
    # windows shorter than min_cycles periods are left out
    few = fq.drift(_torus(1000.0, 0.25), 0.25, min_cycles=15.0)
    assert list(few["splits"]) == [2, 4] and few["W"][-1] == pytest.approx(250.0)
    assert math.isnan(few["slope"])  # one split of at least MIN_WINDOWS windows: no exponent
    none = fq.drift(_torus(1000.0, 0.25), 0.25, min_cycles=60.0)
    assert none["splits"].size == 0 and math.isnan(none["slope"]) and math.isnan(none["f"])
    with pytest.raises(ValueError, match="splits"):
        fq.drift(_torus(1000.0, 0.25), 0.25, splits=(1, 4))
    with pytest.raises(ValueError, match="splits"):
        fq.drift(_torus(1000.0, 0.25), 0.25, splits=())
    with pytest.raises(ValueError, match="min_cycles"):
        fq.drift(_torus(1000.0, 0.25), 0.25, min_cycles=0.0)


def test_drift_leaves_out_a_split_with_a_window_without_the_line():
    # the line at 0.1 stops half way (0.3 from then on, outside the band around f_ref = 0.1): the
    # split into 2 has a window without it; the finer splits' first halves hold it, their second
    # halves not, so only splits whose every window has the line remain
    t = np.arange(0.0, 8000.0, 0.25)
    x = np.where(t < 4000.0, np.cos(2 * math.pi * 0.1 * t), 0.0) + 0.01 * np.cos(2 * math.pi * 0.3 * t)
    d = fq.drift(x, 0.25, splits=(2, 4, 8, 16))
    assert d["splits"].size == 0 and math.isnan(d["slope"])
    # no line anywhere (white noise has no stable leading line, but f_ref exists): spreads are large
    noise = np.random.default_rng(0).normal(size=t.size)
    dn = fq.drift(noise, 0.25, splits=(2, 4, 8, 16), min_cycles=1.0)
    assert np.all(dn["D"] > 1e-3)


def test_the_refined_frequency_does_not_depend_on_the_number_of_blas_threads():
    """A sum in BLAS (np.dot) over 8e4 samples came out differently with one thread and with two, and
    a torus's convergence exponent followed the cores the run was pinned to; the refinement sums in
    numpy's own order."""
    import os
    import subprocess
    import sys

    code = ("import math, numpy as np; from sleighsim.chaos.frequency import leading_frequency; "
            "t = np.arange(0.0, 2e4, 0.25); "
            "x = np.cos(2 * math.pi * 0.1414 * t) + 0.3 * np.cos(2 * math.pi * 0.031 * t + 1.0); "
            "print(repr(leading_frequency(x, 0.25)))")
    out = {n: subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                             env={**os.environ, "OPENBLAS_NUM_THREADS": n, "OMP_NUM_THREADS": n}).stdout
           for n in ("1", "2")}
    assert out["1"] and out["1"] == out["2"], out


@pytest.mark.parametrize("splits, least, ok", [([4, 2], 1, [2, 4]), ([2], 1, [2]), ([2], 2, None), ([2, 2, 4], 1, None),
                                               ([1, 2], 1, None), ([2.5, 4], 1, None), (["a"], 1, None), ([], 1, None)])
def test_one_check_of_window_counts_serves_frequency_analysis_and_birkhoff(splits, least, ok):
    """chaos.common.check_splits (frequency analysis asks one count, Birkhoff two): sorted, distinct, >= 2."""
    from sleighsim.chaos.common import check_splits

    if ok is None:
        with pytest.raises(ValueError, match="splits"):
            check_splits(splits, least)
    else:
        assert check_splits(splits, least) == ok
