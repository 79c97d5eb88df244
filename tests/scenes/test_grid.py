"""The F11 grid's per-row faithfulness gauge (sleighsim.scenes.grid): which arithmetic follows each row's orbit."""

import math

import pytest


def test_each_rows_faithful_arithmetic_and_whether_lambda_1s_follows_on_each_branch():
    """faithful_code indexes grid.LADDER (double, long double, double-double, quad): a row double follows, one
    only long double follows, one no arithmetic of the ladder follows, one without a complete spike cycle."""
    from sleighsim.precision import Precision
    from sleighsim.scenes.grid import faithful_words

    names, follow = faithful_words([0.0, 1.0, 4.0, float("nan")], Precision.DOUBLE)
    assert names[:2] == ["double", "long double"] and names[2].startswith("none of double, long double")
    assert names[3].startswith("unknown") and follow == ["follows", "does not follow", "does not follow", "unknown"]
    assert faithful_words([1.0, 2.0], Precision.LONG_DOUBLE)[1] == ["follows", "does not follow"]


@pytest.mark.parametrize("follows, want", [
    (["does not follow", "does not follow", "follows", "follows"], 2.0),  # double-double the cheapest
    (["follows"] * 4, 0.0),
    (["does not follow"] * 4, 4.0),  # none of the ladder: len(LADDER)
    (["unknown"] * 4, math.nan),  # no complete spike cycle: unknown, never a rung
])
def test_a_rows_gauge_names_the_cheapest_arithmetic_that_follows_or_none_or_unknown(monkeypatch, follows, want):
    """grid.row_gauge's faithful_code from the gauge's answer per arithmetic of LADDER (the gauge replaced by
    these answers), and row_log10_gain_rounding of lambda_1's arithmetic."""
    from sleighsim.model.params import Params
    from sleighsim.precision import Precision
    from sleighsim.scenes import grid

    answers = dict(zip(grid.LADDER, follows))
    monkeypatch.setattr(grid, "settled_gains", lambda *a, **k: {
        "ln_gain_max": 30.0, "steps_per_cycle": 1e4, "follows": answers,
        "log10_gain_rounding": {a: float(i) for i, a in enumerate(grid.LADDER)}})
    cfg = {"tol": 1e-12, "compact_mode": True, "T_gain": 100.0, "tau_gain": 5.0, "transient": {"spike_factor": 1.8}}
    g = grid.row_gauge(Params.paper(eps=0.1, b=1.0), [0.0, 0.1, 1.0, 0.0], cfg, 1.0, Precision.LONG_DOUBLE)
    assert g["faithful_code"] == want or (math.isnan(want) and math.isnan(g["faithful_code"]))
    assert g["row_log10_gain_rounding"] == 1.0 and g["row_ln_gain_max"] == 30.0


def test_a_rows_spike_interval_counts_every_spike_of_its_replica_stretch():
    """The main state's row (eps = 0.1): its spikes about 2300 apart and about 2 time units wide; the stretch
    through the replicas sampled every spike_dt (0.5) finds each of them, where 400 samples per spacing (every
    10 time units here) missed about every other one."""
    from sleighsim.model.params import Params
    from sleighsim.scenes.grid import _replicas

    p = Params.paper(eps=0.1, K2=1.1)
    y = [0.06117225, 0.02642411, 3.3143803, 3.64565777]
    cfg = {"replicas": 4, "replica_spacing": 4000.0, "spike_dt": 0.5, "transient": {"spike_factor": 1.8},
           "tol": 2.0**-52}
    states, interval, interval_std = _replicas(p, y, cfg, 1.0, "row")
    assert states.shape == (4, 4) and 2250 < interval < 2400 and interval_std < 30
