"""The transients scene's comparison of aligned curves within and across energy levels."""

import warnings

import numpy as np

from sleighsim.scenes.transients import _level_distances


def test_a_level_without_a_run_of_the_main_group_gives_nan_without_a_warning():
    """Level 1 holds only a run of another group: no across-levels mean exists, NaN and no RuntimeWarning."""
    curves = np.array([[1.0, 2.0, 3.0], [1.1, 2.1, 3.1], [5.0, 6.0, 7.0]])
    level, group, ok = np.array([0, 0, 1]), np.array([0, 0, 1]), np.ones(3, bool)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        attrs, n_groups, main, scale = _level_distances(curves, curves, level, ok, group, [1.0, 2.0], 2)
    assert main == 0 and n_groups == [1, 1] and scale == np.mean(np.abs(curves[:2]))
    assert np.isnan(attrs["across_levels_distance_main_group_unscaled"])
    assert np.isclose(attrs["level0_distance_main_group"], 0.1 / scale)
