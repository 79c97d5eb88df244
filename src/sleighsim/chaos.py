"""Lyapunov scenes and the chaos verdict (F10, F11, C18-C21, C25-C27).

Each function takes its config block and returns one Dataset; the Benettin and
0-1 engines live in :mod:`sleighsim.lyapunov`.
"""

from __future__ import annotations

import logging
import math
import time
from functools import lru_cache

import numpy as np
import sympy as sp
import xarray as xr

from . import lyapunov, mechanics as mech, model, transient
from .integrate import final_state, integrate, sample_grid
from .io import provenance_attrs, read_dataset

log = logging.getLogger("sleighsim")


@lru_cache(maxsize=None)
def _tangent(k, tol, compact):
    """Sleigh plus k tangent vectors (cached per process). compact_mode compiles in
    0.1 s but steps about 2.5x slower; full mode compiles in 11 s (k = 1) to 60 s (k = 4)."""
    ta, _, compile_s = lyapunov.tangent_integrator(model.heyoka_system(), k, tol,
                                                   model.Params.paper(eps=0.1).values, compact_mode=compact)
    return ta, compile_s


@lru_cache(maxsize=None)
def _tangent_batch(batch_size, tol, compact):
    """Sleigh plus one tangent vector in ``batch_size`` SIMD lanes (cached per process)."""
    ta, _, compile_s = lyapunov.tangent_integrator_batch(model.heyoka_system(), batch_size, tol,
                                                         npars=len(model.PARAM_NAMES), compact_mode=compact)
    return ta, compile_s


@lru_cache(maxsize=None)
def _divergence_integrator(tol):
    """The flow plus a quadrature D' = trace J(y): D(T)/T is the mean phase-space
    contraction, computed without tangent vectors."""
    import heyoka as hy

    d = mech.derive()
    trace = sum(sp.diff(d.rhs[i], s) for i, s in enumerate(mech.STATE))
    sys = model.heyoka_system()
    hv = [v for v, _ in sys]
    smap = {s: v for s, v in zip(mech.STATE, hv)}
    smap.update({s: hy.par[i] for i, s in enumerate(mech.PHYSICAL)})
    D = hy.make_vars("D")
    return hy.taylor_adaptive(sys + [(D, hy.from_sympy(trace, smap))], [0.0, 0.1, 1.0, 0.0, 0.0], tol=tol,
                              pars=list(model.Params.paper(eps=0.1).values))


def mean_divergence(params, y0, T, tol) -> float:
    """(1/T) integral of trace J along the orbit from y0 over [0, T]."""
    ta = _divergence_integrator(tol)
    ta.time = 0.0
    ta.state[:] = [*np.asarray(y0, float), 0.0]
    ta.pars[:] = params.values
    ta.propagate_until(float(T))
    return float(ta.state[4] / T)


def _settle(params, y0, t_pre, tol, label, tc):
    """Plain pre-run with the transient rule of sleighsim.transient; returns (end state, over?, settling time)."""
    dt = tc["dt_fraction"] * t_pre
    pre = integrate(params, y0, sample_grid(0.0, t_pre, dt), tol=tol, scene=f"{label}.pre", progress=1)
    settle = transient.settling_time(pre.time.values, pre.omega.values, window=tc["window_fraction"] * t_pre,
                                     rtol=tc["rtol"])
    over = bool(np.isfinite(settle) and settle <= (1 - 2 * tc["window_fraction"]) * t_pre)
    return final_state(pre), over, settle


def _run(params, y, *, k, cfg, compact, label, T=None, seed=0):
    ta, compile_s = _tangent(k, cfg["tol"], compact)
    ta.pars[:] = params.values
    out = lyapunov.benettin(ta, 4, k, y, t_align=cfg["t_align"], T=cfg["T"] if T is None else T, tau=cfg["tau"],
                            n_blocks=cfg["n_blocks"], seed=seed, label=label)
    out["compile_time_s"] = compile_s
    return out


def _common_attrs(params, y0, cfg, scene):
    out = model.state_attrs(params, y0)
    out.update(scene=scene, backend="heyoka", method="Benettin QR on var_ode_sys", tol=cfg["tol"],
               tau=cfg["tau"], t_align=cfg["t_align"], n_blocks=cfg["n_blocks"])
    return out


def spectrum(cfg: dict, scene: str = "") -> xr.Dataset:
    """All four exponents at one state after a transient, lambda_i(T) on a log grid, the
    independent mean divergence over the same window (C18), and the alignment effect."""
    start = time.perf_counter()
    params = model.Params.from_config(cfg["params"])
    y0 = model.state_at_label(cfg["y0"], params, cfg["energy_label"])
    y, over, settle = _settle(params, y0, cfg["t_transient"], cfg["tol"], scene, cfg["transient"])
    res = _run(params, y, k=4, cfg=cfg, compact=cfg["compact_mode"], label=scene)
    # The same window without alignment shows the bias of the initial directions.
    no_align = _run(params, y, k=4, cfg=dict(cfg, t_align=0.0), compact=cfg["compact_mode"], label=f"{scene}.noalign",
                    T=cfg["T_bias_check"])
    aligned_short = res["running"][max(0, np.searchsorted(res["T_grid"], cfg["T_bias_check"], side="right") - 1)]
    div = mean_divergence(params, _advance(params, y, cfg["t_align"], cfg["tol"]), cfg["T"], cfg["tol"])
    ds = xr.Dataset(
        {
            "exponent": ("i", res["exponents"], {"long_name": "Lyapunov exponent", "units": "1/time"}),
            "stderr": ("i", res["stderr"], {"long_name": "standard error from block estimates", "units": "1/time"}),
            "block_estimate": (("block", "i"), res["block_estimates"], {"units": "1/time"}),
            "running": (("T", "i"), res["running"], {"long_name": "finite-time estimate lambda_i(T)", "units": "1/time"}),
        },
        coords={"i": np.arange(1, 5), "T": ("T", res["T_grid"], {"units": "time"}),
                "block": np.arange(cfg["n_blocks"])},
    )
    ds.attrs.update(_common_attrs(params, y0, cfg, scene))
    lam = res["exponents"]
    ds.attrs.update(
        t_transient=cfg["t_transient"], T=cfg["T"], transient_over=int(over), transient_settling_time=settle,
        mean_divergence=div, sum_lambda_1_4=float(lam[0] + lam[3]), sum_all=float(lam.sum()),
        T_bias_check=cfg["T_bias_check"],
        lambda_1_no_alignment=float(no_align["exponents"][0]), lambda_1_aligned_at_T_bias_check=float(aligned_short[0]),
        lambda_1_decay_slope_last_decade=_decay_slope(res["T_grid"], res["running"][:, 0]),
        compile_time_s=res["compile_time_s"], wall_time_s=time.perf_counter() - start,
        energy_max_rel_drift=float(abs(model.energy(res["final_state"], params) / model.energy(y0, params) - 1)),
    )
    ds.attrs.update(provenance_attrs())
    log.info("%s: exponents %s +- %s; lambda1+lambda4 %.3g vs mean divergence %.3g", scene, lam, res["stderr"],
             lam[0] + lam[3], div)
    return ds


def _advance(params, y, t, tol):
    if t <= 0:
        return y
    out = integrate(params, y, [0.0, t], tol=tol, progress=1)
    return final_state(out)


def _decay_slope(T, lam):
    """Slope of log|lambda_1(T)| against log T over the last decade of T: about -1 for
    a zero exponent (bounded tangent growth), about 0 for a converged nonzero one."""
    sel = T >= T[-1] / 10
    a = np.abs(lam[sel])
    if np.any(a == 0) or sel.sum() < 3:
        return float("nan")
    return float(np.polyfit(np.log(T[sel]), np.log(a), 1)[0])


def protocol(cfg: dict, scene: str = "") -> xr.Dataset:
    """The paper's protocol (pre-run, T, renormalisation interval tau) from several initial
    states on one energy level, to show the spread of its finite-time exponents (C19)."""
    start = time.perf_counter()
    params = model.Params.from_config(cfg["params"])
    states = [model.state_at_label(s, params, cfg["energy_label"]) for s in cfg["states"]]
    exps, errs = [], []
    for j, y0 in enumerate(states):
        y = _advance(params, y0, cfg["t_transient"], cfg["tol"])
        r = _run(params, y, k=4, cfg=cfg, compact=True, label=f"{scene}[{j}]", seed=j)
        exps.append(r["exponents"])
        errs.append(r["stderr"])
        log.info("%s[%d]: %s", scene, j, r["exponents"])
    ds = xr.Dataset(
        {"exponent": (("state", "i"), np.array(exps), {"units": "1/time"}),
         "stderr": (("state", "i"), np.array(errs), {"units": "1/time"}),
         "y0": (("state", "component"), np.array(states))},
        coords={"i": np.arange(1, 5), "component": list(model.STATE_NAMES)},
    )
    ds.attrs.update(_common_attrs(params, states[0], cfg, scene))
    ds.attrs.update(t_transient=cfg["t_transient"], T=cfg["T"], wall_time_s=time.perf_counter() - start,
                    spread_lambda_1=float(np.ptp(np.array(exps)[:, 0])))
    ds.attrs.update(provenance_attrs())
    return ds


def energy_sweep(cfg: dict, scene: str = "") -> xr.Dataset:
    """Max LE at several energy labels, horizons scaled by the time-scaling law so every
    label costs the same; the law's prediction from the reference label; a fitted exponent."""
    start = time.perf_counter()
    params = model.Params.from_config(cfg["params"])
    labels = np.asarray(cfg["labels"], float)
    lam, err = np.empty(labels.size), np.empty(labels.size)
    for j, lab in enumerate(labels):
        s = math.sqrt(cfg["reference_label"] / lab)  # time unit at this label relative to the reference
        y0 = model.state_at_label(cfg["y0"], params, lab)
        y = _advance(params, y0, cfg["t_transient"] * s, cfg["tol"])
        r = _run(params, y, k=1, cfg=dict(cfg, t_align=cfg["t_align"] * s, tau=cfg["tau"] * s),
                 compact=cfg["compact_mode"], label=f"{scene}[E={lab:g}]", T=cfg["T"] * s)
        lam[j], err[j] = r["exponents"][0], r["stderr"][0]
        log.info("%s: E label %g: lambda_1 = %.4g +- %.2g", scene, lab, lam[j], err[j])
    ref = int(np.argmin(np.abs(np.log(labels / cfg["reference_label"]))))
    law = lam[ref] * np.sqrt(labels / labels[ref])
    ok = lam > 0
    slope, slope_err = _fit_loglog(labels[ok], lam[ok], err[ok])
    ds = xr.Dataset(
        {"lambda_1": ("label", lam, {"units": "1/time"}), "stderr": ("label", err, {"units": "1/time"}),
         "law": ("label", law, {"long_name": "time-scaling law from the reference label", "units": "1/time"})},
        coords={"label": ("label", labels, {"long_name": "paper energy label"})},
    )
    ds.attrs.update(_common_attrs(params, model.state_at_label(cfg["y0"], params, cfg["reference_label"]), cfg, scene))
    ds.attrs.update(
        reference_label=cfg["reference_label"], T_reference=cfg["T"], t_transient_reference=cfg["t_transient"],
        horizon_rule="T, t_transient, t_align and tau scaled by sqrt(reference_label / label)",
        fitted_exponent=slope, fitted_exponent_stderr=slope_err, n_positive=int(ok.sum()),
        max_rel_deviation_from_law=float(np.max(np.abs(lam / law - 1))), wall_time_s=time.perf_counter() - start,
    )
    ds.attrs.update(provenance_attrs())
    return ds


def _fit_loglog(x, y, yerr):
    """Weighted least-squares slope of log y against log x, with its standard error."""
    if len(x) < 3:
        return float("nan"), float("nan")
    w = 1.0 / np.maximum(yerr / y, 1e-12) ** 2
    X = np.c_[np.log(x), np.ones(len(x))]
    cov = np.linalg.inv(X.T @ (w[:, None] * X))
    beta = cov @ X.T @ (w * np.log(y))
    resid = np.log(y) - X @ beta
    scale = max(1.0, float(np.sum(w * resid**2) / max(1, len(x) - 2)))
    return float(beta[0]), float(math.sqrt(cov[0, 0] * scale))


def grid_axes(cfg: dict) -> tuple[np.ndarray, np.ndarray]:
    """The log-spaced eps and b values of the grid."""
    return np.geomspace(*cfg["eps_range"], cfg["n_eps"]), np.geomspace(*cfg["b_range"], cfg["n_b"])


def b_image(y, b_from: float, b_to: float) -> np.ndarray:
    """The state at b_to that the length-scale symmetry maps y (at b_from) to: u scales with b.

    With K2 fixed, (u / b, Omega, omega, delta) obeys b-free equations (mechanics.b_free_form),
    so the image of a point on the attractor at b_from lies on the attractor at b_to."""
    y = np.array(y, dtype=float)
    y[0] *= b_to / b_from
    return y


def grid_time_scale(cfg: dict, eps: float) -> float:
    """Fast time unit at eps relative to reference_eps: the ratio of rotor speeds when the rotor
    carries the whole energy at the label (close to the mean rotor speed on the attractor:
    measured within 5% for eps <= 0.37, 19% at eps = 0.5). Horizons scaled by it cost about the
    same number of integrator steps at every eps."""
    def omega_rot(e):
        return model.state_at_label([0.0, 0.0, 1.0, 0.0], model.Params.paper(eps=e), cfg["energy_label"])[2]
    return float(omega_rot(cfg["reference_eps"]) / omega_rot(eps))


def grid_pre_run(cfg: dict, eps: float) -> float:
    """Pre-run length at eps: t_pre (eps_ref / eps)^2 (transients grow like 1/eps^2), at least t_pre_min."""
    return max(cfg["t_pre_min"], cfg["t_pre"] * (cfg["reference_eps"] / eps) ** 2)


def grid_chunk(cfg: dict, chunk: int, n_chunks: int, scene: str = "") -> xr.Dataset:
    """Max LE at the grid points of one chunk: the eps rows chunk, chunk + n_chunks, ...

    Per row: one pre-run from y0 (the reference state at the label) at the first b, of
    grid_pre_run(eps), checked with the transient rule of sleighsim.transient. Every b of the
    row then starts from that settled state mapped by the length-scale symmetry (b_image), so
    no point pays the transient again. The Benettin phase (one tangent vector) runs ``batch_size``
    b values at once in heyoka's SIMD batch mode over T, t_align and tau scaled by
    grid_time_scale(eps). Each lane's transient is verified in the run itself: the block means of
    omega at the renormalisation times must lie within transient.rtol of their mean. A point is
    flagged when its row's pre-run or its own run is not steady, or when lambda_1 <= flag_sigma
    stderr or stderr >= flag_rel_err lambda_1. A point's wall time is its share of the pre-run
    and of its batch."""
    start = time.perf_counter()
    eps_all, bs = grid_axes(cfg)
    B, tc = cfg["batch_size"], cfg["transient"]
    n_steps = int(round(cfg["T"] / cfg["tau"]))
    n_align = int(math.ceil(cfg["t_align"] / cfg["tau"]))
    ta, compile_s = _tangent_batch(B, cfg["tol"], cfg["compact_mode"])
    rows = []
    for eps in eps_all[chunk::n_chunks]:
        s, t_pre = grid_time_scale(cfg, eps), grid_pre_run(cfg, eps)
        p0 = model.Params.paper(eps=eps, b=bs[0])
        t0 = time.perf_counter()
        y, pre_over, settle = _settle(p0, model.state_at_label(cfg["y0"], p0, cfg["energy_label"]), t_pre,
                                      cfg["tol"], f"{scene}[eps={eps:.4g}]", tc)
        pre_share = (time.perf_counter() - t0) / bs.size
        log.info("%s[eps=%.4g]: pre-run %.4g, omega settled at %.4g (%s)", scene, eps, t_pre, settle,
                 "over" if pre_over else "NOT over")
        for first in range(0, bs.size, B):
            group = list(bs[first:first + B])
            lanes = group + [group[-1]] * (B - len(group))  # pad a short last batch
            ta.pars[:] = np.array([model.Params.paper(eps=eps, b=b).values for b in lanes]).T
            r = lyapunov.max_le_batch(ta, 4, np.array([b_image(y, bs[0], b) for b in lanes]), np.full(B, cfg["tau"] * s),
                                      t_align_steps=n_align, n_steps=n_steps, n_blocks=cfg["n_blocks"],
                                      label=f"{scene}[eps={eps:.4g}, batch {first // B}]")
            om = r["state_block_means"][:, 2, :]
            drift = np.max(np.abs(om / om.mean(axis=0) - 1.0), axis=0)
            share = r["wall_time_s"] / len(group)
            for j, b in enumerate(group):
                lam, err = float(r["exponents"][j]), float(r["stderr"][j])
                over = pre_over and drift[j] <= tc["rtol"]
                converged = lam > cfg["flag_sigma"] * err and err < cfg["flag_rel_err"] * abs(lam)
                rows.append((eps, b, lam, err, s, cfg["T"] * s, t_pre, settle, drift[j], int(over), int(converged),
                             pre_share + share))
                log.info("%s[eps=%.4g, b=%.4g]: lambda_1 = %.4g +- %.2g, omega block drift %.2g, transient %s, %s",
                         scene, eps, b, lam, err, drift[j], "over" if over else "NOT over",
                         "converged" if converged else "NOT converged")
    names = ["eps", "b", "lambda_1", "stderr", "time_scale", "T", "t_pre", "settling_time", "omega_block_drift",
             "transient_over", "converged", "wall_time_s"]
    a = np.array(rows, dtype=float).reshape(-1, len(names))
    ds = xr.Dataset({n: ("point", a[:, i]) for i, n in enumerate(names)})
    ds.attrs.update(chunk=chunk, n_chunks=n_chunks, wall_time_s=time.perf_counter() - start, tol=cfg["tol"],
                    energy_label=cfg["energy_label"], batch_size=B, compile_time_s=compile_s,
                    method=f"Benettin (one tangent vector) in heyoka batch mode, {B} lanes",
                    start_rule=grid_chunk.__doc__.split("\n\n")[1].replace("\n", " ").strip())
    ds.attrs.update(provenance_attrs())
    return ds


def grid_gather(paths, cfg: dict) -> xr.Dataset:
    """Assemble chunk datasets into the (eps, b) grid, with per-row statistics: the spread of
    lambda_1 across b (the b values of a row are one system under the length-scale symmetry, so
    where lambda_1 T >> 37 the spread measures the sampling error of one point) and the
    reference point's relative error."""
    chunks = [read_dataset(p) for p in paths]
    parts = xr.concat(chunks, dim="point")
    eps, bs = grid_axes(cfg)
    out = {}
    for name in ("lambda_1", "stderr", "transient_over", "converged", "wall_time_s", "T", "omega_block_drift"):
        grid = np.full((eps.size, bs.size), np.nan)
        for e, b, v in zip(parts.eps.values, parts.b.values, parts[name].values):
            grid[np.argmin(np.abs(eps - e)), np.argmin(np.abs(bs - b))] = v
        out[name] = (("eps", "b"), grid)
    ds = xr.Dataset(out, coords={"eps": eps, "b": bs})
    flagged = (ds.transient_over.values == 0) | (ds.converged.values == 0)
    ds["flagged"] = (("eps", "b"), flagged.astype(np.int8))
    lam, err = ds.lambda_1.values, ds.stderr.values
    ds["row_mean"] = ("eps", lam.mean(axis=1), {"long_name": "mean of lambda_1 over b", "units": "1/time"})
    ds["row_spread"] = ("eps", lam.std(axis=1, ddof=1) if bs.size > 1 else np.full(eps.size, np.nan),
                        {"long_name": "standard deviation of lambda_1 over b", "units": "1/time"})
    ds["row_stderr"] = ("eps", err.mean(axis=1), {"long_name": "mean block standard error over b", "units": "1/time"})
    ds["row_lambda_T"] = ("eps", np.abs(ds.row_mean.values) * ds["T"].values.mean(axis=1),
                          {"long_name": "|mean lambda_1| x T: the b lanes start from one state (u scaled), so they "
                                        "sample independently only once this is well above ln(1e16) = 37"})
    ref = (int(np.argmin(np.abs(np.log(eps / cfg["reference_eps"])))), int(np.argmin(np.abs(np.log(bs)))))
    ratio = (ds.row_spread.values / ds.row_stderr.values)[ds.row_lambda_T.values >= 100]
    ds.attrs.update(
        reference_point_eps=float(eps[ref[0]]), reference_point_b=float(bs[ref[1]]),
        reference_point_rel_err=float(err[ref] / abs(lam[ref])),
        median_row_spread_over_stderr=float(np.nanmedian(ratio)) if ratio.size else float("nan"),
        spread_rule="median over rows with lambda_1 T >= 100 of (standard deviation over b) / (mean block stderr)",
        chunk_wall_time_s=float(sum(c.attrs["wall_time_s"] for c in chunks)),
        start_rule=chunks[0].attrs["start_rule"],
        horizon_rule="T, t_align and tau scaled by grid_time_scale(eps) (same integrator steps at every eps); "
        f"pre-run max(t_pre_min, t_pre (eps_ref / eps)^2) with t_pre = {cfg['t_pre']:g}, eps_ref = "
        f"{cfg['reference_eps']:g}",
        energy_label=cfg["energy_label"], n_points=int(eps.size * bs.size), fraction_flagged=float(flagged.mean()),
        min_lambda_1=float(np.nanmin(ds.lambda_1.values)), max_lambda_1=float(np.nanmax(ds.lambda_1.values)),
        min_lambda_1_unflagged=float(np.nanmin(np.where(flagged, np.nan, ds.lambda_1.values))) if (~flagged).any()
        else float("nan"),
        cost_per_point_s=float(np.nanmean(ds.wall_time_s.values)), cost_total_s=float(np.nansum(ds.wall_time_s.values)),
        flag_rule=f"transient not over, or lambda_1 <= {cfg['flag_sigma']} stderr, or stderr >= "
        f"{cfg['flag_rel_err']} |lambda_1|", tol=cfg["tol"], T_reference=cfg["T"],
    )
    ds.attrs.update(provenance_attrs())
    return ds


def verdict(spectrum_nc, poincare_nc, cfg: dict) -> xr.Dataset:
    """Chaos verdict from the exponents and the 0-1 test on the P_2pi iterates (C19-C21, C27).

    chaotic: lambda_1 > sigma stderr, lambda_1(T) not decaying (slope of log lambda_1(T) over the
    last decade above -slope_limit) and K > K_threshold; quasi-periodic: lambda_1 within sigma
    stderr of 0 or decaying like 1/T, and K < K_threshold from a record spanning at least
    min_lyapunov_times Lyapunov times at the largest rate the exponent allows (|lambda_1| + sigma
    stderr); otherwise undecided.

    A short record of a slowly chaotic flow is a smooth, oversampled signal, for which the
    0-1 test returns K near 0 whatever the dynamics: such a K is not counted as evidence of
    regularity."""
    spec, pc = read_dataset(spectrum_nc), read_dataset(poincare_nc)
    n = cfg["max_samples"]
    z = lyapunov.zero_one_test(pc[cfg["observable"]].values[:n], n_c=cfg["n_c"])
    t = pc.p2pi_time.values[:n]
    lam, err = float(spec.exponent.values[0]), float(spec.stderr.values[0])
    record = float(t[-1] - t[0])
    lyap_times = (abs(lam) + cfg["sigma"] * err) * record
    informative = lyap_times >= cfg["min_lyapunov_times"]
    slope = spec.attrs["lambda_1_decay_slope_last_decade"]
    positive = lam > cfg["sigma"] * err and slope > -cfg["slope_limit"]
    zero = abs(lam) <= cfg["sigma"] * err or slope <= -cfg["slope_limit"]
    chaotic_01 = z["K"] > cfg["K_threshold"]
    if positive and chaotic_01:
        v = "chaotic"
    elif zero and not chaotic_01 and informative:
        v = "quasi-periodic"
    else:
        v = "undecided"
    ds = xr.Dataset()
    ds.attrs.update({f"zero_one_{k}": val for k, val in z.items()})
    ds.attrs.update(
        verdict=v, lambda_1=lam, lambda_1_stderr=err, lambda_1_decay_slope=slope, T=spec.attrs["T"],
        zero_one_record_time=record, zero_one_record_lyapunov_times=lyap_times,
        zero_one_informative=int(informative or chaotic_01),
        exponents_agree_with_indicator=int(positive == chaotic_01),
        observable=f"{cfg['observable']} at the P_2pi crossings", rule=" ".join(verdict.__doc__.split("\n\n")[1].split()),
        sources=f"{spectrum_nc}, {poincare_nc}",
    )
    ds.attrs.update(provenance_attrs())
    log.info("verdict %s: lambda_1 %.3g +- %.2g, K %.3f from a record of %.3g Lyapunov times", v, lam, err, z["K"],
             lyap_times)
    return ds


def feasibility(cfg: dict, scene: str = "") -> xr.Dataset:
    """C25: what small eps costs. Measures, from the reference state at a few eps, the
    length of the transient (first Omega spike, sleighsim.transient) and the steps per time
    unit on the attractor; fits power laws in eps and extrapolates both, with the measured
    time per step, to the target eps values."""
    start = time.perf_counter()
    rows = []
    for eps, horizon in zip(cfg["eps"], cfg["horizons"]):
        p = model.Params.paper(eps=eps)
        y0 = model.state_at_label(cfg["y0"], p, cfg["energy_label"])
        ds = integrate(p, y0, sample_grid(0.0, horizon, cfg["dt"]), tol=cfg["tol"], scene=f"{scene}[eps={eps:g}]")
        spikes = transient.spike_times(ds.time.values, ds.Omega.values, t_min=cfg["t_min"])
        rows.append((eps, float(spikes[0]) if spikes.size else np.nan, ds.attrs["steps"] / horizon,
                     ds.attrs["wall_time_s"] / ds.attrs["steps"]))
        log.info("%s: eps %g: first spike %.6g, %.3g steps per time unit", scene, *rows[-1][:3])
    a = np.array(rows)
    ok = np.isfinite(a[:, 1])
    k_t, c_t = np.polyfit(np.log(a[ok, 0]), np.log(a[ok, 1]), 1) if ok.sum() >= 2 else (np.nan, np.nan)
    k_s, c_s = np.polyfit(np.log(a[:, 0]), np.log(a[:, 2]), 1)
    us = float(np.median(a[:, 3]))
    targets = np.asarray(cfg["targets"], float)
    t_tr = np.exp(c_t) * targets**k_t
    steps = t_tr * np.exp(c_s) * targets**k_s
    ds = xr.Dataset(
        {"first_spike": ("eps", a[:, 1], {"units": "time"}), "steps_per_time": ("eps", a[:, 2]),
         "transient_estimate": ("target", t_tr, {"units": "time"}), "steps_estimate": ("target", steps),
         "wall_estimate_s": ("target", steps * us, {"units": "s"})},
        coords={"eps": a[:, 0], "target": targets},
    )
    ds.attrs.update(
        transient_exponent=float(k_t), steps_per_time_exponent=float(k_s), seconds_per_step=us,
        energy_label=cfg["energy_label"], tol=cfg["tol"], wall_time_s=time.perf_counter() - start,
        method="first Omega spike from the reference state; log-log least squares in eps; cost = transient x "
        "steps per time unit x measured seconds per step (one core)",
    )
    ds.attrs.update(provenance_attrs())
    return ds
