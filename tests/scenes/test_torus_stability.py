"""The torus-stability scene (sleighsim.scenes.torus_stability): starts on the energy level at the asked
size, section crossings and states from the Taylor jets against direct double-double propagation (and
independent of the turns before them), the main torus' reversal train, the chunking and its checks, and
a short run chunked and gathered into a classified dataset with the family's laws."""

import math

import numpy as np
import pytest
import xarray as xr

from sleighsim.analysis import torus
from sleighsim.engine.ddtaylor import DDFlow
from sleighsim.io.netcdf import write_dataset
from sleighsim.model.equations import energy
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.scenes import torus_stability as ts
from sleighsim.scenes.checks import ConfigError

P = Params.paper(eps=0.1, b=1.0, K2=1.1)
#: a state near the main torus (u, Omega, omega, delta)
Y = np.array([0.0459, 0.0301, 3.348, 3.26])

SMALL = dict(params={"eps": 0.3, "b": 1.0, "K2": 1.3}, energy_label=0.1127, y0=[0.0, 0.1, 1.0, 0.0],
             t_transient=1000.0, transient={"dt": 1.0, "window": 100.0, "rtol": 0.05, "spike_factor": 1.8,
                                            "t_min": 50.0},
             tol=1e-12, tol_dd=1e-32, T=2500.0, T_reference=3000.0, dt=0.5, amplitudes=[1e-6, 1e-4], directions=2,
             seed=39, min_intervals=4, train_factor=10.0, max_intervals=4, sigma=3.0, law_amplitudes=[1e-6, 1e-4],
             n_chunks=2)
#: The paper config's block (eps 0.1: the main torus, spike cycles of about 2340).
PAPER = dict(SMALL, params={"eps": 0.1, "b": 1.0, "K2": 1.1}, t_transient=20000.0, tol=2.0**-52,
             transient={"dt": 10.0, "window": 2500.0, "rtol": 0.02, "spike_factor": 1.8, "t_min": 200.0})


@pytest.fixture(scope="module")
def flow():
    return DDFlow(P)


@pytest.mark.parametrize("a", [1e-12, 1e-6, 1e-3])
def test_perturbed_start_is_on_the_level_at_the_asked_size(a):
    """Energy kept to rounding; the relative distance (max component over max |velocity|) between a / 2
    and a (the Euclidean size is a); seeded: the same direction again gives the same start."""
    y0 = ts.perturbed_start(Y, P, a, 0, 39)
    assert abs(energy(y0, P) / energy(Y, P) - 1) < 1e-14
    rel = np.abs(y0 - Y).max() / np.abs(Y[:3]).max()
    assert 0.4 * a < rel < 1.01 * a
    assert np.array_equal(y0, ts.perturbed_start(Y, P, a, 0, 39))
    assert not np.array_equal(y0, ts.perturbed_start(Y, P, a, 1, 39))


def test_section_crossings_match_direct_propagation(flow):
    """Every crossing of delta = 0 (mod 2 pi) over 30 time units from the jets of samples 0.5 apart:
    about 3.3 / (2 pi) per time unit; at three of them, propagating to the crossing time directly
    gives delta = 0 mod 2 pi and the same (u, Omega, omega) to 1e-13."""
    y0 = state_at_label(Y, P, 0.1127)
    grid = np.arange(0.0, 30.25, 0.5)
    hi, lo = flow.propagate_grid(y0, grid)
    t, x = ts.section(flow, hi, lo, grid)
    assert 13 <= t.size <= 18 and np.all(np.diff(t) > 1.5)
    for i in (0, t.size // 2, t.size - 1):
        h, _ = flow.propagate(y0, t[i])
        assert abs(math.remainder(h[3], 2 * math.pi)) < 1e-12
        assert np.max(np.abs(h[:3] - x[i])) < 1e-13


def test_section_states_do_not_depend_on_the_turns_before_them(flow):
    """The crossings of the last 40 time units of a 4000-unit record (about 2000 turns of delta) found from
    the whole record and from its tail alone agree to rounding: no running sum of turns enters them (an
    angle unwrapped over the record moved them by up to 1e-10 after 1e4 turns)."""
    y0 = state_at_label(Y, P, 0.1127)
    grid = np.arange(0.0, 4000.25, 0.5)
    hi, lo = flow.propagate_grid(y0, grid)
    t, x = ts.section(flow, hi, lo, grid)
    tail = grid >= 3960.0
    t2, x2 = ts.section(flow, hi[tail], lo[tail], grid[tail])
    mine = t >= 3961.0
    n = int(mine.sum())
    assert n >= 15 and np.max(np.abs(t[mine] - t2[-n:])) < 1e-12 and np.max(np.abs(x[mine] - x2[-n:])) < 1e-15


def test_the_main_torus_reversal_train_is_strictly_periodic(flow):
    """From the paper config's settled point over 8000 time units (4 reversals, at least 3 flips): the
    reversal intervals agree to 1e-10 (the refined events' resolution) and match the flips' interval to
    1e-6; the energy drift is at rounding level."""
    params, y, _ = ts.settled_point(PAPER)
    run = ts.propagate_orbits(DDFlow(params), [y], [8000.0], 0.5)[0]
    ev = ts.cycle_events(DDFlow(params), run, "test")
    d = np.diff(ev["reversal_time"])
    assert ev["reversal_time"].size == 4 and ev["flip_time"].size >= 3 and 2300 < d[0] < 2400
    assert np.ptp(d) < 1e-10 and np.max(ev["reversal_time_err"]) < 1e-10
    assert abs(np.diff(ev["flip_time"])[0] - d[0]) < 1e-6 and ev["energy_max_rel_drift"] < 1e-28


def test_orbits_chunk_work_and_checks():
    """The reference first, then amplitude by amplitude; chunk k holds orbits k, k + n, ...; its work is
    the pre-run and its orbits' horizons; too many chunks, a short reference or an empty law range are
    refused."""
    cfg = dict(SMALL, amplitudes=[1e-6, 1e-3], directions=3, n_chunks=3)
    assert ts.orbits(cfg)[:3] == [(0.0, -1), (1e-6, 0), (1e-6, 1)] and len(ts.orbits(cfg)) == 7
    w = ts.chunk_work(cfg)
    assert w == [1000.0 + 3000.0 + 2 * 2500.0, 1000.0 + 2 * 2500.0, 1000.0 + 2 * 2500.0]  # orbits 0 3 6, 1 4, 2 5
    assert ts.TORUS_STABILITY.work(cfg) == sum(w)
    ts.TORUS_STABILITY.checks("s", cfg)
    for bad, key in ((dict(n_chunks=8), "n_chunks"), (dict(T_reference=1000.0), "T_reference"),
                     (dict(law_amplitudes=[1e-3, 1e-6]), "law_amplitudes")):
        with pytest.raises(ConfigError, match=key):
            ts.TORUS_STABILITY.checks("s", dict(cfg, **bad))


def test_chunks_gather_into_a_classified_dataset(tmp_path):
    """eps = 0.3 (cycles about every 330; its state is not settled after 1000, and no orbit's train is
    periodic there): two chunk jobs, gathered; orbit 0 is the reference, every orbit gets a class of the
    rule with its reason, the perturbed ones an identity ("undetermined" when not shown to be on a torus),
    events per cycle, the laws (none fitted without tori) and the provenance; energy drift of the
    double-double orbits at rounding level; a missing chunk is refused."""
    paths = [write_dataset(ts.chunk(SMALL, k, scene="t"), tmp_path / f"{k}.nc") for k in range(2)]
    ds = ts.gather(paths, SMALL, scene="t")
    assert ds.orbit.values.tolist() == [0, 1, 2, 3, 4] and ds.amplitude.values.tolist() == [0.0, 1e-6, 1e-6, 1e-4, 1e-4]
    assert set(ds.torus_class.values) <= set(torus.CLASSES) and ds.torus_identity.values[0] == torus.REFERENCE
    assert all(i == torus.UNDETERMINED for c, i in zip(ds.torus_class.values[1:], ds.torus_identity.values[1:])
               if c == torus.NOT_SHOWN)
    assert np.all(ds.n_cycles.values >= 4) and np.all(np.isfinite(ds.period.values))
    ok = np.isfinite(ds.reversal_time.values)
    assert np.all(ds.reversal_time_err.values[ok] > 0) and np.all(np.isfinite(ds.reversal_Omega.values[ok]))
    assert np.all(ds.start_distance.values[1:] > 0) and ds.start_distance.values[0] == 0
    assert ds.attrs["energy_max_rel_drift"] < 1e-25 and "train_rule" in ds.attrs and "law_rule" in ds.attrs
    assert ds.attrs["n_perturbed"] == 4 and sum(ds.attrs[f"n_{ts.slug(c)}"] for c in torus.CLASSES) == 4
    assert sum(ds.attrs[f"n_{ts.slug(c)}"] for c in torus.IDENTITIES[1:]) == 4
    assert ds.law_direction.values.tolist() == [0, 1] and ds.attrs["period_law_slope_directions"] == 0
    with pytest.raises(ValueError, match="expected 0 ... 4"):
        ts.gather(paths[:1], SMALL, scene="t")


def test_laws_fit_the_tori_in_the_law_range():
    """The laws read only perturbed orbits shown to be on tori with a in law_amplitudes: two directions,
    period difference -80 (direction 0) and -90 (direction 1) per decade, offsets 1e-3 a^0.2 and 2e-3 a^0.3;
    an orbit not shown to be on a torus and one outside the range change nothing."""
    a = np.array([0.0, 1e-6, 1e-5, 1e-4, 1e-6, 1e-5, 1e-4, 1e-3, 1e-8])
    d = np.array([-1, 0, 0, 0, 1, 1, 1, 1, 0])
    s, p, c = np.where(d == 0, -80.0, -90.0), np.where(d == 0, 0.2, 0.3), np.where(d == 0, 1e-3, 2e-3)
    cls = [torus.PERIODIC] * 7 + [torus.NOT_SHOWN, torus.PERIODIC]
    ds = xr.Dataset({"torus_class": ("orbit", cls), "period_difference": ("orbit", s * np.log10(a + 1e-300) + 7),
                     "spike_point_offset": ("orbit", c * a**p)},
                    coords={"orbit": np.arange(9), "amplitude": ("orbit", a), "direction": ("orbit", d)})
    law = ts.laws(ds, dict(SMALL, law_amplitudes=[1e-6, 1e-3]))
    assert law["period"]["slope"] == pytest.approx(-85.0) and law["period"]["slope_err"] == pytest.approx(5.0)
    assert law["offset"]["slope"] == pytest.approx(0.25) and law["offset"]["slope_err"] == pytest.approx(0.05)
    assert law["period"]["K"] == 2 and law["period"]["residual"] < 1e-9


def test_the_orbits_of_a_chunk_are_lanes_each_bit_for_bit_the_scalar_engines():
    """propagate_orbits batches the orbits of each horizon (engine.ddbatch): every orbit's samples and steps
    equal DDFlow's from the same start, whatever horizon group it is in."""
    flow = DDFlow(Params.from_config({"eps": 0.1, "b": 1.0, "K2": 1.1}), tol=1e-24)
    starts = [np.array([0.02, 0.02, 3.3, 2.5]), np.array([0.0, 0.1, 1.0, 0.0]), np.array([0.021, 0.019, 3.31, 2.4])]
    runs = ts.propagate_orbits(flow, starts, [30.0, 12.0, 30.0], 0.5)
    for y0, T, run in zip(starts, (30.0, 12.0, 30.0), runs):
        hi, lo = flow.propagate_grid(y0, np.arange(0.0, T + 0.25, 0.5))
        assert np.array_equal(run["hi"], hi) and np.array_equal(run["lo"], lo) and run["steps"] == flow.steps
        assert run["grid"][-1] == T and run["cpu_s"] >= 0
