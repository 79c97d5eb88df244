"""One judge per claim of paper/CLAIMS.md. A judge takes the paper's values (the ``value`` column,
parsed) and the datasets named for it in :data:`sleighsim.claims.evidence.EVIDENCE`, in that order, and
returns a :class:`~sleighsim.claims.rules.Judgement` whose texts are composed from measured numbers."""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.verdicts import polynomial_rate_bound
from sleighsim.model.equations import rhs
from sleighsim.model.params import Params
from sleighsim.engine.transient import phases
from sleighsim.claims.rules import (
    CANNOT,
    DIFFERS,
    K_SIGMA,
    NOT_YET,
    REL_TOL,
    REPRODUCED,
    Judgement,
    all_of,
    digits,
    finite,
    fmt,
    number,
    relative,
)


def c01(paper, fig2) -> Judgement:
    a = fig2.attrs
    om_end = float(np.max(np.abs(fig2.Omega_closed.values[:, -1])))
    V = float(np.max(np.abs(fig2.u_closed.values[:, -1])))
    th = fig2.path_theta.values
    turning = float(abs(th[-1] - th[int(0.9 * th.size)]))
    ok = a["closed_form_max_abs_error"] < 1e-10 and om_end < 1e-3 * V and turning < 1e-3
    return Judgement(
        REPRODUCED if ok else DIFFERS, units="rad/time",
        measured=f"|Omega(t_end)| = {om_end:.2g} against u -> {V:.4g}; heading turns by {turning:.2g} rad over the last "
                 f"10% of the path; closed form against heyoka {a['closed_form_max_abs_error']:.1e}",
        rule="integration matches the closed form to 1e-10, |Omega(end)| < 1e-3 u(end) and the heading turns by less "
             "than 1e-3 rad over the last tenth of the path (a straight line)")


def c02(paper) -> Judgement:
    p = Params.paper(eps=0.1)
    rng = np.random.default_rng(0)
    rest = np.c_[rng.uniform(-2, 2, 100), np.zeros(100), np.zeros(100), rng.uniform(-7, 7, 100)]
    moving = np.c_[rng.uniform(-2, 2, 100), rng.uniform(0.01, 1, (100, 2)) * rng.choice([-1, 1], (100, 2)),
                   rng.uniform(-7, 7, 100)]
    at_rest = float(np.max(np.abs(rhs(rest, p))))
    elsewhere = float(np.min(np.max(np.abs(rhs(moving, p)), axis=1)))
    ok = at_rest < 1e-14 and elsewhere > 0
    return Judgement(
        REPRODUCED if ok else DIFFERS,
        measured=f"max |rhs| with Omega = omega = 0: {at_rest:.1e}; smallest max |rhs| at 100 states with Omega, "
                 f"omega != 0: {elsewhere:.2g}",
        rule="the right-hand side vanishes on Omega = omega = 0 and nowhere else sampled (deltadot = Omega - omega, "
             "and Omegadot = omegadot = 0 force Omega = omega = 0)", note="sleighsim.model.equations.rhs (derived equations)")


def _phases(fig3):
    return phases(fig3.time.values, fig3.u.values, fig3.Omega.values, fig3.omega.values)


def c03(paper, fig3) -> Judgement:
    t1 = _phases(fig3)["sleigh_phase_end"]
    limit = paper["sleigh_phase_end_max"]
    verdict = NOT_YET if not finite(t1) else REPRODUCED if t1 <= limit * (1 + REL_TOL) else DIFFERS
    return Judgement(verdict, measured=f"the sleigh-like phase ends at t = {t1:g}", units="time",
                     rule=f"end of the sleigh-like phase (running mean of u first reaches 99% of its maximum before the "
                          f"first spike) at most {limit:g} (+{REL_TOL:.0%})", note="(sleighsim.engine.transient.phases)",
                     difference=max(0.0, t1 / limit - 1) if finite(t1) else math.nan)


def c04(paper, fig3, scaling) -> Judgement:
    first = _phases(fig3)["first_spike"]
    want = paper["first_spike"]
    return Judgement(
        number(want, first), units="time", difference=relative(want, first),
        measured=f"{first:.5g}; across eps the first spike scales like eps^{scaling.attrs['first_spike_slope']:.2f}",
        rule=f"number, within {REL_TOL:.0%}", note="(first Omega spike)",
        reason=f"the first spike comes {want - first:.4g} time units earlier" if finite(first) and first < want else "")


def c05(paper, fig3) -> Judgement:
    ph = _phases(fig3)
    mean, std, n = ph["spike_interval_mean"], ph["spike_interval_std"], ph["n_spikes"]
    stderr = std / math.sqrt(n - 2) if n > 2 else math.nan
    want = paper["spike_interval"]
    return Judgement(
        number(want, mean, stderr), units="time", uncertainty=fmt(stderr, 2), difference=relative(want, mean),
        measured=f"{mean:.5g} from {n - 2 if n > 2 else 0} intervals (standard deviation {std:.3g})",
        rule=f"number, within {REL_TOL:.0%} or {K_SIGMA:g} standard errors of the mean interval",
        note="(spike intervals, sleighsim.engine.transient.phases)")


def c06(paper, fig4) -> Judgement:
    a = fig4.attrs
    levels = sorted(set(fig4.level.values.tolist()))
    ok_runs = fig4.reached.values == 1
    groups = []
    for g in sorted(set(fig4.group.values[ok_runs].tolist())):
        sel = (fig4.group.values == g) & ok_runs
        groups.append(f"group {g}: {sel.sum()} runs, interval {np.mean(fig4.spike_interval_level0_units.values[sel]):.0f}")
    long = []
    for k, g in enumerate(fig4.group_id.values):
        sp = fig4.long_spike_time.values[k]
        d = np.diff(sp[np.isfinite(sp)])
        if d.size >= 2:
            long.append(f"group {int(g)}: intervals {d[0]:.0f} -> {d[-1]:.0f} by t = {sp[np.isfinite(sp)][-1]:.3g}")
    n_groups = [int(a[f"level{li}_n_groups"]) for li in levels]
    one = all(n == 1 for n in n_groups)
    if not ok_runs.any():
        verdict = NOT_YET
    else:
        verdict = REPRODUCED if one else DIFFERS
    return Judgement(
        verdict, units="fraction of mean |omega|",
        measured=f"interval groups per level {n_groups} ({'; '.join(groups)}); omega distance within the main group "
                 f"{max(a[f'level{li}_distance_main_group'] for li in levels):.3g}, across levels after the time "
                 f"scaling {a.get('across_levels_distance_main_group_scaled', math.nan):.3g}, unscaled "
                 f"{a.get('across_levels_distance_main_group_unscaled', math.nan):.3g}; long runs: " + "; ".join(long),
        rule=f"one attractor per level: every run on a level falls in one steady spike-interval group (within "
             f"{a['group_rel_tol']:g})",
        reason="" if one else f"{sum(n - 1 for n in n_groups)} extra steady state(s) on the levels: runs keep "
                              "distinct spike intervals (long runs above)")


def c07(paper, fig6) -> Judgement:
    v = fig6.attrs["order1_max_abs"]
    return Judgement(REPRODUCED if v == paper["order1"] else DIFFERS,
                     measured=f"max |u1, Omega1, omega1, delta1| = {v:.1g}",
                     rule="exactly zero along the integration (the order-1 equations are linear and homogeneous)")


def c08(paper, fig6) -> Judgement:
    a = fig6.attrs
    T1, tw = a["T1_Omega2"], a["two_pi_over_omega0"]
    parts = [digits(paper["_text"]["T1"], T1, a["T1_Omega2_uncertainty"]),
             digits(paper["_text"]["two_pi_over_omega0"], tw, a["two_pi_over_omega0_uncertainty"])]
    return Judgement(all_of(parts), units="time", uncertainty=fmt(a["T1_Omega2_uncertainty"], 1),
                     difference=max(relative(paper["T1"], T1), relative(paper["two_pi_over_omega0"], tw)),
                     measured=f"T1 = {T1:.5f} (u2: {a['T1_u2']:.5f}); 2 pi / omega0 = {tw:.5f}",
                     rule="each within one unit of the paper's last printed digit (or 2 uncertainties)")


def c09(paper, fig6) -> Judgement:
    a = fig6.attrs
    parts = [number(paper["Omega2_amplitude"], a["Omega2_amplitude"], a["Omega2_amplitude_uncertainty"]),
             number(paper["phi1_over_pi"], a["phi1_over_pi"], a["phi1_uncertainty"] / math.pi)]
    sign = "+" if a["theory_phi1"] >= 0 else "-"
    return Judgement(
        all_of(parts), difference=max(relative(paper["Omega2_amplitude"], a["Omega2_amplitude"]),
                                      relative(paper["phi1_over_pi"], a["phi1_over_pi"])),
        measured=f"amplitude {a['Omega2_amplitude']:.4f}, phi1 = {a['phi1_over_pi']:.4f} pi (the paper's closed forms "
                 f"with our u0, omega0: {a['theory_Omega2_amplitude']:.4f}, phi1 = {a['theory_phi1'] / math.pi:.4f} pi)",
        rule=f"numbers, within {REL_TOL:.0%} or {K_SIGMA:g} uncertainties; phase from the fit Omega2 ~ -A sin(delta0 + phi1)",
        reason=f"the printed phi1 = arctan(-omega0 b K^2 / u0) has sign {sign}: {a['theory_phi1'] / math.pi:.4f} pi "
               f"against the fitted {a['phi1_over_pi']:.4f} pi")


def c10(paper, fig6) -> Judgement:
    a = fig6.attrs
    pairs = [("T2", "T2", a["T2_uncertainty"]), ("T2_theory", "theory_T2", 0.0), ("B", "B", a["B_uncertainty"]),
             ("B_theory", "theory_B", 0.0), ("growth", "omega2_growth", a["omega2_growth_uncertainty"]),
             ("growth_theory", "theory_omega2_growth", 0.0)]
    vs = {k: number(paper[k], a[ours], unc) for k, ours, unc in pairs}
    return Judgement(
        all_of(vs.values()), difference=max(relative(paper[k], a[ours]) for k, ours, _ in pairs),
        measured="; ".join(f"{k} {a[ours]:.4g} ({vs[k]})" for k, ours, _ in pairs),
        rule=f"each number within {REL_TOL:.0%} or {K_SIGMA:g} uncertainties; simulation: a line plus a sinusoid fitted "
             f"to omega2 on [{a['fit_window_start']:g}, {a['fit_window_end']:g}]; theory: the paper's closed forms with "
             "our u0, omega0",
        reason="; ".join(f"{k}: {a[ours]:.4g} against {paper[k]:g}" for k, ours, _ in pairs if vs[k] == DIFFERS))


def c11(paper, fig5) -> Judgement:
    a = fig5.attrs
    e = a["omega_rel_error_at_t_end"]
    want = paper["omega_rel_error"]
    return Judgement(number(want, e), units="relative", difference=relative(want, e),
                     measured=f"{100 * e:.3g}% at t = {a['t_end']:g} (u {100 * a['u_rel_error_at_t_end']:.3g}%, "
                              f"Omega {100 * a['Omega_rel_error_at_t_end']:.3g}%)",
                     rule=f"number, within {REL_TOL:.0%}",
                     reason=f"the derived hierarchy's error is {want / e:.3g} times smaller than the paper's" if finite(e)
                     and e < want else "")


def c12(paper, hierarchy) -> Judgement:
    a = hierarchy.attrs
    ok = a["order3_forcing_vanishes"] == 1 and a["order3_max_abs_along_solution"] == 0 and a["order4_n_secular"] > 0
    return Judgement(
        REPRODUCED if ok else DIFFERS,
        measured=f"order-3 forcing with order 1 = 0: {a['order3_forcing_with_order1_zero']}; max |x3| = "
                 f"{a['order3_max_abs_along_solution']:.1g}; {a['order4_n_secular']} of {a['order4_n_terms']} order-4 "
                 f"forcing terms secular; |omega4| grows like t^{a['growth_exponent_omega4']:.2f} (|omega2| like "
                 f"t^{a['growth_exponent_omega2']:.2f})",
        rule="order 3 vanishes symbolically and along the solution; at least one secular order-4 term ("
             + a["order4_secular_rule"] + ")")


def _backward_stretch(t, u, window=5.0):
    """Centre and length of the longest stretch where the running maximum of u (over ``window``) is negative."""
    n = max(1, int(round(window / (t[1] - t[0]))))
    runmax = np.array([u[max(0, i - n): i + n + 1].max() for i in range(u.size)])
    neg = runmax < 0
    if not neg.any():
        return math.nan, 0.0
    edges = np.flatnonzero(np.diff(np.r_[0, neg.astype(int), 0]))
    starts, ends = edges[::2], edges[1::2] - 1
    k = int(np.argmax(t[ends] - t[starts]))
    return float(0.5 * (t[starts[k]] + t[ends[k]])), float(t[ends[k]] - t[starts[k]])


def c13(paper, fig7) -> Judgement:
    t, u, Om, th = fig7.time.values, fig7.u.values, fig7.Omega.values, fig7.theta.values
    i = int(np.argmax(np.abs(Om)))
    turn = float(np.interp(t[i] + 300, t, th) - np.interp(t[i] - 300, t, th)) / math.pi
    back, length = _backward_stretch(t, u)
    parts = [REPRODUCED if finite(back) and abs(back - paper["backward_time"]) < 0.05 * paper["backward_time"] else DIFFERS,
             REPRODUCED if abs(t[i] - paper["spike_time"]) < 0.05 * paper["spike_time"] else DIFFERS,
             REPRODUCED if abs(abs(turn) - paper["turn_over_pi"]) < REL_TOL else DIFFERS]
    return Judgement(
        all_of(parts), difference=relative(paper["spike_time"], t[i]),
        measured=(f"u stays negative for {length:.3g} time units around t = {back:.0f}" if finite(back) else
                  "u never stays negative in the window") + f"; the largest spike at t = {t[i]:.0f} turns the heading "
                                                            f"by {turn:.3f} pi",
        rule="a backward stretch (running maximum of u over 5 time units negative) within 5% of the paper's time, the "
             "largest spike within 5% of the paper's time and |turn| within 10% of pi")


def c14(paper, fig8) -> Judgement:
    x, y, t = fig8.x.values, fig8.y.values, fig8.time.values
    r = np.hypot(x - x[0], y - y[0])
    reach = np.maximum.accumulate(r)
    growth = float(reach[-1] / reach[reach.size // 2])
    step = max(1, x.size // 5000)
    X = np.c_[x[::step], y[::step]]
    size = float(np.sqrt(np.mean(np.sum((X - X.mean(0)) ** 2, axis=1))))
    lags = range(max(1, int(50 / (t[step] - t[0]))), X.shape[0] // 3)
    recurrence = min(float(np.sqrt(np.mean(np.sum((X[L:] - X[:-L]) ** 2, axis=1)))) for L in lags) / size
    bounded, aperiodic = growth < 1.2, recurrence > 0.01
    return Judgement(
        REPRODUCED if bounded and aperiodic else DIFFERS, units="length",
        measured=f"the farthest distance from the start grows by {growth:.3f} from half the path to all of it "
                 f"(bounded about 1, diffusive 1.41, straight 2), reaching {reach[-1]:.3g}; the path never repeats "
                 f"itself to better than {recurrence:.3g} of its size at any lag of 50 to {t[-1] - t[0]:.3g} / 3",
        rule="bounded: the farthest distance from the start grows by less than 1.2 over the second half of the path; "
             "not periodic: at every lag the RMS distance between the path and its shifted copy exceeds 0.01 of its size",
        reason="" if bounded else f"the path keeps leaving: its reach grows by {growth:.2f} over the second half")


def c15(paper, ref) -> Judgement:
    a = ref.attrs
    # a periodic orbit of period q <= 50 returns to within the integration error (1e-12 relative):
    # 1e-6 of the set's size separates it from the close, but never exact, returns of a dense curve
    thin, many, aperiodic = a["p2pi_curve_thickness"] < 0.01, a["n_p2pi"] >= 1000, a["p2pi_recurrence"] > 1e-6
    verdict = REPRODUCED if thin and many and aperiodic else DIFFERS
    return Judgement(
        verdict,
        measured=f"{a['n_p2pi']} iterates; curve thickness {a['p2pi_curve_thickness']:.2g} of the radius; iterates "
                 f"never come back closer than {a['p2pi_recurrence']:.2g} of the set's size (q <= 50); rotation number "
                 f"{a['rotation_number']:.5g} (halves {a['rotation_number_first_half']:.5g}, "
                 f"{a['rotation_number_second_half']:.5g})",
        rule="at least 1000 iterates (thousands), curve thickness < 0.01 (a closed curve) and no return closer than "
             "1e-6 of the set's size within 50 iterates (not periodic: a periodic orbit returns to integration accuracy)",
        reason="" if verdict == REPRODUCED else ", ".join(
            w for w, bad in (("fewer than 1000 iterates", not many), ("the set is not a thin curve", not thin),
                             ("the iterates repeat", not aperiodic)) if bad))


def c16(paper, ref) -> Judgement:
    a = ref.attrs
    return Judgement(REPRODUCED if a["n_loops"] == paper["loops"] else DIFFERS,
                     measured=f"{a['n_loops']} loops (per class {[int(n) for n in a['loops_per_class']]}; "
                              f"{a['n_components_projected']} components in the 3-D projection)",
                     rule="exact count of k-NN graph components per section class (loop rule in the dataset)")


def c17(paper, ref, high, small, scaling) -> Judgement:
    persists = high.attrs["n_loops"] == 4 and small.attrs["n_loops"] == 4
    f_ref, f_high, f_small = (d.attrs["attractor_flatness"] for d in (ref, high, small))
    flatter_at_larger_eps = f_ref < f_small
    sc = scaling.attrs
    return Judgement(
        REPRODUCED if persists and flatter_at_larger_eps else DIFFERS,
        measured=f"loops {high.attrs['n_loops']} (E label {high.attrs['energy_label']:.4g}), {small.attrs['n_loops']} "
                 f"(eps {small.attrs['param_eps']:g}); flatness (smallest / largest axis) {f_ref:.3g} at eps "
                 f"{ref.attrs['param_eps']:g}, {f_small:.3g} at eps {small.attrs['param_eps']:g}, {f_high:.3g} at E label "
                 f"{high.attrs['energy_label']:.4g}; the higher label divided by c = {sc['scale_factor_c']:.4g} lies "
                 f"{sc['distance_scaled_median']:.2g} of the size from the reference set (unscaled "
                 f"{sc['distance_unscaled_median']:.2g})",
        rule="the 4 loops persist at the higher label and at the smaller eps, and the attractor is flatter at the larger "
             "eps; the energy changes only the scale (exact time-scaling symmetry), so it cannot change the shape",
        reason="" if persists and flatter_at_larger_eps else
        ("the loops do not persist; " if not persists else "") +
        ("" if flatter_at_larger_eps else f"the attractor is not flatter at the larger eps ({f_ref:.3g} against "
                                          f"{f_small:.3g}); ") + f"at the same eps the shape does not depend on the energy "
                                                                 f"({f_ref:.3g} against {f_high:.3g})")


def c18(paper, spectrum) -> Judgement:
    a = spectrum.attrs
    div, unc = a["mean_divergence"], a["mean_divergence_stderr"]
    contracts, expands = div + K_SIGMA * unc < 0, div - K_SIGMA * unc > 0
    verdict = REPRODUCED if contracts else DIFFERS
    return Judgement(
        verdict, units="1/time", uncertainty=fmt(unc, 2),
        measured=f"mean divergence {div:.3g} (plain flow, {a['replicas']} replicas); sum of exponents {a['sum_all']:.3g} "
                 f"+- {a['sum_all_stderr']:.2g} (variational runs); lambda_1 + lambda_4 = {a['sum_lambda_1_4']:.3g} +- "
                 f"{a['sum_lambda_1_4_stderr']:.2g}",
        rule=f"contraction: the mean trace of J plus {K_SIGMA:g} standard errors over independent replicas is below 0",
        reason="" if contracts else ("the flow expands phase-space volume on average" if expands else
                                     f"no contraction resolved: the mean divergence is within {K_SIGMA:g} standard "
                                     f"errors ({unc:.2g}) of zero"))


def c19(paper, protocol, spectrum) -> Judgement:
    want = np.sort(np.asarray(paper["exponents"], float))[::-1]
    lam, err = spectrum.exponent.values, spectrum.stderr.values
    parts = [number(w, o, e) for w, o, e in zip(want, lam, err)]
    spread = protocol.exponent.values
    return Judgement(
        all_of(parts), units="1/time", uncertainty=fmt(err, 2),
        difference=max(relative(w, o) for w, o in zip(want, lam)),
        measured=f"converged spectrum (T = {spectrum.attrs['T']:g} per replica, {spectrum.attrs['replicas']} replicas): "
                 f"{fmt(lam, 3)}; the paper's protocol (T = {protocol.attrs['T']:g} after {protocol.attrs['t_transient']:g}) "
                 f"from {spread.shape[0]} states on the level gives lambda_1 in [{spread[:, 0].min():.2g}, "
                 f"{spread[:, 0].max():.2g}] and lambda_4 in [{spread[:, 3].min():.2g}, {spread[:, 3].max():.2g}]",
        rule=f"each paper exponent (sorted) within {REL_TOL:.0%} or {K_SIGMA:g} standard errors of our converged one; the "
             "protocol's spread over states is reported, not judged",
        reason="; ".join(f"lambda_{i + 1}: {o:.3g} +- {e:.2g} against {w:.3g}" for i, (w, o, e, v)
                         in enumerate(zip(want, lam, err, parts)) if v == DIFFERS))


def fake_rates(rows) -> np.ndarray:
    """Per row of lambda_1 rows (T, tau per row): the rate polynomial growth fakes over the row's
    horizon, 2 ln(T / tau) / T (chaos.verdicts.polynomial_rate_bound); NaN for a row not computed. A finite-time lambda_1 below
    it does not show chaos: a regular orbit's tangent vector grows like a power of t."""
    return np.array([polynomial_rate_bound(T, tau) if np.isfinite(T) and np.isfinite(tau) else math.nan
                     for T, tau in zip(rows["T"].values, rows["tau"].values)])


_FAKE = "2 ln(T / tau) / T, the rate polynomial growth fakes over the row's horizon"


def c20(paper, energy) -> Judgement:
    labels, lam, err = energy.label.values, energy.lambda_1.values, energy.stderr.values
    inside = (labels >= paper["label_min"] * (1 - 1e-9)) & (labels <= paper["label_max"] * (1 + 1e-9))
    k = int(np.flatnonzero(inside)[np.argmin(lam[inside])]) if inside.any() else None
    smallest = number(paper["smallest"], lam[k], err[k]) if k is not None else NOT_YET
    low = np.flatnonzero(np.isclose(labels, paper["positive_down_to"], rtol=1e-9))
    if low.size:
        j = int(low[0])
        fake = fake_rates(energy)[j]
        positive = REPRODUCED if lam[j] - K_SIGMA * err[j] > fake else DIFFERS if lam[j] + K_SIGMA * err[j] < 0 else NOT_YET
        low_text = (f"at E label {labels[j]:g}: lambda_1 = {lam[j]:.2g} +- {err[j]:.1g} (polynomial growth fakes up to "
                    f"{fake:.2g} over its horizon)")
    else:
        positive, low_text = NOT_YET, f"E label {paper['positive_down_to']:g} not computed"
    return Judgement(
        all_of([smallest, positive]), units="1/time", uncertainty=fmt(err[k], 2) if k is not None else "",
        difference=relative(paper["smallest"], lam[k]) if k is not None else math.nan,
        measured=(f"smallest lambda_1 over labels {paper['label_min']:g} to {paper['label_max']:g}: {lam[k]:.2g} (E label "
                  f"{labels[k]:g})" if k is not None else "no label in the paper's range") + f"; {low_text}; fitted "
                 f"exponent of lambda_1 against E {energy.attrs['fitted_exponent']:.4f} (law: 0.5)",
        rule=f"the smallest value within {REL_TOL:.0%} or {K_SIGMA:g} standard errors of the paper's, and lambda_1 resolved "
             f"positive at the lowest energy the paper names (lambda_1 - {K_SIGMA:g} stderr > {_FAKE})",
        reason=(f"the smallest value is {lam[k]:.2g}, not {paper['smallest']:g}; " if smallest == DIFFERS else "")
        + ("lambda_1 is not resolved positive at the lowest energy" if positive != REPRODUCED else ""))


def _elsewhere(ds, eps) -> str:
    """The rows a dataset leaves to another config, as text ("" when none)."""
    eps = np.atleast_1d(np.asarray(eps, float))
    if not eps.size:
        return ""
    where = ds.attrs["elsewhere_config"] or "another config"
    return f"; not computed in this run: eps {', '.join(f'{e:.3g}' for e in eps)} (computed by {where})"


def c21(paper, grid) -> Judgement:
    floor = paper["smallest_above"]
    eps, lam, err, status = grid.eps.values, grid.lambda_1.values, grid.stderr.values, grid.status.values
    steady = (grid.transient_over.values == 1) & (grid.steady.values == 1)
    above = (status == "converged") & steady & (lam - K_SIGMA * err > np.maximum(floor, fake_rates(grid)))
    below = steady & ((status == "regular") | ((status == "converged") & (lam + K_SIGMA * err < floor)))
    away = status == "elsewhere"
    unresolved = ~above & ~below & ~away
    verdict = DIFFERS if below.any() else (CANNOT if unresolved.any() else REPRODUCED)

    def listed(sel):
        return ", ".join(f"{e:.3g}" for e in eps[sel]) or "none"

    return Judgement(
        verdict, units="1/time",
        measured=f"{grid.attrs['n_rows']} eps rows (b is a symmetry): resolved above {floor:g} and above the polynomial "
                 f"rate at eps {listed(above)}; below or regular at eps {listed(below)}; unresolved within the run's "
                 f"horizon (below the polynomial rate, capped or not steady) at eps {listed(unresolved)}; smallest resolved "
                 "lambda_1 "
                 f"{np.min(lam[above]) if above.any() else math.nan:.2g}" + _elsewhere(grid, eps[away]),
        rule=f"reproduced when every row resolves lambda_1 - {K_SIGMA:g} stderr above {floor:g} and above {_FAKE}; differs "
             f"when a steady row is resolved below {floor:g} or regular; cannot be reproduced when the rest are not resolved "
             "within the configured horizon (max_rounds) or are not steady",
        reason="" if verdict == REPRODUCED else
        (f"lambda_1 is resolved below {floor:g} or regular at eps {listed(below)}" if below.any() else
         f"lambda_1 is not resolved above {floor:g} and the polynomial rate (or the row is capped or not steady) at eps "
         f"{listed(unresolved)}"))


def c22(paper, ref) -> Judgement:
    a = ref.attrs
    tie = paper["tie"]
    n = a["return_time_n_adjacent_pairs_within_tie_tol"]
    N, width = a["n_p2pi"] - 1, a["return_time_max"] - a["return_time_min"]
    expected = N * N * tie / width if width > 0 else math.nan
    return Judgement(
        REPRODUCED if n == 0 else DIFFERS, units="time",
        measured=f"{N} return times in [{a['return_time_min']:.5g}, {a['return_time_max']:.5g}]; {n} adjacent pairs closer "
                 f"than {tie:g}; smallest difference {a['return_time_min_pairwise_difference']:.2g}",
        rule=f"no two return times closer than the paper's {tie:g}",
        reason=f"{N} values spread over {width:.3g} give about {expected:.3g} pairs closer than {tie:g} by chance"
        if n else "")


def _band(paper, psd) -> Judgement:
    a = psd.attrs
    want = paper["band"]
    ours = (a["Omega_band_low"], a["Omega_band_high"])
    resolution = 1.0 / a["psd_segment"]
    tol = max(REL_TOL * (want[1] - want[0]), resolution)
    ok = all(abs(o - w) <= tol for o, w in zip(ours, want))
    return Judgement(
        REPRODUCED if ok else DIFFERS, units="cycles/time",
        difference=max(relative(w, o) for w, o in zip(want, ours)),
        measured=f"Omega band [{ours[0]:.4g}, {ours[1]:.4g}] (u: [{a['u_band_low']:.4g}, {a['u_band_high']:.4g}]); "
                 f"{a['Omega_n_peaks_near_zero']} distinct peaks near 0; resolution {resolution:.2g}",
        rule=f"both band edges within {REL_TOL:.0%} of the paper's band width or one frequency bin, whichever is larger "
             f"({tol:.2g})")


def c23(paper, psd) -> Judgement:
    return _band(paper, psd)


def c24(paper, psd) -> Judgement:
    return _band(paper, psd)


def c25(paper, cost) -> Judgement:
    targets, hours = cost.target.values, cost.wall_estimate_s.values / 3600
    k = int(np.argmin(np.abs(np.log(targets / paper["eps_min"]))))
    budget = cost.attrs["budget_core_hours"]
    over = bool(hours[k] > budget)
    return Judgement(
        CANNOT if over else NOT_YET, units="core-hours", difference=hours[k] / budget if finite(hours[k]) else math.nan,
        measured="; ".join(f"eps {e:g}: transient ~{t:.2g} time units, ~{h:.2g} core-hours" for e, t, h in
                           zip(targets, cost.transient_estimate.values, hours)) + f"; budget {budget:g} core-hours",
        rule="the cost of reaching the attractor at the paper's smallest eps, extrapolated from measured transients and "
             "step rates, against the budget stated in the config",
        reason=f"eps {targets[k]:g} would take about {hours[k]:.3g} core-hours, above the budget of {budget:g}" if over else
        f"eps {targets[k]:g} fits the budget ({hours[k]:.3g} core-hours) but is not run" if finite(hours[k]) else
        "the transient was not measured at the configured eps, so the cost is not determined")


def c26(paper, formal) -> Judgement:
    """Above the paper's eps only rows whose transient was checked over count (a missing check counts
    as not checked); one resolved lambda_1 above the bound differs, all resolved below reproduce."""
    eps, lam, err = formal.eps.values, formal.lambda_1.values, formal.stderr.values
    over = formal["transient_over"].values == 1 if "transient_over" in formal else np.zeros(eps.size, bool)
    big = eps > paper["eps_above"]
    if not big.any():
        return Judgement(NOT_YET, measured="no eps above the paper's threshold computed", rule="")
    settled = big & over
    below = lam + K_SIGMA * err < paper["lambda_below"]
    above = lam - K_SIGMA * err > paper["lambda_below"]
    verdict = DIFFERS if (settled & above).any() else REPRODUCED if (below[big] & over[big]).all() else NOT_YET
    unsettled = ", ".join(f"{e:g}" for e in eps[big & ~over])
    resolved_above = ", ".join(f"{e:g}" for e in eps[settled & above])
    reasons = ([f"lambda_1 resolved above {paper['lambda_below']:g} at settled eps {resolved_above}"]
               if resolved_above else []) + ([f"transient not over at eps {unsettled}"] if unsettled else [])
    away = formal.attrs["eps_elsewhere"] if "eps_elsewhere" in formal.attrs else []
    return Judgement(
        verdict, units="1/time",
        measured="; ".join(f"eps {e:g}: lambda_1 = {m:.2g} +- {s:.1g}{'' if o else ' (transient not over)'}"
                           for e, m, s, o in zip(eps, lam, err, over)) + _elsewhere(formal, away),
        reason="; ".join(reasons),
        rule=f"at every eps above {paper['eps_above']:g} with its transient over, lambda_1 + {K_SIGMA:g} stderr < "
             f"{paper['lambda_below']:g} (the formal system: m_c = 1 - eps < 0)")


def c27(paper, rows) -> Judgement:
    """Quasi-periodic route to chaos near eps = 0, from lambda_1 against eps (the F11 rows, or the
    on-request regime diagram)."""
    eps, lam, err, status = rows.eps.values, rows.lambda_1.values, rows.stderr.values, rows.status.values
    steady = (rows.transient_over.values == 1) & (rows.steady.values == 1)
    thin = np.asarray(rows.curve_thickness.values) < 0.01
    chaotic = steady & (status == "converged") & (lam - K_SIGMA * err > fake_rates(rows))
    regular = steady & (status == "regular")
    order = np.argsort(eps)
    eps, chaotic, regular, thin = eps[order], chaotic[order], regular[order], thin[order]
    first_chaos = eps[chaotic].min() if chaotic.any() else math.nan
    below = eps < first_chaos if finite(first_chaos) else np.zeros(eps.size, bool)

    def listed(sel):
        return ", ".join(f"{e:.3g}" for e in eps[sel]) or "none"

    resolved_below = below & regular
    if not chaotic.any():
        verdict, reason = NOT_YET, "no row is resolved chaotic"
    elif not resolved_below.any():
        verdict, reason = NOT_YET, (f"no row below the first chaotic eps ({first_chaos:.3g}) is resolved regular: a "
                                    f"route, if any, lies below the computed range or the rows there are unresolved")
    elif np.all(thin[resolved_below]):
        verdict, reason = REPRODUCED, ""
    else:
        verdict, reason = DIFFERS, (f"regular rows below the first chaotic eps ({first_chaos:.3g}) without a thin P_2pi "
                                    f"curve (not a torus) at eps {listed(resolved_below & ~thin)}")
    return Judgement(
        verdict,
        measured=f"{eps.size} eps rows in [{eps.min():.3g}, {eps.max():.3g}]: chaotic (lambda_1 resolved above the "
                 f"polynomial rate) at eps "
                 f"{listed(chaotic)}; regular at eps {listed(regular)}; regular with a thin P_2pi curve at eps "
                 f"{listed(regular & thin)}",
        rule=f"below the smallest chaotic eps (lambda_1 - {K_SIGMA:g} stderr > {_FAKE}), the rows resolved regular must have "
             "a thin P_2pi curve (thickness < 0.01: a torus): reproduced when at least one such row exists and all "
             "have it, differs when one does not, not yet computed when none is resolved regular (unresolved rows "
             "are not counted)",
        reason=reason)


def d1(paper, audit) -> Judgement:
    a = audit.attrs
    return Judgement(DIFFERS if a["printed_max_abs_rel_change"] > 1e-6 else REPRODUCED,
                     measured=f"printed: max |E/E0 - 1| = {a['printed_max_abs_rel_change']:.3g}; derived: "
                              f"{a['derived_max_abs_rel_change']:.2g}",
                     rule="the printed equation differs when it changes E by more than 1e-6")


def d2(paper, audit) -> Judgement:
    a = audit.attrs
    ic, ir = a["d2_Omegadot_residual_with_Ic"], a["d2_Omegadot_residual_with_Ir"]
    return Judgement(DIFFERS if ic < 1e-12 < ir else REPRODUCED,
                     measured=f"printed Omegadot against the derivation: residual {ic:.1e} with I_c = (K^2 - 1) b^2, "
                              f"{ir:.2g} with I_r",
                     rule="differs when only I_c (not the printed I_r) makes the printed Omegadot hold",
                     reason="the definition must read K^2 = 1 + I_c / (m b^2)" if ic < 1e-12 < ir else "")


def d3(paper, audit) -> Judgement:
    a = audit.attrs
    return Judgement(DIFFERS if a["d3_n_differences"] else REPRODUCED,
                     measured=f"{a['d3_n_differences']} entries differ: {a['d3_differences']}", rule="symbolic comparison")


def d4(paper, audit) -> Judgement:
    a = audit.attrs
    return Judgement(DIFFERS if a["d4_dL_dbeta"] != "0" else REPRODUCED, measured=f"dL/dbeta = {a['d4_dL_dbeta']}",
                     rule="symbolic: the printed beta equation omits dL/dbeta, which is not zero")


def d5(paper, audit) -> Judgement:
    a = audit.attrs
    E = a["d5_reference_energy_physical"]
    want = paper["label"]
    return Judgement(number(want, E), units="energy", difference=relative(want, E),
                     measured=f"{E:.4g} for the reference state at eps = {a['param_eps']:g}",
                     rule=f"number, within {REL_TOL:.0%}")


def d6(paper, audit) -> Judgement:
    a = audit.attrs
    eps, m_c, det = a["d6_eps"], a["d6_m_c"], a["d6_min_det_M"]
    unphysical, formal_ok = bool(np.all(m_c < 0)), bool(np.all(det > 0))
    return Judgement(
        DIFFERS if unphysical else REPRODUCED,
        measured="; ".join(f"eps {e:g}: m_c = {m:g}, min det M = {d:.3g}" for e, m, d in zip(eps, m_c, det)),
        rule="from the derivation: eps = m_r / m >= 1 makes the sleigh's mass m_c = 1 - eps non-positive; the formal "
             "system is well defined where M(delta) stays positive definite",
        reason=f"eps > {paper['eps']:g} is a formal system (m_c < 0)" + (", whose inertia stays positive definite"
                                                                          if formal_ok else ""))


#: Claim id -> judge.
JUDGES = {
    "C01": c01,
    "C02": c02,
    "C03": c03,
    "C04": c04,
    "C05": c05,
    "C06": c06,
    "C07": c07,
    "C08": c08,
    "C09": c09,
    "C10": c10,
    "C11": c11,
    "C12": c12,
    "C13": c13,
    "C14": c14,
    "C15": c15,
    "C16": c16,
    "C17": c17,
    "C18": c18,
    "C19": c19,
    "C20": c20,
    "C21": c21,
    "C22": c22,
    "C23": c23,
    "C24": c24,
    "C25": c25,
    "C26": c26,
    "C27": c27,
    "D1": d1,
    "D2": d2,
    "D3": d3,
    "D4": d4,
    "D5": d5,
    "D6": d6,
}
