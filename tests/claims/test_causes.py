"""Each cause test of the ledger driven to "explained by" and to "not explained", with synthetic sweeps."""

import numpy as np
import pytest
import xarray as xr
from test_judges import PAPER, _audit, _psd, _ref

from sleighsim.analysis import torus
from sleighsim.claims import causes
from sleighsim.claims.rules import Judgement

J = Judgement("differs", "m", "r")
K2 = [1.05, 1.1, 1.2, 1.3]


def _k2(**vars_):
    return xr.Dataset({k: ("K2", np.asarray(v, float)) for k, v in vars_.items()}, coords={"K2": K2})


def _err(first=(5500.0,) * 3, interval=(2380.0,) * 3, rel=(0.0007,) * 3, protocol=None):
    protocol = protocol if protocol is not None else [[5e-4, 1e-6, -1e-6, -5e-4]] * 2
    return xr.Dataset({"first_spike": ("rtol", list(first)), "spike_interval": ("rtol", list(interval)),
                       "omega_rel_error": ("rtol", list(rel)),
                       "protocol_exponent": (("lyapunov_rtol", "i"), np.asarray(protocol, float))},
                      coords={"rtol": [1e-3, 1e-6, 1e-10], "lyapunov_rtol": [1e-3, 1e-6]}, attrs={"method": "RK45"})


def _law(first=(5280.0, 5420.0, 5590.0, 5640.0), saturated=(0, 0, 0, 1)):
    """A trigger law: first spikes at tol 1e-8, 1e-12, 1e-14 and 1e-16 (the last saturated), and its two ranges."""
    return xr.Dataset({"tol": ("run", [1e-8, 1e-12, 1e-14, 1e-16]), "first_spike": ("run", list(first)),
                       "saturated": ("run", list(saturated)), "in_slopes": ("run", [1 - v for v in saturated]),
                       "range_label": ("range", ["double", "long double"]), "range_tol_max": ("range", [1e-8, 1e-12]),
                       "range_tol_min": ("range", [1e-12, 1e-14]), "range_slope": ("range", [-35.0, -85.0]),
                       "range_slope_stderr": ("range", [4.0, 9.0])}, attrs={"slopes_dof": 3})


def test_a_crossing_of_the_sweep_explains_and_names_the_setting():
    k2 = _k2(first_spike=[5000, 6000, 8000, 9500], spike_interval=[1800, 2000, 2300, 2600])
    text = causes.c04(J, PAPER["C04"], k2, _err(), _audit(printed_first_spike=np.nan, printed_spikes_t_end=2e4), _law())
    assert text.startswith("explained by the unstated K") and "8700 at K2 1.2" in text
    text = causes.c05(J, PAPER["C05"], k2, _err(), _audit(printed_spike_interval=np.nan))
    assert text.startswith("explained by the unstated K")


def test_no_cause_in_range_says_so_with_what_was_tested():
    k2 = _k2(first_spike=[5000, 5200, 5400, 5600], spike_interval=[2300, 2350, 2400, 2450])
    text = causes.c04(J, PAPER["C04"], k2, _err(), _audit(printed_first_spike=np.nan, printed_spikes_t_end=2e4), _law())
    assert text.startswith(causes.NONE) and "first_spike from 5000 to 5600" in text and "no spike by t = 20000" in text
    assert "first spike from 5280 to 5590 over injected error 1e-14 to 1e-08" in text


def test_the_printed_equation_and_the_integrator_are_causes_too():
    k2 = _k2(first_spike=[5000] * 4, spike_interval=[2600] * 4)
    text = causes.c04(J, PAPER["C04"], k2, _err(), _audit(printed_first_spike=8800.0, printed_spikes_t_end=2e4), _law())
    assert text.startswith("explained by the printed udot")
    text = causes.c05(J, PAPER["C05"], k2, _err(interval=(2200.0, 2600.0, 2600.0)),
                      _audit(printed_spike_interval=np.nan))
    assert text.startswith("explained by integration error (RK45)") and "1e-03" in text


@pytest.mark.parametrize("B, growth, explained", [([0.2, 0.22, 0.24, 0.26], [0.03, 0.04, 0.045, 0.05], True),
                                                  ([0.2, 0.22, 0.24, 0.26], [0.01, 0.02, 0.02, 0.02], False)])
def test_one_k2_must_fit_every_number_of_c10(B, growth, explained):
    k2 = _k2(T2=[3.14] * 4, B=B, omega2_growth=growth)
    text = causes.c10(J, PAPER["C10"], k2)
    assert text.startswith("explained") == explained
    assert ("one K2 fits them all: 1.2" in text) == explained


def test_c09_and_c11_and_c13():
    assert causes.c09(J, PAPER["C09"], _k2(Omega2_amplitude=[0.88, 0.89, 0.9, 0.91],
                                            phi1_over_pi=[0.47] * 4)).startswith("explained")
    assert causes.c09(J, PAPER["C09"], _k2(Omega2_amplitude=[0.88] * 4,
                                            phi1_over_pi=[-0.47] * 4)).startswith(causes.NONE)
    assert causes.c11(J, PAPER["C11"], _k2(omega_rel_error=[0.005] * 4),
                      _err(rel=(0.02, 0.001, 0.0007))).startswith("explained by integration error")
    assert causes.c11(J, PAPER["C11"], _k2(omega_rel_error=[0.005] * 4), _err()).startswith(causes.NONE)
    hit = _k2(first_spike=[5500] * 4, spike_interval=[1500, 2250, 2300, 2400])
    assert causes.c13(J, PAPER["C13"], hit).startswith("explained")
    miss = _k2(first_spike=[5500] * 4, spike_interval=[20000] * 4)
    assert causes.c13(J, PAPER["C13"], miss).startswith(causes.NONE)


def test_protocol_causes():
    paper_like = [[2.9e-4, 2.203e-4, 2.02e-5, -2.2e-4], [5e-4, 1e-6, -1e-6, -5e-4]]
    assert causes.c19(J, PAPER["C19"], _err(protocol=paper_like)).startswith("explained")
    assert causes.c19(J, PAPER["C19"], _err()).startswith(causes.NONE)
    dissipative = [[5e-4, 1e-6, -1e-6, -9e-4], [5e-4, 1e-6, -1e-6, -5e-4]]
    assert causes.c18(J, PAPER["C18"], _err(protocol=dissipative)).startswith("explained")
    assert causes.c18(J, PAPER["C18"], _err(protocol=[[5e-4, 0, 0, -4e-4]] * 2)).startswith(causes.NONE)
    assert causes.c20(J, PAPER["C20"], _err(protocol=[[1.05e-4, 0, 0, 0]] * 2)).startswith("explained")
    assert causes.c20(J, PAPER["C20"], _err()).startswith(causes.NONE)
    assert causes.c21(J, PAPER["C21"], _err(protocol=[[1.0e-4, 0, 0, 0]] * 2)).startswith("explained")


def test_c22_near_ties_by_chance():
    many, few = (_ref(n_p2pi=n, return_time_min=5.0, return_time_max=6.0) for n in (20000, 100))
    assert causes.c22(J, PAPER["C22"], many).startswith("explained")
    assert causes.c22(J, PAPER["C22"], few).startswith(causes.NONE)


def test_band_causes_units_and_aliasing():
    rad = _psd(1.45 / (2 * np.pi), 1.8 / (2 * np.pi), segment=1000.0)
    assert causes.c24(J, {"band": [1.45, 1.8]}, rad).startswith("explained by units")
    assert causes.c24(J, PAPER["C24"], _psd(15.84, 15.88, segment=50.0)).startswith("explained by sampling")
    assert causes.c24(J, PAPER["C24"], _psd(0.2, 0.5, segment=1000.0)).startswith(causes.NONE)
    k2 = _k2(band_low=[1.3, 1.4, 1.5, 1.6], band_high=[1.6, 1.7, 1.85, 1.9])
    assert "explained by" in causes.c23(J, PAPER["C23"], _psd(0.2, 0.3, segment=1000.0), k2)
    flat = _k2(band_low=[0.2] * 4, band_high=[0.3] * 4)
    assert causes.c23(J, PAPER["C23"], _psd(0.2, 0.3, segment=1000.0), flat).startswith(causes.NONE)


def test_d5_energy_normalisations():
    hit = _audit(d5_normalisation_names="m b^2 | m", d5_normalisation_values=np.array([0.0071, 0.113]))
    assert causes.d5(J, PAPER["D5"], hit).startswith("explained by an energy normalisation")
    miss = _audit(d5_normalisation_names="m b^2 | m", d5_normalisation_values=np.array([0.0071, 0.5]))
    assert causes.d5(J, PAPER["D5"], miss).startswith(causes.NONE)


@pytest.mark.parametrize("first, explained", [
    ((5280.0, 5420.0, 5590.0, 5640.0), False),  # the measured first spikes stay below 8700
    ((5280.0, 7000.0, 9000.0, 9100.0), True),   # they pass 8700 between 1e-12 and 1e-14
    ((5280.0, 5420.0, 8400.0, 9900.0), True),   # within 10% of 8700 at 1e-14 (1e-16, saturated, left out)
])
def test_the_injected_error_explains_the_first_spike_only_within_the_measured_range(first, explained):
    """No line is extrapolated: the first spikes of the runs in the slopes must reach the paper's 8700 at a level
    measured; the text names the range measured, the saturated runs and every range's slope."""
    k2 = _k2(first_spike=[5000, 5200, 5400, 5600], spike_interval=[2300, 2350, 2400, 2450])
    text = causes.c04(J, PAPER["C04"], k2, _err(), _audit(printed_first_spike=np.nan, printed_spikes_t_end=2e4),
                      _law(first))
    assert text.startswith("explained by the injected error") == explained, text
    assert "over injected error 1e-14 to 1e-08" in text and "1 saturated left out" in text
    assert "double 1e-08 to 1e-12: -35 +- 4" in text and "long double 1e-12 to 1e-14: -85 +- 9" in text
    assert "measured down to 1e-14, nothing extrapolated beyond it" in text and "would need" not in text


def test_a_law_without_runs_in_reach_says_so():
    name, ok, text = causes._trigger(_law(saturated=(1, 1, 1, 1)), 8700.0)
    assert name.startswith("the injected error") and not ok and text == "no run within reach of the slopes"


def _torus_family(identities=(torus.ANOTHER, torus.ANOTHER), periods=(2300.0, 2010.0)):
    """A torus-stability dataset: the reference (period 2337.6) and perturbed orbits of these identities."""
    return xr.Dataset({"torus_identity": ("orbit", [torus.REFERENCE, *identities]),
                       "amplitude": ("orbit", [0.0, 1e-6, 1e-3]), "period": ("orbit", [2337.6, *periods])},
                      attrs={"reference_period": 2337.6})


def _fig4_groups(extra):
    """fig4 runs: four in the main group (2300) and one extra group at ``extra``."""
    return xr.Dataset({"reached": ("run", [1] * 5), "group": ("run", [0, 0, 0, 0, 1]),
                       "spike_interval_level0_units": ("run", [2300.0, 2310.0, 2290.0, 2320.0, extra])})


@pytest.mark.parametrize(("classes", "extra", "explained"), [
    ((torus.ANOTHER, torus.ANOTHER), 2100.0, True),  # the extra group inside the family's span
    ((torus.ANOTHER, torus.ANOTHER), 1295.0, False),  # outside it
    ((torus.ANOTHER, torus.UNDETERMINED), 2100.0, False),  # an orbit not shown to be on a torus: no family shown
    ((torus.ANOTHER, torus.SAME), 2100.0, False),  # one back on the reference's torus: not each on its own
])
def test_c06_a_family_of_tori_explains_extra_groups_only_within_its_span(classes, extra, explained):
    text = causes.c06(J, {}, _torus_family(classes), _fig4_groups(extra))
    assert text.startswith("explained by a family of tori, each orbit on its own") == explained
    assert text.startswith(causes.NONE) != explained
    assert f"the extra groups' {extra:.5g} " + ("within that span" if extra > 2000 else "outside it") in text
