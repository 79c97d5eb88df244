"""The torus-stability scene (sleighsim.scenes.torus_stability): starts on the energy level at the asked
size, section crossings and spike states from the Taylor jets against direct double-double propagation,
the chunking and its checks, and a short run chunked and gathered into a classified dataset."""

import math

import numpy as np
import pytest

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
             tol=1e-12, tol_dd=1e-32, T=2000.0, T_reference=3000.0, dt=0.5, amplitudes=[1e-6], directions=2, seed=39,
             spike_factor=1.8, spike_half_width=50.0, curve_order=10, min_spikes=5, leave_distance=0.1,
             change_factor=2.0, same_factor=3.0, sigma=3.0, period_rtol=1e-9, n_chunks=2)


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


def test_section_crossings_and_fast_phases_match_direct_propagation(flow):
    """Every crossing of delta = 0 (mod 2 pi) over 30 time units from the jets of samples 0.5 apart:
    about 3.3 / (2 pi) per time unit; at three of them, propagating to the crossing time directly
    gives delta = 0 mod 2 pi and the same (u, Omega, omega) to 1e-13; the fast phase at given times
    likewise."""
    y0 = state_at_label(Y, P, 0.1127)
    grid = np.arange(0.0, 30.25, 0.5)
    hi, lo = flow.propagate_grid(y0, grid)
    t, x = ts.section(flow, hi, lo, grid)
    assert 13 <= t.size <= 18 and np.all(np.diff(t) > 1.5)
    for i in (0, t.size // 2, t.size - 1):
        h, _ = flow.propagate(y0, t[i])
        assert abs(math.remainder(h[3], 2 * math.pi)) < 1e-12
        assert np.max(np.abs(h[:3] - x[i])) < 1e-13
    times = np.array([3.1, 17.77, 29.9])
    phase = ts.fast_phase(flow, hi, lo, grid, times)
    for k, tk in enumerate(times):
        h, _ = flow.propagate(y0, tk)
        assert abs(math.remainder(h[3] - phase[k], 2 * math.pi)) < 1e-12 and 0 <= phase[k] < 2 * math.pi


def test_orbits_chunk_work_and_checks():
    """The reference first, then amplitude by amplitude; chunk k holds orbits k, k + n, ...; its work is
    the pre-run and its orbits' horizons; too many chunks or a short reference are refused."""
    cfg = dict(SMALL, amplitudes=[1e-6, 1e-3], directions=3, n_chunks=3)
    assert ts.orbits(cfg)[:3] == [(0.0, -1), (1e-6, 0), (1e-6, 1)] and len(ts.orbits(cfg)) == 7
    w = ts.chunk_work(cfg)
    assert w == [1000.0 + 3000.0 + 2 * 2000.0, 1000.0 + 2 * 2000.0, 1000.0 + 2 * 2000.0]  # orbits 0 3 6, 1 4, 2 5
    assert ts.TORUS_STABILITY.work(cfg) == sum(w)
    ts.TORUS_STABILITY.checks("s", cfg)
    with pytest.raises(ConfigError, match="n_chunks"):
        ts.TORUS_STABILITY.checks("s", dict(cfg, n_chunks=8))
    with pytest.raises(ConfigError, match="T_reference"):
        ts.TORUS_STABILITY.checks("s", dict(cfg, T_reference=1000.0))


def test_chunks_gather_into_a_classified_dataset(tmp_path):
    """eps = 0.3 (spikes about every 330): two chunk jobs, gathered; orbit 0 is the reference, the others
    get a class of the rule with its reason, distances per spike, and the provenance; energy drift of
    the double-double orbits at rounding level; a missing chunk is refused."""
    paths = [write_dataset(ts.chunk(SMALL, k, scene="t"), tmp_path / f"{k}.nc") for k in range(2)]
    ds = ts.gather(paths, SMALL, scene="t")
    assert ds.orbit.values.tolist() == [0, 1, 2] and ds.amplitude.values.tolist() == [0.0, 1e-6, 1e-6]
    assert ds.torus_class.values[0] == "reference" and set(ds.torus_class.values[1:]) <= set(torus.CLASSES)
    assert ds.n_spikes.values[0] >= 8 and np.all(ds.n_spikes.values[1:] >= 5)
    ok = np.isfinite(ds.spike_time.values)
    assert np.all(np.isfinite(ds.curve_distance.values[ok])) and not np.any(np.isfinite(ds.curve_distance.values[~ok]))
    assert np.all(ds.start_distance.values[1:] > 0) and ds.start_distance.values[0] == 0
    assert ds.attrs["energy_max_rel_drift"] < 1e-25 and "classification_rule" in ds.attrs
    assert ds.attrs["n_perturbed"] == 2 and sum(ds.attrs[f"n_{c.replace(' ', '_')}"] for c in torus.CLASSES) == 2
    with pytest.raises(ValueError, match="expected 0 ... 2"):
        ts.gather(paths[:1], SMALL, scene="t")
