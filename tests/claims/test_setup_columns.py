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
    (REPRODUCED, 10.5, sc.BOTH),  # 5% off: within REL_TOL
    (DIFFERS, 10.5, f"{sc.PAPER_ONLY} (K2 = 1.12)"),
    (REPRODUCED, 20.0, f"{sc.CONVERGED_ONLY} (differs under the paper's setup: K2 = 1.12)"),
    (DIFFERS, 20.0, f"{sc.NEITHER} (tried: K2)"),
    (DIFFERS, 11.5, f"{sc.NEITHER} (tried: K2)"),  # 15% off: outside REL_TOL
])
def test_each_verdict_branch_follows_the_ledgers_tolerance(converged, best_x, expected):
    value, verdict = sc.columns("X", converged, _setup(best_x, 1.0))
    assert value == f"a {best_x:.4g}" and verdict == expected


def test_a_band_edge_is_judged_by_the_spectra_judges_tolerance():
    ds = _setup(10.0, 1.0)
    band = ds.isel(paper_number=[1, 1]).assign(name=("paper_number", np.array(["band_low", "band_high"], object)),
                                               paper=("paper_number", [1.0, 2.0]), best=("paper_number", [1.09, 2.0]),
                                               best_sd=("paper_number", [0.0, 0.0]))
    assert sc.columns("Y", DIFFERS, band)[1].startswith(sc.PAPER_ONLY)  # 0.09 <= 10% of the width 1
    band["best"] = ("paper_number", [1.2, 2.0])
    assert sc.columns("Y", DIFFERS, band)[1].startswith(sc.NEITHER)


def test_rows_the_setup_cannot_move_are_not_applicable_with_the_reason():
    assert sc.columns("Z", DIFFERS, _setup(10.0, 1.0)) == ("", "not applicable: the setup moves none of its numbers")
    assert sc.columns("X", DIFFERS, None)[1].startswith("not applicable: no paper_setup dataset")
    assert sc.columns("X", DIFFERS, _setup(10.0, 1.0, inferred=False))[1] == sc.NOT_INFERRED


def test_an_unexplained_cause_says_the_joint_setup_was_tried_and_others_stay():
    told = sc.cause_with_setup(f"{NONE}: details", "differs under both (tried: K2)")
    assert told.endswith("also tried under the joint setup (paper_setup.nc): differs under both (tried: K2)")
    assert sc.cause_with_setup("explained by the unstated K: x", "differs under both (tried: K2)") == \
        "explained by the unstated K: x"
    assert sc.cause_with_setup(f"{NONE}: d", "not applicable: the setup moves none of its numbers") == f"{NONE}: d"
