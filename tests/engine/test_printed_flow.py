"""The paper's printed equations integrated (audit D1)."""

import numpy as np
import pytest

from sleighsim.engine import printed_flow
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE


def test_printed_udot_does_not_conserve_energy():
    ds = printed_flow.energy_drift(Params.paper(eps=0.1), REFERENCE_STATE, np.linspace(0, 1000, 101))
    assert ds.attrs["derived_max_abs_rel_change"] < 1e-11
    assert ds.attrs["printed_max_abs_rel_change"] > 0.5  # measured: about 1.37 within 1000 time units


def test_printed_equations_need_paper_form_parameters():
    p = Params.physical(m_c=2.0, m_r=0.0, I_c=0.5, I_r=0.3, a=0.0, b=1.0)
    with pytest.raises(ValueError, match="paper-form"):
        printed_flow.trajectory(p, REFERENCE_STATE, np.linspace(0, 1, 3))
