"""Where each escape lands (sleighsim.scenes.trigger_fate): the landing check, which runs go to triple-double,
and what the dataset says of each, on every branch (the engines replaced by made-up trains)."""

import math

import numpy as np
import pytest

from sleighsim.chaos.faithfulness import DOES_NOT_FOLLOW, FOLLOWS, UNKNOWN
from sleighsim.model.params import Params
from sleighsim.scenes import trigger_fate as tf

P = Params.paper(eps=0.1, K2=1.1)
CFG = {"tol": 1e-32, "td_tol": 1e-47, "lead": 50.0, "half_width": 25.0, "periodic_factor": 3.0, "T": 1e4}


def _train(*times, err=1e-5):
    return {"times": np.array(times, float), "errors": np.full(len(times), err)}


@pytest.mark.parametrize("dd, td, confirmed", [
    (_train(300.0, 2363.1), _train(300.0, 2363.1), 1),           # the same two spikes
    (_train(300.0, 2363.1), _train(300.0, 2420.0), 0),           # lands elsewhere
    (_train(300.0), _train(300.00001), 1),                       # one spike, within 3 x its error
    (_train(300.0, 2363.1), _train(300.0), 0),                   # triple-double has fewer spikes
    (_train(), _train(300.0), -1),                               # nothing to check
])
def test_the_landing_check_on_each_branch(monkeypatch, dd, td, confirmed):
    monkeypatch.setattr(tf, "follow", lambda batch, jets, starts, cfg: ([td], None))
    rows = [dict(dd)]
    tf.check(None, rows, None, np.zeros((1, 4, 3)), CFG)
    assert rows[0]["confirmed"] == confirmed and rows[0]["check_cpu_s"] >= 0
    assert math.isfinite(rows[0]["check_difference"]) == (confirmed == 1 or td["times"].size >= dd["times"].size > 0)


@pytest.mark.parametrize("follows, confirmed, cycles, finer", [
    (FOLLOWS, 1, 4, False), (FOLLOWS, 0, 4, True), (DOES_NOT_FOLLOW, 1, 4, True), (UNKNOWN, 1, 2, True),
    (UNKNOWN, -1, 0, False),
])
def test_which_runs_go_to_triple_double(follows, confirmed, cycles, finer):
    assert tf.finer_needed({"follows": follows, "confirmed": confirmed, "cycles": cycles}) is finer


def _row(arithmetic, follows, log10_gr, **extra):
    return {"arithmetic": arithmetic, "follows": follows, "log10_gain_rounding": log10_gr, "cpu_s": 12.5,
            "confirmed": 1, **extra}


@pytest.mark.parametrize("row, words", [
    (None, ["no escape within t_end"]),
    (_row(tf.DD, FOLLOWS, -10.84), ["followed by double-double (G x steps x rounding 10^-10.8)"]),
    (_row(tf.DD, UNKNOWN, math.nan), ["unknown (no complete cycle measured) for double-double"]),
    (_row(tf.TD, FOLLOWS, -8.2, instead_of=_row(tf.DD, DOES_NOT_FOLLOW, 0.6)),
     ["not followed by double-double (G x steps x rounding 10^0.6): needs rounding below 10^-35.5",
      "; followed by triple-double (G x steps x rounding 10^-8.2), at 12.5 CPU-s"]),
    (_row(tf.TD, DOES_NOT_FOLLOW, 2.5, instead_of=_row(tf.DD, DOES_NOT_FOLLOW, -1.9)),
     ["not followed by triple-double (G x steps x rounding 10^2.5): needs rounding below 10^-50.7"]),
    (_row(tf.TD, FOLLOWS, -20.0, instead_of=_row(tf.DD, FOLLOWS, -9.0, confirmed=0)),
     ["followed by double-double (G x steps x rounding 10^-9.0), but triple-double lands elsewhere; followed by "
      "triple-double"]),
])
def test_what_the_dataset_says_of_each_run(row, words):
    text = tf.follows_text(row)
    assert all(w in text for w in words), text


def test_runs_double_double_does_not_follow_are_followed_again_in_triple_double(monkeypatch):
    """Four runs (one without an escape): the landing check sends the second elsewhere, the gauge the third; both
    are followed again in triple-double, checked against twins perturbed by TWIN_REL, and keep their
    double-double rows; the first stays."""
    checked = []

    def followed(batch, jets, starts, cfg, arithmetic):
        n = len(starts[0]) if isinstance(starts, tuple) else len(starts)
        follows = [FOLLOWS, FOLLOWS, DOES_NOT_FOLLOW] if arithmetic == tf.DD else [FOLLOWS] * n
        return [{"arithmetic": arithmetic, "follows": f, "cycles": 3} for f in follows[:n]]

    def check(jets, rows, twin, starts, cfg):
        checked.append(starts)
        for r, c in zip(rows, (1, 0, 1) if rows[0]["arithmetic"] == tf.DD else (1, 1)):
            r.update(confirmed=c)

    monkeypatch.setattr(tf, "followed", followed)
    monkeypatch.setattr(tf, "check", check)
    y = np.array([0.07, 0.009, 2.16, 2.09])
    rows = tf.landed(P, [y, y, None, y], CFG)
    assert rows[2] is None and [r["arithmetic"] for r in (rows[0], rows[1], rows[3])] == [tf.DD, tf.TD, tf.TD]
    assert rows[1]["instead_of"]["confirmed"] == 0 and rows[1]["confirmed"] == 1
    assert rows[3]["instead_of"]["follows"] == DOES_NOT_FOLLOW
    assert len(checked) == 2 and checked[1].shape == (2, 4, 3)
    assert np.allclose(checked[1][:, :, 2] - checked[0][1:, :, 2], tf.TWIN_REL * y, rtol=1e-6)  # the twins' kick
    assert tf.landed(P, [None, None], CFG) == [None, None]
