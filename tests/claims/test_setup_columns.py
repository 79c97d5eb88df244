"""The ledger's paper_setup columns on each branch, from a small synthetic paper_setup dataset."""

import numpy as np
import pytest
import xarray as xr

from sleighsim.claims import setup_columns as sc
from sleighsim.claims.causes import NONE
from sleighsim.claims.rules import DIFFERS, REPRODUCED


def _setup(best_x: float, best_y: float, inferred: bool = True) -> xr.Dataset:
    """Claim X (one number, moved by K2) and claim Y (one number, moved by psd)."""
    ds = xr.Dataset({"claim": ("paper_number", np.array(["X", "Y"], object)),
                     "name": ("paper_number", np.array(["a", "b"], object)),
                     "paper": ("paper_number", [10.0, 1.0]), "best": ("paper_number", [best_x, best_y]),
                     "best_sd": ("paper_number", [0.0, 0.0]),
                     "moved_by": ("paper_number", np.array(["K2", "psd"], object)),
                     "changed_by": ("paper_number", np.array(["K2 = 1.12", ""], object))},
                    coords={"paper_number": ["X:a", "Y:b"]})
    if inferred:
        ds.attrs["best_K2"] = 1.12
    return ds


@pytest.mark.parametrize("converged, best_x, expected", [
    (REPRODUCED, 10.5, "reproduced (under both)"),
    (DIFFERS, 10.5, "reproduced under the paper's setup (K2 = 1.12)"),
    (REPRODUCED, 20.0, "reproduced under converged physics only (differs under the paper's setup: K2 = 1.12)"),
    (DIFFERS, 20.0, "differs under both (tried: K2)"),
])
def test_each_verdict_branch_follows_the_ledgers_tolerance(converged, best_x, expected):
    value, verdict = sc.columns("X", converged, _setup(best_x, 1.0))
    assert value == f"a {best_x:.4g}" and verdict == expected


def test_rows_the_setup_cannot_move_are_not_applicable_with_the_reason():
    assert sc.columns("Z", DIFFERS, _setup(10.0, 1.0)) == ("", "not applicable: the setup moves none of its numbers")
    assert sc.columns("X", DIFFERS, None)[1].startswith("not applicable: no paper_setup dataset")
    assert sc.columns("X", DIFFERS, _setup(10.0, 1.0, inferred=False))[1].startswith("not yet computed")


def test_an_unexplained_cause_says_the_joint_setup_was_tried_and_others_stay():
    told = sc.cause_with_setup(f"{NONE}: details", "differs under both (tried: K2)")
    assert told.endswith("also tried under the joint setup (paper_setup.nc): differs under both (tried: K2)")
    assert sc.cause_with_setup("explained by the unstated K: x", "differs under both (tried: K2)") == \
        "explained by the unstated K: x"
    assert sc.cause_with_setup(f"{NONE}: d", "not applicable: the setup moves none of its numbers") == f"{NONE}: d"
