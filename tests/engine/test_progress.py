"""Progress of long kernels (sleighsim.engine.progress): a line every EVERY seconds while a kernel runs, read from
the times it writes, none for a short one; the double-double lanes report while they run (their kernels hold
no GIL) and give the same orbits bit for bit."""

import logging
import time

import numpy as np
import pytest

from sleighsim.engine import progress
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE


def test_a_line_reports_the_lane_furthest_behind_and_the_time_left(caplog):
    reached, ends = np.zeros(2), np.array([10.0, 40.0])

    def run():
        for k in range(1, 5):
            reached[:] = (5.0 * k, 5.0 * k)  # lane 1 furthest behind: 5 k of 40
            time.sleep(0.15)
        return "done"

    with caplog.at_level(logging.INFO, logger="sleighsim"):
        assert progress.watched(run, reached, ends, "lanes", every=0.1) == "done"
    lines = [r.getMessage() for r in caplog.records]
    assert len(lines) >= 3 and all(m.startswith("lanes: ") for m in lines)
    assert "t = 20 of 40)" in lines[-1] and "s left" in lines[-1]
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="sleighsim"):
        progress.watched(lambda: None, reached, ends, "lanes", every=5.0)
    assert not caplog.records  # a kernel that ends sooner says nothing


def test_double_double_lanes_report_while_they_run_and_keep_their_orbits(caplog, monkeypatch):
    """Two lanes over 3000 time units (about a second): with a line every 0.02 s, several lines arrive while the
    kernel runs (it releases the GIL); the orbits are those of a run without lines."""
    p = Params.paper(eps=0.1, K2=1.1)
    y = np.tile(np.array(REFERENCE_STATE), (2, 1))
    y[1, 0] += 1e-3
    grid = np.linspace(0.0, 3000.0, 7)
    monkeypatch.setattr(progress, "EVERY", 1e9)
    quiet = DDBatch(p).propagate_grid(y, grid)
    monkeypatch.setattr(progress, "EVERY", 0.02)
    start = time.perf_counter()
    with caplog.at_level(logging.INFO, logger="sleighsim"):
        loud = DDBatch(p).propagate_grid(y, grid)
    wall = time.perf_counter() - start
    lines = [r.getMessage() for r in caplog.records if r.getMessage().startswith("double-double, 2 lanes: ")]
    if wall < 0.2:
        pytest.skip(f"the run took {wall:.2f} s: too short to see lines every 0.02 s")
    assert len(lines) >= 3, lines
    assert all(np.array_equal(a, b) for a, b in zip(quiet, loud))
