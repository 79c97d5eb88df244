"""The price of the arithmetic a landed torus would need (sleighsim.scenes.trigger_price): the record's checks,
the rounding needed, the cheapest candidate fine enough or none, and which fate rows get a price."""

import pytest
import yaml
from conftest import ROOT

from sleighsim.chaos.faithfulness import DOES_NOT_FOLLOW, FOLLOWS
from sleighsim.scenes import trigger, trigger_fate, trigger_price

RECORD = {"schema": trigger_price.SCHEMA, "git_commit": "c40dc66abc",
          "rows": [{"candidate": "real 256", "rounding": 8.6e-78, "cpu_s_per_tu": 0.030},
                   {"candidate": "real 192", "rounding": 1.6e-58, "cpu_s_per_tu": 0.016},
                   {"candidate": "triple-double", "rounding": 7.0e-46, "cpu_s_per_tu": 0.0009}]}


@pytest.mark.parametrize("content, problem", [
    (None, "no such file"),
    ("schema: [unclosed", "not YAML"),
    (yaml.safe_dump({"schema": "sleighsim.ddbatch/1", "rows": []}), "not a sleighsim.multiprec/1 record"),
    (yaml.safe_dump({"schema": trigger_price.SCHEMA, "rows": []}), "no candidate rows"),
    (yaml.safe_dump({"schema": trigger_price.SCHEMA, "rows": [{"candidate": "x", "rounding": 1e-40}]}), "rows 0 lack"),
    (yaml.safe_dump(RECORD), ""),
])
def test_a_price_record_is_checked_before_use(tmp_path, content, problem):
    path = tmp_path / "record.yaml"
    if content is not None:
        path.write_text(content)
    found = "; ".join(trigger_price.problems(path))
    assert (problem in found) if problem else found == ""
    if problem:
        with pytest.raises(ValueError, match=problem.split()[0]):
            trigger_price.load(path)


def test_the_repository_s_record_is_usable():
    assert trigger_price.problems(ROOT / "benchmarks" / "multiprec.yaml") == []


@pytest.mark.parametrize("needed, words", [
    (1e-50, "real 192 (rounding 1.6e-58) would: 0.016 CPU-s per time unit, 56 per cycle"),  # the cheapest fine one
    (1e-60, "real 256 (rounding 8.6e-78) would: 0.03 CPU-s per time unit, 105 per cycle"),
    (1e-80, "no candidate of benchmarks/multiprec.yaml at c40dc66 rounds below 1.0e-80"),
])
def test_the_cheapest_candidate_fine_enough_or_none(needed, words):
    assert words in trigger_price.price(RECORD, needed, 3500.0)


def test_the_rounding_needed_is_the_limit_over_g_and_steps():
    """An arithmetic of rounding 1e-32 at G x steps x rounding 10^2 would need 1e-3 / (10^2 / 1e-32) = 1e-37."""
    assert trigger_price.log10_needed(2.0, 1e-32, 1e-3) == pytest.approx(-37.0)


def test_only_tori_not_followed_are_priced():
    rows = [None, {"follows": FOLLOWS},
            {"follows": DOES_NOT_FOLLOW, "arithmetic": trigger_fate.TD, "log10_gain_rounding": -2.4,
             "interval": 3556.9}]
    trigger.priced(rows, RECORD)
    assert "price" not in rows[1] and rows[2]["price"].startswith("real 192")
    text = trigger_fate.follows_text({**rows[2], "ln_gain": 88.1, "cpu_s": 1.0, "confirmed": 1})
    assert "needs rounding below 10^-45.8; real 192" in text  # -3 - (-2.4 + 45.15)
