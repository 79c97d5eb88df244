"""docs/tutorial.py runs, on the smoke horizons (SLEIGHSIM_TUTORIAL_OVERLAY=config/smoke.yaml), and what
it shows holds. One test, so that the tutorial runs once under pytest-xdist; its CPU time is printed
(pytest -s)."""

import math
import runpy
import time

import numpy as np
import pytest
from conftest import ROOT

from sleighsim.chaos.faithfulness import FAITHFUL_MAX, FOLLOWS, UNKNOWN
from sleighsim.chaos.verdicts import VERDICTS
from sleighsim.model.symmetries import energy_label
from sleighsim.precision import Precision


def test_the_tutorial_runs_and_its_orbits_gauge_and_verdict_say_what_the_rules_say(tmp_path, monkeypatch):
    monkeypatch.setenv("SLEIGHSIM_TUTORIAL_OVERLAY", "config/smoke.yaml")
    monkeypatch.setenv("SLEIGHSIM_TUTORIAL_OUT", str(tmp_path))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    start = time.process_time()
    ns = runpy.run_path(str(ROOT / "docs" / "tutorial.py"), run_name="__main__")
    print(f"docs/tutorial.py on the smoke horizons: {time.process_time() - start:.1f} CPU-s")
    assert float(energy_label(ns["y0"], ns["params"])) == pytest.approx(ns["label"], rel=1e-12)
    for run in (ns["double"], ns["long_double"]):
        assert run["energy_max_rel_drift"] < 1e-10
        assert np.all(np.diff(run["spikes"]) > 0) and np.all((run["spikes"] > 0) & (run["spikes"] <= ns["t"][-1]))
    sep = ns["separation"]
    assert sep.shape == ns["t"].shape and np.all(np.isfinite(sep)) and sep[0] < 1e-12
    assert (tmp_path / "tutorial-separation.png").stat().st_size > 10000
    faith = ns["faith"]
    for p in Precision:
        g = faith["log10_gain_rounding"][p]
        assert faith["follows"][p] == (UNKNOWN if math.isnan(g) else FOLLOWS if g < math.log10(FAITHFUL_MAX)
                                       else "does not follow")
    judged, said = ns["judged"], ns["verdict_of_mine"]
    assert list(judged.state.values) == ["state"] and judged.verdict.item() in VERDICTS
    assert said.verdict == judged.verdict.item() and said.why and said.arithmetic
    decided = {ind for ind, v in zip(judged.decisive_indicator.values, judged.decisive_indicator_verdict.values[0])
               if v != "undecided"}
    assert decided <= set(judged.attrs["decisive_voters"])  # only the audited judges vote (chaos.rule.vote_gate)
    assert judged.verdict.item() == "undecided" or decided
    assert said.verdict in ("chaotic", "regular") or said.to_decide  # an undecided state: what would decide it
