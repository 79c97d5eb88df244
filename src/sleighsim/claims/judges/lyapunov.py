"""The Lyapunov exponents: the spectrum and the paper's protocol, lambda_1 against the energy label
and over (eps, b), what small eps costs, the formal system and the route to chaos (figures F10,
F11; C18-C21, C25-C27).

Each judge takes the paper's values and its datasets (:data:`sleighsim.claims.evidence.EVIDENCE`)
and returns a :class:`~sleighsim.claims.rules.Judgement`."""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.verdicts import polynomial_rate_bound, resolving_horizon
from sleighsim.claims.rules import (
    CANNOT,
    DIFFERS,
    K_SIGMA,
    NOT_YET,
    REL_TOL,
    REPRODUCED,
    Judgement,
    all_of,
    finite,
    fmt,
    number,
    relative,
)

#: The paper's claims that the rotor's steady state is chaotic: positive Lyapunov exponents (C19-C21), chaos
#: down to eps = 1e-5 (C25) and the quasiperiodic route to it (C27); the finding's paragraph names their verdicts.
CHAOS_CLAIMS = ("C19", "C20", "C21", "C25", "C27")


def c18(paper, spectrum) -> Judgement:
    """C18, "flow contracts phase-space volume although E is invariant": judged from the paper's values
    ``paper`` and ``spectrum``; returns its Judgement."""
    a = spectrum.attrs
    div, unc = a["mean_divergence"], a["mean_divergence_stderr"]
    contracts, expands = div + K_SIGMA * unc < 0, div - K_SIGMA * unc > 0
    verdict = REPRODUCED if contracts else DIFFERS
    return Judgement(
        verdict, units="1/time", uncertainty=fmt(unc, 2),
        measured=f"mean divergence {div:.3g} (plain flow, {a['replicas']} replicas); sum of exponents "
                 f"{a['sum_all']:.3g} +- {a['sum_all_stderr']:.2g} (variational runs); lambda_1 + lambda_4 = "
                 f"{a['sum_lambda_1_4']:.3g} +- {a['sum_lambda_1_4_stderr']:.2g}",
        rule=f"contraction: the mean trace of J plus {K_SIGMA:g} standard errors over independent replicas is below 0",
        reason="" if contracts else ("the flow expands phase-space volume on average" if expands else
                                     f"no contraction resolved: the mean divergence is within {K_SIGMA:g} standard "
                                     f"errors ({unc:.2g}) of zero"))


def c19(paper, protocol, spectrum) -> Judgement:
    """C19, "four Lyapunov exponents (T = 4000 after 10000 pre-simulation, dt = 0.01)": judged from the paper's
    values ``paper`` and ``protocol``, ``spectrum``; returns its Judgement."""
    want = np.sort(np.asarray(paper["exponents"], float))[::-1]
    lam, err = spectrum.exponent.values, spectrum.stderr.values
    parts = [number(w, o, e) for w, o, e in zip(want, lam, err)]
    spread = protocol.exponent.values
    return Judgement(
        all_of(parts), units="1/time", uncertainty=fmt(err, 2),
        difference=max(relative(w, o) for w, o in zip(want, lam)),
        measured=f"converged spectrum (T = {spectrum.attrs['T']:g} per replica, {spectrum.attrs['replicas']} "
                 f"replicas): {fmt(lam, 3)}; the paper's protocol (T = {protocol.attrs['T']:g} after "
                 f"{protocol.attrs['t_transient']:g}) from {spread.shape[0]} states on the level gives lambda_1 in "
                 f"[{spread[:, 0].min():.2g}, "
                 f"{spread[:, 0].max():.2g}] and lambda_4 in [{spread[:, 3].min():.2g}, {spread[:, 3].max():.2g}]",
        rule=f"each paper exponent (sorted) within {REL_TOL:.0%} or {K_SIGMA:g} standard errors of our converged "
             "one; the protocol's spread over states is reported, not judged",
        reason="; ".join(f"lambda_{i + 1}: {o:.3g} +- {e:.2g} against {w:.3g}" for i, (w, o, e, v)
                         in enumerate(zip(want, lam, err, parts)) if v == DIFFERS))


def fake_rates(rows) -> np.ndarray:
    """Per row of lambda_1 rows (T, tau per row): the rate polynomial growth fakes over the row's
    horizon, 2 ln(T / tau) / T (chaos.verdicts.polynomial_rate_bound); NaN for a row not computed. A
    finite-time lambda_1 below it does not show chaos: a regular orbit's tangent vector grows like a power of t."""
    return np.array([polynomial_rate_bound(T, tau) if np.isfinite(T) and np.isfinite(tau) else math.nan
                     for T, tau in zip(rows["T"].values, rows["tau"].values)])


_FAKE = "2 ln(T / tau) / T, the rate polynomial growth fakes over the row's horizon"


def c20(paper, energy) -> Judgement:
    """C20, "max LE grows with E and stays positive down to E = 1e-4; smallest in fig:lyap": judged from the
    paper's values ``paper`` and ``energy``; returns its Judgement."""
    labels, lam, err = energy.label.values, energy.lambda_1.values, energy.stderr.values
    inside = (labels >= paper["label_min"] * (1 - 1e-9)) & (labels <= paper["label_max"] * (1 + 1e-9))
    k = int(np.flatnonzero(inside)[np.argmin(lam[inside])]) if inside.any() else None
    smallest = number(paper["smallest"], lam[k], err[k]) if k is not None else NOT_YET
    low = np.flatnonzero(np.isclose(labels, paper["positive_down_to"], rtol=1e-9))
    if low.size:
        j = int(low[0])
        fake = fake_rates(energy)[j]
        positive = (REPRODUCED if lam[j] - K_SIGMA * err[j] > fake
                    else DIFFERS if lam[j] + K_SIGMA * err[j] < 0 else NOT_YET)
        low_text = (f"at E label {labels[j]:g}: lambda_1 = {lam[j]:.2g} +- {err[j]:.1g} (polynomial growth fakes up to "
                    f"{fake:.2g} over its horizon)")
    else:
        positive, low_text = NOT_YET, f"E label {paper['positive_down_to']:g} not computed"
    return Judgement(
        all_of([smallest, positive]), units="1/time", uncertainty=fmt(err[k], 2) if k is not None else "",
        difference=relative(paper["smallest"], lam[k]) if k is not None else math.nan,
        measured=(f"smallest lambda_1 over labels {paper['label_min']:g} to {paper['label_max']:g}: {lam[k]:.2g} "
                  f"(E label {labels[k]:g})" if k is not None else "no label in the paper's range")
                 + f"; {low_text}; fitted "
                 f"exponent of lambda_1 against E {energy.attrs['fitted_exponent']:.4f} (law: 0.5)",
        rule=f"the smallest value within {REL_TOL:.0%} or {K_SIGMA:g} standard errors of the paper's, and lambda_1 "
             f"resolved positive at the lowest energy the paper names (lambda_1 - {K_SIGMA:g} stderr > {_FAKE})",
        reason=(f"the smallest value is {lam[k]:.2g}, not {paper['smallest']:g}; " if smallest == DIFFERS else "")
        + ("lambda_1 is not resolved positive at the lowest energy" if positive != REPRODUCED else ""))


def _elsewhere(ds, eps) -> str:
    """The rows a dataset leaves to another config, as text ("" when none)."""
    eps = np.atleast_1d(np.asarray(eps, float))
    if not eps.size:
        return ""
    where = ds.attrs["elsewhere_config"] or "another config"
    return f"; not computed in this run: eps {', '.join(f'{e:.3g}' for e in eps)} (computed by {where})"


def at_eps(eps) -> str:
    """Where rows are, as text: "at eps 0, 0.05" (every value printed, 0 included), "at no eps row" when there
    is none (never "none" or a bare 0 that reads like a value)."""
    eps = np.atleast_1d(np.asarray(eps, float))
    return "at eps " + ", ".join(f"{e:.3g}" for e in eps) if eps.size else "at no eps row"


def followed_rows(grid) -> np.ndarray:
    """Per eps row, whether lambda_1's arithmetic follows the row's orbit by its faithfulness gauge
    (``lambda_1_follows``; fails closed: an unknown answer or a dataset without the gauge follows nowhere)."""
    if "lambda_1_follows" not in grid.data_vars:
        return np.zeros(grid.sizes["eps"], bool)
    return grid.lambda_1_follows.values == "follows"


def _needs(grid, sel) -> str:
    """The arithmetic each selected row needs, as text ("eps 0.1: double-double; ...")."""
    names = grid.faithful_arithmetic.values if "faithful_arithmetic" in grid.data_vars else ["unknown"] * sel.size
    return "; ".join(f"eps {e:.3g}: {n}" for e, n, k in zip(grid.eps.values, names, sel) if k)


def c21(paper, grid) -> Judgement:
    """C21, "max LE positive over the (eps, b) range of fig:LE; smallest value": judged from the paper's values
    ``paper`` and ``grid``, on the rows whose orbit lambda_1's arithmetic follows (``followed_rows``); returns its
    Judgement."""
    floor = paper["smallest_above"]
    eps, lam, err, status = grid.eps.values, grid.lambda_1.values, grid.stderr.values, grid.status.values
    away = status == "elsewhere"
    steady = (grid.transient_over.values == 1) & (grid.steady.values == 1) & followed_rows(grid)
    unfollowed = ~away & ~followed_rows(grid)
    above = (status == "converged") & steady & (lam - K_SIGMA * err > np.maximum(floor, fake_rates(grid)))
    below = steady & ((status == "regular") | ((status == "converged") & (lam + K_SIGMA * err < floor)))
    unresolved = ~above & ~below & ~away & ~unfollowed
    verdict = DIFFERS if below.any() else (CANNOT if (unresolved | unfollowed).any() else REPRODUCED)

    def listed(sel):
        return at_eps(eps[sel])

    return Judgement(
        verdict, units="1/time",
        measured=f"{grid.attrs['n_rows']} eps rows (b is a symmetry): resolved above {floor:g} and above the "
                 f"polynomial rate {listed(above)}; below or regular {listed(below)}; unresolved within "
                 f"the run's horizon (below the polynomial rate, capped or not steady) {listed(unresolved)}; "
                 f"lambda_1's arithmetic does not follow the row's orbit (the row's gauge) {listed(unfollowed)}"
                 + (f" (the arithmetic each needs: {_needs(grid, unfollowed)})" if unfollowed.any() else "")
                 + "; smallest resolved lambda_1 "
                 f"{np.min(lam[above]) if above.any() else math.nan:.2g}" + _elsewhere(grid, eps[away]),
        rule=f"on the rows whose orbit lambda_1's arithmetic follows (the row's faithfulness gauge): reproduced when "
             f"every row resolves lambda_1 - {K_SIGMA:g} stderr above {floor:g} and above {_FAKE}; "
             f"differs when a steady row is resolved below {floor:g} or regular; cannot be reproduced when the rest "
             "are not resolved within the configured horizon (max_rounds), are not steady, or are rows whose orbit "
             "the arithmetic does not follow (their lambda_1 measures its rounding, not the orbit)",
        reason="" if verdict == REPRODUCED else
        (f"lambda_1 is resolved below {floor:g} or regular {listed(below)}" if below.any() else
         "; ".join(x for x in (
             f"lambda_1 is not resolved above {floor:g} and the polynomial rate (or the row is capped or not steady) "
             f"{listed(unresolved)}" if unresolved.any() else "",
             f"double does not follow the orbit {listed(unfollowed)}" if unfollowed.any() else "") if x)))


def c25(paper, cost) -> Judgement:
    """C25, "chaos persists down to eps = 1e-5; numerics unreliable below": judged from the paper's values
    ``paper`` and ``cost``; returns its Judgement."""
    targets, hours = cost.target.values, cost.wall_estimate_s.values / 3600
    k = int(np.argmin(np.abs(np.log(targets / paper["eps_min"]))))
    budget = cost.attrs["budget_core_hours"]
    over = bool(hours[k] > budget)
    return Judgement(
        CANNOT if over else NOT_YET, units="core-hours", difference=hours[k] / budget if finite(hours[k]) else math.nan,
        measured="; ".join(f"eps {e:g}: transient ~{t:.2g} time units, ~{h:.2g} core-hours" for e, t, h in
                           zip(targets, cost.transient_estimate.values, hours)) + f"; budget {budget:g} core-hours",
        rule="the cost of reaching the attractor at the paper's smallest eps, extrapolated from measured transients "
             "and step rates, against the budget stated in the config",
        reason=(f"eps {targets[k]:g} would take about {hours[k]:.3g} core-hours, above the budget of {budget:g}"
                if over else
                f"eps {targets[k]:g} fits the budget ({hours[k]:.3g} core-hours) but is not run" if finite(hours[k])
                else "the transient was not measured at the configured eps, so the cost is not determined"))


def _uncertifiable(formal) -> np.ndarray:
    """Per eps: whether the pre-run's rule cannot certify it settled, its omega block means scattering
    about their line by at least the rule's rtol (dimensionless; variable block_fluctuation); False
    where the dataset does not record it."""
    if "block_fluctuation" not in formal or "transient_rtol" not in formal.attrs:
        return np.zeros(formal.eps.size, bool)
    return formal["block_fluctuation"].values >= formal.attrs["transient_rtol"]


def _c26_cannot(formal, rows) -> str:
    """The reason C26 cannot be decided at the eps of ``rows`` (a mask), from the dataset's numbers."""
    a, fl = formal.attrs, formal["block_fluctuation"].values
    listed = ", ".join(f"eps {e:g} (scatter {f:.2g}, pre-run {w:.2g} s)" for e, f, w in
                       zip(formal.eps.values[rows], fl[rows], formal["pre_run_wall_s"].values[rows]))
    return (f"at {listed} omega's block means over {a['transient_window']:g} time units scatter about their trend "
            f"by at least the settling rule's rtol {a['transient_rtol']:g} over the second half of the "
            f"{a['t_transient']:g}-time-unit pre-run: a fluctuation of the orbit that a longer pre-run does not "
            "narrow, so the rule (block means within rtol of one value) cannot tell whether the transient is "
            "over, and lambda_1 there is not counted")


def c26(paper, formal) -> Judgement:
    """C26, "for eps > 20 the leading LE falls below 1e-5" (lambda_1 in 1/time). Above the paper's eps only
    rows whose transient was checked over count (a missing check counts as not checked); one resolved
    lambda_1 above the bound differs, all resolved below reproduce; a row whose pre-run the settling
    rule cannot certify (its block means scatter by rtol or more) makes it cannot be reproduced."""
    eps, lam, err = formal.eps.values, formal.lambda_1.values, formal.stderr.values
    over = formal["transient_over"].values == 1 if "transient_over" in formal else np.zeros(eps.size, bool)
    big = eps > paper["eps_above"]
    if not big.any():
        return Judgement(NOT_YET, measured="no eps above the paper's threshold computed", rule="")
    settled, never = big & over, big & ~over & _uncertifiable(formal)
    below = lam + K_SIGMA * err < paper["lambda_below"]
    above = lam - K_SIGMA * err > paper["lambda_below"]
    open_ = (big & ~over & ~never) | (settled & ~below)
    verdict = (DIFFERS if (settled & above).any() else NOT_YET if open_.any() else CANNOT if never.any()
               else REPRODUCED)
    unsettled = ", ".join(f"{e:g}" for e in eps[big & ~over & ~never])
    resolved_above = ", ".join(f"{e:g}" for e in eps[settled & above])
    reasons = ([f"lambda_1 resolved above {paper['lambda_below']:g} at settled eps {resolved_above}"]
               if resolved_above else []) + ([f"transient not over at eps {unsettled}"] if unsettled else [])
    reasons += [_c26_cannot(formal, never)] if never.any() else []
    away = formal.attrs["eps_elsewhere"] if "eps_elsewhere" in formal.attrs else []
    return Judgement(
        verdict, units="1/time",
        measured="; ".join(f"eps {e:g}: lambda_1 = {m:.2g} +- {s:.1g}{'' if o else ' (transient not over)'}"
                           for e, m, s, o in zip(eps, lam, err, over)) + _elsewhere(formal, away),
        reason="; ".join(reasons),
        rule=f"at every eps above {paper['eps_above']:g} with its transient over, lambda_1 + {K_SIGMA:g} stderr < "
             f"{paper['lambda_below']:g} (the formal system: m_c = 1 - eps < 0); an eps whose pre-run the settling "
             "rule cannot certify (omega's block means scatter about their trend by rtol or more over its second "
             "half) is not counted: the claim then cannot be reproduced, unless a settled eps differs or another "
             "eps's transient may still end (not yet computed)")


def resolving_cost(rows, sel) -> tuple[np.ndarray, float]:
    """Per row of ``sel`` (a mask over the rows, in their order): the per-replica horizon (time) at which
    polynomial growth fakes less than the measured lambda_1 - K_SIGMA stderr (inf when that is not
    positive), and the wall time (s) of the whole rounds still needed to reach it, priced by the
    row's own rounds (rounds_wall_s per T); NaN cost when the dataset does not record them."""
    lam, err, T, tau = (rows[v].values[sel] for v in ("lambda_1", "stderr", "T", "tau"))
    need = np.array([resolving_horizon(m - K_SIGMA * e, t) for m, e, t in zip(lam, err, tau)])
    if "rounds_wall_s" not in rows or "round_length" not in rows:
        return need, math.nan
    wall, length = rows["rounds_wall_s"].values[sel], rows["round_length"].values[sel]
    more = np.ceil(need / length) * length - T  # whole rounds; inf where no horizon resolves the row
    return need, float(np.sum(wall / T * np.maximum(more, 0.0)))


def _c27_open(rows, first_chaos, unresolved) -> tuple[str, str]:
    """(verdict, reason) of C27 when no regular row below the first chaotic eps decides it: cannot be
    reproduced when resolving the rows there would cost more than the run's stated budget (s)."""
    if not unresolved.any():
        return NOT_YET, ("no row is resolved chaotic" if not finite(first_chaos) else
                         f"no row below the first chaotic eps ({first_chaos:.3g}) is computed here: a route, if "
                         "any, lies below the computed range")
    need, cost = resolving_cost(rows, unresolved)
    budget = float(rows.attrs.get("resolve_budget_s", math.nan))
    text = ((f"the rows below the first chaotic eps ({first_chaos:.3g})" if finite(first_chaos) else
             "no row is resolved chaotic; the rows") + f" are unresolved {at_eps(rows.eps.values[unresolved])}: their "
            f"lambda_1 - {K_SIGMA:g} stderr, as measured, clears {_FAKE} from per-replica horizons {fmt(need, 2)} "
            f"(run: {fmt(rows['T'].values[unresolved], 2)})")
    if not finite(cost):
        return NOT_YET, text
    text += f", about {cost:.3g} s more of their rounds on this machine (each row's rounds' measured wall time per T)"
    if finite(budget) and cost > budget:
        return CANNOT, text + f", above the {budget:g} s the run affords (resolve_budget_s)"
    return NOT_YET, text + (f", within the {budget:g} s the run affords, but not run" if finite(budget) else "")


def c27(paper, rows) -> Judgement:
    """C27, quasi-periodic route to chaos near eps = 0, from lambda_1 (1/time) against eps (the F11 rows,
    or the on-request regime diagram): regular rows below the first chaotic eps must be tori; cannot be
    reproduced when the rows that would decide cost more to resolve than the run affords."""
    order = np.argsort(rows.eps.values)
    rows = rows.isel(eps=order)
    eps, lam, err, status = rows.eps.values, rows.lambda_1.values, rows.stderr.values, rows.status.values
    steady = (rows.transient_over.values == 1) & (rows.steady.values == 1)
    thin = np.asarray(rows.curve_thickness.values) < 0.01
    chaotic = steady & (status == "converged") & (lam - K_SIGMA * err > fake_rates(rows))
    regular = steady & (status == "regular")
    first_chaos = eps[chaotic].min() if chaotic.any() else math.nan
    below = eps < first_chaos if finite(first_chaos) else np.ones(eps.size, bool)

    def listed(sel):
        return at_eps(eps[sel])

    resolved_below = below & regular & chaotic.any()
    if not resolved_below.any():
        verdict, reason = _c27_open(rows, first_chaos, below & ~chaotic & ~regular & (status != "elsewhere"))
    elif np.all(thin[resolved_below]):
        verdict, reason = REPRODUCED, ""
    else:
        verdict, reason = DIFFERS, (f"regular rows below the first chaotic eps ({first_chaos:.3g}) without a thin "
                                    f"P_2pi curve (not a torus) {listed(resolved_below & ~thin)}")
    return Judgement(
        verdict,
        measured=f"{eps.size} eps rows in [{eps.min():.3g}, {eps.max():.3g}]: chaotic (lambda_1 resolved above the "
                 f"polynomial rate) "
                 f"{listed(chaotic)}; regular {listed(regular)}; regular with a thin P_2pi curve "
                 f"{listed(regular & thin)}",
        rule=f"below the smallest chaotic eps (lambda_1 - {K_SIGMA:g} stderr > {_FAKE}), the rows resolved regular "
             "must have a thin P_2pi curve (thickness < 0.01: a torus): reproduced when at least one such row exists "
             "and all have it, differs when one does not; when none is resolved regular, cannot be reproduced if "
             "resolving the unresolved rows there (all rows if none is chaotic) would take more wall time than the "
             "run's resolve_budget_s (the rounds still needed to the horizon where the polynomial rate falls below "
             "lambda_1 - 2 stderr, priced by each row's measured rounds), else not yet computed",
        reason=reason)
