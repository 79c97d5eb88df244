"""The faithfulness gauge (sleighsim.chaos.faithfulness): the one-period gain on synthetic tangent maps,
each branch of the follows-the-orbit rule, and the gain on the sleigh's main state."""

import math

import numpy as np
import pytest

from sleighsim.chaos import faithfulness as fa
from sleighsim.engine.precision import Precision


def _diag(*d):
    return np.diag(np.array(d, float))


def test_gain_of_a_uniform_stretch_is_its_product_over_the_cycle():
    R = np.array([_diag(2.0, 1.0, 1.0, 0.5)] * 39)
    got = fa.cycle_gains(R, [0, 10, 20, 30])
    assert got == pytest.approx([10 * math.log(2.0)] * 2)  # the third cycle's last window would end past the run


def test_gain_is_maximised_over_where_the_period_starts():
    """Against brute force on random non-normal maps: the largest one-period singular value over
    every start in the cycle, which exceeds the spike-to-spike map's."""
    rng = np.random.default_rng(7)
    R = np.triu(rng.normal(size=(40, 4, 4)))
    R[:, range(4), range(4)] = np.exp(rng.normal(scale=1.5, size=(40, 4)))

    def sigma_1(i, m):
        return math.log(np.linalg.svd(np.linalg.multi_dot(R[i + 1: i + m + 1][::-1]), compute_uv=False)[0])

    got = fa.cycle_gains(R, [0, 12, 24])
    assert got == pytest.approx([max(sigma_1(i, 12) for i in range(a, a + 12)) for a in (0, 12)], rel=1e-12)
    assert got[0] > sigma_1(0, 12) + 1.0


def test_gain_stays_finite_beyond_the_range_of_double():
    R = np.array([_diag(1e30, 1, 1, 1e-30)] * 60)
    assert fa.cycle_gains(R, [0, 20])[0] == pytest.approx(20 * 30 * math.log(10))


def test_spike_steps_must_increase():
    with pytest.raises(ValueError, match="increase"):
        fa.cycle_gains(np.array([np.eye(4)] * 10), [5, 2])


@pytest.mark.parametrize("ln_gain, rounding, want", [
    (36.0, Precision.DOUBLE.rounding, fa.DOES_NOT_FOLLOW),   # G r = 0.5
    (36.0, Precision.LONG_DOUBLE.rounding, fa.FOLLOWS),      # G r = 2.3e-4
    (36.0, Precision.QUAD.rounding, fa.FOLLOWS),
    (math.log(1e-3 / 2.0**-53), Precision.DOUBLE.rounding, fa.DOES_NOT_FOLLOW),  # exactly at the bound
    (math.nan, Precision.QUAD.rounding, fa.UNKNOWN),          # no complete cycle: never counted as following
])
def test_follows_on_each_branch(ln_gain, rounding, want):
    assert fa.follows(ln_gain, rounding) == want


def test_tangent_run_refuses_a_horizon_shorter_than_two_steps():
    with pytest.raises(ValueError, match="tau"):
        fa.tangent_run(None, np.zeros(4), T=1.0, tau=1.0)


def test_the_main_state_amplifies_rounding_beyond_double_precision(hy):
    """The settled main state (eps = 0.1, label 0.1127): ln G of about 33-46 per spike cycle, so
    double precision does not follow its orbit and quad does."""
    from sleighsim.engine import integrators
    from sleighsim.model.params import Params

    p = Params.paper(eps=0.1, K2=1.1)
    flow, _ = integrators.flow(False, 2.0**-52)
    integrators.set_pars(flow, p)
    flow.time = 0.0
    integrators.load(flow, np.array([0.0, 0.1, 1.0, 0.0]))
    flow.propagate_until(2.0e4, callback=integrators.bounded(flow))
    ta, _ = integrators.sleigh_tangent(4, 2.0**-52, True)
    integrators.set_pars(ta, p)
    g = fa.spike_cycle_gains(ta, integrators.read(flow, 4), T=1.2e4)
    assert 3 <= g["ln_gain"].size <= 4 and np.all((g["ln_gain"] > 25) & (g["ln_gain"] < 50))
    assert g["follows"]["double"] == fa.DOES_NOT_FOLLOW and g["follows"]["quad"] == fa.FOLLOWS
    assert g["log10_gain_rounding"]["double"] - g["log10_gain_rounding"]["quad"] == pytest.approx(60 * math.log10(2))


def test_the_report_names_the_arithmetic_that_follows_each_orbit(tmp_path):
    import xarray as xr

    from sleighsim.io.netcdf import write_dataset
    from sleighsim.report.build import chaos_answers

    ds = xr.Dataset({"verdict": ("state", np.array(["undecided", "regular"], dtype=object)),
                     "reason": ("state", np.array(["r0", "r1"], dtype=object)),
                     "ln_gain_max": ("state", [36.2, math.nan]),
                     "log10_gain_rounding": (("state", "arithmetic"), [[-0.2, -3.5, -18.3], [math.nan] * 3]),
                     "follows_orbit": (("state", "arithmetic"),
                                       np.array([["does not follow", "follows", "follows"], ["unknown"] * 3],
                                                dtype=object))},
                    coords={"state": ["main", "rotor"], "arithmetic": [p.value for p in Precision]})
    write_dataset(ds, tmp_path / "v.nc")
    (main, v0, why0, decided, _), (_, _, why1, _, _) = chaos_answers({"chaos_verdict": tmp_path / "v.nc"})
    assert main == "main" and decided == "follows the orbit: long double, quad"
    assert v0 == "undecided" and why0.startswith("r0. Rounding amplified by ln G = 36.2")
    assert "double: does not follow (G x rounding = 10^-0.2); long double: follows" in why0
    assert why1 == ("r1. Faithfulness gauge: no complete spike cycle within T_gain, so which arithmetic follows "
                    "the orbit is unknown")


def test_the_report_prices_the_decisive_run_only_where_a_verdict_left_it_undone(tmp_path):
    """decisive_cost: quad_T from the cluster config times quad's measured cost per time unit; the
    answers show it only when a state is neither chaotic nor regular and its quad run was not made."""
    import xarray as xr
    import yaml

    from sleighsim.io.netcdf import write_dataset
    from sleighsim.report.build import answers, decisive_cost

    cost = tmp_path / "cost.yaml"
    rows = [{"system": s, "precision": p, "compact_mode": c, "high_accuracy": False, "cost_s_per_tu": v}
            for s, p, c, v in (("flow", "quad", True, 6e-3), ("flow", "quad", False, 9e-3),
                               ("tangent", "quad", True, 1.0))]
    cost.write_text(yaml.safe_dump({"date": "2026-11-24T00:00", "machine": {"cpu_model": "cpu X"}, "rows": rows}))
    cluster = tmp_path / "cluster.yaml"
    cluster.write_text(yaml.safe_dump({"scenes": {"chaos_verdict": {"frequency": {"quad_T": 1e5}}}}))
    text = decisive_cost(cost, cluster)
    assert "quad_T = 100000" in text and "0.006 s per time unit" in text and "about 10 min per state" in text
    assert "(cpu X, 2026-11-24; cost.yaml)" in text
    unmeasured = tmp_path / "unmeasured.yaml"
    unmeasured.write_text(yaml.safe_dump({"date": "2026-11-24", "machine": {"cpu_model": "cpu X"}, "rows": rows[2:]}))
    with pytest.raises(ValueError, match="no measured cost of the flow in quad"):
        decisive_cost(unmeasured, cluster)
    for verdict, quad_T, shown in (("undecided", 0.0, True), ("fragile", 0.0, True), ("regular", 0.0, False),
                                   ("undecided", 3e4, False)):
        ds = xr.Dataset({"verdict": ("state", np.array([verdict], dtype=object)),
                         "reason": ("state", np.array(["r"], dtype=object))}, coords={"state": ["main"]},
                        attrs={"frequency_quad_T": quad_T})
        write_dataset(ds, tmp_path / "v.nc")
        a = answers([], {"chaos_verdict": tmp_path / "v.nc"}, {}, decisive=text)
        assert a["decisive"] == (text if shown else ""), (verdict, quad_T)


def test_the_first_screen_names_the_arithmetic_each_state_was_decided_in():
    """report._decided_in: MEGNO's precision, the frequency analysis' precisions, and which arithmetic
    follows the orbit (some, none, or unknown when the gauge saw no complete cycle)."""
    import xarray as xr

    from sleighsim.report.build import _decided_in

    follows = np.array([["does not follow", "follows", "follows"], ["does not follow"] * 3, ["unknown"] * 3],
                       dtype=object)
    ds = xr.Dataset({"megno_precision": ("state", np.array(["long double", "double", "double"], dtype=object)),
                     "follows_orbit": (("state", "arithmetic"), follows)},
                    coords={"state": ["a", "b", "c"], "arithmetic": [p.value for p in Precision],
                            "frequency_precision": ["double", "long double"]})
    assert _decided_in(ds, 0) == ("MEGNO: long double; frequency analysis: double, long double; "
                                  "follows the orbit: long double, quad")
    assert _decided_in(ds, 1).endswith("follows the orbit: none")
    assert _decided_in(ds, 2).endswith("follows the orbit: unknown")
    assert _decided_in(xr.Dataset(coords={"state": ["a"]}), 0) == ""
