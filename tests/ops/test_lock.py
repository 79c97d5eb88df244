import hashlib
import re
import shutil
import subprocess
import sys

import pytest
from conftest import ROOT

from sleighsim.io import lockfile
from sleighsim.ops import lockcheck


def test_the_checkouts_locks_are_in_step_with_pyproject():
    assert lockcheck.problems(ROOT) == []
    res = subprocess.run([sys.executable, "-m", "sleighsim.ops.lockcheck"], capture_output=True, text=True)
    assert res.returncode == 0 and "in step" in res.stdout, res.stdout + res.stderr


@pytest.fixture
def checkout(tmp_path):
    """A copy of the checkout's pyproject.toml and locks to spoil."""
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    shutil.copytree(ROOT / "requirements", tmp_path / "requirements")
    return tmp_path


def _edit(path, old, new):
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))


def test_a_dependency_unpinned_or_outside_its_specifier_or_without_hashes_is_reported(checkout):
    lock = checkout / "requirements" / "py311.lock"
    numpy = lockfile.pins(lock)["numpy"]
    _edit(checkout / "pyproject.toml", '"numpy>=1.26"', f'"numpy>{numpy}"')
    _edit(checkout / "pyproject.toml", '"pyyaml>=6.0"', '"pyyaml>=6.0", "tomli-w>=1.0"')
    lock.write_text(re.sub(r"(sympy==\S+) \\\n(    --hash=\S+( \\)?\n)+", r"\1\n", lock.read_text()))
    found = lockcheck.problems(checkout)
    assert f"py311.lock: numpy=={numpy} is outside numpy>{numpy}" in found
    assert "py311.lock: tomli-w>=1.0 is not pinned" in found
    assert f"py311.lock: sympy=={lockfile.pins(lock)['sympy']} has no hashes" in found
    assert "py311-test.lock: tomli-w>=1.0 is not pinned" in found
    assert lockcheck.main(["--root", str(checkout)]) == 1


def test_locks_that_pin_a_shared_package_differently_are_reported(checkout):
    test_lock = checkout / "requirements" / "py311-test.lock"
    version = lockfile.pins(test_lock)["jinja2"]
    _edit(test_lock, f"jinja2=={version}", "jinja2==3.1.0")
    assert lockcheck.problems(checkout) == [f"py311-test.lock: jinja2==3.1.0, but py311.lock pins {version}"]


def test_no_lock_is_exit_status_2(tmp_path):
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    (tmp_path / "requirements").mkdir()
    assert lockcheck.main(["--root", str(tmp_path)]) == 2


def _lock(path, pins):
    path.write_text("".join(f"{n}=={v} \\\n    --hash=sha256:{'0' * 64}\n" for n, v in pins.items()))
    return path


def test_datasets_name_the_lock_only_when_the_environment_matches_it_pin_for_pin(tmp_path, monkeypatch):
    have = lockfile.installed()
    required = {name: have[name] for name in lockfile.required()}  # a lock pins every requirement (issue 55)
    matching = _lock(tmp_path / "a.lock", {**required, "NumPy": have["numpy"], "netCDF4": have["netcdf4"]})
    monkeypatch.setenv("SLEIGHSIM_LOCK", str(matching))
    lockfile.lock_attrs.cache_clear()
    assert lockfile.lock_attrs() == {"lock_file": "a.lock",
                                     "lock_sha256": hashlib.sha256(matching.read_bytes()).hexdigest()}
    for pins in ({"numpy": have["numpy"] + ".1"}, {"numpy": have["numpy"], "no-such-package": "1.0"}, {}):
        monkeypatch.setenv("SLEIGHSIM_LOCK", str(_lock(tmp_path / "b.lock", pins)))
        lockfile.lock_attrs.cache_clear()
        assert lockfile.lock_attrs() == {}, pins
    lockfile.lock_attrs.cache_clear()
