"""The peer comparison of the bench (``cfg["peers"]``, sleighsim.engine.peer_*): every engine a Python
user would pick instead (SciPy with the Python and with compiled right-hand sides, diffrax) and
heyoka's bare propagation at the same rtols, all against the same long-double reference with the
same error metric, each timed after a warm-up as the median of ``repeats``, compile times beside;
the Lyapunov kernel compared with lyapax on Lorenz and the sleigh. A missing peer is a row whose
note says how to install it. Part of :mod:`sleighsim.scenes.bench`."""

from __future__ import annotations

import logging
import math

import numpy as np
import xarray as xr

from sleighsim.engine import integrators, peer_lyapunov, peer_table, peers

log = logging.getLogger("sleighsim")


def heyoka_end_state(params, y0, t_end, tol):
    """heyoka's bare propagation to t_end (delta kept bounded), the engine-level peer of
    peer_scipy.scipy_run: returns (run() -> end state, compile seconds)."""
    ta, compile_s = integrators.flow(False, tol)

    def run():
        ta.time = 0.0
        integrators.load(ta, y0)
        integrators.set_pars(ta, params)
        ta.propagate_until(float(t_end), callback=integrators.bounded(ta))
        return integrators.read(ta, 4)

    return run, compile_s


def peer_runs(cfg: dict, params, y0, ref) -> list[dict]:
    """Every peer engine at every rtol of cfg["peers"] and heyoka at every tolerance of
    cfg["heyoka_tols"]: end-state error at t_short against
    the long-double reference ``ref`` (max over components, delta modulo 2 pi), median wall after
    warm-up, compile seconds. A peer that is missing or fails is a row with error None and a note."""
    pc = cfg["peers"]
    rows = peer_table.integration_table(
        params.values, y0, cfg["t_short"], rtols=pc["rtols"], atol_factor=cfg["atol_factor"],
        scipy_methods=pc["scipy_methods"], rhs_kinds=pc["rhs_kinds"], diffrax_solvers=pc["diffrax_solvers"],
        repeats=pc["repeats"], warmup=pc["warmup"], reference=ref, log=log.info)
    for tol in cfg["heyoka_tols"]:
        run, compile_s = heyoka_end_state(params, y0, cfg["t_short"], tol)
        y, wall, walls = peers.timed(run, repeats=pc["repeats"], warmup=pc["warmup"])
        rows.append(dict(engine="heyoka taylor", rtol=tol, atol=tol, compile_s=compile_s,
                         error=peers.state_error(y, ref), wall_s=wall, walls=walls, note=f"tol = {tol:g}"))
        log.info("bench peers: heyoka taylor tol %.0e: error %.2e in %.3g ms", tol, rows[-1]["error"], wall * 1e3)
    return rows


def peer_ratios(engine, error, wall, targets, ours: str = "heyoka taylor") -> tuple[list, np.ndarray]:
    """For each error target and each other engine: (fastest wall of that engine reaching the target)
    / (fastest wall of ``ours`` reaching it); NaN where either never reaches it. Returns (engines, ratios
    with shape (target, engine))."""
    engine, error, wall = np.asarray(engine), np.asarray(error, float), np.asarray(wall, float)
    others = [e for e in dict.fromkeys(engine.tolist()) if e != ours]

    def fastest(name, target):
        ok = (engine == name) & np.isfinite(error) & np.isfinite(wall) & (error <= target)
        return float(wall[ok].min()) if ok.any() else math.nan

    return others, np.array([[fastest(e, t) / fastest(ours, t) for e in others] for t in targets])


def peer_comparison(cfg: dict, params, y0, ref) -> xr.Dataset:
    """The peer rows, the ratio table against heyoka at each error target, and the Lyapunov peers."""
    rows = peer_runs(cfg, params, y0, ref)

    def col(key, fill=math.nan):
        return [fill if r.get(key) is None else r[key] for r in rows]

    engine, error, wall = col("engine"), col("error"), col("wall_s")
    others, ratios = peer_ratios(engine, error, wall, cfg["error_targets"])
    compile_of = {r["engine"]: float(r["compile_s"]) for r in rows if r.get("compile_s") is not None}
    ds = xr.Dataset(
        {"peer_engine": ("peer_run", np.array(engine)), "peer_rtol": ("peer_run", np.array(col("rtol"), float)),
         "peer_error": ("peer_run", np.array(error, float)), "peer_wall": ("peer_run", np.array(wall, float)),
         "peer_compile_s": ("peer_run", np.array(col("compile_s"), float)),
         "peer_note": ("peer_run", np.array(col("note", ""), dtype=object).astype(str)),
         "peer_ratio": (("error_target", "peer"), ratios),
         "peer_engine_compile_s": ("peer", np.array([compile_of.get(e, math.nan) for e in others]))},
        coords={"error_target": np.array(cfg["error_targets"], float), "peer": np.array(others)},
        attrs={"peer_repeats": cfg["peers"]["repeats"], "peer_warmup": cfg["peers"]["warmup"],
               "peer_versions": ", ".join(f"{k} {v}" for k, v in peers.peer_versions().items() if v),
               "peer_ratio_rule": "fastest wall of the peer reaching the error target / fastest wall of heyoka "
                                  "reaching it (both the median after warm-up); compile times apart"})
    lyap = lyapunov_peers(cfg, params)
    out = xr.merge([ds, lyap])
    out.attrs.update({**ds.attrs, **lyap.attrs})
    return out


def lyapunov_peers(cfg: dict, params) -> xr.Dataset:
    """lambda_1 with lyapax (fixed-step RK, JAX) and with heyoka's variational Benettin, on Lorenz
    and on the sleigh over the same T and tau; a missing lyapax is a row with a note."""
    lc = cfg["peers"]["lyapunov"]
    kw = dict(tau=lc["tau"], repeats=lc["repeats"])
    runs = [("lorenz", f"lyapax RK4 dt {dt:g}", lambda dt=dt: peer_lyapunov.lyapax_lorenz(
        T=lc["T_lorenz"], dt=dt, **kw)) for dt in lc["lyapax_dt"]]
    runs += [("lorenz", f"heyoka tol {tol:g}", lambda tol=tol: peer_lyapunov.heyoka_lorenz(
        T=lc["T_lorenz"], tol=tol, **kw)) for tol in lc["heyoka_tols"]]
    runs += [("sleigh", f"lyapax RK4 dt {dt:g}", lambda dt=dt: peer_lyapunov.lyapax_sleigh(
        params.values, T=lc["T_sleigh"], dt=dt, **kw)) for dt in lc["lyapax_dt_sleigh"]]
    runs += [("sleigh", f"heyoka tol {tol:g}", lambda tol=tol: peer_lyapunov.heyoka_sleigh(
        params.values, T=lc["T_sleigh"], tol=tol, **kw)) for tol in lc["heyoka_tols"]]
    out = []
    for system, name, fn in runs:
        try:
            r = fn()
            out.append((system, name, r.lambda_1, r.wall_s, r.compile_s, ""))
        except peers.PeerUnavailable as exc:
            out.append((system, name, math.nan, math.nan, math.nan, str(exc)))
        log.info("bench Lyapunov peers: %s %s: lambda_1 %.5g in %.3g s (compile %.3g s) %s", system, *out[-1][1:])
    cols = list(zip(*out))
    return xr.Dataset({"lyap_peer_system": ("lyap_peer", np.array(cols[0])),
                       "lyap_peer_engine": ("lyap_peer", np.array(cols[1])),
                       "lyap_peer_lambda_1": ("lyap_peer", np.array(cols[2], float)),
                       "lyap_peer_wall": ("lyap_peer", np.array(cols[3], float)),
                       "lyap_peer_compile_s": ("lyap_peer", np.array(cols[4], float)),
                       "lyap_peer_note": ("lyap_peer", np.array(cols[5], dtype=object).astype(str))},
                      attrs={"lyap_peer_T_lorenz": lc["T_lorenz"], "lyap_peer_T_sleigh": lc["T_sleigh"],
                             "lyap_peer_tau": lc["tau"], "lorenz_lambda_1_literature": peer_lyapunov.LORENZ_LAMBDA_1})
