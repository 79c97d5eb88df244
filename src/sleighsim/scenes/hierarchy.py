"""Scenes of the perturbation hierarchy: the exact flow against the truncated series (F5, C11)
and its convergence as eps -> 0, the order-0 and order-2 terms with the paper's numbers (F6,
C07-C10), and the printed hierarchy against the derived one with orders 3 and 4 (C12).
The hierarchy itself is derived in :mod:`sleighsim.model.perturbation`."""

from __future__ import annotations

import logging
import math
import time

import numpy as np
import sympy as sp
import xarray as xr

from sleighsim.analysis import fits
from sleighsim.engine.hierarchy import integrate_hierarchy
from sleighsim.engine.integrate import integrate, sample_grid
from sleighsim.io import cf
from sleighsim.io.vocabulary import STATE_KINDS
from sleighsim.model import perturbation as pert
from sleighsim.model.attrs import state_attrs
from sleighsim.model.equations import state_difference
from sleighsim.model.params import Params
from sleighsim.scenes import memory
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.kind import SceneKind

log = logging.getLogger("sleighsim")


def _hierarchy_params(cfg):
    """(eps, b, K2, kappa) of a perturbation scene: K2 - 1 = kappa eps."""
    p = Params.from_config(cfg["params"])
    return p, p.eps, p.b, p.K2, (p.K2 - 1.0) / p.eps


def _series_error(order, eps, K2, y0, times, tol):
    """Max abs error over ``times`` of the order-``order`` partial sum against the exact flow
    (delta compared modulo 2 pi: both runs keep it bounded)."""
    ds = integrate_hierarchy(order, y0, times, K2=K2, kappa_value=(K2 - 1.0) / eps, tol=tol)
    ex = integrate(Params.paper(eps=eps, K2=K2), y0, times, tol=tol, progress=1)
    series = np.stack([pert.partial_sum(ds, v, eps, order) for v in pert.VARS], axis=-1)
    exact = np.stack([ex[v].values for v in pert.VARS], axis=-1)
    return float(np.max(np.abs(state_difference(series, exact))))


def convergence_study(cfg: dict) -> dict:
    """Error of the truncated series against eps on a short window, per truncation order,
    with the log-log slope and the order the hierarchy predicts (next non-vanishing order)."""
    eps_list = np.asarray(cfg["eps"], float)
    times = sample_grid(0.0, cfg["t_end"], cfg["dt"])
    out = {}
    for order in cfg["orders"]:
        errs = np.array([_series_error(order, e, 1.0 + cfg["kappa"] * e, cfg["y0"], times, cfg["tol"])
                         for e in eps_list])
        slope = fits.loglog(eps_list, errs)[0]
        # Odd orders vanish for zero odd-order initial data, so the first omitted term is eps^(order + 2)
        # after an even truncation order.
        predicted = order + 2 if order % 2 == 0 else order + 1
        out[order] = (errs, float(slope), predicted)
    return out


def series_errors(exact: xr.Dataset, h: xr.Dataset, eps: float, order: int) -> dict:
    """The exact flow, the partial sum of orders 0..order and their errors for u, Omega, omega, as
    Dataset variables on the common time grid. The relative error is taken against the largest
    |exact| so far: Omega passes through zero, omega does not (there the two definitions agree to the
    size of its oscillation)."""
    data = {}
    for v in ("u", "Omega", "omega"):
        s = pert.partial_sum(h, v, eps, order)
        kind = STATE_KINDS[v]
        data[f"{v}_exact"] = ("time", exact[v].values, cf.attrs(f"{v}, exact flow", kind))
        data[f"{v}_series"] = ("time", s, cf.attrs(f"{v}, sum of orders 0..{order}", kind))
        err = np.abs(s - exact[v].values)
        data[f"{v}_abs_error"] = ("time", err, cf.attrs(f"|series - exact|, {v}", kind))
        data[f"{v}_rel_error"] = ("time", err / np.maximum(np.maximum.accumulate(np.abs(exact[v].values)), 1e-300),
                                  cf.attrs(f"|series - exact| / max |exact| up to t, {v}"))
    return data


def series_vs_exact(cfg: dict, scene: str = "") -> xr.Dataset:
    """Exact flow against u0 + eps u1 + eps^2 u2 (and Omega, omega) on [0, t_end], the relative
    error of each over time (C11), and the convergence of the series as eps -> 0."""
    start = time.perf_counter()
    params, eps, b, K2, kap = _hierarchy_params(cfg)
    y0 = np.asarray(cfg["y0"], float)
    times = sample_grid(0.0, cfg["t_end"], cfg["dt"])
    order = cfg["order"]
    exact = integrate(params, y0, times, tol=cfg["tol"], scene=scene, progress=1)
    h = integrate_hierarchy(order, y0, times, b=b, K2=K2, kappa_value=kap, tol=cfg["tol"])
    data = series_errors(exact, h, eps, order)
    conv = convergence_study({"tol": cfg["tol"], **cfg["convergence"]})
    cc = cfg["convergence"]
    for o, (errs, _slope, _predicted) in conv.items():
        data[f"convergence_error_order{o}"] = (("eps_study",), errs,
                                               cf.attrs(f"max error of the order-{o} partial sum on "
                                                        f"[0, {cc['t_end']:g}] (u, Omega, omega, delta, in their "
                                                        "model units)"))
    ds = xr.Dataset(data, coords={"time": times, "eps_study": np.asarray(cc["eps"], float)})
    ds.attrs.update(state_attrs(params, y0))
    t_end = float(times[-1])
    ds.attrs.update(
        scene=scene, order=order, kappa=kap, convention=pert.CONVENTION,
        energy_max_rel_drift=exact.attrs["energy_max_rel_drift"], tol=cfg["tol"], backend="heyoka",
        steps=exact.attrs["steps"], hierarchy_steps=h.attrs["steps"],
        **{f"{v}_rel_error_at_t_end": float(ds[f"{v}_rel_error"].values[-1]) for v in ("u", "Omega", "omega")},
        **{f"{v}_max_abs_error": float(ds[f"{v}_abs_error"].max()) for v in ("u", "Omega", "omega")},
        t_end=t_end, convergence_window=cc["t_end"], convergence_kappa=cc["kappa"],
        convergence_rule="exact flow at (eps, K2 = 1 + kappa eps) against the hierarchy at the same K2; "
                         "slope of log(max error) against log(eps), least squares",
        **{f"convergence_slope_order{o}": s for o, (_, s, _) in conv.items()},
        **{f"convergence_predicted_order{o}": p for o, (_, _, p) in conv.items()},
        wall_time_s=time.perf_counter() - start,
    )
    log.info("%s: done in %.3g s; relative error at t = %g: u %.3g, Omega %.3g, omega %.3g; slopes %s", scene,
             ds.attrs["wall_time_s"], t_end,
             ds.attrs["u_rel_error_at_t_end"], ds.attrs["Omega_rel_error_at_t_end"],
             ds.attrs["omega_rel_error_at_t_end"], {o: round(s, 3) for o, (_, s, _) in conv.items()})
    return ds


SERIES_VS_EXACT = SceneKind(
    name="series_vs_exact",
    title=("the perturbation series to order 2 against the exact flow, and its convergence as eps -> 0 (figure"
           " F5, claim C11)"),
    compute=series_vs_exact,
    records=lambda c: [*memory.series(c, "", c["order"]),
                       *memory.series(c, "convergence.", max(c["convergence"]["orders"]))])


def _paper_closed_forms(u0, omega0, b, K2) -> dict:
    """The paper's approximations (eq:Omega2_sol, eq:w2_approx) as printed, with our u0, omega0."""
    A = omega0**2 / K2 / math.sqrt(omega0**2 + u0**2 / (b**2 * K2**2))
    growth = u0 * A / (2 * b * K2)
    return {"Omega2_amplitude": A, "phi1": math.atan(-omega0 * b * K2 / u0),
            "phi1_abs": math.atan(omega0 * b * K2 / u0),
            "T1": 2 * math.pi / omega0, "T2": math.pi / omega0, "B": math.hypot(growth, omega0**2 / (2 * K2)),
            "omega2_growth": growth}


def hierarchy_numbers(y0, times, *, b: float, K2: float, kappa: float, tol: float, fit_window) -> tuple:
    """The hierarchy to order 2 from y0 on ``times`` and the numbers of C07-C10 measured on
    ``fit_window``, beside the paper's closed forms. Returns (hierarchy dataset, numbers)."""
    h = integrate_hierarchy(2, y0, times, b=b, K2=K2, kappa_value=kappa, tol=tol)
    w0, w1 = fit_window
    win = (times >= w0) & (times <= w1)
    tw = times[win]
    u0_end, omega0_end = float(h.u0.values[-1]), float(h.omega0.values[-1])
    meas = {}
    for v, harmonic in (("u2", 1), ("Omega2", 1), ("omega2", 2)):
        f = fits.line_plus_sinusoid(tw, h[v].values[win], harmonic * omega0_end)
        meas.update({f"{v}_{k}": val for k, val in f.items()})
    ph = fits.phase_against(h.Omega2.values[win], h.delta0.values[win])
    half = tw.size // 2
    ph_halves = [fits.phase_against(h.Omega2.values[win][s], h.delta0.values[win][s]) for s in
                 (slice(0, half), slice(half, None))]
    omega0_w = h.omega0.values[win]
    theory = _paper_closed_forms(u0_end, omega0_end, b, K2)
    numbers = dict(
        order1_max_abs=max(float(np.max(np.abs(h[f"{v}1"].values))) for v in pert.VARS),
        u0_end=u0_end, omega0_end=omega0_end, two_pi_over_omega0=2 * math.pi / omega0_end,
        two_pi_over_omega0_uncertainty=float(2 * math.pi * np.ptp(omega0_w) / omega0_end**2),
        T1_u2=meas["u2_period"], T1_u2_uncertainty=meas["u2_period_uncertainty"],
        T1_Omega2=meas["Omega2_period"], T1_Omega2_uncertainty=meas["Omega2_period_uncertainty"],
        Omega2_amplitude=meas["Omega2_amplitude"], Omega2_amplitude_uncertainty=meas["Omega2_amplitude_uncertainty"],
        phi1=ph["phase"], phi1_over_pi=ph["phase"] / math.pi, phi1_rms_residual=ph["rms_residual"],
        phi1_uncertainty=0.5 * abs(ph_halves[0]["phase"] - ph_halves[1]["phase"]),
        T2=meas["omega2_period"], T2_uncertainty=meas["omega2_period_uncertainty"],
        B=meas["omega2_amplitude"], B_uncertainty=meas["omega2_amplitude_uncertainty"],
        omega2_growth=meas["omega2_slope"], omega2_growth_uncertainty=meas["omega2_slope_uncertainty"],
        **{f"theory_{k}": v for k, v in theory.items()},
    )
    return h, numbers


def hierarchy_terms(cfg: dict, scene: str = "") -> xr.Dataset:
    """Orders 0 and 2 of u, Omega, omega from the paper's data (order 1 checked to stay zero)
    and the numbers of C08-C10 measured on a late window, beside the paper's closed forms."""
    start = time.perf_counter()
    params, eps, b, K2, kap = _hierarchy_params(cfg)
    y0 = np.asarray(cfg["y0"], float)
    times = sample_grid(0.0, cfg["t_end"], cfg["dt"])
    h, numbers = hierarchy_numbers(y0, times, b=b, K2=K2, kappa=kap, tol=cfg["tol"], fit_window=cfg["fit_window"])
    w0, w1 = cfg["fit_window"]
    keep = ["u0", "u2", "Omega0", "Omega2", "omega0", "omega2", "delta0"]
    ds = xr.Dataset({v: ("time", h[v].values) for v in keep}, coords={"time": times})
    ds.attrs.update(state_attrs(params, y0))
    ds.attrs.update(
        scene=scene, kappa=kap, tol=cfg["tol"], backend="heyoka", steps=h.attrs["steps"],
        two_pi_over_omega0_method="omega0 at t_end; uncertainty from the range of omega0 over the fit window",
        fit_window_start=w0, fit_window_end=w1, fit_method=fits.METHOD,
        phi1_method="least squares Omega2 ~ -A sin(delta0 + phi1) on the fit window, delta0 from the integration; "
                    "uncertainty: half-difference of the fits on the two halves of the window",
        theory_method="the paper's closed forms (eq:Omega2_sol, eq:w2_approx) as printed, evaluated with our "
                      "u0 and omega0 at t_end and K^2 = K2",
        wall_time_s=time.perf_counter() - start,
        **numbers,
    )
    log.info("%s: done in %.3g s; T1 %.5g, 2pi/omega0 %.5g, A %.4g, phi1 %.4f pi, T2 %.5g, B %.4g, growth %.4g",
             scene, ds.attrs["wall_time_s"], numbers["T1_u2"], numbers["two_pi_over_omega0"],
             numbers["Omega2_amplitude"], numbers["phi1_over_pi"], numbers["T2"], numbers["B"],
             numbers["omega2_growth"])
    return ds


def _hierarchy_terms_checks(w, cfg):
    lo, hi = cfg["fit_window"]
    if not 0 <= lo < hi <= cfg["t_end"]:
        raise ConfigError(f"{w}.fit_window = [{lo}, {hi}] must be increasing within [0, t_end = {cfg['t_end']}]")


HIERARCHY_TERMS = SceneKind(
    name="hierarchy_terms",
    title=("the order-0 and order-2 terms of the perturbation hierarchy with the paper's numbers (figure F6, "
           "claims C07-C10)"),
    compute=hierarchy_terms, checks=_hierarchy_terms_checks,
                            records=memory.hierarchy)


def _classify_terms(terms, values, t, late_start, decay_rel=1e-6, mean_rel=0.05, growth_ratio=1.2):
    """Each forcing term on [late_start, end]: 'decays' (RMS below decay_rel of the largest),
    'secular' (|mean| > mean_rel RMS, or RMS growing by growth_ratio from the first half to the
    second) or 'bounded'."""
    late = t >= late_start
    vals = [np.broadcast_to(np.asarray(v, float), t.shape)[late] for v in values]
    rms = np.array([np.sqrt(np.mean(v**2)) for v in vals])
    top = rms.max() if rms.size else 0.0
    rows = []
    for term, v, r in zip(terms, vals, rms):
        h = v.size // 2
        grow = float(np.sqrt(np.mean(v[h:] ** 2)) / max(np.sqrt(np.mean(v[:h] ** 2)), 1e-300))
        mean = float(v.mean() / r) if r > 0 else 0.0
        kind = ("decays" if r <= decay_rel * top else
                "secular" if abs(mean) > mean_rel or grow > growth_ratio else "bounded")
        rows.append((str(term), kind, mean, grow, float(r)))
    return rows


def _growth_exponent(t, x, block, t_from):
    """Log-log slope of the block maxima of |x| against time for t >= t_from."""
    n = max(1, int(round(block / (t[1] - t[0]))))
    m = len(x) // n
    bm = np.abs(x[: m * n]).reshape(m, n).max(axis=1)
    tb = t[: m * n].reshape(m, n).mean(axis=1)
    sel = (tb >= t_from) & (bm > 0)
    return fits.loglog(tb[sel], bm[sel], min_points=3)[0]


def _audit_variables(rows: list[dict], classified: list[tuple], h: xr.Dataset) -> dict:
    """The audit dataset's variables: every printed term that differs from the derived one (per
    difference), the classified order-4 forcing terms (per term4), and u, Omega, omega at orders 2
    and 4 along the solution (per time)."""
    return {
        "equation": ("difference", [r["equation"] for r in rows]),
        "term": ("difference", [r["term"] for r in rows]),
        "derived": ("difference", [r["derived"] for r in rows]),
        "derived_with_kappa": ("difference", [r["derived_with_kappa"] for r in rows]),
        "printed": ("difference", [r["printed"] for r in rows]),
        "order4_equation": ("term4", [c[0] for c in classified]),
        "order4_term": ("term4", [c[1] for c in classified]),
        "order4_kind": ("term4", [c[2] for c in classified]),
        "order4_mean_over_rms": ("term4", [c[3] for c in classified]),
        "order4_rms_growth": ("term4", [c[4] for c in classified]),
        "order4_late_rms": ("term4", [c[5] for c in classified]),
        **{f"{v}{k}": ("time", h[f"{v}{k}"].values) for v in ("u", "Omega", "omega") for k in (2, 4)},
    }


def hierarchy_audit(cfg: dict, scene: str = "") -> xr.Dataset:
    """The derived hierarchy against the printed one (every differing term), and C12: order 3
    along the paper's data, and the secular forcing terms of order 4."""
    start = time.perf_counter()
    params, eps, b, K2, kap = _hierarchy_params(cfg)
    rows = pert.compare_printed(kappa_value=1)
    order = 4
    times = sample_grid(0.0, cfg["t_end"], cfg["dt"])
    h = integrate_hierarchy(order, cfg["y0"], times, b=b, K2=K2, kappa_value=kap, tol=cfg["tol"])
    cols = [h[n].values for n in pert.state_names(order)]
    # Order 3: symbolic forcing with the order-1 unknowns set to zero, and along the solution.
    x = pert.symbols(order)
    zero1 = {x[v][1]: 0 for v in pert.VARS}
    forcing3 = [sp.sympify(sum(pert.forcing_terms(3, v))).subs(zero1) for v in pert.VARS]
    order3_max = max(float(np.max(np.abs(h[f"{v}3"].values))) for v in pert.VARS)
    classified = []
    for v in pert.VARS:
        terms = pert.forcing_terms(order, v)
        if not terms:
            continue
        vals = pert.lambdify_terms(terms, order)(*cols, b, K2, kap)
        classified += [(f"d{v}4/dt", *r) for r in _classify_terms(terms, vals, times, cfg["late_start"])]
    ds = xr.Dataset(_audit_variables(rows, classified, h), coords={"time": times})
    n_sec = sum(c[2] == "secular" for c in classified)
    ds.attrs.update(params.attrs())
    ds.attrs.update(
        scene=scene, kappa=kap, comparison_kappa=1, n_differences=len(rows),
        comparison_rule="orders 0-2, coefficients of every monomial in the hierarchy variables and "
                        "sin/cos(delta0) (sin^2 reduced), derived at kappa = 1 against printed with K^2 = K2",
        order3_forcing_with_order1_zero=" ; ".join(str(f) for f in forcing3),
        order3_forcing_vanishes=int(all(f == 0 for f in forcing3)), order3_max_abs_along_solution=order3_max,
        order4_n_terms=len(classified), order4_n_secular=n_sec,
        order4_secular_rule=f"on t >= {cfg['late_start']:g}: secular when |mean| > 0.05 RMS or RMS grows by 1.2x "
                            "from the first to the second half; 'decays' when RMS < 1e-6 of the largest term",
        tol=cfg["tol"], t_end=float(times[-1]), backend="heyoka", steps=h.attrs["steps"],
        wall_time_s=time.perf_counter() - start, growth_block=cfg["growth_block"], late_start=cfg["late_start"],
        growth_rule="log-log least-squares slope of the block maxima of |x| (blocks of growth_block) "
                    "for t >= late_start",
        **{f"growth_exponent_{v}{k}": _growth_exponent(times, h[f"{v}{k}"].values, cfg["growth_block"],
                                                       cfg["late_start"])
           for v in pert.VARS for k in (2, 4)},
    )
    log.info("%s: done in %.3g s; %d printed terms differ; order 3 forcing vanishes: %s; %d of %d order-4 terms "
             "secular", scene, ds.attrs["wall_time_s"], len(rows), ds.attrs["order3_forcing_vanishes"], n_sec,
             len(classified))
    return ds


HIERARCHY_AUDIT = SceneKind(
    name="hierarchy_audit",
    title=("the printed perturbation hierarchy against the derived one, order 3 and the secular terms of order"
           " 4 (claim C12)"),
    compute=hierarchy_audit, records=memory.hierarchy)
