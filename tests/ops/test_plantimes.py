"""The README's times table: generated from the committed benchmark records (sleighsim.ops.plantimes),
written between markers (sleighsim.ops.readme), and in step with the records and the cluster config."""

import shutil

import pytest
import yaml
from conftest import ROOT

from sleighsim.claims.fidelity import config_sha256
from sleighsim.ops import costs, plantimes, readme
from sleighsim.ops.config import merged_config

DOC = "intro\n<!-- BEGIN times: generated -->\nold\n<!-- END times -->\nrest\n"


def test_a_block_is_read_and_replaced_between_its_markers():
    assert readme.block(DOC, "times") == "old\n"
    new = readme.replaced(DOC, "times", "| a |\n")
    assert new == "intro\n<!-- BEGIN times: generated -->\n| a |\n<!-- END times -->\nrest\n"
    assert readme.block(new, "times") == "| a |\n"


@pytest.mark.parametrize("text", ["no markers", DOC + DOC, "<!-- END times -->\n<!-- BEGIN times -->\n"])
def test_a_block_whose_markers_are_missing_repeated_or_reversed_is_refused(text):
    with pytest.raises(ValueError, match="BEGIN times"):
        readme.block(text, "times")


def _records(tmp_path, *names):
    (tmp_path / "benchmarks").mkdir()
    for name in names:
        shutil.copy(ROOT / name, tmp_path / name)
    return tmp_path


def test_each_record_present_gives_its_rows_and_an_absent_one_none(tmp_path):
    full = yaml.safe_load((ROOT / plantimes.FULL_RUN).read_text())
    rows = plantimes.rows(_records(tmp_path, plantimes.FULL_RUN))
    assert [r[0] for r in rows] == ["full run at paper fidelity, 2 cores (measured)",
                                    "full run at paper fidelity on 4 / 8 / 16 cores (predicted)"]
    assert rows[0][2].startswith(plantimes.duration(full["wall_s"])) and f"{full['jobs_total']} jobs" in rows[0][2]
    assert full["git_commit"][:8] in rows[0][3] and plantimes.FULL_RUN in rows[0][3]
    (tmp_path / "none").mkdir()
    assert plantimes.rows(_records(tmp_path / "none")) == []


def test_each_timed_command_that_ended_well_gives_a_row(tmp_path):
    (tmp_path / "benchmarks").mkdir()
    record = {"date": "2026-11-29T08:00:00+00:00", "git_commit": "0123456789abcdef" * 2 + "01234567",
              "machine": {"nproc": 2, "cpu_model": "AMD EPYC"},
              "runs": [{"what": "the executed tutorial", "command": "python docs/tutorial.py", "wall_s": 526.0,
                        "returncode": 0},
                       {"what": "a judged state", "command": "sleighsim judge", "wall_s": 60.0, "returncode": 1}]}
    (tmp_path / plantimes.COMMANDS).write_text(yaml.safe_dump(record))
    rows = plantimes.rows(tmp_path)
    assert [r[:3] for r in rows] == [("the executed tutorial, one process (measured)", "`python docs/tutorial.py`",
                                      plantimes.duration(526.0))]  # the failed command gives no row
    assert plantimes.COMMANDS in rows[0][3] and "commit 01234567" in rows[0][3]


def test_the_readme_holds_the_table_the_records_give():
    """Regenerate with: sleighsim costs times --readme README.md"""
    assert readme.block((ROOT / "README.md").read_text(), plantimes.BLOCK) == plantimes.table()


def test_the_table_has_a_row_per_committed_record():
    whats = [r[0] for r in plantimes.rows()]
    assert any(w.startswith("full run") for w in whats) and any(w.startswith("smoke run") for w in whats)
    assert any(w.startswith("cluster config") for w in whats)


def test_the_committed_cluster_estimate_is_of_todays_cluster_config_and_full_run():
    """Rewrite it with: sleighsim costs estimate --configfile config/cluster.yaml --out benchmarks/cluster_estimate.yaml
    (then sleighsim costs times --readme README.md)."""
    record = yaml.safe_load((ROOT / plantimes.CLUSTER).read_text())
    full = yaml.safe_load((ROOT / plantimes.FULL_RUN).read_text())
    assert record["schema"] == costs.RECORD_SCHEMA
    assert record["config"]["sha256"] == config_sha256(merged_config([ROOT / "config" / "cluster.yaml"]))
    assert record["measured"]["date"] == full["date"] and record["measured"]["file"] == plantimes.FULL_RUN
    assert record["schedule"]["wall_s"] and record["schedule"]["longest"]["job"]


def test_the_times_command_writes_the_block_and_refuses_a_file_without_one(tmp_path, capsys):
    target = tmp_path / "README.md"
    target.write_text(DOC)
    assert costs.main(["times", "--readme", str(target)]) == 0
    assert readme.block(target.read_text(), "times") == plantimes.table()
    target.write_text("no block")
    assert costs.main(["times", "--readme", str(target)]) == 2 and "BEGIN times" in capsys.readouterr().err
    assert costs.main(["times"]) == 0 and capsys.readouterr().out == plantimes.table()
