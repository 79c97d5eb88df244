"""The perturbation hierarchy in eps: its order-0 and order-2 terms, the series against the exact
flow, and the printed hierarchy against the derived one (figures F5, F6; C07-C12).

Each judge takes the paper's values and its datasets (:data:`sleighsim.claims.evidence.EVIDENCE`)
and returns a :class:`~sleighsim.claims.rules.Judgement`."""

from __future__ import annotations

import math

from sleighsim.claims.rules import (
    DIFFERS,
    K_SIGMA,
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


def c07(paper, fig6) -> Judgement:
    """C07, "O(eps) perturbation terms stay zero for these initial conditions": judged from the paper's values
    ``paper`` and ``fig6``; returns its Judgement."""
    v = fig6.attrs["order1_max_abs"]
    return Judgement(REPRODUCED if v == paper["order1"] else DIFFERS,
                     measured=f"max |u1, Omega1, omega1, delta1| = {v:.1g}",
                     rule="exactly zero along the integration (the order-1 equations are linear and homogeneous)")


def c08(paper, fig6) -> Judgement:
    """C08, "period of u2 and Omega2: T1 = 6.276, close to 2 pi/omega0 = 6.277": judged from the paper's values
    ``paper`` and ``fig6``; returns its Judgement."""
    a = fig6.attrs
    T1, tw = a["T1_Omega2"], a["two_pi_over_omega0"]
    parts = [digits(paper["_text"]["T1"], T1, a["T1_Omega2_uncertainty"]),
             digits(paper["_text"]["two_pi_over_omega0"], tw, a["two_pi_over_omega0_uncertainty"])]
    return Judgement(all_of(parts), units="time", uncertainty=fmt(a["T1_Omega2_uncertainty"], 1),
                     difference=max(relative(paper["T1"], T1), relative(paper["two_pi_over_omega0"], tw)),
                     measured=f"T1 = {T1:.5f} (u2: {a['T1_u2']:.5f}); 2 pi / omega0 = {tw:.5f}",
                     rule="each within one unit of the paper's last printed digit (or 2 uncertainties)")


def c09(paper, fig6) -> Judgement:
    """C09, "Omega2 steady amplitude 0.892, phase phi1 = 0.4705 pi": judged from the paper's values ``paper``
    and ``fig6``; returns its Judgement."""
    a = fig6.attrs
    parts = [number(paper["Omega2_amplitude"], a["Omega2_amplitude"], a["Omega2_amplitude_uncertainty"]),
             number(paper["phi1_over_pi"], a["phi1_over_pi"], a["phi1_uncertainty"] / math.pi)]
    sign = "+" if a["theory_phi1"] >= 0 else "-"
    return Judgement(
        all_of(parts), difference=max(relative(paper["Omega2_amplitude"], a["Omega2_amplitude"]),
                                      relative(paper["phi1_over_pi"], a["phi1_over_pi"])),
        measured=f"amplitude {a['Omega2_amplitude']:.4f}, phi1 = {a['phi1_over_pi']:.4f} pi (the paper's closed forms "
                 f"with our u0, omega0: {a['theory_Omega2_amplitude']:.4f}, "
                 f"phi1 = {a['theory_phi1'] / math.pi:.4f} pi)",
        rule=f"numbers, within {REL_TOL:.0%} or {K_SIGMA:g} uncertainties; "
             "phase from the fit Omega2 ~ -A sin(delta0 + phi1)",
        reason=f"the printed phi1 = arctan(-omega0 b K^2 / u0) has sign {sign}: {a['theory_phi1'] / math.pi:.4f} pi "
               f"against the fitted {a['phi1_over_pi']:.4f} pi")


def c10(paper, fig6) -> Judgement:
    """C10, "omega2: period T2 = 3.138 (sim) vs 3.135 (theory); B = 0.241 vs 0.238; mean growth 0.0445 vs
    0.0415": judged from the paper's values ``paper`` and ``fig6``; returns its Judgement."""
    a = fig6.attrs
    pairs = [("T2", "T2", a["T2_uncertainty"]), ("T2_theory", "theory_T2", 0.0), ("B", "B", a["B_uncertainty"]),
             ("B_theory", "theory_B", 0.0), ("growth", "omega2_growth", a["omega2_growth_uncertainty"]),
             ("growth_theory", "theory_omega2_growth", 0.0)]
    vs = {k: number(paper[k], a[ours], unc) for k, ours, unc in pairs}
    return Judgement(
        all_of(vs.values()), difference=max(relative(paper[k], a[ours]) for k, ours, _ in pairs),
        measured="; ".join(f"{k} {a[ours]:.4g} ({vs[k]})" for k, ours, _ in pairs),
        rule=f"each number within {REL_TOL:.0%} or {K_SIGMA:g} uncertainties; simulation: a line plus a sinusoid "
             f"fitted to omega2 on [{a['fit_window_start']:g}, {a['fit_window_end']:g}]; theory: the paper's closed "
             "forms with our u0, omega0",
        reason="; ".join(f"{k}: {a[ours]:.4g} against {paper[k]:g}" for k, ours, _ in pairs if vs[k] == DIFFERS))


def c11(paper, fig5) -> Judgement:
    """C11, "error of perturbation omega vs exact about 2% at t = 100": judged from the paper's values ``paper``
    and ``fig5``; returns its Judgement."""
    a = fig5.attrs
    e = a["omega_rel_error_at_t_end"]
    want = paper["omega_rel_error"]
    return Judgement(number(want, e), units="relative", difference=relative(want, e),
                     measured=f"{100 * e:.3g}% at t = {a['t_end']:g} (u {100 * a['u_rel_error_at_t_end']:.3g}%, "
                              f"Omega {100 * a['Omega_rel_error_at_t_end']:.3g}%)",
                     rule=f"number, within {REL_TOL:.0%}",
                     reason=(f"the derived hierarchy's error is {want / e:.3g} times smaller than the paper's"
                             if finite(e) and e < want else ""))


def c12(paper, hierarchy) -> Judgement:
    """C12, "third-order terms vanish; fourth order has secular terms": judged from the paper's values ``paper``
    and ``hierarchy``; returns its Judgement."""
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
