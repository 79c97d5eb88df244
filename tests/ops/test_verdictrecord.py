"""The record of a chaos verdict measured with another config (sleighsim.ops.verdictrecord): every lane of the
decisive job with the numbers behind its verdict, and refused from a commit nobody could check."""

import numpy as np
import pytest
import xarray as xr

from sleighsim.ops import verdictrecord
from sleighsim.precision import parsed
from sleighsim.scenes import verdict_decisive, verdict_lanes

INDICATORS = ("benettin", "ftle", "megno", "two_trajectory", "loschmidt", "frequency")
ALL = frozenset(INDICATORS) | {"section_megno", "birkhoff"}  # every indicator votes


def _stage1(y):
    """A first-stage chunk dataset of one state, every indicator undecided, settled at y."""
    return xr.Dataset({
        "indicator_verdict": (("state", "indicator"), np.array([["undecided"] * 6], dtype=object)),
        "indicator_reason": (("state", "indicator"), np.array([["none"] * 6], dtype=object)),
        "indicator_value": (("state", "indicator"), [[7e-4, 7e-4, 1.0, 1e-2, 1e-3, 1e-5]]),
        "indicator_uncertainty": (("state", "indicator"), [[5e-5, 5e-5, 0.1, 1e-3, 1e-4, 1e-6]]),
        "ln_gain_max": ("state", [36.0]), "gain_steps_per_cycle": ("state", [1.8e4]),
        "exponent": (("state", "i"), [[7e-4, 0.0, -1e-4, -6e-4]]),
        "sum_exponents": ("state", [0.0]), "sum_exponents_stderr": ("state", [1e-5]),
        "R_image": ("state", np.array(["stays"], dtype=object)), "settled_state": (("state", "var"), [y]),
    }, coords={"state": ["main"], "indicator": list(INDICATORS)})


def _decisive_cfg():
    return parsed({"params": {"eps": 0.1, "b": 1.0, "K2": 1.1}, "sigma": 3.0, "tau": 10.0,
                   "frequency": {"component": "omega", "min_cycles": 2.0}, "transient": {"spike_factor": 1.8},
                   "decisive": {"states": ["main"], "precision": "double-double", "tol": 1e-20, "T": 200.0,
                                "dt": 0.5, "splits": [2, 4], "megno_samples": 4}})


@pytest.fixture(scope="module")
def job():
    """A decisive job of two lanes (realizations 0 and 1 of one state) over T = 200 in double-double."""
    starts = ([0.02, 0.02, 3.3, 2.5], [0.021, 0.02, 3.3, 2.5])
    lanes = [(_stage1(y), ALL, {"vote_horizon": 1.0, "vote_why": ""}) for y in starts]
    parts = verdict_decisive.decisive_lanes(_decisive_cfg(), lanes, ["a#0", "a#1"])
    return verdict_lanes.pack(parts, [0, 1])


def test_the_record_holds_every_lane_with_the_numbers_behind_its_verdict(job):
    rec = verdictrecord.record(job.assign_attrs(git_commit="0123456789abcdef" * 2 + "01234567"), "config/x.yaml")
    assert rec["config"] == "config/x.yaml" and [r["realization"] for r in rec["realizations"]] == [0, 1]
    for r, (_, lane) in zip(rec["realizations"], verdict_lanes.unpack(job)):
        assert r["verdict"] == str(lane.decisive_verdict.values[0]) and r["T"] == 200.0
        assert set(r["indicators"]) == {"megno", "section_megno", "frequency", "birkhoff"}
        assert r["birkhoff_digits"] == [float(x) for x in lane.decisive_birkhoff_digits.values[0]]
        assert np.isfinite(r["megno_Y_final"]) and r["spike_intervals"] is not None


@pytest.mark.parametrize("commit", ["0123456789ab", "0123456789abcdef" * 2 + "01234567-dirty", ""])
def test_a_record_from_a_commit_nobody_could_check_is_refused(job, commit):
    with pytest.raises(ValueError, match="not a full clean commit"):
        verdictrecord.record(job.assign_attrs(git_commit=commit), "config/x.yaml")
