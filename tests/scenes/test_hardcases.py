"""Hard cases: the reliable ones stay within their stated error, refused ones raise."""

import numpy as np
import pytest

from sleighsim.model.params import Params
from sleighsim.scenes import hardcases

CFG = dict(small_eps=[1e-3, 1e-5], large_eps=[0.99], labels=[1e-6, 1e6], T_eps=20.0, T_scaling=20.0, T_long=2000.0,
           tol=2.220446049250313e-16, scipy_rtol=1e-12, max_drift=1e-10, max_disagreement=1e-6,
           max_scaling_error=1e-9, max_drift_long=1e-8)


@pytest.fixture(scope="module")
def cases():
    return hardcases.hardcases(CFG)


def test_every_case_has_an_outcome(cases):
    assert set(cases.outcome.values) <= {"reliable", "degraded", "refused"}
    assert cases.attrs["n_reliable"] + cases.attrs["n_degraded"] + cases.attrs["n_refused"] == cases.sizes["case"]


def test_reliable_cases_stay_within_their_bounds(cases):
    for i, case in enumerate(cases.case.values):
        if cases.outcome.values[i] != "reliable":
            continue
        drift, dis = cases.drift.values[i], cases.disagreement.values[i]
        if np.isfinite(dis):
            assert drift < CFG["max_drift"] and dis < CFG["max_disagreement"], case
        if case.startswith("energy label"):
            assert cases.error.values[i] < CFG["max_scaling_error"], case
    expected_reliable = {"eps = 0.001", "eps = 1e-05", "eps = 0.99", "energy label 1e-06", "energy label 1e+06",
                         "velocity exactly zero", "delta exactly pi/2 (on a section)"}
    got = {c for c, o in zip(cases.case.values, cases.outcome.values) if o == "reliable"}
    assert expected_reliable <= got


def test_refused_cases_raise_the_documented_error(cases):
    refused = {c: d for c, o, d in zip(cases.case.values, cases.outcome.values, cases.detail.values) if o == "refused"}
    assert set(refused) == {"eps = 1.5", "eps = 0", "energy label 0"}
    assert "admissible range (0, 1)" in refused["eps = 1.5"] and "formal=True" in refused["eps = 1.5"]
    assert "must be positive" in refused["eps = 0"]
    with pytest.raises(ValueError, match="admissible range"):
        Params.paper(eps=1.5)
