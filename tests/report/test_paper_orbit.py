"""The first screen's sentence on the paper's own orbit (sleighsim.report.paper_orbit), from a trigger-law
dataset built here: the escape still moving with the error or not, the landed tori and how many are followed."""

import xarray as xr

from sleighsim.report import finding
from sleighsim.report.paper_orbit import describe


def trigger(slope=-86.0, err=13.0, landed=True):
    ds = xr.Dataset({"first_spike": ("run", [5282.0, 5600.0, 5638.0]), "tol": ("run", [1e-8, 1e-14, 1e-16]),
                     "saturated": ("run", [0, 0, 1]), "range_slope": ("range", [slope]),
                     "range_slope_stderr": ("range", [err]), "range_label": ("range", ["long double"])},
                    attrs={"y0_u": 0.0, "y0_Omega": 0.1, "y0_omega": 1.0, "y0_delta": 0.0})
    if landed:
        ds["landed_interval"] = ("run", [1791.6, 2407.7, 2503.3])
        ds["landed_follows"] = ("run", ["follows", "does not follow", "follows"])
        ds["landed_class"] = ("run", ["strictly periodic"] * 3)
        ds["landed_arithmetic"] = ("run", ["double-double", "triple-double", "double-double"])
    return ds


def test_the_sentence_says_the_error_decides_the_escape_and_where_each_escape_lands():
    text = describe(trigger())
    assert text.startswith("From the paper's own start (0, 0.1, 1, 0)") and "t = 5282 to 5600" in text
    assert "1e-08 to 1e-14 (2 runs)" in text and "still moving 86 +- 13" in text
    assert "the integration error decides" in text
    assert "(strictly periodic) whose spike interval depends on that error: 1792 to 2408, 1 of 2 followed in " \
           "double-double." in text


def test_an_escape_no_longer_moving_and_a_dataset_without_landings_are_said_so():
    text = describe(trigger(slope=-10.0, err=13.0, landed=False))
    assert "no longer moving at the finest range (long double)." in text and "lands" not in text


def test_the_finding_carries_the_sentence_only_for_a_reproduction():
    rows = []
    ident = {"config_label": "paper", "config_sha256": "0" * 64}
    f = finding.facts(rows, [], None, ident, {"git_commit": "", "date": ""}, orbit="The orbit sentence.")
    assert "The orbit sentence." in finding.paragraph(f)
    f = finding.facts(rows, [], None, {**ident, "config_label": "smoke"}, {"git_commit": "", "date": ""},
                      orbit="The orbit sentence.")
    assert "The orbit sentence." not in finding.paragraph(f)
