"""Claims ledger rules, completeness against CLAIMS.md, and the rendered report."""

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sleighsim.outputs import claims
from sleighsim.io import write_dataset

ROOT = Path(__file__).resolve().parents[1]
CLAIMS_MD = ROOT / "paper" / "CLAIMS.md"


def test_parse_claims_finds_every_table_row_once():
    text = CLAIMS_MD.read_text()
    ids_in_file = re.findall(r"^\|\s*([FCD]\d+)\s*\|", text, flags=re.M)
    parsed = [cid for cid, _, _ in claims.parse_claims(CLAIMS_MD)]
    assert parsed == ids_in_file and len(set(parsed)) == len(parsed)
    assert {c[0] for c in parsed} == {"F", "C", "D"}


def test_number_rule():
    assert claims.judge_number(2200.0, 2080.0) == "reproduced"  # within 10%
    assert claims.judge_number(8700.0, 5440.0) == "differs"
    assert claims.judge_number(1.0, 1.5, uncertainty=0.3) == "reproduced"  # within 2 standard errors
    assert claims.judge_number(1.0, float("nan")) == "not yet computed"
    assert claims.judge_interval((1.45, 1.8), (1.46, 1.79)) == "reproduced"
    assert claims.judge_interval((1.45, 1.8), (0.52, 0.57)) == "differs"


def _fig9(path, n_loops, pairs):
    ds = xr.Dataset()
    ds.attrs.update(n_loops=n_loops, loops_per_class=np.ones(4, np.int32), n_components_projected=2,
                    return_time_min=1.0, return_time_max=2.0, return_time_min_pairwise_difference=1e-3,
                    return_time_n_adjacent_pairs_within_tie_tol=pairs, transient_over=1)
    write_dataset(ds, path)


def test_ledger_on_synthetic_datasets(tmp_path):
    """Reproduced, differs and missing rows from hand-made datasets; every id exactly once."""
    data = tmp_path / "data"
    _fig9(data / "fig9_ref.nc", n_loops=4, pairs=3)
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures")}
    assert list(rows) == [cid for cid, _, _ in claims.parse_claims(CLAIMS_MD)]
    assert rows["C16"].verdict == "reproduced" and "4 loops" in rows["C16"].measured
    assert rows["C22"].verdict == "differs" and rows["C22"].reason
    assert rows["C03"].verdict == "not yet computed" and rows["C03"].measured == ""
    assert rows["F3"].verdict == "not yet computed"
    assert rows["C02"].verdict == "reproduced"  # needs only the model
    # A built figure is no better than the claims it illustrates.
    row = claims.Row(id="F12", statement="", paper_value="", verdict="reproduced")
    claims._figure_from_claims(row, {"C22": rows["C22"]}, ("C22",))
    assert row.verdict == "differs" and "C22" in row.reason
    _fig9(data / "fig9_ref.nc", n_loops=3, pairs=0)
    rows = {r.id: r for r in claims.ledger(CLAIMS_MD, data, tmp_path / "figures")}
    assert rows["C16"].verdict == "differs" and rows["C22"].verdict == "reproduced"
    ds = claims.to_dataset(list(rows.values()))
    assert sum(ds.attrs[f"n_{v.replace(' ', '_')}"] for v in claims.VERDICTS) == len(rows)


def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    return None


@pytest.mark.workflow
def test_report_renders_in_headless_chromium(smoke_run, tmp_path):
    """Render the smoke workflow's report: every image loads and every claim id appears."""
    browser = _chromium()
    if browser is None:
        pytest.skip("Chromium is not installed (apt-get install chromium); .ci/run installs it")
    page = smoke_run / "results" / "report" / "index.html"
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", "--no-first-run", f"--user-data-dir={tmp_path / 'chrome'}",
             "--virtual-time-budget=10000"]
    dom = subprocess.run([browser, *flags, "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120)
    m = re.search(r"images: (\d+) broken: (\d+)", dom.stdout)
    assert m, dom.stdout[-2000:] + dom.stderr[-2000:]
    assert int(m.group(1)) >= 12 and int(m.group(2)) == 0
    for cid, _, _ in claims.parse_claims(CLAIMS_MD):
        assert f"id='{cid}'" in page.read_text() or f'id="{cid}"' in dom.stdout, cid
    shot = tmp_path / "shot.png"
    subprocess.run([browser, *flags, f"--screenshot={shot}", "--window-size=1200,2000", page.as_uri()],
                   capture_output=True, timeout=120)
    assert shot.exists() and shot.stat().st_size > 10000
    md = (smoke_run / "results" / "report" / "README.md").read_text()
    assert "## Claims ledger" in md and "| C16 |" in md
