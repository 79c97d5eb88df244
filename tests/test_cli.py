"""The ``sleighsim`` command (sleighsim.cli): each subcommand runs its module's main with the rest
of the arguments and returns its exit status; a missing or unknown subcommand is a usage error."""

import numpy as np
import pytest
import xarray as xr

from sleighsim import cli
from sleighsim.io.netcdf import write_dataset


def test_help_lists_every_subcommand(capsys):
    with pytest.raises(SystemExit) as stop:
        cli.main(["--help"])
    assert stop.value.code == 0
    out = capsys.readouterr().out
    assert all(name in out for name in cli.COMMANDS)


@pytest.mark.parametrize("argv", [[], ["nosuch"]])
def test_a_missing_or_unknown_subcommand_is_a_usage_error(argv):
    with pytest.raises(SystemExit) as stop:
        cli.main(argv)
    assert stop.value.code == 2


def test_diff_returns_the_comparison_status(tmp_path):
    for name, value in (("old", 1.0), ("same", 1.0), ("moved", 1.5)):
        (tmp_path / name / "data").mkdir(parents=True)
        write_dataset(xr.Dataset({"x": ("t", np.array([value]))}), tmp_path / name / "data" / "a.nc")
    assert cli.main(["diff", str(tmp_path / "old"), str(tmp_path / "same")]) == 0
    assert cli.main(["diff", str(tmp_path / "old"), str(tmp_path / "moved")]) == 1


def test_claims_refuses_an_absent_data_directory(tmp_path):
    assert cli.main(["claims", "--data", str(tmp_path / "absent")]) == 2


@pytest.mark.parametrize("name", list(cli.COMMANDS))
def test_each_subcommands_help_names_it_in_plain_text(name, capsys):
    """`sleighsim NAME --help` prints a usage naming `sleighsim NAME` (it printed `__main__.py` or
    `python -m ...`) and no reStructuredText markup."""
    assert cli.main([name, "--help"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"usage: sleighsim {name} ")
    assert "``" not in out and ":mod:" not in out and ":func:" not in out
