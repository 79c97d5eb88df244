"""C26's rows gauged (sleighsim.scenes.formal_gauge): the cheapest arithmetic that follows a formal row's orbit, or
the rounding it would need and its measured price, or unknown without a spike cycle."""

import math

import numpy as np
import pytest

from sleighsim.chaos.faithfulness import DOES_NOT_FOLLOW, FAITHFUL_MAX, FOLLOWS, log10_gain_rounding
from sleighsim.model.params import Params
from sleighsim.precision import Precision
from sleighsim.scenes import formal_gauge

RECORD = {"schema": "sleighsim.multiprec/1", "git_commit": "c40dc66abc",
          "rows": [{"candidate": "real 256", "rounding": 8.6e-78, "cpu_s_per_tu": 0.030},
                   {"candidate": "real 192", "rounding": 1.6e-58, "cpu_s_per_tu": 0.016}]}
GAUGE = {"T": 100.0, "tau": 5.0}
P25 = Params.paper(eps=25.0, b=1.0, K2=1.1, formal=True)


def fake(monkeypatch, follows, ln_gain=83.4, steps=3.25e4):
    answers = dict(zip(formal_gauge.LADDER, follows))
    monkeypatch.setattr(formal_gauge, "settled_gains", lambda *a, **k: {
        "ln_gain_max": ln_gain, "steps_per_cycle": steps, "follows": answers,
        "spike_times": np.array([100.0, 500.0, 1000.0])})


@pytest.mark.parametrize("follows, want", [
    ([FOLLOWS] * 4, "double"),
    ([DOES_NOT_FOLLOW, DOES_NOT_FOLLOW, FOLLOWS, FOLLOWS], "double-double"),
])
def test_a_row_some_arithmetic_follows_names_the_cheapest_without_a_price(monkeypatch, follows, want):
    fake(monkeypatch, follows)
    g = formal_gauge.row_gauge(P25, [0.0, 0.1, 1.0, 0.0], GAUGE, 1e-12, True, 1.8, RECORD)
    assert g["faithful_arithmetic"] == want and g["faithful_price"] == ""
    assert g["gauge_spike_interval"] == 450.0 and math.isnan(g["gauge_needed_log10_rounding"])


def test_a_row_none_follows_gets_the_rounding_it_needs_and_the_cheapest_candidate_fine_enough(monkeypatch):
    """G x steps x rounding below FAITHFUL_MAX needs rounding below FAITHFUL_MAX / (G steps): 1e-43.6 here, so real
    192 (1.6e-58), the cheaper of the two, priced per cycle of the mean interval (450)."""
    fake(monkeypatch, [DOES_NOT_FOLLOW] * 4)
    g = formal_gauge.row_gauge(P25, [0.0, 0.1, 1.0, 0.0], GAUGE, 1e-12, True, 1.8, RECORD)
    want = math.log10(FAITHFUL_MAX) - (83.4 + math.log(3.25e4)) / math.log(10)
    assert g["gauge_needed_log10_rounding"] == pytest.approx(want)
    lgr = log10_gain_rounding(83.4, Precision.QUAD.rounding, 3.25e4)
    assert g["faithful_arithmetic"] == ("none of double, long double, double-double, quad "
                                        f"(G x steps x rounding 10^{lgr:.1f} in quad)")
    assert g["faithful_price"].startswith("real 192 (rounding 1.6e-58) would: 0.016 CPU-s per time unit, 7.2 per cycle")


def test_a_row_without_two_spikes_within_t_is_unknown_and_not_priced():
    """The real gauge on the eps = 25 formal orbit over 100 time units (its spikes hundreds apart)."""
    g = formal_gauge.row_gauge(P25, [0.0, 0.1, 1.0, 0.0], {"T": 100.0, "tau": 2.0}, 2.0**-52, True, 1.8, RECORD)
    assert g["faithful_arithmetic"].startswith("unknown (fewer than two spikes within gauge.T = 100)")
    assert math.isnan(g["row_ln_gain_max"]) and g["faithful_price"] == ""
