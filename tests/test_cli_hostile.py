"""Issue 55: ``sleighsim claims --claims`` naming a binary file is a usage error (before: a
UnicodeDecodeError traceback)."""

from sleighsim import cli


def test_claims_on_a_binary_claims_file_is_a_usage_error(tmp_path, capsys):
    (tmp_path / "data").mkdir()
    (tmp_path / "figures").mkdir()
    status = cli.main(["claims", "--claims", "/bin/ls", "--data", str(tmp_path / "data"), "--figures",
                       str(tmp_path / "figures"), "--out", str(tmp_path / "claims.csv")])
    assert status == 2 and "--claims /bin/ls: not a UTF-8 text file" in capsys.readouterr().err
