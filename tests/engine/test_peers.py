"""Peer engines (sleighsim.engine.peers): the right-hand sides agree, the peers integrate the same orbit,
lyapax reproduces Lorenz's lambda_1, and a missing peer says how to install it. Each optional
peer is skipped cleanly when it is not installed."""

import sys
import types

import numpy as np
import pytest

from sleighsim.engine import peer_jax, peer_lyapunov, peer_scipy, peers
from sleighsim.model.equations import Params

PARAMS = Params.paper(eps=0.1).values
Y0 = peers.Y0_REFERENCE


def _rhs(how):
    if how == "numba":
        pytest.importorskip("numba")
    if how == "heyoka":
        pytest.importorskip("heyoka")
    return peer_scipy.rhs_function(PARAMS, how)


@pytest.fixture(scope="module")
def states():
    rng = np.random.default_rng(7)
    ys = rng.uniform(-2.0, 2.0, size=(200, 4))
    ys[:, 3] = rng.uniform(-20.0, 20.0, size=200)
    return ys


def test_timed_warms_up_then_takes_the_median():
    calls = []
    result, median, walls = peers.timed(lambda: calls.append(1) or len(calls), repeats=5, warmup=1)
    assert len(calls) == 6 and result == 6 and len(walls) == 5
    assert median == sorted(walls)[2]
    with pytest.raises(ValueError):
        peers.timed(lambda: None, repeats=0)


@pytest.mark.parametrize("how", ["numba", "heyoka"])
def test_compiled_rhs_agrees_with_numpy_rhs(how, states):
    """Relative to the size of the vector field (a component can be a cancellation near zero)."""
    f_np = _rhs("numpy")
    f = _rhs(how)
    assert f.compile_s > 0.0
    for y in states:
        a, b = f_np(0.0, y), f(0.0, y)
        assert b.shape == (4,)
        assert np.max(np.abs(b - a)) <= 1e-14 * np.max(np.abs(a)), (how, y)


def test_the_heyoka_lyapunov_peer_is_our_compiled_system_with_its_parameters(states):
    """The heyoka row of the Lyapunov peers integrates the engine's system (coefficients as runtime
    parameters computed from the physical ones), which equals the peers' NumPy rhs."""
    hy = pytest.importorskip("heyoka")
    sys_ = peer_lyapunov.sleigh_heyoka()
    f = hy.cfunc([e for _, e in sys_], vars=[v for v, _ in sys_])
    pars = np.tile(np.array(peer_lyapunov.sleigh_heyoka_pars(PARAMS))[:, None], (1, len(states)))
    got = f(states.T.copy(), pars=pars).T
    want = np.array([_rhs("numpy")(0.0, y) for y in states])
    assert np.max(np.abs(got - want)) <= 1e-13 * np.max(np.abs(want))
    with pytest.raises(ValueError, match="6 parameter values"):
        peer_lyapunov.sleigh_heyoka_pars(PARAMS[:5])


def test_compiled_rhs_rejects_unknown_kind():
    with pytest.raises(ValueError, match="numba"):
        peer_scipy.compiled_rhs(PARAMS, how="cython")


@pytest.mark.parametrize("how", ["numba", "heyoka"])
def test_scipy_with_compiled_rhs_follows_the_numpy_orbit(how):
    y_np, nfev_np = peer_scipy.scipy_run(_rhs("numpy"), Y0, 10.0, "DOP853", 1e-10, 1e-13)
    y, nfev = peer_scipy.scipy_run(_rhs(how), Y0, 10.0, "DOP853", 1e-10, 1e-13)
    assert nfev > 0 and abs(nfev - nfev_np) <= 0.05 * nfev_np
    assert peers.state_error(y, y_np) < 1e-9


def test_diffrax_dopri8_agrees_with_scipy_dop853():
    pytest.importorskip("diffrax")
    ref, _ = peer_scipy.scipy_run(_rhs("numpy"), Y0, 10.0, "DOP853", 1e-12, 1e-15)
    y = peer_jax.diffrax_run(PARAMS, Y0, 10.0, 1e-10, 1e-13, solver="Dopri8")
    assert y.shape == (4,) and y.dtype == np.float64
    assert peers.state_error(y, ref) < 1e-8
    solve = peer_jax.diffrax_solver(10.0, 1e-10, 1e-13, "Dopri8")
    assert solve.compile_s > 0.0


def test_lyapax_lorenz_lambda_1():
    pytest.importorskip("lyapax")
    run = peer_lyapunov.lyapax_lorenz(T=500.0, tau=1.0, dt=0.01, t_transient=50.0, repeats=1)
    assert abs(run.lambda_1 - peer_lyapunov.LORENZ_LAMBDA_1) < 0.05 * peer_lyapunov.LORENZ_LAMBDA_1
    assert run.compile_s > 0.0 and run.wall_s > 0.0 and run.settings["T"] == pytest.approx(500.0)


def test_heyoka_lorenz_lambda_1():
    """The baseline lyapax is compared against: Benettin on heyoka's variational equations."""
    pytest.importorskip("heyoka")
    run = peer_lyapunov.heyoka_lorenz(T=500.0, tau=1.0, t_transient=50.0, repeats=1, warmup=0)
    assert abs(run.lambda_1 - peer_lyapunov.LORENZ_LAMBDA_1) < 0.05 * peer_lyapunov.LORENZ_LAMBDA_1


@pytest.mark.parametrize(
    ("module", "call"),
    [
        ("numba", lambda: peer_scipy.compiled_rhs(PARAMS, how="numba")),
        ("diffrax", lambda: peer_jax.diffrax_run(PARAMS, Y0, 1.0, 1e-8, 1e-11)),
        ("lyapax", lambda: peer_lyapunov.lyapax_lorenz(T=10.0)),
    ],
)
def test_missing_peer_raises_with_install_hint(monkeypatch, module, call):
    monkeypatch.setitem(sys.modules, module, None)  # makes `import module` raise ImportError
    with pytest.raises(peers.PeerUnavailable, match=rf"{module} is not installed: pip install 'sleighsim\[bench\]'"):
        call()
    assert issubclass(peers.PeerUnavailable, ImportError)


def test_lyapax_api_mismatch_is_a_peer_unavailable(monkeypatch):
    monkeypatch.setitem(sys.modules, "lyapax", types.ModuleType("lyapax"))
    with pytest.raises(peers.PeerUnavailable, match="lacks"):
        peer_lyapunov.lyapax_lorenz(T=10.0)


def test_peer_versions_lists_every_peer():
    versions = peers.peer_versions()
    assert set(versions) == set(peers.PEERS) and versions["numpy"]
