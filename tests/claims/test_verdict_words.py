"""The ledger's verdict words: a difference worded by its size, a failed process check apart from a difference,
a run not at the paper's fidelity judged against nothing, the configuration's identity, and the verdicts
as CF flags."""

import math

import numpy as np
import pytest
import xarray as xr
from conftest import SMOKE, write_fixture
from test_claims_report import CLAIMS_MD, PLAIN

from sleighsim.claims import fidelity, figure_rows, rules
from sleighsim.claims import ledger as claims
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset
from sleighsim.ops.config import merged_config
from sleighsim.report.figures.catalog import FIGURES


@pytest.mark.parametrize("verdict, difference, word", [
    ("differs", 0.12, "differs slightly"),
    ("differs", rules.SLIGHT - 1e-9, "differs slightly"),
    ("differs", rules.SLIGHT, "differs"),
    ("differs", 0.4, "differs"),
    ("differs", rules.GREAT, "differs greatly"),
    ("differs", 26.0, "differs greatly"),  # a 27-fold band
    ("differs", math.nan, "differs"),  # a qualitative claim: no size measured
    ("reproduced", 0.4, "reproduced"),
    ("not yet computed", math.nan, "not yet computed"),
])
def test_a_difference_is_worded_by_its_size(verdict, difference, word):
    assert rules.severity(verdict, difference) == word


def test_every_verdict_has_a_meaning_and_differing_words_rank_mildest_first():
    assert set(rules.MEANINGS) == set(rules.VERDICTS) and len(rules.VERDICTS) == len(set(rules.VERDICTS))
    assert rules.DIFFERING == ("differs slightly", "differs", "differs greatly")
    assert rules.SLIGHT < rules.GREAT and rules.REL_TOL < rules.SLIGHT


def _row(cid, verdict, **kw):
    return claims.Row(id=cid, statement="", paper_value="", verdict=verdict, **kw)


def test_a_figure_takes_the_most_severe_word_of_its_differing_claims_and_a_failed_check_stays_apart():
    judged = {"C1": _row("C1", "differs slightly"), "C2": _row("C2", "differs greatly"), "C3": _row("C3", "reproduced")}
    fig = _row("F1", "reproduced")
    figure_rows.figure_from_claims(fig, judged, ("C1", "C2", "C3"))
    assert fig.verdict == "differs greatly" and fig.reason == "its claims differ: C1, C2"
    fig = _row("F1", "reproduced")
    figure_rows.figure_from_claims(fig, judged, ("C3",))
    assert fig.verdict == "reproduced"
    failed = _row("F1", "check failed", reason="the transient is not shown to be over in fig8.nc")
    figure_rows.figure_from_claims(failed, judged, ("C3",))
    assert failed.verdict == "check failed" and failed.reason.endswith("; its claims: C3 reproduced")


def test_a_failed_check_without_spikes_names_what_it_could_not_measure():
    ds = xr.Dataset(attrs={"transient_over": 0, "transient_n_spikes": 0, "transient_first_spike": math.nan,
                           "transient_spike_interval_mean_first_half": math.nan,
                           "transient_spike_interval_mean_second_half": 2300.0, "transient_settling_time": math.nan})
    text = figure_rows.transient_cause("fig9_ref", ds)
    assert "nan" not in text.lower()
    assert text == ("fig9_ref: the pre-run holds 0 spikes, no spike interval over the first half, spike interval "
                    "over the second half 2300, no settling time: too short to show the transient over")


def test_the_label_decides_whether_a_run_is_judged_against_the_paper():
    assert fidelity.reproduction({"label": "paper"}) and fidelity.reproduction({"label": "cluster"})
    assert not fidelity.reproduction({"label": "smoke"}) and not fidelity.reproduction({"label": "mine"})
    with pytest.raises(ValueError, match="names no 'label'"):
        fidelity.label({"scenes": {}})
    smoke, paper = merged_config([SMOKE]), merged_config()
    assert fidelity.label(smoke) == "smoke" and fidelity.label(paper) == "paper"
    assert smoke["results"] != paper["results"]  # a smoke run never replaces a paper run's results


def test_the_config_hash_ignores_key_order_and_sees_every_value():
    a = {"label": "paper", "scenes": {"x": {"kind": "k", "T": 1.0}}}
    b = {"scenes": {"x": {"T": 1.0, "kind": "k"}}, "label": "paper"}
    assert fidelity.config_sha256(a) == fidelity.config_sha256(b)
    assert fidelity.config_sha256(a) != fidelity.config_sha256({**a, "scenes": {"x": {"kind": "k", "T": 1.5}}})
    ident = fidelity.identity(a)
    assert ident["config_label"] == "paper" and len(ident["config_sha256"]) == 64
    assert fidelity.describe(ident) == f"config paper (sha256 {ident['config_sha256'][:12]})"


def test_a_smoke_ledger_calls_nothing_reproduced_and_keeps_its_own_datas_verdict(tmp_path):
    """The same datasets judged as a paper run and as a smoke run: the smoke rows all read "not a
    reproduction", each keeping the paper run's verdict as its run_verdict; the paper rows' run_verdict is
    their verdict. A config without a label is refused before anything is judged."""
    data = tmp_path / "data"
    write_fixture(xr.Dataset(attrs=dict(omega_rel_error_at_t_end=7e-4, t_end=100.0, u_rel_error_at_t_end=0.01,
                                        Omega_rel_error_at_t_end=0.01)), data / "fig5.nc")
    paper = claims.ledger(CLAIMS_MD, data, tmp_path / "figures", PLAIN, FIGURES)
    smoke = claims.ledger(CLAIMS_MD, data, tmp_path / "figures", {**PLAIN, "label": "smoke"}, FIGURES)
    assert {r.verdict for r in paper} >= {"reproduced", "not yet computed"}
    assert all(r.run_verdict == r.verdict for r in paper)
    assert {r.verdict for r in smoke} == {"not a reproduction"}
    assert [r.run_verdict for r in smoke] == [r.verdict for r in paper]
    c02 = {r.id: r for r in smoke}["C02"]
    assert c02.reason.startswith("a smoke run (config smoke (sha256 ") and "on its own data, reproduced" in c02.reason
    with pytest.raises(ValueError, match="label"):
        claims.ledger(CLAIMS_MD, data, tmp_path / "figures", {"scenes": {}}, FIGURES)


def test_the_ledger_dataset_holds_its_verdicts_as_cf_flags_and_the_configs_identity(tmp_path):
    rows = [_row("C1", "reproduced", run_verdict="reproduced"), _row("C2", "not a reproduction", run_verdict="differs"),
            _row("F1", "check failed", run_verdict="check failed")]
    ident = fidelity.identity({"label": "smoke", "scenes": {}})
    claims.write(rows, tmp_path / "claims.csv", tmp_path / "claims.nc", identity=ident)
    ds = read_dataset(tmp_path / "claims.nc")
    assert ds.attrs["config_label"] == "smoke" and ds.attrs["config_sha256"] == ident["config_sha256"]
    assert "smoke" in ds.attrs["fidelity_rule"] and ds.attrs["slight"] == rules.SLIGHT
    for var, text in (("verdict_flag", "verdict"), ("run_verdict_flag", "run_verdict")):
        flag = ds[var]
        meanings = flag.attrs["flag_meanings"].split()
        assert list(flag.attrs["flag_values"]) == list(range(len(meanings))) and flag.dtype == np.int8
        assert [meanings[v].replace("_", " ") for v in flag.values] == [str(x) for x in ds[text].values]
        assert flag.attrs["long_name"] == claims.VOCABULARY[var][0] and flag.attrs["units"] == "1"
    assert cf.missing(ds) == []
    assert [r.run_verdict for r in claims.read(tmp_path / "claims.nc")] == ["reproduced", "differs", "check failed"]
    assert (tmp_path / "claims.csv").read_text().splitlines()[0].endswith(",run_verdict")


@pytest.mark.parametrize("text, want", [
    ("nan from 0 intervals (sd nan)", "not computed from 0 intervals (sd not computed)"),
    ("transient ~nan time units; lambda_1 nan", "transient ~not computed time units; lambda_1 not computed"),
    ("nanoseconds, finance, fig_nan, 1.nan", "nanoseconds, finance, fig_nan, 1.nan"),  # words that hold nan are kept
    ("NaN", "not computed"),
])
def test_a_number_a_judge_could_not_compute_reads_as_words(text, want):
    assert rules.readable(text) == want


def test_the_ledger_writes_no_bare_nan(tmp_path, monkeypatch):
    for cid in list(claims.JUDGES):
        monkeypatch.setitem(claims.JUDGES, cid, lambda paper, *ds: rules.Judgement(
            "not yet computed", f"{math.nan:.3g} from 0 intervals", "a rule", reason=f"lambda_1 {math.nan}"))
    rows = claims.ledger(CLAIMS_MD, tmp_path, tmp_path, PLAIN, FIGURES)
    judged = [r for r in rows if r.id in claims.JUDGES and r.verdict == "not yet computed" and r.measured]
    assert judged and all(r.measured == "not computed from 0 intervals" for r in judged)
    assert not any(rules._NAN.search(v) for r in rows for v in vars(r).values() if isinstance(v, str))
