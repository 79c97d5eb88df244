"""The benchmark's analysis helpers, and the configured tolerances against its measurements."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from sleighsim.scenes import bench, bench_peers

ROOT = Path(__file__).resolve().parents[2]


def test_loosest_converged_tolerance():
    tols = [1e-6, 1e-8, 1e-10, 1e-12, 2.2e-16]
    values = [0.7, 0.95, 0.999, 1.0001, 1.0]
    assert bench.loosest_converged(tols, values, rel=0.01) == 1e-10
    assert bench.loosest_converged(tols, values, rel=0.5) == 1e-6
    assert bench.loosest_converged(tols, [2.0, 1.0, 1.0, 1.0, 1.0], rel=0.01) == 1e-8
    # not converged: the second-tightest tolerance already disagrees, or is undetermined
    assert np.isnan(bench.loosest_converged(tols, [1.0, 1.0, 1.0, 1.5, 1.0], rel=0.01))
    assert np.isnan(bench.loosest_converged(tols, [1.0, 1.0, 1.0, np.nan, 1.0], rel=0.01))
    assert np.isnan(bench.loosest_converged([1e-12], [1.0], rel=0.01))


def test_fastest_table_picks_the_fastest_run_reaching_each_error():
    ds = xr.Dataset({"backend": ("run", np.array(["heyoka", "heyoka", "scipy", "scipy"])),
                     "method": ("run", np.array(["taylor", "taylor", "DOP853", "RK45"])),
                     "tol": ("run", [1e-8, 1e-12, 1e-10, 1e-6]),
                     "error_short": ("run", [1e-7, 1e-11, 1e-9, 1e-5]),
                     "wall_short": ("run", [0.01, 0.02, 5.0, 1.0])})
    rows = {r["target"]: r for r in bench.fastest_table(ds, [1e-4, 1e-8, 1e-10, 1e-13])}
    assert rows[1e-4]["fastest"].startswith("heyoka") and rows[1e-4]["speedup_vs_fastest_scipy"] == pytest.approx(100)
    assert rows[1e-8]["speedup_vs_fastest_scipy"] == pytest.approx(250)  # 5.0 s against 0.02 s
    assert np.isnan(rows[1e-10]["speedup_vs_fastest_scipy"])
    assert 1e-13 not in rows


def test_configured_tolerances_are_at_least_as_tight_as_the_converged_ones():
    """Every integrating scene of the paper config (its own tol or the default) is at least as tight
    as the loosest tolerance at which the bench found the scene observables converged."""
    from sleighsim.scenes import catalog

    summary_file = ROOT / "benchmarks" / "bench_summary.yaml"
    if not summary_file.exists():
        pytest.skip("no benchmark summary yet: run `snakemake -c2 bench` and "
                    "`python -m sleighsim.scenes.bench results/data/bench.nc "
                    "--summarize benchmarks/bench_summary.yaml`")
    summary = yaml.safe_load(summary_file.read_text())
    converged = {k: v for k, v in summary.items() if k.startswith("loosest_converged_tol_")}
    assert converged, "the summary holds no converged tolerances"
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    tols = {name: catalog.scene_config(config, name)["tol"] for name in catalog.datasets(config)
            if "tol" in catalog.scene_config(config, name)}
    assert len(tols) >= 10
    for scene, tol in tols.items():
        for name, limit in converged.items():
            assert tol <= limit, f"scenes.{scene}.tol = {tol} is looser than {name} = {limit}"


def test_peer_ratios_compare_the_fastest_run_of_each_engine_reaching_each_target():
    engine = ["heyoka taylor", "heyoka taylor", "scipy DOP853 + numpy rhs", "scipy DOP853 + numpy rhs", "diffrax Tsit5"]
    error = [1e-7, 1e-11, 1e-7, 1e-9, np.nan]  # diffrax failed: no error
    wall = [0.001, 0.002, 0.05, 0.08, 0.01]
    others, ratios = bench_peers.peer_ratios(engine, error, wall, [1e-6, 1e-8, 1e-10, 1e-12])
    assert others == ["scipy DOP853 + numpy rhs", "diffrax Tsit5"]
    assert ratios[0, 0] == pytest.approx(50)  # 0.05 s against 0.001 s
    assert ratios[1, 0] == pytest.approx(40)  # only the tighter runs reach 1e-8: 0.08 s against 0.002 s
    assert np.isnan(ratios[2, 0])  # the peer never reaches 1e-10
    assert np.isnan(ratios[3]).all()  # nobody reaches 1e-12, heyoka included
    assert np.isnan(ratios[:, 1]).all()  # a failed peer has no ratio


def test_quick_bench_holds_the_peer_comparison(tmp_path):
    """The quick bench runs the peers side by side with heyoka against the same reference; a peer
    that is not installed is a row that says so rather than a crash."""
    cfg = dict(bench.QUICK, heyoka_tols=[1e-8, 1e-12], scipy={"DOP853": [1e-8]}, T_lyapunov=100.0, t_long=200.0)
    ds = bench.bench(cfg)
    heyoka = ds.peer_engine.values == "heyoka taylor"
    assert heyoka.sum() == len(cfg["heyoka_tols"]) and np.isfinite(ds.peer_error.values[heyoka]).all()
    ran = np.isfinite(ds.peer_error.values)
    assert (ran | (ds.peer_note.values != "")).all()
    assert ds.peer_ratio.shape == (len(cfg["error_targets"]), ds.sizes["peer"])
    assert ds.sizes["lyap_peer"] == 4 and np.isfinite(ds.lyap_peer_lambda_1.values[1])  # heyoka on Lorenz always runs


def test_the_report_tables_each_peer_ratio_with_its_compile_time():
    from sleighsim.report import build as report

    ds = xr.Dataset({"peer_ratio": (("error_target", "peer"), [[12.0, np.nan]]),
                     "peer_engine_compile_s": ("peer", [0.5, 1.25])},
                    coords={"error_target": [1e-8], "peer": ["diffrax Dopri8", "scipy LSODA + numba rhs"]},
                    attrs={"peer_ratio_rule": "rule", "peer_versions": "diffrax 0.7.2"})
    t = report.peer_table(ds)
    assert t.head == ["error target", "diffrax Dopri8 (compile 0.5 s)", "scipy LSODA + numba rhs (compile 1.2 s)"]
    assert t.rows == [["1e-08", "12x", "not reached"]] and t.note == "rule; versions: diffrax 0.7.2"


def test_the_command_reads_the_bench_block_of_a_config(tmp_path, monkeypatch):
    """`python -m sleighsim.scenes.bench OUT --config config/config.yaml` reads scenes.bench (it read a
    top-level `bench` key, a KeyError on every config) and writes the dataset with its kind's title."""
    from pathlib import Path

    from sleighsim.io.netcdf import read_dataset
    from sleighsim.scenes import bench

    seen = {}

    def fake(cfg):
        seen.update(cfg)
        return xr.Dataset({"wall_short": ("run", [1.0])}, coords={"run": [0]})

    monkeypatch.setattr(bench, "bench", fake)
    bench.main([str(tmp_path / "b.nc"), "--config", str(Path(__file__).parents[2] / "config" / "config.yaml")])
    assert seen["kind"] == "bench" and "t_short" in seen
    assert bench.BENCH.title in read_dataset(tmp_path / "b.nc").attrs["title"]
