"""The integration engine: backends, datasets, failures, atomic writes."""

import numpy as np
import pytest

from sleighsim.engine.integrate import IntegrationError, integrate, sample_grid
from sleighsim.io import netcdf
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE
from sleighsim.precision import Precision

REF = REFERENCE_STATE
P = Params.paper(eps=0.1)


def test_heyoka_and_scipy_agree_over_100_time_units():
    t = sample_grid(0.0, 100.0, 0.5)
    hy = integrate(P, REF, t, kinematics=True)
    sp = integrate(P, REF, t, kinematics=True, backend="scipy", method="DOP853", rtol=1e-13, atol=1e-15)
    diff = max(float(np.max(np.abs(hy[n] - sp[n]))) for n in hy.data_vars)
    assert diff < 1e-8, diff
    assert sp.attrs["backend"] == "scipy" and sp.attrs["steps"] > 0


def test_dataset_records_how_it_was_computed(tmp_path):
    """The run's settings from integrate(); provenance (versions, commit, time) added once, when written."""
    ds = integrate(P, REF, sample_grid(0.0, 10.0, 1.0), t0=0.0, scene="unit")
    for key in ("param_m_c", "param_m_r", "param_I_c", "param_I_r", "param_a", "param_b", "param_eps", "param_K2",
                "y0_u", "y0_Omega", "y0_omega", "y0_delta", "energy_label", "energy_physical", "backend", "method",
                "tol", "steps", "wall_time_s", "energy_max_rel_drift", "compile_time_s"):
        assert key in ds.attrs, key
    assert "git_commit" not in ds.attrs
    written = netcdf.read_dataset(netcdf.write_dataset(ds, tmp_path / "unit.nc"))
    for key in ("git_commit", "version_heyoka", "version_numpy", "version_scipy", "created_utc", "python_version"):
        assert written.attrs[key], key
    assert "git_commit" not in ds.attrs  # writing does not change the dataset in memory
    assert ds.attrs["energy_label"] == pytest.approx(0.1127)
    assert ds.u.attrs["units"] and ds.Omega.attrs["long_name"]
    assert list(ds.data_vars) == ["u", "Omega", "omega", "delta"]


def test_sampling_after_a_silent_pre_run_matches_a_full_run():
    full = integrate(P, REF, sample_grid(0.0, 200.0, 1.0))
    late = integrate(P, REF, sample_grid(150.0, 200.0, 1.0), t0=0.0)
    assert np.max(np.abs(full.u.sel(time=late.time) - late.u)) < 1e-12


def test_bad_inputs_raise_clear_errors():
    with pytest.raises(ValueError, match="strictly increasing"):
        integrate(P, REF, [0.0, 2.0, 1.0])
    with pytest.raises(ValueError, match="has 2 components; expected 4"):
        integrate(P, [1.0, 2.0], [0.0, 1.0])
    with pytest.raises(ValueError, match="not finite"):
        integrate(P, [np.nan, 0, 0, 0], [0.0, 1.0])
    with pytest.raises(ValueError, match="tol"):
        integrate(P, REF, [0.0, 1.0], tol=0.0)
    with pytest.raises(ValueError, match="backend"):
        integrate(P, REF, [0.0, 1.0], backend="euler")
    with pytest.raises(ValueError, match="dt"):
        sample_grid(0.0, 1.0, -0.1)


@pytest.mark.parametrize("backend", ["heyoka", "scipy"])
def test_integrator_failure_names_scene_time_and_state(backend):
    with pytest.raises(IntegrationError, match=r"scene blowup: integration failed at t = .*state = \["):
        integrate(P, [1e150, 1e150, 1e150, 0.0], [0.0, 1.0], scene="blowup", backend=backend, max_steps=2000)


@pytest.mark.parametrize("precision", [p for p in Precision if p is not Precision.DOUBLE_DOUBLE])  # heyoka's
def test_step_limit_stops_a_run_cleanly_in_every_precision(precision):
    """The message formats the time and state of any arithmetic (a real128 time has no format code:
    found by the property test, quad at max_steps)."""
    failed = r"scene slow: integration failed at t = [0-9.e+-]+, .*outcome step_limit"
    with pytest.raises(IntegrationError, match=failed):
        integrate(P, REF, [0.0, 1e4], scene="slow", max_steps=50, precision=precision)


def test_write_dataset_is_atomic(tmp_path, monkeypatch):
    ds = integrate(P, REF, [0.0, 1.0])
    target = tmp_path / "out.nc"
    netcdf.write_dataset(ds, target)
    before = target.read_bytes()

    def explode(self, path, *a, **k):
        open(path, "wb").write(b"partial")
        raise KeyboardInterrupt("interrupted while writing")

    monkeypatch.setattr(type(ds), "to_netcdf", explode)
    with pytest.raises(KeyboardInterrupt):
        netcdf.write_dataset(ds, target)
    assert target.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]  # no temporary left behind
    monkeypatch.undo()
    back = netcdf.read_dataset(target)
    assert np.array_equal(back.u.values, ds.u.values)
    assert back.attrs["energy_max_rel_drift"] == ds.attrs["energy_max_rel_drift"]


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_written_files_get_the_permissions_the_umask_allows(tmp_path, umask):
    """Written through a private temporary file, results end up readable as the umask says
    (0644 under the usual 022), so a group on a shared cluster can read them."""
    import os
    import stat

    old = os.umask(umask)
    try:
        nc = netcdf.write_dataset(integrate(P, REF, [0.0, 1.0]), tmp_path / "a.nc")
        txt = netcdf.write_text(tmp_path / "a.txt", "x")
    finally:
        os.umask(old)
    for path in (nc, txt):
        assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask, oct(path.stat().st_mode)


def test_the_jit_cache_goes_where_the_environment_says(tmp_path):
    import stat
    import subprocess
    import sys

    code = ("import heyoka as hy; from sleighsim.engine import integrators; integrators.flow(False, 1e-10); "
            "print(hy.llvm_state.get_diskcache_path())")
    env = {**__import__("os").environ, "SLEIGHSIM_JIT_CACHE": str(tmp_path / "jit")}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == str(tmp_path / "jit") and any((tmp_path / "jit").iterdir())
    assert stat.S_IMODE((tmp_path / "jit").stat().st_mode) == 0o700  # created private


@pytest.mark.parametrize("owner_other", [False, True])
def test_a_jit_cache_another_user_controls_is_refused_before_heyoka_uses_it(tmp_path, monkeypatch, owner_other):
    """heyoka runs the code it finds in its cache: a directory others can write, or that another user
    owns (as /tmp/$USER can be, created first by someone else), is refused naming the setting."""
    import os

    import heyoka as hy

    from sleighsim.engine import integrators
    from sleighsim.io.cachedir import UnsafeDirectory

    cache = tmp_path / "jit"
    cache.mkdir(mode=0o700 if owner_other else 0o777)
    cache.chmod(0o700 if owner_other else 0o777)
    if owner_other:
        monkeypatch.setattr(os, "geteuid", lambda: cache.stat().st_uid + 4242)
    monkeypatch.setenv("SLEIGHSIM_JIT_CACHE", str(cache))
    before = hy.llvm_state.get_diskcache_path()
    why = "is owned by uid" if owner_other else "is writable by its group or by others"
    with pytest.raises(UnsafeDirectory, match=rf"^SLEIGHSIM_JIT_CACHE {cache}: refused as a cache, since .*{why}"):
        integrators.guarded_heyoka()
    assert hy.llvm_state.get_diskcache_path() == before


@pytest.mark.parametrize("precision, tol", [(Precision.LONG_DOUBLE, 2.0**-63), (Precision.QUAD, 2.0**-112)])
def test_an_extended_precision_run_follows_the_double_one_where_both_are_faithful(precision, tol):
    """Over 200 time units from the reference state every arithmetic follows one orbit: the runs
    agree to about double's rounding, with or without the path, and the dataset names its arithmetic."""
    p, times = Params.from_config({"eps": 0.1, "b": 1.0, "K2": 1.1}), sample_grid(0.0, 200.0, 0.5)
    for kinematics in (False, True):
        d = integrate(p, REFERENCE_STATE, times, kinematics=kinematics)
        e = integrate(p, REFERENCE_STATE, times, kinematics=kinematics, tol=tol, precision=precision)
        assert e.attrs["precision"] == precision and e.u.dtype == np.float64
        for v in ("u", "Omega", "omega"):
            assert np.max(np.abs(d[v].values - e[v].values)) < 1e-11
        assert e.attrs["energy_max_rel_drift"] < 1e-15


def test_scipy_outside_double_is_refused_before_any_work():
    p = Params.from_config({"eps": 0.1, "b": 1.0, "K2": 1.1})
    with pytest.raises(ValueError, match="double only"):
        integrate(p, REFERENCE_STATE, [0.0, 1.0], backend="scipy", precision=Precision.LONG_DOUBLE)


def test_a_run_without_a_scene_is_named_in_the_log(caplog):
    """The log never starts with an empty label (': done in ...'): a run its caller left unnamed says so."""
    with caplog.at_level("INFO", logger="sleighsim"):
        integrate(P, REF, [0.0, 1.0])
    done = [r.getMessage() for r in caplog.records if "done in" in r.getMessage()]
    assert done and all(m.startswith("an unnamed run") for m in done), done


def test_a_precision_is_accepted_by_its_name_as_by_the_type():
    """Issue 53: precision="quad" crashed ('str' object has no attribute 'epsilon')."""
    from sleighsim.engine.orbits import sleigh_orbit

    by_name = integrate(P, REF, [0.0, 5.0], precision="long double", tol=2.0**-63)
    by_type = integrate(P, REF, [0.0, 5.0], precision=Precision.LONG_DOUBLE, tol=2.0**-63)
    assert by_name.attrs["precision"] == "long double" and by_name.u.values.tolist() == by_type.u.values.tolist()
    assert sleigh_orbit(P, REF, "long double", 2.0**-63, 3, 1.0).precision is Precision.LONG_DOUBLE
    with pytest.raises(ValueError, match="precision 'quadruple': choose one of"):
        integrate(P, REF, [0.0, 1.0], precision="quadruple")


def test_double_double_samples_and_crossings_agree_with_heyoka_where_double_follows():
    """Over 300 time units of the paper's start (before any spike cycle amplifies double's error), the
    double-double path of integrate and of poincare.crossings agrees with heyoka's double to double's error,
    crossing for crossing and class for class; the path (kinematics) is refused, naming it."""
    from sleighsim.engine import poincare

    p = Params.paper(eps=0.1, K2=1.1)
    y = [0.0, 0.1, 1.0, 0.0]
    grid = sample_grid(0.0, 300.0, 0.5)
    a, b = integrate(p, y, grid), integrate(p, y, grid, precision="double-double", tol=1e-32)
    assert float(abs(a.u - b.u).max()) < 1e-11 and b.attrs["backend"] == "sleighsim.engine.ddtaylor"
    ca = poincare.crossings(p, y, 0.0, 300.0)
    cb = poincare.crossings(p, y, 0.0, 300.0, tol=1e-32, precision=Precision.DOUBLE_DOUBLE)
    assert ca["time"].size == cb["time"].size > 100 and np.array_equal(ca["k"], cb["k"])
    assert np.max(np.abs(ca["time"] - cb["time"])) < 1e-9 and cb["time"][0] > 0
    with pytest.raises(ValueError, match="kinematics"):
        integrate(p, y, grid, kinematics=True, precision="double-double", tol=1e-32)


def test_double_double_crossings_of_a_fast_rotor_sample_finer_and_miss_none():
    """eps = 0.01 with the rotor carrying the energy (|Omega - omega| about 100: a quarter turn every 0.016): the
    double-double sampling step shrinks to an eighth of a turn at the start's rate, and its crossings agree with
    heyoka's double crossing for crossing over 20 time units; a slow rotor keeps DD_SAMPLE_DT; a step too long
    for the orbit is refused, naming the turn."""
    from sleighsim.engine import poincare

    p = Params.paper(eps=0.01, K2=1.01)
    y = [1.05784728e-02, 5.03551489e-04, 1.00102322e+02, 4.66151657e+00]
    assert poincare.dd_sample_dt(y) == pytest.approx(0.25 * np.pi / (y[2] - y[1]))
    assert poincare.dd_sample_dt([0.06, 0.026, 3.31, 3.6]) == poincare.DD_SAMPLE_DT
    assert poincare.dd_sample_dt([0.1, 0.0, 0.0, 0.0]) == poincare.DD_SAMPLE_DT
    ca = poincare.crossings(p, y, 0.0, 20.0)
    cb = poincare.crossings(p, y, 0.0, 20.0, tol=1e-32, precision=Precision.DOUBLE_DOUBLE)
    assert ca["time"].size == cb["time"].size > 1200 and np.array_equal(ca["k"], cb["k"])
    assert np.max(np.abs(ca["time"] - cb["time"])) < 1e-9


def test_double_double_crossings_refuse_a_sampling_step_longer_than_a_quarter_turn(monkeypatch):
    from sleighsim.engine import poincare

    monkeypatch.setattr(poincare, "dd_sample_dt", lambda y0: 0.1)
    with pytest.raises(RuntimeError, match="more than a quarter turn"):
        poincare.dd_crossings(Params.paper(eps=0.01, K2=1.01), [0.0106, 5e-4, 100.1, 4.66], 0.0, 2.0, tol=1e-32)
