"""Which datasets the claims ledger reads is what the run's config declares (its precision ladders
and realizations: sleighsim.scenes.catalog.laddered, realized), never which files lie in the data
directory: a stale file from an older config is not read, and a declared one that was not built
leaves its claim "not yet computed"."""

import subprocess
import sys

import yaml
from conftest import SMOKE, write_fixture
from test_claims_report import CLAIMS_MD, LADDERED, PLAIN, REALIZED, _fig9, _ladder
from test_judges import _spectrum

from sleighsim.claims import ledger as claims
from sleighsim.claims.rules import DIFFERING
from sleighsim.io import layout
from sleighsim.ops.config import merged_config
from sleighsim.report.figures.catalog import FIGURES
from sleighsim.scenes import catalog

FINE = "precision/double_double/fig9_ref"


def _rows(data, config):
    return {r.id: r for r in claims.ledger(CLAIMS_MD, data, data.parent / "figures", config, FIGURES)}


def _spectra(data, ks, div=-1e-3):
    """lyap_spectrum's realizations ``ks`` (0: the scene itself); contracting (C18 reproduced) at div < 0."""
    for k in ks:
        write_fixture(_spectrum(div, 1e-4), data / f"{layout.realization('lyap_spectrum', k)}.nc")


def _laddered_fig9(data, loops_double=4, loops_fine=3):
    _fig9(data / "fig9_ref.nc", n_loops=loops_double, pairs=0)
    _fig9(data / f"{FINE}.nc", n_loops=loops_fine, pairs=0)
    _ladder(data)


def test_the_smoke_config_judges_fig9_ref_in_double_double_and_lyap_spectrum_on_every_realization(tmp_path):
    config = merged_config([SMOKE])
    n = catalog.realized(config, on_request=True)["lyap_spectrum"]
    assert "double-double" in catalog.laddered(config, on_request=True)["fig9_ref"] and n >= 3
    data = tmp_path / "data"
    _laddered_fig9(data)
    _spectra(data, range(n))
    rows = _rows(data, config)
    assert rows["C16"].precision.startswith("double-double") and "3 loops" in rows["C16"].measured
    assert rows["C18"].realizations == f"all {n} realizations agree"


def test_a_stale_precision_variant_the_config_does_not_ask_for_is_not_read(tmp_path):
    data = tmp_path / "data"
    _laddered_fig9(data)  # left from an older config that laddered fig9_ref
    rows = _rows(data, PLAIN)
    assert rows["C16"].precision == "double" and rows["C16"].verdict == "reproduced"
    assert "4 loops" in rows["C16"].measured and rows["C16"].double_value == ""
    _fig9(data / "fig9_ref.nc", n_loops=4, pairs=3)  # C22 differs in double: its causes read double too
    c22 = _rows(data, PLAIN)["C22"]
    assert c22.verdict in DIFFERING and c22.evidence.endswith("causes: fig9_ref.nc")


def test_a_declared_precision_variant_or_ladder_not_built_leaves_the_claim_not_yet_computed(tmp_path):
    data = tmp_path / "data"
    _fig9(data / "fig9_ref.nc", n_loops=4, pairs=0)
    _ladder(data)
    c16 = _rows(data, LADDERED)["C16"]  # LADDERED: fig9_ref in long double
    long = layout.variant("fig9_ref", "long double")
    assert c16.verdict == "not yet computed" and long in c16.reason and c16.measured == ""
    _fig9(data / f"{long}.nc", n_loops=4, pairs=0)
    (data / "ladder" / "fig9_ref.nc").unlink()
    c16 = _rows(data, LADDERED)["C16"]
    assert c16.verdict == "not yet computed" and "ladder/fig9_ref" in c16.reason


def test_a_stale_realization_the_config_does_not_ask_for_is_not_read(tmp_path):
    data = tmp_path / "data"
    _spectra(data, range(3))
    _spectra(data, [3], div=1e-3)  # realization 3, left from an older config, would make C18 fragile
    assert _rows(data, REALIZED)["C18"].realizations == "all 3 realizations agree"
    c18 = _rows(data, PLAIN)["C18"]
    assert c18.verdict == "reproduced" and c18.realizations == ""


def test_a_declared_realization_not_built_leaves_the_claim_not_yet_computed(tmp_path):
    data = tmp_path / "data"
    _spectra(data, [0, 1])  # realization 2 of 3 missing: not judged on the two there are
    c18 = _rows(data, REALIZED)["C18"]
    assert c18.verdict == "not yet computed" and "realization/2/lyap_spectrum" in c18.reason
    assert c18.realizations == ""
    _spectra(data, [2])
    (data / "realization" / "1" / "lyap_spectrum.nc").unlink()
    c18 = _rows(data, REALIZED)["C18"]
    assert c18.verdict == "not yet computed" and "realization/1/lyap_spectrum" in c18.reason


def _cli(tmp_path, *config):
    """The ledger the command line writes from a partial tree (it exits 3, naming what is missing)."""
    out = tmp_path / "ledger" / "claims.csv"
    (tmp_path / "figures").mkdir(exist_ok=True)
    run = subprocess.run([sys.executable, "-m", "sleighsim.cli", "claims", "--data", str(tmp_path / "data"),
                          "--figures", str(tmp_path / "figures"), "--out", str(out), *config], check=False,
                         capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 3 and "are missing or unreadable" in run.stderr, run.stderr
    return {r.id: r for r in claims.read(out.with_suffix(".nc"))}


def test_command_line_reads_the_ladders_and_realizations_of_the_config_files_it_is_given(tmp_path):
    """No --config: config/config.yaml; --config files are merged onto it in order (a file that sets
    one key of one scene is enough)."""
    n = catalog.realized(merged_config(), on_request=True)["lyap_spectrum"]
    data = tmp_path / "data"
    _laddered_fig9(data)
    _spectra(data, range(n))
    rows = _cli(tmp_path)
    assert rows["C16"].precision.startswith("double-double")
    assert rows["C18"].realizations == f"all {n} realizations agree"
    more = tmp_path / "more.yaml"
    more.write_text(yaml.safe_dump({"scenes": {"lyap_spectrum": {"realizations": n + 1}}}))
    c18 = _cli(tmp_path, "--config", str(SMOKE), str(more))["C18"]  # a smoke run: judged against nothing
    assert c18.verdict == "not a reproduction" and c18.run_verdict == "not yet computed"
    assert f"realization/{n}/lyap_spectrum" in c18.reason and c18.reason.startswith("a smoke run (config smoke")
    bad = subprocess.run([sys.executable, "-m", "sleighsim.cli", "claims", "--out", str(tmp_path / "x.csv"), "--config",
                          str(tmp_path / "none.yaml")], check=False, capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "none.yaml: no such file" in bad.stderr
