"""The trigger law and its fate (sleighsim.scenes.trigger): the runs within reach of the slopes, saturated runs
left out of them, and the scene on a short run (first spikes refined, tori landed on, followed and checked)."""

import math

import numpy as np
import pytest
from conftest import ROOT

from sleighsim.io import cf
from sleighsim.precision import Precision, parsed
from sleighsim.scenes import trigger

D, LD, Q = Precision.DOUBLE, Precision.LONG_DOUBLE, Precision.QUAD


@pytest.mark.parametrize("runs, want", [
    ([(D, 1e-12), (LD, 1e-12), (D, 1e-10)], [0, 1, 1]),
    ([(LD, 1e-12), (D, 1e-12), (Q, 1e-12)], [0, 0, 1]),  # the finest, in any order
    ([(D, 1e-15), (LD, 1e-15)], [0, 1]),  # 1e-15 is within 100x of double's rounding
    ([(D, 2.0**-52), (LD, 1e-19)], [0, 0]),  # each at its own rounding
])
def test_a_tolerance_run_in_several_arithmetics_is_chosen_once_in_the_finest(runs, want):
    assert trigger.chosen(runs).astype(int).tolist() == want


def _escape(first, drift):
    return {"first": first, "first_err": 1e-5, "drift": drift, "after": None, "cpu_s": 0.0}


def test_the_law_leaves_saturated_and_spikeless_runs_out_of_the_slopes():
    """The paper config's ladder with made-up escapes: long double's 1e-15 and 1e-16 give the same first spike
    and drift (saturated), double's 1e-12 is chosen in long double, the machine-epsilon runs are out of reach, a
    run without a first spike is out; the slopes span double and long double with a bridge between them."""
    runs = [(D, t) for t in (1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 2.0**-52)] + \
           [(LD, t) for t in (1e-12, 1e-13, 1e-14, 1e-15, 1e-16, 2.0**-63)]
    first = [5280, 5337, 5398, 5395, 5418, 5594, 5418, 5503, 5590, 5638.1, 5638.3, math.nan]
    drift = [2e-7, 2e-8, 2e-9, 1e-9, 1e-10, 1e-13, 1e-10, 2e-11, 8e-14, 6.8e-15, 5.7e-15, 7e-17]
    cfg = {"saturation": {"spike": 1.0, "drift": 2.0}, "range_decades": 4.0}
    found = trigger.law(runs, [_escape(f, d) for f, d in zip(first, drift)], cfg)
    assert found["saturated"].astype(int).tolist() == [0] * 9 + [1, 1, 0]
    assert found["in_slopes"].astype(int).tolist() == [1, 1, 1, 1, 0, 0, 1, 1, 1, 0, 0, 0]
    assert [r["label"] for r in found["ranges"]] == ["double", "double -> long double", "long double"]
    assert found["ranges"][2]["tol_min"] == pytest.approx(1e-14) and found["dof"] == 3


def test_trigger_scene_on_a_short_run():
    """eps = 0.2 (transients 4x shorter than at 0.1): every run escapes; the same tolerance in double and long
    double gives nearly the same first spike, the long double one in the slopes; every escape lands on a torus
    double-double follows, confirmed in triple-double (the shortest shown strictly periodic over two intervals, the
    others with one interval undetermined); every variable has its CF attributes."""
    cfg = dict(params={"eps": 0.2, "b": 1.0, "K2": 1.2}, y0=[0.0, 0.1, 1.0, 0.0], t_end=2000.0, dt=1.0, t_min=250.0,
               spike_factor=1.8, half_width=25.0, tols={"double": [1e-8, 1e-12], "long double": [1e-12]},
               saturation={"spike": 1.0, "drift": 2.0}, range_decades=4.0, price_record="benchmarks/multiprec.yaml",
               fate={"offset": 100.0, "T": 2600.0, "dt": 0.5, "tol": 1e-32, "td_tol": 1e-47, "tau": 20.0,
                     "lead": 50.0, "min_intervals": 2, "periodic_factor": 3.0})
    ds = trigger.trigger_law(parsed(cfg), {"price": ROOT / cfg["price_record"]}, "t")
    assert ds.in_slopes.values.tolist() == [1, 0, 1] and not ds.saturated.values.any()
    assert abs(ds.first_spike.values[1] - ds.first_spike.values[2]) < 0.1 < ds.first_spike.values[1] - 900.0
    assert np.all(ds.first_spike_err.values < 0.1) and np.all(ds.run_energy_max_rel_drift.values < 1e-6)  # dt = 1
    assert ds.landed_arithmetic.values.tolist() == ["double-double"] * 3
    assert ds.landed_follows.values.tolist() == ["follows"] * 3 and ds.landing_confirmed.values.tolist() == [1] * 3
    step = np.abs(np.diff(ds.landed_interval.values))
    assert ds.landed_cycles.values.tolist() == [2, 1, 1] and step[0] > 10 > 0.1 > step[1]  # 1e-12 twice: one torus
    assert ds.landed_class.values.tolist() == ["strictly periodic", "undetermined", "undetermined"]
    assert ds.sizes["range"] == 1 and ds.range_slope.values[0] < 0
    assert cf.missing(cf.complete(ds)) == []
    assert "fate_T" in ds.attrs and "saturation_rule" in ds.attrs and ds.attrs["cpu_s"] > 0
    assert "price" not in " ".join(ds.follows.values)  # every torus followed: no price to name
