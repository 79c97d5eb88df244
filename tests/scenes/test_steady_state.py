"""Poincare crossings, rotation numbers, loop counting, spectra, transient detection."""

import math

import numpy as np
import pytest

from sleighsim.analysis import spectra
from sleighsim.engine import poincare, transient
from sleighsim.io.netcdf import read_dataset, write_dataset
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE
from sleighsim.ops.resultdiff import compare_datasets
from sleighsim.precision import Precision, parsed
from sleighsim.scenes import steady_state


def test_crossings_complete_and_on_the_section_for_uniform_rotation():
    """Rotor-free sleigh at rest in (u, Omega): delta(t) = delta0 - omega0 t exactly."""
    p = Params.sleigh0(b=1.0, K2=1.1)
    delta0, omega0, t0, t1 = 0.3, 1.7, 5.0, 400.0
    c = poincare.crossings(p, [0.2, 0.0, omega0, delta0], t0, t1)
    # delta at t is delta0 - omega0 (t - t0); crossings k pi/2 for k from floor(...) down
    k = np.arange(math.floor(delta0 / (math.pi / 2)), math.ceil((delta0 - omega0 * (t1 - t0)) / (math.pi / 2)) - 1, -1)
    expected = t0 + (delta0 - k * math.pi / 2) / omega0
    expected = expected[(expected > t0) & (expected <= t1)]
    assert len(c["time"]) == len(expected)
    assert np.max(np.abs(c["time"] - expected)) < 1e-10
    assert np.max(c["residual"]) < 1e-12
    k_expected = k[(t0 + (delta0 - k * math.pi / 2) / omega0 > t0) & (t0 + (delta0 - k * math.pi / 2) / omega0 <= t1)]
    assert np.array_equal(c["k"], k_expected % 4)  # the section class, delta = k pi/2 mod 2 pi


def test_crossing_residuals_on_the_sleigh_attractor_region():
    p = Params.paper(eps=0.1)
    c = poincare.crossings(p, REFERENCE_STATE, 0.0, 3000.0)
    assert len(c["time"]) > 1000
    assert np.max(c["residual"]) < 1e-12
    assert np.all(np.diff(c["time"]) > 0)
    E = equations.energy(np.c_[c["u"], c["Omega"], c["omega"], c["k"] * math.pi / 2], p)
    assert np.max(np.abs(E / equations.energy(REFERENCE_STATE, p) - 1)) < 1e-10


def _embedded_circle(theta):
    return np.c_[np.cos(theta) + 0.2, 2.0 * np.sin(theta), 0.3 * np.cos(theta) - 0.1 * np.sin(theta)]


@pytest.mark.parametrize("rho", [0.0123456, -(3 - math.sqrt(5)) / 2, 0.2])
def test_rotation_number_of_a_rigid_rotation(rho):
    theta = 0.4 + 2 * math.pi * rho * np.arange(5000)
    rot = poincare.rotation_number(_embedded_circle(theta))
    assert rot["rotation_number"] == pytest.approx(abs(rho), abs=2e-4)
    assert abs(rot["rotation_number_first_half"] - rot["rotation_number_second_half"]) < 2e-4


def test_rotation_number_of_a_nonlinear_circle_map():
    """theta -> theta + 2 pi Omega - (K / 2 pi) sin(2 pi theta'), K < 1: compare with the lift."""
    Om, K, n = 0.0731, 0.6, 20000
    x = np.empty(n)
    x[0] = 0.1
    for i in range(n - 1):
        x[i + 1] = x[i] + Om - K / (2 * math.pi) * math.sin(2 * math.pi * x[i])
    exact = (x[-1] - x[0]) / (n - 1)
    rot = poincare.rotation_number(_embedded_circle(2 * math.pi * x))
    assert rot["rotation_number"] == pytest.approx(abs(exact), abs=5e-4)
    assert poincare.curve_thickness(_embedded_circle(2 * math.pi * x)) < 1e-2


def test_scattered_points_are_not_a_thin_curve(rng):
    assert poincare.curve_thickness(rng.normal(size=(3000, 3))) > 0.1


@pytest.mark.parametrize("n_loops", [1, 2, 4])
def test_knn_components_count_synthetic_loops(n_loops, rng):
    pts = []
    for j in range(n_loops):
        th = 2 * math.pi * ((math.sqrt(5) - 1) / 2 * np.arange(2000) + rng.uniform())  # circle-rotation iterates
        centre = np.array([3.0 * math.cos(2 * math.pi * j / n_loops), 3.0 * math.sin(2 * math.pi * j / n_loops), 0.0])
        loop = np.c_[np.cos(th), 0.5 * np.sin(th), 0.5 * np.sin(2 * th)]  # thin closed curves, like the iterates
        pts.append(centre + loop + rng.normal(0, 0.002, (2000, 3)))
    count, labels = poincare.knn_components(np.vstack(pts), k=10)
    assert count == n_loops
    assert len(np.unique(labels[:2000])) == 1


def test_count_loops_per_class_separates_crossing_loops(rng):
    """Two loops that cross in the projection: one component together, two loops by class."""
    th = 2 * math.pi * (math.sqrt(2) * np.arange(3000) % 1.0)
    a = np.c_[np.cos(th[:1500]), np.sin(th[:1500]), np.zeros(1500)]
    b = np.c_[np.cos(th[1500:]), np.zeros(1500), np.sin(th[1500:])]
    out = poincare.count_loops(np.vstack([a, b]), np.r_[np.zeros(1500), np.ones(1500)], k=10)
    assert out["n_loops"] == 2 and out["loops_per_class"] == {0: 1, 1: 1}
    assert out["n_components_projected"] == 1


def test_min_pairwise_difference():
    assert poincare.min_pairwise_difference([5.0, 1.0, 3.5, 1.25]) == 0.25


def test_psd_recovers_known_frequencies_within_one_bin(rng):
    dt, T = 0.01, 2000.0
    t = np.arange(0, T, dt)
    freqs = [0.013, 0.55, 1.7]
    x = sum(a * np.sin(2 * math.pi * f * t + ph) for a, f, ph in zip([1.0, 0.5, 0.2], freqs, [0.1, 1.0, 2.0]))
    x = x + rng.normal(0, 0.05, t.size)
    f, S = spectra.psd(x, dt, segment=T)
    df = f[1] - f[0]
    found = f[np.argsort(S)[::-1]]
    for f0 in freqs:
        assert np.min(np.abs(found[:12] - f0)) <= df
    lo, hi, fpk = spectra.band_edges(f, S, f_split=0.2, rel_threshold=1e-2)
    assert abs(fpk - 0.55) <= df and lo <= 0.55 <= hi and abs(hi - 1.7) <= 1.01 * df
    peaks = spectra.peaks_near_zero(f, S, f_split=0.2, prominence_decades=1.0, floor_rel=1e-3)
    assert np.any(np.abs(peaks - 0.013) <= df)
    assert len(peaks) <= 3  # the noise floor, 1e-5 of the maximum, gives no peaks


def test_band_edges_of_a_broadband_signal(rng):
    from scipy import signal

    dt = 0.01
    sos = signal.butter(6, [1.45, 1.8], btype="bandpass", fs=1 / dt, output="sos")
    x = signal.sosfilt(sos, rng.normal(size=400000))
    f, S = spectra.psd(x, dt, segment=200.0)
    lo, hi, _ = spectra.band_edges(f, S, f_split=0.2, rel_threshold=0.1)
    assert lo == pytest.approx(1.45, abs=0.08) and hi == pytest.approx(1.8, abs=0.08)


def test_transient_detector_finds_known_change_points():
    t = np.arange(0, 20000, 0.5)
    omega = np.where(t < 6000, 1 + 2.5 * t / 6000, 3.5 + 0.05 * np.sin(2 * math.pi * t / 2000))
    Omega = 0.03 * np.sin(3.4 * t)
    spikes = [6100.0, 8100.0, 10100.0, 12100.0, 14100.0, 16100.0, 18100.0]
    for s in spikes:
        Omega = Omega + 0.08 * np.exp(-((t - s) / 20.0) ** 2)
    Omega = Omega + 0.1 * np.exp(-((t - 3.0) / 2.0) ** 2)  # the first, sleigh-like phase
    found = transient.spike_times(t, Omega, factor=1.8, t_min=200.0)
    assert np.allclose(found, spikes, atol=5.0)  # located to within the fast oscillation
    settle = transient.settling_time(t, omega, window=2000.0, rtol=0.02)
    assert 5000.0 <= settle <= 8000.0
    rep = transient.steady_state_report(t, Omega, omega, window=2000.0, t_min=200.0)
    assert rep["first_spike"] == pytest.approx(6100.0, abs=5.0)
    assert rep["spike_interval_mean_second_half"] == pytest.approx(2000.0, abs=5.0)


def test_settling_time_is_nan_when_still_drifting():
    t = np.arange(0, 10000, 1.0)
    assert math.isnan(transient.settling_time(t, 1 + t / 1000, window=500.0, rtol=0.01))


def test_block_fluctuation_tells_a_drift_from_a_scatter():
    t = np.arange(0, 20000, 1.0)
    # a drift: block means on a line, no scatter about it, though the rule finds no settling
    assert transient.block_fluctuation(t, 1 + t / 1000, window=1000.0) == pytest.approx(0.0, abs=1e-12)
    # block means alternating +- 10 % about 1: a scatter of that size about their line
    scatter = 1 + 0.1 * np.where((t // 1000) % 2 == 0, 1.0, -1.0)
    assert 0.08 < transient.block_fluctuation(t, scatter, window=1000.0) < 0.12
    assert math.isnan(transient.settling_time(t, scatter, window=1000.0, rtol=0.02))
    assert math.isnan(transient.block_fluctuation(t[:4000], scatter[:4000], window=1000.0))  # two blocks there


# the reference orbit's maps in long double, tiny: about a second
MAPS = parsed({"kind": "poincare", "params": {"eps": 0.1, "b": 1.0, "K2": 1.1}, "y0": [0.0, 0.1, 1.0, 0.0],
        "energy_label": 0.1127, "t_settle": 300.0, "t_map": 100.0, "attractor_span": 20.0, "attractor_dt": 0.1,
        "max_stored_pi2": 1000, "loop_knn": 10, "return_time_tie_tol": 1.0e-7,
        "transient": {"dt": 0.5, "window": 100.0, "rtol": 0.02, "spike_factor": 1.8, "t_min": 50.0},
        "tol": 2.220446049250313e-16, "precision": "long double", "precision_chunks": 2})


def _parts(tmp_path):
    return [write_dataset(steady_state.poincare_chunk(MAPS, k, scene="maps"), tmp_path / f"{k}.nc",
                          precision="long double") for k in range(steady_state.POINCARE.chunk_count(MAPS))]


def test_the_maps_and_attractor_run_as_two_jobs_give_the_dataset_of_one(tmp_path, hy):
    """Numbers, texts and variable attributes equal (resultdiff's comparison: all but wall and compile times)."""
    one = read_dataset(write_dataset(steady_state.poincare_maps(MAPS, scene="maps"), tmp_path / "one" / "maps.nc",
                                     precision="long double"))
    two = read_dataset(write_dataset(steady_state.poincare_gather(_parts(tmp_path), MAPS, scene="maps"),
                                     tmp_path / "two" / "maps.nc", precision="long double"))
    assert list(two.data_vars) == list(one.data_vars) and "attractor_u" in one
    assert compare_datasets(one, two) == []
    assert all(two[v].attrs == one[v].attrs for v in one.variables)


def test_in_double_double_the_maps_and_attractor_share_one_integration_and_give_the_two_jobs_dataset(tmp_path):
    """In double-double one job integrates once (the attractor stretch a second lane of the maps' DDBatch): its
    dataset is the two jobs' (two integrations of their own), numbers bit for bit."""
    cfg = dict(MAPS, precision=Precision.DOUBLE_DOUBLE, t_map=20.0, attractor_span=10.0)
    one = steady_state.poincare_maps(cfg, scene="maps")
    parts = [write_dataset(steady_state.poincare_chunk(cfg, k, scene="maps"), tmp_path / f"{k}.nc",
                           precision="double-double") for k in range(2)]
    two = steady_state.poincare_gather(parts, cfg, scene="maps")
    assert one.attrs["backend"] == "sleighsim.engine.ddtaylor" and one.attractor_u.size == 101
    assert compare_datasets(*(read_dataset(write_dataset(d, tmp_path / k / "maps.nc", precision="double-double"))
                              for k, d in (("one", one), ("two", two)))) == []
    assert one.attrs["steps"] == two.attrs["steps"]


def test_the_gather_refuses_parts_from_different_settled_states(tmp_path, hy):
    paths = _parts(tmp_path)
    moved = read_dataset(paths[1])
    moved.attrs["settled_state"] = moved.attrs["settled_state"] + 1e-15
    write_dataset(moved, paths[1], precision="long double")
    with pytest.raises(ValueError, match="settled states"):
        steady_state.poincare_gather(paths, MAPS, scene="maps")


@pytest.mark.parametrize(("asked", "jobs"), [(None, 1), (1, 1), (2, 2), (5, 2)])
def test_a_finer_precision_runs_in_one_job_or_two(asked, jobs):
    cfg = {k: v for k, v in MAPS.items() if k != "precision_chunks"}
    assert steady_state.POINCARE.chunk_count(cfg if asked is None else dict(cfg, precision_chunks=asked)) == jobs
