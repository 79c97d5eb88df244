"""The report's first line names the run's configuration and says whether it is a reproduction; every verdict
has a colour, a mark and a meaning; the smoke run's report and ledger say it is no reproduction, carry the
hash the command line computes for the same config files, and show no NaN or leftover text."""

import html
import re

import pytest
from conftest import SMOKE, SMOKE_RESULTS

from sleighsim.claims import fidelity
from sleighsim.claims.rules import MEANINGS, VERDICTS
from sleighsim.report.build import run_line
from sleighsim.report.page import COLOURS, MARKS


def test_every_verdict_has_a_colour_and_a_mark_of_its_own():
    assert list(COLOURS) == list(VERDICTS) and list(MARKS) == list(VERDICTS) and set(MEANINGS) == set(VERDICTS)
    assert len(set(COLOURS.values())) == len(VERDICTS) and len(set(MARKS.values())) == len(VERDICTS)


@pytest.mark.parametrize("label, reproduction", [("paper", True), ("cluster", True), ("smoke", False)])
def test_the_first_line_names_the_config_and_says_whether_it_is_a_reproduction(label, reproduction):
    ident = fidelity.identity({"label": label, "scenes": {}})
    line = run_line(ident)
    assert line["reproduction"] is reproduction and line["config_sha256"] == ident["config_sha256"]
    assert f"config {label} (sha256 {ident['config_sha256'][:12]})" in line["text"]
    assert ("NOT a reproduction" in line["text"]) is not reproduction
    assert ("judged against the paper's numbers" in line["text"]) is reproduction


def _visible_text(page: str) -> str:
    """The text a browser shows of ``page``: no head, scripts, styles or hidden blocks; entities decoded."""
    body = re.sub(r"<(head|script|style)\b.*?</\1>", " ", page, flags=re.S)
    body = re.sub(r"<div[^>]*\bhidden\b[^>]*>.*?</div>", " ", body, flags=re.S)
    return html.unescape(re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", body)))


#: Text the page must not show: a bare NaN, an empty field between separators, the rendering check's line.
UNSHOWN = (re.compile(r"(?<![\w.])nan(?!\w)", re.I), re.compile(r";\s*;"), re.compile(r"images: \d+ broken"))


@pytest.mark.workflow
def test_the_smoke_report_and_ledger_say_they_are_no_reproduction(smoke_run):
    from sleighsim.cli.claims import run_config
    from sleighsim.io.netcdf import read_dataset

    results = smoke_run / SMOKE_RESULTS
    ident = fidelity.identity(run_config([SMOKE]))
    ledger = read_dataset(results / "claims.nc")
    assert {k: ledger.attrs[k] for k in ident} == ident  # the workflow's config, as the command line hashes it
    assert set(ledger.verdict.values) == {"not a reproduction"} and "reproduced" in set(ledger.run_verdict.values)
    html = (results / "report" / "index.html").read_text()
    text = _visible_text(html)
    assert text.strip().startswith(f"A smoke run ({fidelity.describe(ident)}): NOT a reproduction of the paper")
    assert not re.search(r"\d+ of \d+ chaos claims hold", text) and "not judged (smoke run)" in text  # no count
    md = (results / "report" / "README.md").read_text()
    assert md.startswith(f"**A smoke run ({fidelity.describe(ident)}): NOT a reproduction")
    for page, shown in (("index.html", text), ("README.md", md)):
        for pattern in UNSHOWN:
            hit = pattern.search(shown)
            assert not hit, (page, shown[max(0, hit.start() - 200): hit.end() + 100])
    for verdict, mark in MARKS.items():  # the legend: every verdict, its mark and its meaning
        assert f"{mark} {verdict}" in text and MEANINGS[verdict] in text


@pytest.mark.workflow
def test_the_smoke_report_opens_with_its_finding_which_says_it_finds_nothing_about_the_paper(smoke_run):
    import yaml

    from sleighsim.report.finding import paragraph

    report = smoke_run / SMOKE_RESULTS / "report"
    facts = yaml.safe_load((report / "finding.yaml").read_text())
    assert not facts["reproduction"] and facts["config_label"] == "smoke" and facts["states"]
    text = paragraph(facts)
    assert "NOT a reproduction and finds nothing about the paper" in text
    page = _visible_text((report / "index.html").read_text())
    assert page.index(f"The finding. {text}") < page.index("Which of the paper's claims hold?")
    assert f"**The finding.** {text}" in (report / "README.md").read_text()
