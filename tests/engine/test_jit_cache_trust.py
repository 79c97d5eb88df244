"""Issue 54: every heyoka compilation checks the JIT cache directory first (heyoka runs the code it finds
there), not only those built through integrators.compiled: each builder below compiled from an unchecked
directory before."""

import numpy as np
import pytest

from sleighsim.io.cachedir import UnsafeDirectory

hy = pytest.importorskip("heyoka")


def _oscillator():
    x, v = hy.make_vars("x", "v")
    return [(x, v), (v, -x)]


def _builders():
    from sleighsim.chaos import power
    from sleighsim.engine import integrators, peers
    from sleighsim.model.params import Params
    from sleighsim.scenes import bench

    return {
        "tangent_integrator": lambda: integrators.tangent_integrator(_oscillator(), 1),
        "tangent_integrator_batch": lambda: integrators.tangent_integrator_batch(_oscillator(), 2),
        "megno_integrator": lambda: integrators.megno_integrator(_oscillator()),
        "power._flow": lambda: power._flow.__wrapped__("lorenz", "double"),
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
