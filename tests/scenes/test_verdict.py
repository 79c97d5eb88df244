"""The chaos verdict scene (sleighsim.scenes.verdict): the runs it makes for the indicators (the
long-double precision check, the Loschmidt runs, the frequency runs and the precisions the frequency
indicator asks for), the R-image test, and the reversibility the Loschmidt test rests on. The
indicators and judges themselves: test_chaos_*.py."""

import math

import numpy as np
import pytest

from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED
from sleighsim.engine.integrate import integrate, sample_grid
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.precision import Precision
from sleighsim.scenes.verdict_orbits import R, r_image

C, G, U = CHAOTIC, REGULAR, UNDECIDED


def test_r_image_stays_and_leaves():
    p = Params.paper(eps=0.1)
    y = np.array([0.05, 0.02, 0.8, 0.4])
    run = integrate(p, R * y, sample_grid(0.0, 100.0, 0.05), tol=1e-12)
    half = run.time.values >= 50.0
    own = -np.array([run.u.values[half].mean(), run.omega.values[half].mean()])  # what R(state) has, exactly
    assert r_image(p, y, own, T=100.0, tol=1e-12, rtol=0.01, scene="t")[0] == "stays"
    assert r_image(p, y, own * np.array([-1.0, 1.0]) + np.array([1.0, 0.0]), T=100.0, tol=1e-12, rtol=0.01,
                   scene="t")[0] == "leaves"


def test_the_flow_is_reversible_under_R():
    """R(u, Omega, omega, delta) = (-u, -Omega, -omega, delta): if y(t) solves the equations so does
    R y(-t), i.e. f(R y) = -R f(y) at every state."""
    p = Params.paper(eps=0.1)
    rng = np.random.default_rng(3)
    y = np.c_[rng.uniform(-1, 1, (200, 3)), rng.uniform(-np.pi, np.pi, 200)]
    assert np.max(np.abs(equations.rhs(y * R, p) + equations.rhs(y, p) * R)) < 1e-14
    # and not the other way round (the test can fail)
    assert np.max(np.abs(equations.rhs(y * R, p) - equations.rhs(y, p) * R)) > 1e-3
    # along a solution: R y(T) run forward for T returns to R y(0)
    y0 = np.array([0.05, 0.02, 0.8, 0.4])
    yT = integrate(p, y0, [0.0, 50.0], tol=1e-15)
    back = integrate(p, R * np.array([yT[v].values[-1] for v in equations.STATE_NAMES]), [0.0, 50.0], tol=1e-15)
    back_end = np.array([back[v].values[-1] for v in equations.STATE_NAMES])
    assert np.max(np.abs(equations.state_difference(R * back_end, y0))) < 1e-9


@pytest.mark.parametrize("lam, spread, want", [
    (5e-4, 2e-5, "confirmed"),  # bound 2 ln(2e4) / 2e5 = 9.9e-5
    (4e-5, 1e-4, "not confirmed"),  # below the bound
    (3e-4, 2e-3, "not confirmed"),  # above it, but not by 3 standard errors
    (math.nan, 1e-5, "not confirmed"),
])
def test_precision_check_on_each_branch(monkeypatch, lam, spread, want):
    from sleighsim.scenes import verdict_tangent

    tau, T, t_align = 10.0, 2e5, 1000.0
    n = int(T / tau)
    rng = np.random.default_rng(0)
    g = lam * tau + spread * tau * rng.normal(size=n) * np.sqrt(n / 10)  # block means scatter by ~spread
    g[: int(t_align / tau)] = 5.0  # alignment of the vector: must be left out
    monkeypatch.setattr(verdict_tangent, "megno_run", lambda *a, **k: {"log_growth": g})
    cfg = dict(tau=tau, sigma=3.0, T_long_double=T, t_align=t_align)
    out = verdict_tangent.precision_check(Params.paper(eps=0.1), [0.0, 0.1, 1.0, 0.0], cfg, "s")
    assert out["check"] == want and out["reason"].startswith(want)
    if math.isfinite(lam):
        assert out["lambda_1"] == pytest.approx(lam, abs=4 * out["stderr"])


def test_loschmidt_run_in_long_double_has_the_smaller_rounding():
    from sleighsim.scenes.verdict_orbits import loschmidt_run

    p = Params.paper(eps=0.1)
    cfg = dict(tol=2.0**-52, loschmidt_T=[10.0, 40.0], loschmidt_n=3)
    y = np.array([0.05, 0.02, 0.8, 0.4])
    d, ld = loschmidt_run(p, y, cfg), loschmidt_run(p, y, cfg, precision=Precision.LONG_DOUBLE)
    np.testing.assert_allclose(d["T"], [10.0, 20.0, 40.0])
    assert ld["floor"] == pytest.approx(d["floor"] * float(np.finfo(np.longdouble).eps) / float(np.finfo(float).eps))
    assert np.all(d["rel_error"] < 1e-11) and np.all(ld["rel_error"] < 1e-3 * d["rel_error"].max())


# ----------------------------------------------------------------------------- the frequency indicator's runs

# (slope, usable splits, D) of the double, long-double and quad runs; None: that run must not be made
_RUNS = {
    "converged in double": ([(-3.5, 3, 1e-9), None, None], G),
    "converged in long double": ([(0.0, 3, 1e-2), (-3.5, 3, 1e-9), None], G),
    # the main state: the long-double drift is 300 times smaller, then quad converges
    "converged in quad": ([(0.0, 3, 1e-2), (0.05, 3, 4e-5), (-6.5, 2, 9e-8)], G),
    "converged in none": ([(0.0, 3, 1e-2), (0.05, 3, 4e-5), (0.1, 2, 4e-5)], U),
    "too few windows in double": ([(math.nan, 1, 1e-2), None, None], U),
    "no window at all": ([(math.nan, 0, 1e-2), None, None], U),
}


@pytest.mark.parametrize("case", list(_RUNS))
@pytest.mark.parametrize("quad_T", [0.0, 1e5])
def test_frequency_indicator_runs_each_precision_only_when_needed(monkeypatch, case, quad_T):
    from sleighsim.model.params import Params
    from sleighsim.scenes import verdict_frequency

    specs, want = _RUNS[case]
    names = ("double", "long double", "quad")

    def run(params, y, cfg, precision="double"):
        calls.append(precision)
        slope, n, D = specs[names.index(precision)]
        splits = np.array([2, 4, 8][:n])
        return dict(splits=splits, D=np.full(n, D), W=2e5 / splits, D_log_err=1 / np.sqrt(2 * (splits - 1.0)),
                    slope=slope, slope_err=0.55 if n > 2 else 1.18, T=2e5, f=4e-4)

    calls = []
    monkeypatch.setattr(verdict_frequency, "frequency_run", run)
    cfg = dict(tol=2.220446049250313e-16, frequency={"quad_T": quad_T})
    out = verdict_frequency.frequency_indicator(Params.paper(eps=0.1), [0.0, 0.1, 1.0, 0.0], cfg, 3.0)
    expected = [p for p, spec in zip(names, specs) if spec is not None and (p != "quad" or quad_T > 0)]
    assert calls == expected and list(out["runs"]) == expected
    assert out["verdict"][0] == (want if "quad" in expected or case != "converged in quad" else U), out["verdict"][1]
    not_made = "quad run not made" in out["verdict"][1]
    assert not_made == (quad_T == 0 and "long double" in expected and out["verdict"][0] == U
                        and out["runs"]["long double"]["splits"].size >= 2)
    last = out["runs"][expected[-1]]
    if last["D"].size:
        assert out["value"] == pytest.approx(last["D"][0] / last["W"][0])
        assert out["error"] == pytest.approx(out["value"] / math.sqrt(2))
    else:
        assert math.isnan(out["value"]) and math.isnan(out["error"])
    table = verdict_frequency.frequency_table([out], [2, 4, 8, 16])
    made = np.isfinite(table["slope"][0]) | np.isinf(table["slope"][0])
    assert [p for p, m in zip(names, made) if m] == [p for p in expected if not math.isnan(specs[names.index(p)][0])]


def test_a_state_judged_again_in_the_decisive_stage_gets_only_the_double_frequency_run(monkeypatch):
    """frequency_indicator(long_double=False): the double run alone, its verdict kept with the reason why
    no finer run was made (the long-double run would have been made otherwise)."""
    from sleighsim.model.params import Params
    from sleighsim.scenes import verdict_frequency

    calls = []

    def run(params, y, cfg, precision="double"):
        calls.append(precision)
        splits = np.array([2, 4, 8])
        return dict(splits=splits, D=np.full(3, 1e-3), W=2e5 / splits, D_log_err=1 / np.sqrt(2 * (splits - 1.0)),
                    slope=0.0, slope_err=0.55, T=2e5, f=4e-4)

    monkeypatch.setattr(verdict_frequency, "frequency_run", run)
    cfg = dict(tol=2.220446049250313e-16, frequency={"quad_T": 0.0})
    out = verdict_frequency.frequency_indicator(Params.paper(eps=0.1), [0.0, 0.1, 1.0, 0.0], cfg, 3.0,
                                                long_double=False)
    assert calls == ["double"] and out["verdict"][0] == U
    assert "the decisive stage judges this state" in out["verdict"][1]
    calls.clear()
    verdict_frequency.frequency_indicator(Params.paper(eps=0.1), [0.0, 0.1, 1.0, 0.0], cfg, 3.0)
    assert calls == ["double", "long double"]


def test_a_state_judged_again_gets_no_long_double_loschmidt_run(monkeypatch):
    """loschmidt_not_run: the long-double fields NaN (none used), the indicator undecided naming why and
    the double run's verdict (the judge of the double run replaced: its own tests are in test_loschmidt)."""
    from sleighsim.scenes import verdict_orbits

    monkeypatch.setattr(verdict_orbits, "judge_loschmidt_run", lambda L, sigma: (C, "grows"))
    run, los = verdict_orbits.loschmidt_not_run({"rel_error": np.geomspace(1e-15, 1e-3, 10)}, 3.0)
    assert np.isnan(run["rel_error"]).all() and run["rel_error"].shape == (10,) and run["n_used"] == 0
    assert los["verdict"] == (U, "long-double run not made: the decisive stage judges this state; in double: chaotic")
    assert math.isnan(los["value"]) and los["verdict_double"] == C


def test_the_sleighs_flow_runs_in_quad_precision():
    pytest.importorskip("heyoka")
    from sleighsim.engine import integrators
    from sleighsim.model.params import Params
    from sleighsim.scenes import verdict_frequency

    cfg = dict(tol=2.220446049250313e-16, frequency={"T": 200.0, "quad_T": 200.0, "dt": 0.5, "component": "u",
                                                     "splits": [2, 4], "min_cycles": 4.0})
    y = np.array([0.05, 0.02, 0.8, 0.4])
    runs = {p: verdict_frequency.frequency_run(Params.paper(eps=0.1), y, cfg, p) for p in verdict_frequency.PRECISIONS}
    flow, _ = integrators.flow(False, 1.925929944387235853e-34, Precision.QUAD)
    assert "real128" in str(flow.state.dtype)
    # the same orbit (end states agree to 1e-13 here): window frequencies agree to the refinement's
    # precision, which for windows of only 100 (13 periods, bins of 0.01) is about 1e-9 relative
    for p in ("long double", "quad"):
        np.testing.assert_allclose(runs[p]["frequencies"][0], runs["double"]["frequencies"][0], rtol=5e-9)


def test_realizations_perturb_every_state_but_the_first_at_the_given_size():
    from sleighsim.scenes.common import realization_states

    states = {"main": [0.0, 0.1, 1.0, 0.0], "rotor": [0.0, 0.0, 1.0, 0.3]}
    assert realization_states(states, 1e-12, 0) == states
    one, two = realization_states(states, 1e-12, 1), realization_states(states, 1e-12, 2)
    for name, y in states.items():
        rel = (np.array(one[name]) - y) / np.where(np.array(y) == 0, 1, y)
        assert np.all(np.abs(rel) < 1e-11) and np.all(np.array(one[name])[np.array(y) == 0] == 0)
        assert one[name] != y or not np.any(y)
    assert one != two and realization_states(states, 1e-12, 1) == one  # seeded by the realization


def test_a_scene_realization_perturbs_its_y0_and_its_list_of_states_in_order():
    from sleighsim.scenes.common import realization_config, realization_states

    cfg = {"y0": [0.0, 0.1, 1.0, 0.0], "states": [[0.0, 0.1, 1.0, 0.0], [0.05, 0.1, 1.0, 3.1]], "T": 10.0}
    assert realization_config(cfg, 1e-12, 0) == cfg
    one = realization_config(cfg, 1e-12, 1)
    assert one["T"] == 10.0 and one["states"] == realization_states(cfg["states"], 1e-12, 1)
    assert one["y0"] == realization_states([cfg["y0"]], 1e-12, 1)[0] != cfg["y0"]
    assert one["states"][1] != cfg["states"][1] and one["states"][0][0] == 0.0


def test_gather_keeps_an_answer_only_when_every_realization_gives_it(tmp_path):
    """Per-state jobs (state, realization) gathered: each realization's states in the config's order,
    ln G padded to the longest cycle record, then the answer the realizations agree on."""
    import xarray as xr

    from sleighsim.io.netcdf import read_dataset, write_dataset
    from sleighsim.scenes.verdict import CHAOS_VERDICT, gather

    cfg = {"kind": "chaos_verdict", "n_chunks": 3, "realization_rel": 1e-12, "states": {"main": [], "rotor_a": []},
           "decisive": {"states": []}}
    assert CHAOS_VERDICT.chunk_count(cfg) == 6
    per = [["undecided", "regular"], ["chaotic", "regular"], ["undecided", "regular"]]
    paths = []
    for k, v in enumerate(per):
        for i, name in enumerate(("main", "rotor_a")):
            ds = xr.Dataset({"verdict": ("state", np.array([v[i]], dtype=object)),
                             "reason": ("state", np.array([f"r{k}{'ab'[i]}" + "x" * i])),  # texts of two widths
                             "state_class": ("state", np.array([["undetermined", "regular"][i]])),
                             "indicator_value": ("state", [float(k) * (i + 1)]),
                             "ln_gain": (("state", "cycle"), [[36.0] * (i + 2)]),
                             "spike_period": ("state", [2300.0 + k + 10 * i if (k, i) != (2, 1) else np.nan])},
                            coords={"state": [name]},
                            attrs={"chunk": k, "n_chunks": 3, "wall_time_s": 0.75, "transient_over": 1,
                                   "tau_gain": 5.0})
            paths.append(tmp_path / f"{2 * k + i}.nc")
            write_dataset(ds, paths[-1])
    write_dataset(gather(paths[::-1], cfg), tmp_path / "gathered.nc")  # as the gather job writes it
    out = read_dataset(tmp_path / "gathered.nc")
    assert list(out.state.values) == ["main", "rotor_a"]
    assert list(out.verdict.values) == ["fragile", "regular"]
    assert list(out.n_realizations_agreeing.values) == [2, 3]
    assert out.reason.values[0] == "realizations disagree: undecided 2, chaotic 1 of 3; realization 0: r0a"
    assert out.reason.values[1] == "all 3 realizations agree; realization 0: r0bx"  # none truncated
    assert list(out.state_class.values) == ["undetermined", "regular"]
    assert out.indicator_value.values.tolist() == [0.0, 0.0]  # the details are realization 0's
    assert out.ln_gain.values[1].tolist() == [36.0] * 3 and np.isnan(out.ln_gain.values[0, 2])  # padded
    assert out.attrs["transient_over"] == 1
    # the torus each realization reached, and the report's sentence on it
    from sleighsim.report.chaos_answers import _tori_note

    assert out.realization_spike_period.values[:, 0].tolist() == [2300.0, 2301.0, 2302.0]
    assert _tori_note(out, 0).endswith(
        "(median spike interval per realization, to about tau_gain = 5): 2300, 2301, 2302")
    assert _tori_note(out, 1).endswith("2310, 2311, none")
    assert out.attrs["n_realizations"] == 3 and out.attrs["wall_time_s"] == 4.5 and "chunk" not in out.attrs
    with pytest.raises(ValueError, match="expected 0 ... 2"):
        gather(paths[:4], cfg)
    with pytest.raises(ValueError, match="states"):
        gather(paths[:5], cfg)
