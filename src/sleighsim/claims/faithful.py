"""The ledger's faithful columns: each chaos claim judged from a quantity computed in an arithmetic that
follows the claim's orbit (``faithful_value``, ``faithful_arithmetic``, ``faithful_verdict``).

Double does not follow the steady state at eps = 0.1 (the gauge of chaos_verdict); double-double does, and
the decisive stage decides that state there (``decisive_*`` of chaos_verdict, its realizations agreeing or
not). A claim about that state takes its faithful answer from that decision; a claim about the rows of
F11 from each row's own gauge (the grid dataset's ``lambda_1_follows``, ``faithful_arithmetic``); a claim on the
paper's own transient from the trigger law (does the time move with the integration error at the finest
errors measured?); F10's energy labels from the exact time-scaling law (lambda_1 scales as sqrt(E / E0),
the horizon as its inverse). A claim whose quantity no arithmetic that follows its orbit has computed
reads "not yet computed", naming the arithmetic it needs and its price at the decisive stage's measured
cost per time unit. The rule of each is :data:`FAITHFUL_RULE`; the datasets each reads,
:data:`sleighsim.claims.evidence.FAITHFUL`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sleighsim.chaos.faithfulness import FAITHFUL_MAX, FOLLOWS
from sleighsim.chaos.rule import FRAGILE, agree
from sleighsim.claims.judges.steady_state import PATH_RULE, path_verdict
from sleighsim.claims.rules import CANNOT, DIFFERS, K_SIGMA, NOT_YET, REPRODUCED, SLIGHT, fmt, severity
from sleighsim.precision import Precision
from sleighsim.scenes.formal_gauge import FLOATS, TEXTS, not_gauged
from sleighsim.scenes.grid_verdict import NOT_JUDGED

#: faithful_verdict of a claim whose own datasets are computed in an arithmetic that follows their orbits:
#: the ledger puts the row's own verdict in its place.
OWN = "own"


class InLadder:
    """The faithful judge of a claim whose datasets the config ladders up to an arithmetic that may follow
    their orbits: the ledger judges the claim again, with its own judge, on the datasets of the finest precision
    of the ladder, when that ladder's gauge (data/ladder/<scene>.nc, follows_orbit) says it follows each."""


#: The marker of :class:`InLadder` in FAITHFUL_JUDGES.
IN_LADDER = InLadder()

#: Written into the ledger (attribute faithful_rule).
FAITHFUL_RULE = (
    "faithful_verdict: a claim whose datasets the config ladders (C15, C16, C17, C22: F9's maps; C23, C24: F13's and "
    "F14's spectra) by its own judge on the finest precision of the ladder when the ladder's gauge (per spike cycle, "
    "or over the data's whole window where no cycle completes in it) says that arithmetic follows every one of "
    "their orbits (not yet computed otherwise); C18 from the mean divergence over whole spike cycles "
    f"of the decisive orbit of the state at eps = 0.1 in each realization (contracts when the mean plus {K_SIGMA:g} "
    "sigma is below 0, sigma its windows' standard error and quadrature error; all contract: reproduced, none: "
    "differs, some: fragile); C14 by its own rule on the path of each realization's decisive orbit (all bounded and "
    "not periodic: reproduced, none: differs, some: fragile); a claim on the steady state at eps = 0.1 (C19) "
    "from the state chaos_verdict decides in the arithmetic that follows it (the decisive stage, every "
    "realization): a regular state makes a positive exponent differ (by the size of the paper's value over the "
    "exponent bound), a fragile state is fragile, a chaotic or undecided one leaves it not yet computed; F10's "
    "labels (C20) by the exact time-scaling law from that state; F11's rows (C21, C27) each by its own verdict where "
    "the grid judged it regular (scenes.grid_verdict: its exponent bound, in place of double's lambda_1), else in "
    "the arithmetic its own gauge accepts, or, where the row's orbit is a state the chaos verdict decided regular "
    "(same eps and settled state), that state's exponent bound (a followed or decided row's lambda_1 at or below "
    "the paper's floor differs, every row followed and above it reproduces, a row not followed leaves it not yet "
    "computed); "
    "a time on the paper's own transient (C13) cannot be reproduced when it still moves with the integration "
    "error (slope beyond 2 standard errors) at the finest errors the trigger law measured; the rows of C26 (not "
    "gauged) are not yet computed, with the digits an arithmetic needs to follow each positive-exponent orbit over "
    "its horizon (lambda_1 T / ln 10 + 3, a lower bound)."
)


@dataclass(frozen=True)
class Faithful:
    """A claim's faithful columns: its value (text from measured numbers), the arithmetic it was computed in
    (or needs), the verdict."""

    value: str
    arithmetic: str
    verdict: str


@dataclass(frozen=True)
class Decided:
    """A state of chaos_verdict as the decisive stage left it: the verdict over its realizations, the exponent
    bound and its horizon ``T`` (NaN without a bound), the arithmetic and its gauge, the measured cost per time
    unit of one lane (s) and the stage's ``horizon`` (time units)."""

    state: str
    verdict: str
    agreeing: int
    realizations: int
    lambda_max: float
    T: float
    bound: str
    arithmetic: str
    cost: float
    horizon: float

    def answer(self) -> str:
        """The state's verdict in words, with its arithmetic, realizations and exponent bound."""
        return f"{self.state} is {self.verdict} in {self.arithmetic} ({self.agreeing} of {self.realizations} " \
               f"realizations agree; {self.bound})"

    def price(self, T: float) -> str:
        """The price of one orbit over ``T`` (s)."""
        return f"about {self.cost * T:.0f} s over T = {T:.3g}"

    def rate(self) -> str:
        """Where the price per time unit comes from."""
        return (f"priced at the decisive stage's measured {self.cost:.2g} s per time unit of one lane with a "
                f"tangent vector")


def decided(verdicts, state: str = "main") -> Decided:
    """``state`` of the chaos_verdict dataset ``verdicts`` as its decisive stage decided it."""
    s = verdicts.sel(state=state)
    gain = float(s.decisive_log10_gain_rounding)
    return Decided(state, str(s.verdict.values), int(s.n_realizations_agreeing),
                   int(verdicts.attrs["n_realizations"]), float(s.decisive_lambda_max), float(s.decisive_bound_T),
                   str(s.decisive_bound_text.values),
                   f"{verdicts.attrs['decisive_precision']} (G x rounding 10^{gain:.1f} on {state}'s orbit)",
                   float(s.decisive_wall_time_s) / float(verdicts.attrs["decisive_T"]),
                   float(verdicts.attrs["decisive_T"]))


def _unsettled(d: Decided) -> Faithful:
    """The answer for a claim on a state that is not regular: fragile, or not yet computed."""
    why = "its realizations disagree" if d.verdict == FRAGILE else "the exponent's value is not measured there"
    return Faithful(f"{d.answer()}: {why}", d.arithmetic, FRAGILE if d.verdict == FRAGILE else NOT_YET)


def against_regular(d: Decided, paper_lambda: float, what: str, bound: float | None = None) -> Faithful:
    """A claim of chaos (``what``, the paper's exponent ``paper_lambda``, 1/time; NaN: none stated) on the
    decided state ``d``: a regular state differs by (paper - bound) / paper, at least "differs" (``bound``: the
    exponent bound compared, d's own when None)."""
    if d.verdict != "regular":
        return _unsettled(d)
    bound = d.lambda_max if bound is None else bound
    gap = (paper_lambda - bound) / paper_lambda if np.isfinite(paper_lambda) else np.nan
    verdict = severity(DIFFERS, gap) if np.isfinite(gap) and gap >= SLIGHT else DIFFERS
    return Faithful(f"{d.answer()}: {what}", d.arithmetic, verdict)


def needs(d: Decided, what: str, T: float | None = None) -> Faithful:
    """A quantity on ``d``'s orbit that its faithful arithmetic has not computed: what it needs, at what price."""
    return Faithful(f"not computed: needs {what} ({d.price(T or d.horizon)}; {d.rate()})", d.arithmetic.split(" (")[0],
                    NOT_YET)


def finest_range(trigger) -> tuple[float, float, str, bool]:
    """The trigger law's finest range of integration errors: the first spike's local slope there and its standard
    error (time units per decade), its label, and whether it still moves (slope beyond 2 standard errors)."""
    slope, err = float(trigger.range_slope.values[-1]), float(trigger.range_slope_stderr.values[-1])
    return slope, err, str(trigger.range_label.values[-1]), abs(slope) > 2 * err


def spike_time(paper, trigger) -> Faithful:
    """C13: a spike time on the paper's own transient, from the trigger law (first spike against the
    integration error; the local slope of its finest range, time units per decade)."""
    first, tol = trigger.first_spike.values, trigger.tol.values
    ok = trigger.saturated.values == 0
    slope, err, label, moving = finest_range(trigger)
    lo, hi = fmt(np.nanmin(first[ok]), 4), fmt(np.nanmax(first[ok]), 4)
    text = (f"the first spike at t = {lo} to {hi} over integration errors {tol[ok].max():.0e} to "
            f"{tol[ok].min():.0e} ({int(ok.sum())} unsaturated runs); at the finest range "
            f"({label}) it moves {slope:.0f} +- {err:.0f} time units per decade")
    if moving:
        return Faithful(text + ": down to the finest error measured the spike's time is set by the integration "
                        "error, so the data give no time for the exact orbit", f"none converges (finest: {label})",
                        CANNOT)
    return Faithful(text + ": it no longer moves; its time is not compared with the paper's", label, NOT_YET)


def energy_labels(paper, energy, verdicts) -> Faithful:
    """C20 (F10): lambda_1 against the energy label, by the exact time-scaling law from the decided state
    (lambda_1 ~ sqrt(E / E0), the horizon ~ sqrt(E0 / E)); no label is checked directly."""
    d = decided(verdicts)
    if d.verdict != "regular":
        return _unsettled(d)
    E, E0 = energy.label.values, float(verdicts.attrs["energy_label"])
    bounds = d.lambda_max * np.sqrt(E / E0)
    inside = (E >= paper["label_min"] * (1 - 1e-9)) & (E <= paper["label_max"] * (1 + 1e-9))
    lowest = float(bounds[inside][np.argmin(E[inside])]) if inside.any() else np.nan
    listed = ", ".join(f"{b:.2g} at E = {e:.3g}" for e, b in zip(E, bounds))
    what = (f"by the exact time-scaling law every label's state is that torus, regular; lambda_1 <= {listed} "
            f"(not checked directly at any label)")
    return against_regular(d, paper["smallest"], what, bound=lowest)


#: A row of F11 is a state chaos_verdict decided when its eps is the verdict's and its settled state the state's
#: to this relative tolerance (both settle the same start over the same pre-run in double).
SAME_STATE = 1e-12


def decided_rows(grid, verdicts) -> dict[int, Decided]:
    """The rows of ``grid`` whose orbit is a state chaos_verdict decided (``SAME_STATE``; the grid's rows are at
    b = 1 and K2 = 1 + eps): row index -> that state's decision."""
    if "row_settled_state" not in grid or "settled_state" not in verdicts or "param_K2" not in verdicts.attrs:
        return {}  # nothing to match: every row keeps its own gauge
    eps, K2 = float(verdicts.attrs["param_eps"]), float(verdicts.attrs["param_K2"])
    if abs(K2 - (1 + eps)) > SAME_STATE:
        return {}
    out = {}
    for i in np.flatnonzero(np.isclose(grid.eps.values, eps, rtol=SAME_STATE, atol=0.0)):
        row = grid.row_settled_state.values[i]
        for state in verdicts.state.values:
            y = verdicts.settled_state.sel(state=state).values
            if np.all(np.abs(row - y) <= SAME_STATE * np.maximum(np.abs(y), 1e-300)):
                out[int(i)] = decided(verdicts, str(state))
    return out


def grid_rows(paper, grid, verdicts) -> Faithful:
    """C21 (F11): lambda_1 > the paper's floor on every eps row, each row in the arithmetic its gauge accepts, or,
    for a row whose orbit is a state chaos_verdict decided regular (``decided_rows``), that state's exponent bound
    in its arithmetic: a row so bounded at or below the floor differs; all followed and above reproduce; else not
    yet computed."""
    d = decided(verdicts)
    eps, lam, err = grid.eps.values, grid.lambda_1.values.copy(), grid.stderr.values.copy()
    here = grid.status.values != "elsewhere"
    judged = row_verdicts(grid)
    own = judged == "regular"  # the row's own verdict in its arithmetic: its bound, not double's lambda_1
    followed = here & (grid.lambda_1_follows.values == FOLLOWS) & ~own
    shown = [f"eps {e:.3g}: {fmt(v, 2)} +- {fmt(s, 1)}" for e, v, s in zip(eps[followed], lam[followed],
                                                                            err[followed])]
    arith = {str(a) for a in grid.faithful_arithmetic.values[here & ~followed & ~own]}
    arith |= {"double"} if followed.any() else set()
    for i, s in decided_rows(grid, verdicts).items():
        if here[i] and not followed[i] and not own[i] and s.verdict == "regular":
            followed[i], lam[i], err[i] = True, s.lambda_max, 0.0
            shown.append(f"eps {eps[i]:.3g}: the state {s.state} ({s.answer()})")
            arith.add(s.arithmetic.split(" (")[0])
    if own.any():
        followed |= own
        lam[own], err[own] = grid.row_lambda_max.values[own], 0.0
        arith |= {str(a) for a in grid.row_verdict_arithmetic.values[own]}
    shown += [_row_verdict_text(grid, i) for i in np.flatnonzero(judged != "")]
    value = (f"lambda_1 where the row's arithmetic follows it: {'; '.join(shown)}" if followed.any() else
             "no row's lambda_1 is computed in an arithmetic that follows it")
    value += _row_needs(grid, here & ~followed, d)
    low = followed & ~(lam - 2 * err > paper["smallest_above"])
    verdict = DIFFERS if low.any() else REPRODUCED if followed[here].all() else NOT_YET
    return Faithful(value, f"per row: {'; '.join(sorted(arith))}", verdict)


def row_verdicts(grid) -> np.ndarray:
    """Each row's own verdict where the grid judged it (``scenes.grid_verdict``: chaotic, regular, undecided or
    fragile), "" where it did not (not judged, or a grid without row verdicts)."""
    if "row_verdict" not in grid:
        return np.full(grid.eps.size, "", dtype=object)
    v = np.asarray(grid.row_verdict.values, dtype=object)
    return np.where(v == NOT_JUDGED, "", v)


def _row_verdict_text(grid, i: int) -> str:
    """A judged row's verdict in words: verdict, arithmetic, realizations agreeing, reason."""
    g = grid.isel(eps=i)
    return (f"eps {float(g.eps):.3g}: {g.row_verdict.values} in {g.row_verdict_arithmetic.values} "
            f"({g.row_verdict_reason.values})")


def _row_needs(grid, rows, d: Decided) -> str:
    """The rows not followed: the arithmetic each needs and its price. Where the grid judged rows of its own
    (``row_verdict_cost``), the price of the row's verdict; else one orbit over the decisive horizon scaled to
    the row (T x reference_eps / eps) at the decisive stage's cost."""
    if not rows.any():
        return ""
    per_step = row_verdict_cost(grid)
    if np.isfinite(per_step):
        steps = grid.row_gain_steps_per_cycle.values
        parts = [f"eps {grid.eps.values[i]:.3g} needs {grid.faithful_arithmetic.values[i]}"
                 + (f" (about {per_step * steps[i]:.0f} s for its verdict)" if np.isfinite(steps[i]) else "")
                 for i in np.flatnonzero(rows)]
        return ("; not computed: " + "; ".join(parts) + " (priced by the judged rows' measured wall time per step "
                "of a spike cycle, times the row's steps per cycle: the verdict runs as many cycles on every row)")
    s = float(grid.attrs["reference_eps"]) / grid.eps.values[rows]
    parts = [f"eps {e:.3g} needs {a}" + (f" ({d.price(d.horizon * k)})" if "unknown" not in str(a) else "")
             for e, a, k in zip(grid.eps.values[rows], grid.faithful_arithmetic.values[rows], s)]
    return "; not computed: " + "; ".join(parts) + f" ({d.rate()}, over the decisive horizon x reference_eps / eps)"


def row_verdict_cost(grid) -> float:
    """Seconds of a row's verdict per step of one spike cycle (the gauge's steps per cycle in double): the
    median over the rows the grid judged of their wall time over their steps per cycle. Every row's verdict
    runs the same number of cycles (``scenes.grid_verdict``), so a row's price is this times its steps per
    cycle. NaN when the grid judged no row."""
    if "row_verdict_wall_s" not in grid:
        return float("nan")
    wall, steps = grid.row_verdict_wall_s.values, grid.row_gain_steps_per_cycle.values
    ran = (row_verdicts(grid) != "") & (wall > 0) & np.isfinite(steps)
    return float(np.median(wall[ran] / steps[ran])) if ran.any() else float("nan")


def route(paper, grid, verdicts) -> Faithful:
    """C27: the route to chaos near eps = 0 needs the rows nearest 0 followed: not yet computed while the
    smallest computed eps row is not."""
    out = grid_rows({"smallest_above": 0.0}, grid, verdicts)
    here = grid.status.values != "elsewhere"
    nearest = np.argmin(np.where(here, grid.eps.values, np.inf))
    ok = here.all() and (grid.lambda_1_follows.values == FOLLOWS).all()
    if str(grid.lambda_1_follows.values[nearest]) != FOLLOWS:
        return Faithful(out.value + f"; the row nearest eps = 0 (eps {grid.eps.values[nearest]:.3g}) is not followed",
                        out.arithmetic, NOT_YET)
    return Faithful(out.value, out.arithmetic, OWN if ok else NOT_YET)


def exponents(paper, verdicts) -> Faithful:
    """C19: the paper's exponent spectrum, its largest positive, against the decided state's bound."""
    return against_regular(decided(verdicts), float(np.max(paper["exponents"])),
                           "its largest exponent is bounded as stated, against the paper's positive one")


def contracts(mean, sigma):
    """C18's rule per realization: the flow contracts where its mean divergence plus K_SIGMA sigma is below 0
    (``mean``, ``sigma``: arrays, 1/time). Its power and false rate on orbits of known mean divergence:
    ``claims.volume_power``."""
    return np.asarray(mean, float) + K_SIGMA * np.asarray(sigma, float) < 0


def volume(paper, verdicts, state: str = "main") -> Faithful:
    """C18: the flow contracts phase-space volume on ``state``'s orbit. Each realization's mean divergence over
    the decisive orbit's whole cycles (``analysis.volume``; sigma: its windows' standard error and the quadrature
    error in quadrature): it contracts when mean + K_SIGMA sigma < 0. Every realization contracting reproduces,
    none differs, some fragile; without the stage's divergence, not yet computed."""
    d = decided(verdicts, state)
    name = "realization_decisive_mean_divergence"
    if name not in verdicts:
        return needs(d, f"the mean divergence over {state}'s orbit in double-double")
    s = verdicts.sel(state=state)
    mean = s[name].values
    sigma = np.hypot(s["realization_decisive_mean_divergence_stderr"].values,
                     s["realization_decisive_mean_divergence_quadrature"].values)
    cycles = s["realization_decisive_divergence_cycles"].values
    if not np.isfinite(mean).all() or not np.isfinite(sigma).all():
        return needs(d, "the mean divergence over whole spike cycles of every realization (some had too few spikes)")
    shrinks = contracts(mean, sigma)
    bound = float(np.max(np.abs(mean) + K_SIGMA * sigma))
    listed = "; ".join(f"realization {r}: {m:.2g} +- {e:.2g} over {c:.0f} cycles"
                       for r, (m, e, c) in enumerate(zip(mean, sigma, cycles)))
    text = (f"mean divergence (the sum of the exponents) over whole spike cycles of {state}'s orbit in "
            f"{d.arithmetic}: {listed}; ")
    verdict = _over_realizations(shrinks)
    expands = int(np.sum(contracts(-mean, sigma)))
    why = {REPRODUCED: f"every realization contracts ({K_SIGMA:g} sigma)",
           FRAGILE: f"{int(shrinks.sum())} of {shrinks.size} realizations contract",
           DIFFERS: f"the flow expands on average in {expands} of {mean.size} realizations" if expands else
           f"no contraction resolved: |mean divergence| <= {bound:.2g} ({K_SIGMA:g} sigma)"}[verdict]
    return Faithful(text + why, d.arithmetic, verdict)


def _over_realizations(holds) -> str:
    """A claim's faithful verdict from whether it holds in each realization (``chaos.rule.agree``): reproduced when
    it holds in every one, differs when in none, fragile otherwise."""
    return agree([REPRODUCED if h else DIFFERS for h in holds])[0]


def plane_path(paper, verdicts, state: str = "main") -> Faithful:
    """C14: the path of ``state``'s orbit is bounded and not periodic, by the double judge's rule
    (``judges.steady_state.path_verdict``) on each realization's decisive orbit (its path from the orbit's samples,
    ``analysis.path``): every realization's path bounded and not periodic reproduces, none differs, some fragile;
    without the stage's path, not yet computed."""
    d = decided(verdicts, state)
    if "realization_decisive_path_growth" not in verdicts:
        return needs(d, f"the path (x, y) of {state}'s orbit in double-double")
    s = verdicts.sel(state=state)
    growth, reach = s.realization_decisive_path_growth.values, s.realization_decisive_path_reach.values
    recurrence = s.realization_decisive_path_recurrence.values
    if not np.isfinite(np.r_[growth, recurrence]).all():
        return needs(d, "the path of every realization over at least three times the shortest lag")
    ok = [all(path_verdict(g, r)) for g, r in zip(growth, recurrence)]
    listed = "; ".join(f"realization {k}: its reach grows by {g:.3f} over the second half, reaching {x:.3g}, and "
                       f"never repeats to better than {r:.2g} of its size" for k, (g, x, r)
                       in enumerate(zip(growth, reach, recurrence)))
    text = f"the path of {state}'s orbit over T = {float(verdicts.attrs['decisive_T']):.3g} in {d.arithmetic}: {listed}"
    return Faithful(text + f" ({PATH_RULE})", d.arithmetic, _over_realizations(ok))


def digits_to_follow(lam: float, T: float) -> float:
    """The decimal digits an arithmetic needs to follow an orbit of exponent ``lam`` (1/time) over ``T``: the
    tangent map grows by at least e^(lam T), so G x rounding < FAITHFUL_MAX needs rounding below
    FAITHFUL_MAX e^(-lam T) (the Taylor steps' count, which only adds digits, left out: a lower bound)."""
    return lam * T / math.log(10) - math.log10(FAITHFUL_MAX)


def _formal_row_text(e: float, m: float, t: float, arithmetic: str, need: float, price: str, ln_gain: float) -> str:
    """One row of C26's faithful value: lambda_1 in double and what its gauge says (or, not gauged, the digits a
    positive lambda_1 asks for over T: ``digits_to_follow``)."""
    head = f"eps {e:g}: lambda_1 = {m:.2g} in double over T = {t:.3g}"
    if not arithmetic:
        return head + (f", so an arithmetic follows its orbit over T only with at least {digits_to_follow(m, t):.0f} "
                       "decimal digits (not gauged)" if m > 0 else " (not gauged)")
    if math.isfinite(need):
        return (f"{head}; its gauge: ln G up to {ln_gain:.3g} per spike cycle, followed by {arithmetic}; an arithmetic "
                f"needs unit roundoff below 1e{need:.0f} to follow it: {price}")
    return f"{head}; its gauge: {arithmetic}" + (f" follows it (ln G up to {ln_gain:.3g} per spike cycle)"
                                                 if math.isfinite(ln_gain) else "")


def _gauged(formal):
    """The formal dataset with its rows' gauge variables; one written before the gauge existed has every row not
    gauged (``scenes.formal_gauge.not_gauged``)."""
    if "faithful_arithmetic" in formal:
        return formal
    blank = not_gauged()
    return formal.assign({v: ("eps", np.full(formal.eps.size, blank[v], dtype=object if v in TEXTS else float))
                          for v in (*FLOATS, *TEXTS)})


def formal_rows(paper, formal) -> Faithful:
    """C26: lambda_1 below the paper's bound for eps above its threshold, computed in double (the formal system).
    Each row above it is read by its gauge (``scenes.formal_gauge``: the cheapest arithmetic that follows its
    orbit, or the rounding one would need and its measured price): double following every row keeps the row's own
    verdict; otherwise not yet computed, with the arithmetic each row needs and its price (a row not gauged: the
    digits its positive lambda_1 asks for over T, ``digits_to_follow``, a lower bound)."""
    eps, lam, T = formal.eps.values, formal.lambda_1.values, formal.T.values
    big = eps > paper["eps_above"]
    if not big.any():
        return Faithful("not computed: no eps above the paper's threshold computed", "unknown (no row)", NOT_YET)
    g = _gauged(formal)
    arith, need, price, ln_gain = (g[v].values for v in ("faithful_arithmetic", "gauge_needed_log10_rounding",
                                                          "faithful_price", "row_ln_gain_max"))
    rows = np.flatnonzero(big)
    parts = [_formal_row_text(eps[i], lam[i], T[i], str(arith[i]), need[i], str(price[i]), ln_gain[i]) for i in rows]
    if all(str(arith[i]) == Precision.DOUBLE.value for i in rows):
        return Faithful("; ".join(parts) + ": double follows every row, so lambda_1's verdict in double stands",
                        Precision.DOUBLE.value, OWN)
    named = sorted({str(arith[i]) for i in rows if str(arith[i])})
    digits = max((digits_to_follow(lam[i], T[i]) for i in rows if lam[i] > 0 and not str(arith[i])), default=math.nan)
    unpriced = [f"none affordable (at least {digits:.0f} digits over T)"] if math.isfinite(digits) else []
    return Faithful("not computed: " + "; ".join(parts), "; ".join(named + unpriced) or "unknown (not gauged)",
                    NOT_YET)


#: Claim id -> its faithful judge (the paper's values, then the datasets of evidence.FAITHFUL).
FAITHFUL_JUDGES = {
    "C13": spike_time,
    "C14": plane_path,
    "C15": IN_LADDER,
    "C16": IN_LADDER,
    "C17": IN_LADDER,
    "C18": volume,
    "C19": exponents,
    "C20": energy_labels,
    "C21": grid_rows,
    "C22": IN_LADDER,
    "C23": IN_LADDER,
    "C24": IN_LADDER,
    "C26": formal_rows,
    "C27": route,
}
