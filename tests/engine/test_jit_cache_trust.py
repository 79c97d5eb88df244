"""Issue 54: every heyoka compilation checks the JIT cache directory first (heyoka runs the code it finds
there), not only those built through integrators.compiled: each builder below compiled from an unchecked
directory before. numba's cache (it unpickles what it finds there) is checked the same way."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from sleighsim.io.cachedir import UnsafeDirectory

hy = pytest.importorskip("heyoka")


def _oscillator():
    x, v = hy.make_vars("x", "v")
    return [(x, v), (v, -x)]


def _builders():
    from sleighsim.chaos import audit_orbits
    from sleighsim.engine import integrators, peers
    from sleighsim.model.params import Params
    from sleighsim.scenes import bench

    return {
        "tangent_integrator": lambda: integrators.tangent_integrator(_oscillator(), 1),
        "tangent_integrator_batch": lambda: integrators.tangent_integrator_batch(_oscillator(), 2),
        "megno_integrator": lambda: integrators.megno_integrator(_oscillator()),
        "audit_orbits.flow": lambda: audit_orbits.flow.__wrapped__("lorenz", "double", 1),
        "audit_orbits._megno_flow": lambda: audit_orbits._megno_flow.__wrapped__("lorenz", "double"),
        "bench.reference": lambda: bench.reference(Params.paper(eps=0.1), np.array([0.0, 0.1, 1.0, 0.0]), 1.0, 1e-15),
        "peers.require": lambda: peers.require("heyoka"),
    }


@pytest.mark.parametrize("name", list(_builders()))
def test_a_heyoka_build_outside_compiled_refuses_a_jit_cache_others_can_write(name, tmp_path, monkeypatch):
    cache = tmp_path / "jit"
    cache.mkdir()
    cache.chmod(0o777)
    monkeypatch.setenv("SLEIGHSIM_JIT_CACHE", str(cache))
    before = hy.llvm_state.get_diskcache_path()
    with pytest.raises(UnsafeDirectory, match=rf"^SLEIGHSIM_JIT_CACHE {cache}: refused"):
        _builders()[name]()
    assert hy.llvm_state.get_diskcache_path() == before
    assert not any(cache.iterdir())


def test_a_numba_cache_others_can_write_is_refused_before_the_double_double_kernels_use_it(tmp_path):
    """NUMBA_CACHE_DIR is read when numba is imported: a child process imports the kernels."""
    pytest.importorskip("numba")
    cache = tmp_path / "numba"
    cache.mkdir()
    cache.chmod(0o777)
    src = str(Path(__file__).resolve().parents[2] / "src")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": src}
    res = subprocess.run([sys.executable, "-c", "import sleighsim.engine.ddtaylor"], env=env, capture_output=True,
                         text=True, timeout=300)
    assert res.returncode != 0
    assert f"UnsafeDirectory: numba's cache {cache}" in res.stderr, res.stderr[-2000:]
    assert not any(cache.rglob("*.nb[ic]"))
