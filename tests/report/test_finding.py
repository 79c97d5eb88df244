"""The finding in one paragraph (sleighsim.report.finding, sleighsim finding): composed from the ledger and
the chaos verdicts, worded by what they say (undecided, regular elsewhere, chaotic, a smoke run), and the
README's copy in step with the committed record docs/finding.yaml."""

import pytest
import yaml
from conftest import ROOT

from sleighsim import cli
from sleighsim.claims import fidelity
from sleighsim.claims.ledger import Row
from sleighsim.ops import readme
from sleighsim.report.chaos_answers import ChaosAnswer
from sleighsim.report.finding import SCHEMA, decided, facts, paragraph

RUN = {"git_commit": "0123456789abcdef", "date": "2026-11-28"}
CLUSTER = {"config": "config/cluster.yaml", "realizations": [
    {"state": "main", "verdict": "regular", "precision": "double-double", "T": 5e5, "created_utc": f"2026-11-2{k}"}
    for k in (5, 6, 6)]}


def _rows(verdicts: dict, run_verdict: str = "") -> list[Row]:
    return [Row(i, "", "", verdict=v, run_verdict=run_verdict) for i, v in verdicts.items()]


def _facts(states: dict, label="paper", cluster=None, rows=None):
    rows = rows or _rows({"F1": "reproduced", "C19": "differs", "C20": "differs", "C21": "cannot be reproduced"})
    chaos = [ChaosAnswer(s, v, "") for s, v in states.items()]
    return facts(rows, chaos, cluster, fidelity.identity({"label": label, "scenes": {}}), RUN)


def test_the_facts_count_the_ledger_and_name_the_chaos_claims_and_states():
    f = _facts({"main": "undecided"}, cluster=CLUSTER)
    assert f["schema"] == SCHEMA and f["reproduction"] and f["n_rows"] == 4
    assert f["counts"] == {"reproduced": 1, "differs": 2, "cannot be reproduced": 1}
    assert f["chaos_claims"] == {"C19": "differs", "C20": "differs", "C21": "cannot be reproduced"}
    assert f["elsewhere"] == [{"state": "main", "config": "config/cluster.yaml", "n": 3, "counts": {"regular": 3},
                               "precision": "double-double", "T": 5e5, "date": "2026-11-26"}]


def test_no_state_decided_neither_confirms_nor_refutes():
    text = paragraph(_facts({"main": "undecided", "rotor_a": "undecided"}))
    assert 'here main and rotor_a are "undecided"' in text
    assert text.endswith("neither confirm nor refute the paper's claim that the steady state is chaotic: no "
                         "steady state is decided.")
    assert 'C19 and C20 "differs"; C21 "cannot be reproduced"' in text
    assert "of the paper's 4 figures, claims and model items the ledger finds 1 \"reproduced\"" in text


def test_a_state_decided_regular_with_another_config_is_named_with_it():
    f = _facts({"main": "undecided", "rotor_a": "undecided"}, cluster=CLUSTER)
    assert decided(f) == {"main": ("regular", "config/cluster.yaml")}
    text = paragraph(f)
    assert 'with config/cluster.yaml (double-double over T = 500000, 2026-11-26), main is "regular" in 3 of 3' in text
    assert text.endswith("(main, with config/cluster.yaml) it is regular, against the paper's claim that it is "
                         "chaotic; rotor_a remains undecided.")


def test_realizations_that_disagree_decide_nothing():
    split = {**CLUSTER, "realizations": [*CLUSTER["realizations"][:2], {**CLUSTER["realizations"][2],
                                                                         "verdict": "chaotic"}]}
    assert decided(_facts({"main": "undecided"}, cluster=split)) == {}


@pytest.mark.parametrize("states, end", [
    ({"main": "chaotic"}, "support the paper's claim that the steady state is chaotic for main."),
    ({"main": "chaotic", "rotor_a": "regular", "rotor_b": "fragile"},
     "holds for main and not for rotor_a, found regular; rotor_b remains undecided."),
])
def test_a_decided_run_says_whether_the_claim_holds(states, end):
    assert paragraph(_facts(states)).endswith(end)


def test_a_smoke_run_finds_nothing_about_the_paper_and_counts_its_own_data():
    rows = _rows({"F1": "not a reproduction", "C19": "not a reproduction"}, run_verdict="reproduced")
    f = _facts({"main": "undecided"}, label="smoke", cluster=CLUSTER, rows=rows)
    assert not f["reproduction"] and f["counts"] == {"reproduced": 2} and f["elsewhere"] == []
    text = paragraph(f)
    assert text.startswith("This smoke run (config smoke") and "is NOT a reproduction" in text
    assert "bears on the paper's claims" in text and "claim that it is chaotic" not in text


def test_the_readme_holds_the_paragraph_of_the_committed_record():
    """Regenerate with: sleighsim finding results/report/finding.yaml --record docs/finding.yaml --readme README.md
    (results of a paper-fidelity run)."""
    record = yaml.safe_load((ROOT / "docs" / "finding.yaml").read_text())
    assert record["schema"] == SCHEMA and record["reproduction"]
    assert readme.block((ROOT / "README.md").read_text(), "finding") == paragraph(record) + "\n"


def test_the_command_keeps_a_reproductions_finding_and_refuses_a_smoke_runs(tmp_path, capsys):
    paper, smoke = tmp_path / "paper.yaml", tmp_path / "smoke.yaml"
    paper.write_text(yaml.safe_dump(_facts({"main": "undecided"})))
    smoke.write_text(yaml.safe_dump(_facts({"main": "undecided"}, label="smoke")))
    page = tmp_path / "README.md"
    page.write_text("<!-- BEGIN finding: generated -->\nold\n<!-- END finding -->\n")
    assert cli.main(["finding", str(paper), "--record", str(tmp_path / "kept.yaml"), "--readme", str(page)]) == 0
    assert readme.block(page.read_text(), "finding") == paragraph(yaml.safe_load(paper.read_text())) + "\n"
    assert (tmp_path / "kept.yaml").read_text() == paper.read_text()
    assert cli.main(["finding", str(smoke), "--readme", str(page)]) == 2
    assert "not a reproduction" in capsys.readouterr().err
    assert cli.main(["finding", str(smoke)]) == 0 and "NOT a reproduction" in capsys.readouterr().out
