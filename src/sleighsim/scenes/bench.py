"""Speed against error: heyoka at several tolerances against SciPy's solvers and the peers.

Error is measured against a heyoka reference in extended precision (long double),
shown converged by comparing two of its tolerances: the end-state error on a short
horizon (before sensitivity amplifies it) and the maximum relative energy drift on a
long one. Wall times are medians of ``repeats`` runs; heyoka's JIT compile time is
reported apart. The scene observables (spike interval, end of the second transient,
lambda_1 over a fixed horizon, P_2pi rotation number) are measured against tolerance.

The peer comparison (``cfg["peers"]``, :mod:`sleighsim.scenes.bench_peers`) runs every engine a Python
user would pick instead at the same rtols, against the same reference, and the Lyapunov kernel
against lyapax.

Run: ``python -m sleighsim.scenes.bench [--quick] OUT.nc`` or ``snakemake -c2 bench``.
"""

from __future__ import annotations

import argparse
import logging
import math
import time

import numpy as np
import xarray as xr

from sleighsim.chaos import benettin
from sleighsim.engine import integrators, poincare, transient
from sleighsim.engine.integrate import final_state, integrate, sample_grid
from sleighsim.io.netcdf import write_dataset
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.precision import Precision
from sleighsim.scenes import memory
from sleighsim.scenes.bench_peers import heyoka_end_state, peer_comparison
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def reference(params, y0, t_end, tol):
    """End state at t_end with heyoka in long double precision (``integrators.flow``); returns (state, wall)."""
    start = time.perf_counter()
    ta, _ = integrators.flow(False, tol, Precision.LONG_DOUBLE)
    integrators.set_pars(ta, params)
    ta.time = np.longdouble(0)
    integrators.load(ta, np.asarray(y0, np.longdouble))
    ta.propagate_until(np.longdouble(t_end), callback=integrators.bounded(ta))
    return np.asarray(integrators.read(ta, 4), float), time.perf_counter() - start


def _median_run(fn, repeats):
    walls, out = [], None
    for _ in range(repeats):
        out = fn()
        walls.append(out.attrs["wall_time_s"])
    return out, float(np.median(walls))


def work_precision(cfg: dict) -> xr.Dataset:
    """One row per (method, tolerance): short-horizon error, long-horizon drift, wall times,
    and the scene observables measured on the long run."""
    params = Params.from_config(cfg["params"])
    y0 = np.asarray(cfg["y0"], float)
    ref, ref_wall = reference(params, y0, cfg["t_short"], cfg["reference_tols"][0])
    ref2, _ = reference(params, y0, cfg["t_short"], cfg["reference_tols"][1])
    equations.full_rhs(y0, params)  # build the NumPy right-hand side once, outside the timed SciPy runs
    rows = []
    runs = [("heyoka", "taylor", tol, True) for tol in cfg["heyoka_tols"]]
    runs += [("scipy", m, r, True) for m, rtols in cfg["scipy"].items() for r in rtols]
    # Tight SciPy tolerances cost minutes on the long horizon: short horizon only.
    runs += [("scipy", m, r, False) for m, rtols in cfg.get("scipy_short_only", {}).items() for r in rtols]
    for backend, method, tol, with_long in runs:
        kw = dict(backend=backend, tol=tol, progress=1) if backend == "heyoka" else dict(
            backend="scipy", method=method, rtol=tol, atol=tol * cfg["atol_factor"], progress=1)
        if backend == "heyoka":
            integrators.flow(False, tol)  # compile outside the timed runs
        reps = cfg["repeats"] if backend == "heyoka" else cfg["scipy_repeats"]
        short, wall_short = _median_run(lambda kw=kw: integrate(params, y0, [0.0, cfg["t_short"]], **kw), reps)
        err = float(np.max(np.abs(equations.state_difference(final_state(short), ref))))
        row = dict(backend=backend, method=method, tol=tol, error_short=err, wall_short=wall_short,
                   drift_long=np.nan, wall_long=np.nan, steps_long=-1,
                   compile_s=integrators.flow(False, tol)[1] if backend == "heyoka" else 0.0,
                   first_spike=np.nan, spike_interval=np.nan, n_spikes=-1)
        if with_long:
            long_ = integrate(params, y0, sample_grid(0.0, cfg["t_long"], cfg["dt_long"]), **kw)
            spikes = transient.spike_times(long_.time.values, long_.Omega.values, t_min=cfg["t_min"])
            row.update(drift_long=long_.attrs["energy_max_rel_drift"], wall_long=long_.attrs["wall_time_s"],
                       steps_long=long_.attrs["steps"], first_spike=float(spikes[0]) if spikes.size else np.nan,
                       spike_interval=transient.interval_stats(spikes)[0], n_spikes=int(spikes.size))
        rows.append(row)
        log.info("bench %s %s %.0e: error %.2g in %.3g s; drift %.2g in %.3g s; spike interval %.5g", backend,
                 method, tol, err, wall_short, rows[-1]["drift_long"], rows[-1]["wall_long"],
                 rows[-1]["spike_interval"])
    ds = xr.Dataset({k: ("run", np.array([r[k] for r in rows])) for k in rows[0]})
    ds["reference_state"] = ("component", ref)
    ds.attrs.update(params.attrs())
    ds.attrs.update(
        t_short=cfg["t_short"], t_long=cfg["t_long"], repeats_heyoka=cfg["repeats"],
        repeats_scipy=cfg["scipy_repeats"], reference="heyoka long double",
        reference_tols=np.array(cfg["reference_tols"]), reference_self_difference=float(np.max(np.abs(ref - ref2))),
        reference_wall_s=ref_wall, atol_factor=cfg["atol_factor"],
    )
    return ds


LYAPUNOV_TAU = 10.0  # renormalisation interval of the Lyapunov kernel


def _settled(cfg):
    params = Params.from_config(cfg["params"])
    return params, final_state(integrate(params, cfg["y0"], [0.0, cfg["t_settle"]], progress=1))


def observables_vs_tol(cfg: dict) -> xr.Dataset:
    """lambda_1 over a fixed horizon (with its wall time) and the P_2pi rotation number,
    against heyoka's tolerance."""
    params, y = _settled(cfg)
    lam, wall, rot = [], [], []
    for tol in cfg["heyoka_tols"]:
        ta, _ = integrators.sleigh_tangent(1, tol, True)
        integrators.set_pars(ta, params)
        r = benettin.benettin(ta, 4, 1, y, t_align=0.0, T=cfg["T_lyapunov"], tau=LYAPUNOV_TAU)
        lam.append(r["exponents"][0])
        wall.append(r["wall_time_s"])
        c = poincare.crossings(params, y, 0.0, cfg["t_rotation"], tol=tol)
        rot.append(poincare.rotation_number(np.c_[c["u"], c["Omega"], c["omega"]][c["k"] % 4 == 0])["rotation_number"])
        log.info("bench tol %.0e: lambda_1 %.5g in %.3g s, rotation number %.6g", tol, lam[-1], wall[-1], rot[-1])
    return xr.Dataset({"lambda_1": ("tol", lam), "lambda_1_wall": ("tol", wall), "rotation_number": ("tol", rot)},
                      coords={"tol": np.array(cfg["heyoka_tols"], float)},
                      attrs=dict(T_lyapunov=cfg["T_lyapunov"], t_rotation=cfg["t_rotation"], t_settle=cfg["t_settle"],
                                 lyapunov_tau=LYAPUNOV_TAU))


def scipy_max_le(params, y, T, tau, method, rtol, atol, seed=0) -> tuple[float, float]:
    """Benettin's largest exponent with SciPy: the flow and one tangent vector (J(y) v, with
    the derived Jacobian) integrated over T in segments of tau, renormalised after each.
    The same initial tangent vector as sleighsim.chaos.benettin. Returns (lambda_1, wall seconds)."""
    from scipy.integrate import solve_ivp

    def f(t, z):
        return np.concatenate([equations.rhs(z[:4], params), equations.jacobian(z[:4], params) @ z[4:]])

    z = np.r_[np.asarray(y, float), benettin.initial_directions(4, 1, seed)[:, 0]]
    n, total = int(round(T / tau)), 0.0
    start = time.perf_counter()
    for _ in range(n):
        sol = solve_ivp(f, (0.0, tau), z, method=method, rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(f"SciPy {method} Lyapunov run failed: {sol.message}")
        z = sol.y[:, -1]
        z[3] %= 2.0 * math.pi  # an exact symmetry: delta stays bounded
        norm = np.linalg.norm(z[4:])
        total += math.log(norm)
        z[4:] /= norm
    return total / (n * tau), time.perf_counter() - start


def lyapunov_kernel_scipy(cfg: dict) -> xr.Dataset:
    """The Lyapunov kernel (lambda_1 over T_lyapunov from the settled state) with SciPy's methods."""
    params, y = _settled(cfg)
    rows = []
    for method, rtols in cfg["scipy_lyapunov"].items():
        for rtol in rtols:
            lam, wall = scipy_max_le(params, y, cfg["T_lyapunov"], LYAPUNOV_TAU, method, rtol,
                                     rtol * cfg["atol_factor"])
            rows.append((method, rtol, lam, wall))
            log.info("bench Lyapunov SciPy %s %.0e: lambda_1 %.5g in %.3g s", method, rtol, lam, wall)
    return xr.Dataset({"lyap_scipy_method": ("lyap_scipy", [r[0] for r in rows]),
                       "lyap_scipy_rtol": ("lyap_scipy", [r[1] for r in rows]),
                       "lyap_scipy_lambda_1": ("lyap_scipy", [r[2] for r in rows]),
                       "lyap_scipy_wall": ("lyap_scipy", [r[3] for r in rows])})


def loosest_converged(tols, values, rel: float) -> float:
    """The loosest tolerance from which on (to the tightest) the observable stays within
    ``rel`` of its value at the tightest tolerance; NaN (not converged) when not even the
    second-tightest tolerance agrees with the tightest, or the value there is undetermined."""
    order = np.argsort(tols)
    tols, values = np.asarray(tols)[order], np.asarray(values)[order]
    best = values[0]
    ok = np.isfinite(values) & (np.abs(values - best) <= rel * abs(best))
    k = 0
    while k + 1 < len(ok) and ok[k + 1]:
        k += 1
    return float(tols[k]) if k > 0 else float("nan")


def fastest_table(ds: xr.Dataset, targets) -> list[dict]:
    """For each error target: the fastest run reaching it and its speed ratio to the fastest SciPy run."""
    out = []
    for target in targets:
        ok = ds.error_short.values <= target
        if not ok.any():
            continue
        best = int(np.argmin(np.where(ok, ds.wall_short.values, np.inf)))
        sp = ok & (ds.backend.values == "scipy")
        ratio = float(np.min(ds.wall_short.values[sp]) / ds.wall_short.values[best]) if sp.any() else float("nan")
        out.append(dict(target=target, fastest=f"{ds.backend.values[best]} {ds.method.values[best]} "
                        f"tol {ds.tol.values[best]:.0e}", wall=float(ds.wall_short.values[best]),
                        speedup_vs_fastest_scipy=ratio))
    return out


def overhead(cfg: dict) -> dict:
    """Wall time of integrate() (sampling, energy check, Dataset) over a bare propagation, F3 scene."""
    params = Params.from_config(cfg["params"])
    run, _ = heyoka_end_state(params, cfg["y0"], cfg["t_long"], 2.0**-52)
    bare = []
    for _ in range(cfg["repeats"]):
        t0 = time.perf_counter()
        run()
        bare.append(time.perf_counter() - t0)
    full = []
    for _ in range(cfg["repeats"]):
        t0 = time.perf_counter()
        integrate(params, cfg["y0"], sample_grid(0.0, cfg["t_long"], cfg["dt_long"]), progress=20)
        full.append(time.perf_counter() - t0)
    return {"bare_s": float(np.median(bare)), "workflow_s": float(np.median(full)),
            "overhead_ratio": float(np.median(full) / np.median(bare))}


def bench(cfg: dict, scene: str = "") -> xr.Dataset:
    """Everything above in one dataset."""
    start = time.perf_counter()
    wp = work_precision(cfg)
    peer = peer_comparison(cfg, Params.from_config(cfg["params"]), np.asarray(cfg["y0"], float),
                           wp.reference_state.values)
    obs = observables_vs_tol(cfg)
    lyap = lyapunov_kernel_scipy(cfg)
    ds = xr.merge([wp, peer, obs.rename({"tol": "tol_observable"}), lyap], compat="override")
    hy = wp.backend.values == "heyoka"
    conv = {
        "spike_interval": loosest_converged(wp.tol.values[hy], wp.spike_interval.values[hy], cfg["rel_converged"]),
        "first_spike": loosest_converged(wp.tol.values[hy], wp.first_spike.values[hy], cfg["rel_converged"]),
        "lambda_1": loosest_converged(obs.tol.values, obs.lambda_1.values, cfg["rel_converged_lyapunov"]),
        "rotation_number": loosest_converged(obs.tol.values, obs.rotation_number.values, cfg["rel_converged"]),
    }
    table = fastest_table(wp, cfg["error_targets"])
    ds.attrs.update(wp.attrs)
    ds.attrs.update(obs.attrs)
    ds.attrs.update({f"loosest_converged_tol_{k}": v for k, v in conv.items()})
    ds.attrs.update(rel_converged=cfg["rel_converged"], rel_converged_lyapunov=cfg["rel_converged_lyapunov"])
    for row in table:
        key = f"{row['target']:.0e}"
        ds.attrs[f"fastest_at_{key}"] = row["fastest"]
        ds.attrs[f"speedup_vs_scipy_at_{key}"] = row["speedup_vs_fastest_scipy"]
    ds.attrs.update(peer.attrs)
    for i, target in enumerate(peer.error_target.values):
        for j, name in enumerate(peer.peer.values):
            ds.attrs[f"peer_ratio_at_{target:.0e}_{name.replace(' ', '_')}"] = float(peer.peer_ratio.values[i, j])
    ds.attrs.update({f"overhead_{k}": v for k, v in overhead(cfg).items()})
    ds.attrs["wall_time_s"] = time.perf_counter() - start
    return ds


#: The variables only this kind writes: name -> (long_name, kind of quantity) (``sleighsim.io.cf``).
VOCABULARY = {
    "backend": ("integration backend", "text"),
    "error_short": ("max |state difference| from the reference at t_short", "1"),
    "wall_short": ("median wall-clock time of the run to t_short", "s"),
    "drift_long": ("max |E(t) / E(0) - 1| of the run to t_long", "1"),
    "wall_long": ("wall-clock time of the run to t_long", "s"),
    "steps_long": ("integrator steps of the run to t_long (-1: not run)", "1"),
    "tol_observable": ("heyoka tolerance of the observables' runs", "1"),
    "lambda_1_wall": ("wall-clock time of the lambda_1 run", "s"),
    "error_target": ("error target", "1"),
    "peer": ("peer engine", "text"),
    "peer_run": ("index of the peer run", "1"),
    "peer_engine": ("peer engine of the run", "text"),
    "peer_rtol": ("relative tolerance of the peer run", "1"),
    "peer_error": ("max |state difference| of the peer run from the reference", "1"),
    "peer_wall": ("median wall-clock time of the peer run after warm-up", "s"),
    "peer_compile_s": ("compile time of the peer run", "s"),
    "peer_note": ("note on the peer run", "text"),
    "peer_ratio": ("fastest wall-clock time of the peer reaching the error target over heyoka's", "1"),
    "peer_engine_compile_s": ("compile time of the peer engine", "s"),
    "lyap_peer": ("index of the Lyapunov peer run", "1"),
    "lyap_peer_system": ("system of the Lyapunov peer run (the sleigh, or Lorenz in its own time unit)", "text"),
    "lyap_peer_engine": ("engine of the Lyapunov peer run", "text"),
    "lyap_peer_lambda_1": ("largest Lyapunov exponent lambda_1 of the peer run's system", "rate"),
    "lyap_peer_wall": ("wall-clock time of the Lyapunov peer run", "s"),
    "lyap_peer_compile_s": ("compile time of the Lyapunov peer run", "s"),
    "lyap_peer_note": ("note on the Lyapunov peer run", "text"),
    "lyap_scipy": ("index of the SciPy Lyapunov run", "1"),
    "lyap_scipy_method": ("SciPy method of the Lyapunov run", "text"),
    "lyap_scipy_rtol": ("relative tolerance of the SciPy Lyapunov run", "1"),
    "lyap_scipy_lambda_1": ("largest Lyapunov exponent lambda_1 with SciPy's method", "rate"),
    "lyap_scipy_wall": ("wall-clock time of the SciPy Lyapunov run", "s"),
}


BENCH = SceneKind(
    name="bench",
    title="speed against error: heyoka, SciPy and peer engines",
    vocabulary=VOCABULARY,
    compute=bench, integrates=False,
                  records=lambda c: [memory.span(c, "t_long", "dt_long")])


QUICK = dict(
    params={"eps": 0.1, "b": 1.0, "K2": 1.1}, y0=[0.0, 0.1, 1.0, 0.0], t_short=100.0, t_long=600.0, dt_long=0.5,
    t_min=50.0, heyoka_tols=[1e-8, 1e-12, 2.220446049250313e-16], reference_tols=[1e-19, 1e-17],
    scipy={"DOP853": [1e-8], "RK45": [1e-6]}, atol_factor=1e-3, repeats=3, scipy_repeats=1, t_settle=100.0,
    T_lyapunov=200.0, scipy_lyapunov={"DOP853": [1e-8]}, t_rotation=100.0, rel_converged=0.01,
    rel_converged_lyapunov=0.05, error_targets=[1e-6, 1e-8],
    peers=dict(rtols=[1e-6, 1e-8], scipy_methods=["DOP853"], rhs_kinds=["numpy", "heyoka"], diffrax_solvers=["Dopri8"],
               repeats=3, warmup=1, lyapunov=dict(T_lorenz=200.0, T_sleigh=200.0, tau=1.0, repeats=1, lyapax_dt=[0.01],
                                                  lyapax_dt_sleigh=[0.05], heyoka_tols=[1e-9])),
)


def summary(ds: xr.Dataset) -> dict:
    """The numbers worth keeping under version control: loosest converged tolerances,
    speed ratios, overhead, and where they came from."""
    keep = {k: (float(v) if isinstance(v, (float, np.floating)) else str(v)) for k, v in ds.attrs.items()
            if k.startswith(("loosest_converged_tol_", "fastest_at_", "speedup_vs_scipy_at_", "overhead_",
                             "peer_ratio_at_"))
            or k in ("reference_self_difference", "t_short", "t_long", "git_commit", "created_utc")}
    return dict(sorted(keep.items()))


def main(argv=None):
    """The bench from the command line: run it (or ``--quick``) into OUT, or ``--summarize`` an existing one."""
    parser = argparse.ArgumentParser(prog="python -m sleighsim.scenes.bench", description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="netCDF file to write")
    parser.add_argument("--config", help="config YAML whose scenes hold a bench block (default: config/config.yaml)")
    parser.add_argument("--quick", action="store_true", help="a tiny run (seconds), for a first look")
    parser.add_argument("--summarize", metavar="YAML", help="read OUT (an existing bench dataset) and write "
                        "its summary (loosest converged tolerances, speed ratios) to YAML instead of running")
    args = parser.parse_args(argv)
    if args.summarize:
        import yaml

        from sleighsim.io.netcdf import read_dataset, write_text

        write_text(args.summarize, yaml.safe_dump(summary(read_dataset(args.out))))
        return
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(message)s")
    if args.quick:
        cfg = QUICK
    else:
        import yaml

        cfg = yaml.safe_load(open(args.config or "config/config.yaml"))["scenes"]["bench"]
    write_dataset(bench(cfg), args.out, what=BENCH.title, vocabulary=BENCH.vocabulary)


if __name__ == "__main__":
    main()
