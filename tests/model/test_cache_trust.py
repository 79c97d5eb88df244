"""Issue 54: a derivation file planted where sleighsim once kept its derivation cache runs nothing. The
file is never read: the derivation is made afresh and a warning names the file. Each hostile file
below ran code (or hung) when the cache was read back; the sentinel test failed against that code."""

import hashlib
import json
import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from sleighsim.model import equations
from sleighsim.model import mechanics as mech
from sleighsim.model.params import Params

SRC = str(Path(mech.__file__).resolve().parents[2])


def _planted(cache: Path, kind: str, sentinel: Path) -> Path:
    """A derivation file in the old cache's format and place (named by a hash of mechanics.py and the
    SymPy version) whose checksum is valid and whose payload is hostile in the way ``kind`` says."""
    d = mech.derive()
    poly = d.polynomial
    fields = {"M": d.M, "f": d.f, "rhs": list(d.rhs), "energy": d.energy, "lagrangian": d.lagrangian,
              "numerators": list(poly.numerators), "denominator": poly.denominator, "K": list(poly.K),
              "coefficients": list(poly.coefficients)}
    payload = {k: [sp.srepr(e) for e in v] if isinstance(v, list) else sp.srepr(v) for k, v in fields.items()}
    touch = f'__import__("os").system("touch {sentinel}")'
    first = payload["coefficients"][0]
    payload["coefficients"][0] = {
        "symbol": first.replace("Symbol('I_c'", f"Symbol('{touch} * 0 + I_c'", 1),
        "function": f"Add({first}, Function('{touch} or (lambda x: 0)')(Symbol('I_c')))",
        "code": f"{touch} * 0 + 1",
        "exponent": "Pow(Integer(10), Pow(Integer(10), Integer(10)))",
    }[kind]
    assert payload["coefficients"][0] != first
    key = hashlib.sha256(Path(mech.__file__).read_bytes() + sp.__version__.encode()).hexdigest()[:16]
    path = cache / f"derivation-{key}.json"
    digest = hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()
    path.write_text(json.dumps({"sha256": digest, "derivation": payload}))
    return path


def _fresh_caches():
    for f in (mech.derive, equations._coefficients, equations._lambdified):
        f.cache_clear()


@pytest.mark.parametrize("kind", ["symbol", "function", "code"])
def test_a_planted_derivation_file_runs_nothing_and_is_named_in_a_warning(kind, tmp_path, monkeypatch):
    cache, sentinel = tmp_path / "cache", tmp_path / "PWNED"
    cache.mkdir(mode=0o700)
    path = _planted(cache, kind, sentinel)
    expected = equations.heyoka_pars(Params.paper(eps=0.1))
    monkeypatch.setenv("SLEIGHSIM_CACHE", str(cache))
    _fresh_caches()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            pars = equations.heyoka_pars(Params.paper(eps=0.1))
            equations.rhs(np.array([0.1, 0.2, 0.3, 0.4]), Params.paper(eps=0.1))
    finally:
        _fresh_caches()
    assert not sentinel.exists()
    np.testing.assert_array_equal(pars, expected)
    assert [str(w.message) for w in caught if str(path) in str(w.message)], [str(w.message) for w in caught]


def test_a_huge_exponent_in_a_planted_file_neither_hangs_nor_exhausts_memory(tmp_path):
    """Pow(10, Pow(10, 10)) evaluated would take 4 GB and minutes: the child is limited to 2 GB and 120 s."""
    cache = tmp_path / "cache"
    cache.mkdir(mode=0o700)
    path = _planted(cache, "exponent", tmp_path / "unused")
    child = ("import resource; resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30)); "
             "from sleighsim.model import mechanics as m; print(len(m.derive().polynomial.coefficients))")
    env = {**os.environ, "SLEIGHSIM_CACHE": str(cache), "PYTHONPATH": SRC}
    res = subprocess.run([sys.executable, "-c", child], env=env, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    assert int(res.stdout) == len(mech.derive().polynomial.coefficients)
    assert re.search(re.escape(str(path)), res.stderr), res.stderr[-2000:]


def test_the_derivation_is_not_written_to_disk_and_no_warning_without_old_files(tmp_path, monkeypatch):
    monkeypatch.setenv("SLEIGHSIM_CACHE", str(tmp_path / "cache"))
    mech.derive.cache_clear()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            mech.derive()
    finally:
        mech.derive.cache_clear()
    assert not (tmp_path / "cache").exists()
