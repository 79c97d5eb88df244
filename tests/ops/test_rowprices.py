"""The cost estimate's price of a Lyapunov grid's row verdicts (sleighsim.ops.rowprices): the measured cost per
step of a spike cycle, the steps-per-cycle law in eps, and chunk seconds that price every judged row by it."""

import math

import numpy as np
import pytest
import xarray as xr

from sleighsim.ops import rowprices
from sleighsim.scenes import grid

GRID = {"kind": "lyapunov_grid", "eps_range": [0.05, 0.4], "n_eps": 4, "n_chunks": 2, "reference_eps": 0.1,
        "t_pre": 100.0, "t_pre_min": 100.0, "replicas": 2, "replica_spacing": 10.0, "t_align": 1.0, "T_round": 10.0,
        "max_rounds": 1, "poincare_span": 0.0, "T_gain": 10.0, "b_check": [], "b_range": [1.0, 1.0], "n_b": 1,
        "verdict": {"eps_min": 0.15, "realizations": 3, "T": 1000.0}}
EPS = grid.axes(GRID)[0]  # 0.05, 0.1, 0.2, 0.4
STEPS = 2e3 * (EPS / 0.1) ** -2.0  # steps per cycle ~ eps^-2


def measured_grid():
    """Rows 0.2 and 0.4 judged at 0.01 s per step of a cycle; every row gauged."""
    judged = EPS >= 0.15
    return xr.Dataset({"row_gain_steps_per_cycle": ("eps", STEPS),
                       "row_verdict_wall_s": ("eps", np.where(judged, 0.01 * STEPS, 0.0)),
                       "row_verdict": ("eps", np.where(judged, "regular", "not judged").astype(object))},
                      coords={"eps": EPS})


def test_a_grid_gives_its_cost_per_cycle_step_and_its_steps_law():
    section = rowprices.from_grid(measured_grid())
    assert section["cost_per_cycle_step_s"] == pytest.approx(0.01)
    law = section["steps_per_cycle_law"]
    assert law["exponent"] == pytest.approx(-2.0) and law["rows_fitted"] == 4
    assert rowprices.verdict_price(section, 0.05, GRID, GRID) == pytest.approx(0.01 * 8e3)
    twice = dict(GRID, verdict=dict(GRID["verdict"], T=2000.0))
    assert rowprices.verdict_price(section, 0.05, GRID, twice) == pytest.approx(0.01 * 8e3 * 2)


def test_a_grid_that_judged_no_row_or_gauged_one_gives_no_price():
    none = measured_grid().assign(row_verdict=("eps", np.array(["not judged"] * 4, object)))
    assert rowprices.from_grid(none) is None
    one = measured_grid().assign(row_gain_steps_per_cycle=("eps", [np.nan, np.nan, np.nan, 500.0]))
    assert rowprices.from_grid(one) is None


def test_chunk_seconds_price_the_rows_a_target_judges_by_their_steps():
    """Measured chunks built from a rate of 0.5 s per time unit outside the verdict plus their rows' verdicts;
    a target judging every row adds the verdicts of 0.05 and 0.1 at 0.01 s per step of their cycles."""
    section, base = rowprices.from_grid(measured_grid()), 2.0
    work = [w for _, w in grid.grid_rows(GRID, verdict=False)]
    walls = 0.01 * STEPS * (EPS >= 0.15)
    measured = {k: base + sum(0.5 * w + v for w, v in zip(work[k::2], walls[k::2])) for k in range(2)}
    same = rowprices.chunk_seconds(section, GRID, GRID, measured, base)
    assert same == pytest.approx([measured[0], measured[1]])
    everyone = dict(GRID, verdict=dict(GRID["verdict"], eps_min=0.0))
    more = rowprices.chunk_seconds(section, GRID, everyone, measured, base)
    assert more[0] - measured[0] == pytest.approx(0.01 * STEPS[0])  # chunk 0 holds rows 0.05 and 0.2
    assert more[1] - measured[1] == pytest.approx(0.01 * STEPS[1])
    assert math.isclose(sum(more), sum(measured.values()) + 0.01 * (STEPS[0] + STEPS[1]))
    assert all(type(s) is float for s in same + more)  # plain floats: a numpy scalar stops the YAML record
