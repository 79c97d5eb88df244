"""The Lyapunov exponent on the (eps, b) grid (F11, C21), as independent chunk jobs (whole eps
rows) gathered into one dataset."""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import xarray as xr

from .. import lyapunov
from ..io import read_dataset
from ..params import Params
from ..symmetries import b_image, state_at_label
from ..transient import settle

log = logging.getLogger("sleighsim")


def _row_transient(cfg: dict, t_pre: float) -> dict:
    """The transient block (given for the pre-run t_pre at reference_eps) for a row whose pre-run is
    ``t_pre``: sampling interval, window and t_min scale with the pre-run length."""
    tc = cfg["transient"]
    scaled = {k: tc[k] / cfg["t_pre"] * t_pre for k in ("dt", "window", "t_min")}
    return dict(tc, **scaled)


def axes(cfg: dict) -> tuple[np.ndarray, np.ndarray]:
    """The log-spaced eps and b values of the grid."""
    return np.geomspace(*cfg["eps_range"], cfg["n_eps"]), np.geomspace(*cfg["b_range"], cfg["n_b"])


def time_scale(cfg: dict, eps: float) -> float:
    """Fast time unit at eps relative to reference_eps: the ratio of rotor speeds when the rotor
    carries the whole energy at the label (close to the mean rotor speed on the attractor:
    measured within 5% for eps <= 0.37, 19% at eps = 0.5). Horizons scaled by it cost about the
    same number of integrator steps at every eps."""
    def omega_rot(e):
        return state_at_label([0.0, 0.0, 1.0, 0.0], Params.paper(eps=e), cfg["energy_label"])[2]
    return float(omega_rot(cfg["reference_eps"]) / omega_rot(eps))


def pre_run(cfg: dict, eps: float) -> float:
    """Pre-run length at eps: t_pre (eps_ref / eps)^2 (transients grow like 1/eps^2), at least t_pre_min."""
    return max(cfg["t_pre_min"], cfg["t_pre"] * (cfg["reference_eps"] / eps) ** 2)


def chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
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
    eps_all, bs = axes(cfg)
    n_chunks = cfg["n_chunks"]
    B, rtol = cfg["batch_size"], cfg["transient"]["rtol"]
    n_steps = int(round(cfg["T"] / cfg["tau"]))
    n_align = int(math.ceil(cfg["t_align"] / cfg["tau"]))
    ta, compile_s = lyapunov.sleigh_tangent_batch(B, cfg["tol"], cfg["compact_mode"])
    rows = []
    for eps in eps_all[index::n_chunks]:
        s, t_pre = time_scale(cfg, eps), pre_run(cfg, eps)
        p0 = Params.paper(eps=eps, b=bs[0])
        t0 = time.perf_counter()
        y, pre = settle(p0, state_at_label(cfg["y0"], p0, cfg["energy_label"]), t_pre, **_row_transient(cfg, t_pre),
                        tol=cfg["tol"], label=f"{scene}[eps={eps:.4g}]", progress=1)
        pre_over, settled = bool(pre["transient_over"]), pre["transient_settling_time"]
        pre_share = (time.perf_counter() - t0) / bs.size
        log.info("%s[eps=%.4g]: pre-run %.4g, omega settled at %.4g (%s)", scene, eps, t_pre, settled,
                 "over" if pre_over else "NOT over")
        for first in range(0, bs.size, B):
            group = list(bs[first:first + B])
            lanes = group + [group[-1]] * (B - len(group))  # pad a short last batch
            ta.pars[:] = np.array([Params.paper(eps=eps, b=b).values for b in lanes]).T
            r = lyapunov.max_le_batch(ta, 4, np.array([b_image(y, bs[0], b) for b in lanes]), np.full(B, cfg["tau"] * s),
                                      t_align_steps=n_align, n_steps=n_steps, n_blocks=cfg["n_blocks"],
                                      label=f"{scene}[eps={eps:.4g}, batch {first // B}]")
            om = r["state_block_means"][:, 2, :]
            drift = np.max(np.abs(om / om.mean(axis=0) - 1.0), axis=0)
            share = r["wall_time_s"] / len(group)
            for j, b in enumerate(group):
                lam, err = float(r["exponents"][j]), float(r["stderr"][j])
                over = pre_over and drift[j] <= rtol
                converged = lam > cfg["flag_sigma"] * err and err < cfg["flag_rel_err"] * abs(lam)
                rows.append((eps, b, lam, err, s, cfg["T"] * s, t_pre, settled, drift[j], int(over), int(converged),
                             pre_share + share))
                log.info("%s[eps=%.4g, b=%.4g]: lambda_1 = %.4g +- %.2g, omega block drift %.2g, transient %s, %s",
                         scene, eps, b, lam, err, drift[j], "over" if over else "NOT over",
                         "converged" if converged else "NOT converged")
    names = ["eps", "b", "lambda_1", "stderr", "time_scale", "T", "t_pre", "settling_time", "omega_block_drift",
             "transient_over", "converged", "wall_time_s"]
    a = np.array(rows, dtype=float).reshape(-1, len(names))
    ds = xr.Dataset({n: ("point", a[:, i]) for i, n in enumerate(names)})
    ds.attrs.update(chunk=index, n_chunks=n_chunks, wall_time_s=time.perf_counter() - start, tol=cfg["tol"],
                    energy_label=cfg["energy_label"], batch_size=B, compile_time_s=compile_s,
                    method=f"Benettin (one tangent vector) in heyoka batch mode, {B} lanes",
                    start_rule=chunk.__doc__.split("\n\n")[1].replace("\n", " ").strip())
    return ds


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """Assemble chunk datasets into the (eps, b) grid, with per-row statistics: the spread of
    lambda_1 across b (the b values of a row are one system under the length-scale symmetry, so
    where lambda_1 T >> 37 the spread measures the sampling error of one point) and the
    reference point's relative error."""
    chunks = [read_dataset(p) for p in paths]
    parts = xr.concat(chunks, dim="point")
    eps, bs = axes(cfg)
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
    return ds

