"""The findings' paragraph on the paper's inferred setup, composed from a synthetic paper_setup dataset
and ledger rows (sleighsim.report.findings.setup_paragraph)."""

import numpy as np
import xarray as xr

from sleighsim.claims.ledger import Row
from sleighsim.io.netcdf import write_dataset
from sleighsim.report import findings


def _rows():
    return [Row("C01", "", "", verdict="reproduced", paper_setup_verdict="not applicable: the setup moves none"),
            Row("C04", "", "", verdict="differs", paper_setup_verdict="differs under both (tried: K2)"),
            Row("C10", "", "", verdict="differs", paper_setup_verdict="reproduced under the paper's setup (K2 = 1.12)"),
            Row("C09", "", "", verdict="reproduced", paper_setup_verdict="reproduced (under both)")]


def _setup(tmp_path, inferred=True):
    attrs = {"n_setups": 8, "n_ranked": 6, "deviance_baseline": 90.0, "separability": "one at a time"}
    if inferred:
        attrs.update(deviance_best=12.5, best_K2=1.12, best_K2_low=1.11, best_K2_high=1.13, baseline_K2=1.1,
                     misfit_scale=4.0, best_K2_low_scaled=1.09, best_K2_high_scaled=1.15)
        for e in findings.SETUP_ELEMENTS[1:]:
            attrs.update({f"best_{e}": f"{e}-a", f"runner_up_{e}": f"{e}-b", f"gap_{e}": 3.0})
    else:
        attrs["n_setups_note"] = "no setup determines every scored number: none inferred"
    ds = xr.Dataset({"scored": ("paper_number", [1.0, 1.0, 0.0], {"long_name": "s", "units": "1"}),
                     "best_residual": ("paper_number", [-7.0, 2.0, 99.0], {"long_name": "r", "units": "1"})},
                    coords={"paper_number": ("paper_number", ["C04:first_spike", "C10:B", "C10:B_theory"],
                                             {"long_name": "n"})}, attrs=attrs)
    return write_dataset(ds, tmp_path / "paper_setup.nc")


def test_counts_come_from_the_rows_the_setup_moves():
    c = findings.setup_counts(_rows())
    assert c["ids"] == ["C04", "C10", "C09"] and c["setup"] == ["C10", "C09"] and c["converged"] == ["C09"]
    assert (c["total_converged"], c["total_setup"]) == (2, 3)


def test_the_paragraph_states_the_setup_its_counts_and_the_strongest_pull(tmp_path):
    text = findings.setup_paragraph(_rows(), _setup(tmp_path))
    assert ("K2 1.12 (within 1 of the least deviance: 1.11 to 1.13; with the sigmas inflated by the misfit, x 4: "
            "1.09 to 1.15; this run 1.1)") in text
    assert "Under it, 2 of the 3 claims whose numbers it moves hold (C10, C09); under converged physics, 1 hold" in text
    assert "C04:first_spike (-7 sigma)" in text and "B_theory" not in text  # unscored numbers do not pull
    assert np.char.count(text, "deviance +3") == 4


def test_the_paragraph_says_when_no_setup_was_inferred_and_is_absent_without_the_dataset(tmp_path):
    text = findings.setup_paragraph(_rows(), _setup(tmp_path, inferred=False))
    assert text.startswith("The paper's setup is not inferred in this run: no setup determines")
    assert findings.setup_paragraph(_rows(), None) == ""


def test_the_start_sentence_quotes_the_start_and_the_rescaled_t1_range_and_is_absent_without_the_test():
    a = {"start": "the stated reference state", "start_T1": [6.276, 1.577, 111.5],
         "start_T1_residual": [0.3, -9400.0, 2.1e5]}
    text = findings._start_sentence(a)
    assert text.startswith("Start: the stated reference state (C08's T1 6.276, +0.3 sigma;")
    assert "T1 from 1.577 to 111.5, 9.4e+03 sigma or more" in text
    assert findings._start_sentence({}) == ""
