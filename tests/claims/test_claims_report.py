"""Claims ledger rules, completeness against CLAIMS.md, and the rendered report."""

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from conftest import SMOKE_RESULTS, write_fixture
from test_judges import _ref, _spectrum

from sleighsim.claims import figure_rows
from sleighsim.claims import ledger as claims
from sleighsim.claims.rules import DIFFERING
from sleighsim.io.claims_table import parse_claims, parse_values
from sleighsim.io.netcdf import read_dataset
from sleighsim.ops import screenshot
from sleighsim.report.figures.catalog import FIGURES

ROOT = Path(__file__).resolve().parents[2]
CLAIMS_MD = ROOT / "paper" / "CLAIMS.md"
#: Configs as the ledger reads them (sleighsim.scenes.catalog.laddered, realized): one that ladders and
#: realizes nothing, one that ladders fig9_ref in long double, one that realizes lyap_spectrum 3 times.
PLAIN = {"label": "paper", "scenes": {}}
LADDERED = {"label": "paper", "scenes": {"fig9_ref": {"kind": "poincare", "precisions": ["double", "long double"]}}}
REALIZED = {"label": "paper",
            "scenes": {"lyap_spectrum": {"kind": "lyapunov_spectrum", "realizations": 3, "realization_rel": 1e-9}}}


TEX = ROOT / "paper" / "fedonyuk-tallapragada-sleigh-rotor.tex"


def test_parse_claims_finds_every_table_row_once():
    text = CLAIMS_MD.read_text()
    ids_in_file = re.findall(r"^\|\s*([FCD]\d+)\s*\|", text, flags=re.M)
    parsed = [c.id for c in parse_claims(CLAIMS_MD)]
    assert parsed == ids_in_file and len(set(parsed)) == len(parsed)
    assert {c[0] for c in parsed} == {"F", "C", "D"}


def test_value_column_parses_numbers_lists_and_spellings():
    v = parse_values("exponents=[2.9e-4, -2.2e-4]; T=4000; band=[1.45, 1.8]")
    assert v["exponents"] == [2.9e-4, -2.2e-4] and v["T"] == 4000.0 and v["_text"]["band"] == ["1.45", "1.8"]
    assert parse_values("") == {}


def _spellings(text: str) -> set[str]:
    """How the paper's LaTeX may write a number: as is, 8,700, 2.9e^{-4}, 10^{-7}, 2\\%."""
    out, x = {text}, float(text)
    if "e" in text.lower():
        m, e = text.lower().split("e")
        for mm in ([m] if m not in ("1", "1.0") else ["", "1"]):
            forms = (f"{mm}e^{{{int(e)}}}", f"{mm}\\times10^{{{int(e)}}}", f"{mm}\\times10^{int(e)}")
            out |= set(forms) if mm else {f"10^{{{int(e)}}}", f"10^{int(e)}"}
    if x >= 1000 and x == int(x):
        out.add(f"{int(x):,}")
    if 0 < x < 1 and "e" not in text:
        out.add(f"{x * 100:g}\\%")
    return out


def test_every_value_of_the_claims_list_is_written_in_the_paper():
    tex = re.sub(r"\s+", "", TEX.read_text())
    checked = 0
    for c in parse_claims(CLAIMS_MD):
        for name, text in c.values.get("_text", {}).items():
            for t in text if isinstance(text, list) else [text]:
                assert any(sp in tex for sp in _spellings(t)), (c.id, name, t)
                checked += 1
    assert checked >= 40


def _steady(path, **attrs):
    write_fixture(xr.Dataset(attrs=attrs), path)


def test_figure_rows_count_a_missing_transient_check_as_not_checked(tmp_path, monkeypatch):
    from sleighsim.claims.rules import Judgement
    for cid in list(claims.JUDGES):  # the figure row alone is under test
        monkeypatch.setitem(claims.JUDGES, cid, lambda paper, *ds: Judgement("reproduced", "", ""))
    data, figs = tmp_path / "data", tmp_path / "figures"
    figs.mkdir(parents=True)
    name = next(n for n, f in FIGURES.items() if len(f.data) == 1 and f.steady)
    fid, ds_name = FIGURES[name].paper, FIGURES[name].steady[0]
    (figs / f"{name}.png").write_bytes(b"png")
    _steady(data / f"{ds_name}.nc")
    assert {r.id: r for r in claims.ledger(CLAIMS_MD, data, figs, PLAIN, FIGURES)}[fid].verdict == "not yet computed"
    _steady(data / f"{ds_name}.nc", transient_over=0, transient_n_spikes=2, transient_first_spike=5580.5)
    row = {r.id: r for r in claims.ledger(CLAIMS_MD, data, figs, PLAIN, FIGURES)}[fid]
    assert row.verdict == "check failed" and "not shown to be over" in row.reason
    assert row.cause.startswith("this run's pre-run, not the paper: ")
    assert "holds 2 spikes (first at 5580.5)" in row.cause
    _steady(data / f"{ds_name}.nc", transient_over=1)
    row = {r.id: r for r in claims.ledger(CLAIMS_MD, data, figs, PLAIN, FIGURES)}[fid]
    assert row.verdict == "reproduced" and "settled" in row.measured
    (figs / f"{name}.png").unlink()
    assert {r.id: r for r in claims.ledger(CLAIMS_MD, data, figs, PLAIN, FIGURES)}[fid].verdict == "not yet computed"


def test_a_per_row_transient_check_names_the_rows_not_settled_and_those_computed_elsewhere():
    """The cause of a figure row whose per-row transient check failed (the Lyapunov grid's rows)."""
    ds = xr.Dataset({"transient_over": ("eps", [np.nan, 1.0, 0.0]), "t_pre": ("eps", [np.nan, 2e4, 2e4])},
                    coords={"eps": [0.02, 0.1, 0.5]}, attrs={"elsewhere_config": "config/cluster.yaml"})
    assert figure_rows.transient_cause("fig11_grid", ds) == (
        "fig11_grid: eps 0.5 not settled within its pre-run of 2e+04; eps 0.02 not computed in this run "
        "(config/cluster.yaml computes it)")


def _fig9(path, n_loops, pairs):
    ds = _ref(n_loops=n_loops, return_time_min=1.0, return_time_max=2.0,
              return_time_n_adjacent_pairs_within_tie_tol=pairs, transient_over=1, n_p2pi=20000)
    write_fixture(ds, path)


def test_ledger_on_synthetic_datasets(tmp_path):
    """Reproduced, differs (with its cause test) and missing rows from hand-made datasets; every id once."""
    data = tmp_path / "data"
    _fig9(data / "fig9_ref.nc", n_loops=4, pairs=3)
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", PLAIN, FIGURES)}
    assert list(rows) == [c.id for c in parse_claims(CLAIMS_MD)]
    assert rows["C16"].verdict == "reproduced" and "4 loops" in rows["C16"].measured
    assert rows["C22"].verdict in DIFFERING and rows["C22"].reason
    # 19999^2 1e-7 / 1 = 40 near-ties by chance
    assert rows["C22"].cause.startswith("explained by the number of return times")
    assert rows["C03"].verdict == "not yet computed" and rows["C03"].measured == ""
    assert rows["F3"].verdict == "not yet computed"
    assert rows["C02"].verdict == "reproduced"  # needs only the model
    # A built figure is no better than the claims it illustrates.
    row = claims.Row(id="F12", statement="", paper_value="", verdict="reproduced")
    figure_rows.figure_from_claims(row, {"C22": rows["C22"]}, ("C22",))
    assert row.verdict == rows["C22"].verdict and "C22" in row.reason  # the figure takes its claim's word
    _fig9(data / "fig9_ref.nc", n_loops=3, pairs=0)
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", PLAIN, FIGURES)}
    assert rows["C16"].verdict in DIFFERING and rows["C22"].verdict == "reproduced" and not rows["C22"].cause
    ds = claims.to_dataset(list(rows.values()))
    assert sum(ds.attrs[f"n_{v.replace(' ', '_')}"] for v in claims.VERDICTS) == len(rows)


def test_a_cause_whose_datasets_are_missing_says_so(tmp_path):
    data = tmp_path / "data"
    write_fixture(xr.Dataset(attrs=dict(omega_rel_error_at_t_end=7e-4, t_end=100.0, u_rel_error_at_t_end=0.01,
                                        Omega_rel_error_at_t_end=0.01)), data / "fig5.nc")
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", PLAIN, FIGURES)}
    assert rows["C11"].verdict in DIFFERING and rows["C11"].cause.startswith("causes not yet computed: dataset")


def test_command_line_rejudges_without_snakemake_and_names_what_is_missing(tmp_path):
    """An empty tree: the ledger is written (every row but the model-only C02 not yet computed) and
    the exit status is 3 with every missing product named; absent directories, an absent or empty
    claims list and a bad --out stop it with status 2 before anything is judged."""
    out = tmp_path / "ledger" / "claims.csv"
    (tmp_path / "data").mkdir()
    (tmp_path / "figures").mkdir()
    run = subprocess.run([sys.executable, "-m", "sleighsim.cli", "claims", "--data", str(tmp_path / "data"),
                          "--figures", str(tmp_path / "figures"), "--out", str(out)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 3 and "missing or unreadable" in run.stderr, run.stderr
    assert str(tmp_path / "data" / "fig2.nc") in run.stderr and str(tmp_path / "figures" / "fig1.png") in run.stderr
    rows = claims.read(out.with_suffix(".nc"))
    assert {r.verdict for r in rows if r.id != "C02"} == {"not yet computed"}
    (tmp_path / "garbage.md").write_text("no table here\n")
    for args, says in ((["--data", str(tmp_path / "none")], "--data"),
                       (["--figures", str(tmp_path / "none")], "--figures"),
                       (["--claims", str(tmp_path / "none.md")], "none.md"),
                       (["--claims", str(tmp_path / "garbage.md")], "no claim rows"),
                       (["--out", str(tmp_path / "x.txt")], ".csv")):
        base = {"--data": str(tmp_path / "data"), "--figures": str(tmp_path / "figures"), "--out": str(out)}
        base.update(dict(zip(args[::2], args[1::2])))
        bad = subprocess.run([sys.executable, "-m", "sleighsim.cli", "claims", *[x for kv in base.items() for x in kv]],
                             capture_output=True, text=True, timeout=120)
        assert bad.returncode == 2 and says in bad.stderr, (args, bad.stderr)
    helped = subprocess.run([sys.executable, "-m", "sleighsim.cli", "claims", "--help"], capture_output=True, text=True)
    assert helped.returncode == 0 and "--figures" in helped.stdout


def test_caption_math_becomes_mathml():
    from sleighsim.report.page import math_html
    out = math_html("energy $E_0=0.1127$ and $\\epsilon=0.1$ <b>")
    assert "$" not in out and out.count("<math") == 2 and "&lt;b&gt;" in out


def _first_screen_colours(shot: Path) -> set[str]:
    """The verdict colours (report.COLOURS) found in the top 900 px of a screenshot."""
    from matplotlib.image import imread

    from sleighsim.report.page import COLOURS

    img = (imread(shot)[:900, :, :3] * 255).round().astype(int)
    found = set()
    for verdict, hexcol in COLOURS.items():
        rgb = [int(hexcol[i:i + 2], 16) for i in (1, 3, 5)]
        if (abs(img - rgb).max(axis=-1) <= 1).sum() > 200:
            found.add(verdict)
    return found


@pytest.mark.workflow
def test_report_renders_in_headless_chromium(smoke_run, tmp_path):
    """Render the smoke workflow's report in a 1280 x 900 window: every image loads, every claim id
    has its row, the first screen holds the whole claims grid and the chaos answer (measured by the
    browser's layout, and seen in a screenshot as the verdicts' colours)."""
    browser = screenshot.browser()
    if browser is None:
        pytest.skip("Chromium is not installed (apt-get install chromium); .ci/run installs it")
    page = smoke_run / SMOKE_RESULTS / "report" / "index.html"
    flags = screenshot.flags(tmp_path / "chrome")
    dom = subprocess.run([browser, *flags, "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120)
    m = re.search(r"images: (\d+) broken: (\d+)", dom.stdout)
    assert m, dom.stdout[-2000:] + dom.stderr[-2000:]
    assert int(m.group(1)) >= 12 and int(m.group(2)) == 0
    ids = re.findall(r' id="([^"]+)"', dom.stdout)
    assert len(ids) == len(set(ids)), sorted(i for i in set(ids) if ids.count(i) > 1)  # every link has one target
    assert "claims-grid: whole; chaos-answer: whole" in dom.stdout, re.search(r"first-screen-check.{0,120}", dom.stdout)
    ids = [c.id for c in parse_claims(CLAIMS_MD)]
    grid = dom.stdout[dom.stdout.index('id="claims-grid"'): dom.stdout.index('id="chaos-answer"')]
    assert all(f'href="#{i}"' in grid and f'<tr id="{i}"' in dom.stdout for i in ids)
    assert "Is the steady state chaotic?" in dom.stdout and "decided in" in dom.stdout
    assert dom.stdout.index('id="answers"') < dom.stdout.index('id="figures"') < dom.stdout.index('id="ledger"') \
        < dom.stdout.index('id="methods"') < dom.stdout.index('id="costs"')
    body = re.sub(r"<script.*?</script>", "", dom.stdout, flags=re.S)
    text = re.sub(r"<[^>]+>", " ", body)
    assert "$" not in text, text[text.index("$") - 200: text.index("$") + 200]
    answers = dom.stdout[dom.stdout.index('id="answers"'): dom.stdout.index('id="findings"')]
    assert "chaos_verdict" not in answers  # no dataset names in the first screen's labels
    shot = screenshot.screenshot(page, tmp_path / "shot.png", browser)  # as the README's image is made
    ledger = read_dataset(smoke_run / SMOKE_RESULTS / "claims.nc")
    assert set(ledger.verdict.values) <= _first_screen_colours(shot)  # the legend shows every verdict's colour
    md = (smoke_run / SMOKE_RESULTS / "report" / "README.md").read_text()
    assert "## Claims ledger" in md and "| C16 |" in md


@pytest.mark.parametrize("double, finest, want", [
    ("reproduced", "differs", "reproduced only in double precision"),
    ("reproduced", "cannot be reproduced", "reproduced only in double precision"),
    ("reproduced", "reproduced", "reproduced"),
    ("differs", "reproduced", "reproduced"),
    ("differs", "differs", "differs"),
    ("reproduced", "not yet computed", "not yet computed"),
])
def test_a_claim_in_two_precisions_takes_the_finer_verdict_unless_only_double_reproduces(double, finest, want):
    from sleighsim.claims.rules import Judgement

    verdict, reason = claims.in_precision(Judgement(double, "2330", ""), Judgement(finest, "2680", ""), "long double")
    assert verdict == want
    assert ("2330" in reason and "2680" in reason) == (want == "reproduced only in double precision")


def _ladder(data, scene="fig9_ref", converged="not converged"):
    write_fixture(xr.Dataset(attrs={"converged_precision": converged}), data / "ladder" / f"{scene}.nc")


def test_ledger_judges_in_the_finest_precision_computed_beside_double(tmp_path):
    """fig9_ref in double reproduces C16 (4 loops); its long-double run has 3: the row says so, and
    names the precision, the double value and the ladder's status."""
    data = tmp_path / "data"
    _fig9(data / "fig9_ref.nc", n_loops=4, pairs=0)
    _fig9(data / "precision" / "long_double" / "fig9_ref.nc", n_loops=3, pairs=0)
    _ladder(data)
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", LADDERED, FIGURES)}
    c16 = rows["C16"]
    assert c16.verdict == "reproduced only in double precision"
    assert c16.precision == "long double (fig9_ref: not converged)" and "4 loops" in c16.double_value
    assert "3 loops" in c16.measured
    assert rows["C22"].verdict == "reproduced" and rows["C22"].precision.startswith("long double")
    assert rows["C02"].precision == "double"  # judged from the model alone
    assert claims.summary(list(rows.values()))["reproduced only in double precision"] == 1
    assert c16.cause == f"{claims.ARITHMETIC}: {c16.reason}" and "4 loops" in c16.cause and "3 loops" in c16.cause
    assert rows["C22"].cause == ""  # reproduced: no cause
    fig = claims.Row(id="Fx", statement="", paper_value="", verdict="reproduced")  # a figure showing C16
    figure_rows.figure_from_claims(fig, {"C16": c16}, ("C16",))
    assert fig.verdict == "differs" and fig.cause == f"C16: {c16.cause}"  # double only: a difference of no size
    assert fig.paper_setup_verdict == ""  # C16 was not set beside a setup here
    c16.paper_setup_verdict = "differs under both (tried: K2)"
    figure_rows.figure_from_claims(fig, {"C16": c16}, ("C16",))
    assert fig.paper_setup_verdict.startswith("not applicable") and fig.paper_setup_verdict.endswith(
        "C16: differs under both (tried: K2)")


def test_a_claim_whose_realizations_disagree_is_fragile_and_one_whose_realizations_agree_keeps_its_verdict(tmp_path):
    data = tmp_path / "data"
    for k in ("", "realization/1/", "realization/2/"):
        write_fixture(_spectrum(-1e-3, 1e-4), data / f"{k}lyap_spectrum.nc")
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", REALIZED, FIGURES)}
    assert rows["C18"].verdict == "reproduced" and rows["C18"].realizations == "all 3 realizations agree"
    assert rows["C02"].realizations == ""  # no dataset, no realizations
    write_fixture(_spectrum(1e-3, 1e-4), data / "realization" / "2" / "lyap_spectrum.nc")
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", REALIZED, FIGURES)}
    c18 = rows["C18"]
    assert c18.verdict == "fragile" and c18.realizations == "realizations disagree: reproduced 2, differs 1 of 3"
    assert c18.reason.startswith(c18.realizations) and "mean divergence -0.001" in c18.measured
    assert claims.summary(list(rows.values()))["fragile"] == 1
    row = claims.Row(id="Fx", statement="", paper_value="", verdict="reproduced")  # a figure showing C18
    figure_rows.figure_from_claims(row, {"C18": c18}, ("C18",))
    assert row.verdict == "fragile" and "C18" in row.reason


def test_a_claim_judged_in_a_finer_precision_keeps_its_verdict_and_reports_its_double_realizations(tmp_path):
    """Realizations run in double: C18 judged in long double (one run) keeps long double's verdict when
    the double realizations disagree, and its column says both."""
    data = tmp_path / "data"
    for k, div in (("", -1e-3), ("realization/1/", -1e-3), ("realization/2/", 1e-3)):
        write_fixture(_spectrum(div, 1e-4), data / f"{k}lyap_spectrum.nc")
    write_fixture(_spectrum(-1e-3, 1e-4), data / "precision" / "long_double" / "lyap_spectrum.nc")
    _ladder(data, "lyap_spectrum", "long double")
    both = {"label": "paper", "scenes": {"lyap_spectrum": {**REALIZED["scenes"]["lyap_spectrum"],
                                         "precisions": ["double", "long double"]}}}
    c18 = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", both, FIGURES)}["C18"]
    assert c18.verdict == "reproduced" and c18.precision.startswith("long double")
    assert c18.realizations == "in double: realizations disagree: reproduced 2, differs 1 of 3; long double: one run"


def test_the_causes_of_a_claim_judged_in_a_finer_precision_read_that_precision(tmp_path):
    data = tmp_path / "data"
    _fig9(data / "fig9_ref.nc", n_loops=4, pairs=0)
    _fig9(data / "precision" / "long_double" / "fig9_ref.nc", n_loops=4, pairs=3)
    _ladder(data)
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", LADDERED, FIGURES)}
    c22 = rows["C22"]
    assert c22.verdict == "reproduced only in double precision"  # long double has near-ties, double none
    _fig9(data / "fig9_ref.nc", n_loops=4, pairs=3)
    c22 = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures", LADDERED, FIGURES)}["C22"]
    assert c22.verdict in DIFFERING and c22.evidence.endswith("causes: precision/long_double/fig9_ref.nc")
