"""A faithful verdict per eps row of the Lyapunov grid (F11; claims C21, C27).

Each row's settled orbit is judged again by the decisive stage's judges (MEGNO and the return map's MEGNO
from one tangent vector, the frequency analysis of omega and the weighted Birkhoff averages;
:mod:`sleighsim.scenes.verdict_decisive`), over realizations: the settled state perturbed at the rounding level
(``common.realization_states``), one lane each.

The judge-power audit ran its known orbits with every time scaled by their period over its ``spike_period``, so
its horizons count cycles. A row is run at the audited settings in its own cycles: T and dt of the block (the
audit's units) times MARGIN x the row's spike period / the record's spike_period, and the record's vote at those
settings (``chaos.power.stage_vote``) says who votes. Its arithmetic is the cheapest of VERDICT_LADDER that
follows the orbit closely enough for every voter (``faithfulness.follows`` with ``indicator_limit`` at what the
voter must resolve; the row's ln G per cycle and Taylor steps per cycle). Each realization is decided by
``chaos.decision.decide_state`` without a first stage; the row's verdict is the realizations' one answer
(``over_realizations``: "fragile" when they differ). Rows below ``eps_min``, rows without a measured spike
period or gauge, and rows no arithmetic of the ladder follows are "not judged" and say why. Times in the flow's
time unit, rates in 1/time."""

from __future__ import annotations

import logging
import math
import time

from sleighsim.chaos.birkhoff import DIG_MIN
from sleighsim.chaos.decision import decide_state, over_realizations
from sleighsim.chaos.faithfulness import FOLLOWS, follows, indicator_follows, indicator_limit, injected_rounding
from sleighsim.chaos.frequency import PRECISION
from sleighsim.chaos.power import stage_vote
from sleighsim.chaos.rule import FRAGILE, TANGENT_BASED
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED
from sleighsim.precision import Precision
from sleighsim.scenes.common import realization_states
from sleighsim.scenes.verdict_decisive import four_judges, what_regular_bounds
from sleighsim.scenes.verdict_decisive_orbits import lane_orbits

log = logging.getLogger("sleighsim")

#: A row the block does not judge (the reason says why).
NOT_JUDGED = "not judged"
#: A row's verdicts in the order of their CF flag values (``row_verdict_flag``).
ROW_VERDICT_FLAGS = (CHAOTIC, REGULAR, UNDECIDED, FRAGILE, NOT_JUDGED)

#: The arithmetics a row's verdict may run in, cheapest first (heyoka's double; engine.ddbatch's lanes).
VERDICT_LADDER = (Precision.DOUBLE, Precision.DOUBLE_DOUBLE)
#: A row runs this many times the audited cycles (its spike period is measured to about a per cent).
MARGIN = 1.1
#: What each voter must resolve for the arithmetic's choice: the Birkhoff averages DIG_MIN digits, the frequency
#: analysis its refinement's precision; the tangent-based judges nothing (``indicator_limit``'s FAITHFUL_MAX).
RESOLVES = {"birkhoff": 10.0 ** -DIG_MIN, "frequency": PRECISION}

#: Written into the grid dataset (attribute row_verdict_rule).
ROW_VERDICT_RULE = (
    "per eps row from verdict.eps_min on: the row's settled state and realizations - 1 copies perturbed at "
    "realization_rel (common.realization_states), each run with one tangent vector over verdict.T x s sampled every "
    f"verdict.dt x s, s = {MARGIN:g} x the row's spike period / the record's spike_period (the judge-power audit's "
    "horizons count cycles: its known orbits ran with every time scaled by their period), in the cheapest of "
    f"{', '.join(p.value for p in VERDICT_LADDER)} that follows the orbit closely enough for every judge that votes "
    "(faithfulness.follows with indicator_limit, the row's ln G and Taylor steps per cycle; double-double at "
    "verdict.tol_dd, double at its machine epsilon); judged by MEGNO, the return map's MEGNO, the frequency analysis "
    "of omega and the Birkhoff averages (scenes.verdict_decisive), each set aside unless the arithmetic follows "
    "closely enough for what it resolved and unless the record lets it vote at the block's settings "
    "(chaos.power.stage_vote); decided per realization (chaos.rule.decide: a tangent-based judge and one without "
    "tangent dynamics must agree, none saying otherwise) and over realizations (chaos.rule.agree: fragile when they "
    "differ). Not judged: rows below eps_min, rows without a spike period or gauge, rows no arithmetic of the ladder "
    "follows.")

#: The row's verdict variables: floats, then texts (each (eps,)), and the realizations' verdicts.
FLOATS = ("row_verdict_agree", "row_lambda_max", "row_bound_T", "row_verdict_wall_s")
TEXTS = ("row_verdict", "row_verdict_reason", "row_verdict_arithmetic")


def not_judged(why: str, arithmetic: str = "", realizations: int = 1) -> dict:
    """A row the block does not judge: NOT_JUDGED, ``why``, the arithmetic it would need (if known)."""
    return {"row_verdict": NOT_JUDGED, "row_verdict_reason": why, "row_verdict_arithmetic": arithmetic,
            "row_verdict_agree": 0.0, "row_lambda_max": math.nan, "row_bound_T": math.nan, "row_verdict_wall_s": 0.0,
            "realization_verdicts": [NOT_JUDGED] * realizations}


def vote_block(vc: dict) -> dict:
    """The verdict settings in the shape ``chaos.power.stage_vote`` reads (a chaos_verdict block's)."""
    return {"decisive": {k: vc[k] for k in ("T", "dt", "megno_samples", "splits")},
            "frequency": {"min_cycles": vc["min_cycles"]}, "sigma": vc["sigma"]}


def cycle_scale(period: float, record: dict) -> float:
    """The factor on the audited settings' times that runs an orbit of spike period ``period`` over MARGIN times
    the judge-power audit's cycles (``record``'s spike_period): MARGIN x period / spike_period."""
    return MARGIN * period / float(record["spike_period"])


def row_dc(vc: dict, precision: Precision, scale: float, spike_factor: float) -> dict:
    """The decisive functions' settings for one row in ``precision``: T and dt of the block times ``scale`` (the
    row's cycles in the audit's), tolerance verdict.tol_dd in double-double, the machine epsilon in double."""
    tol = vc["tol_dd"] if precision is Precision.DOUBLE_DOUBLE else precision.epsilon
    return {"precision": precision, "tol": tol, "T": vc["T"] * scale, "dt": vc["dt"] * scale, "splits": vc["splits"],
            "megno_samples": vc["megno_samples"], "tau": vc["tau"] * scale, "component": "omega",
            "min_cycles": vc["min_cycles"], "spike_factor": spike_factor, "vote_horizon": math.nan}


def row_arithmetic(gauge: dict, voters) -> Precision | None:
    """The cheapest of VERDICT_LADDER that follows the row's orbit closely enough for every judge in ``voters``
    (what each must resolve: RESOLVES), by the row's gauge; None when none does or the gauge is unknown."""
    ln_gain, steps = gauge["row_ln_gain_max"], gauge["row_gain_steps_per_cycle"]
    for p in VERDICT_LADDER:
        if all(follows(ln_gain, p.rounding, indicator_limit(k, RESOLVES.get(k, math.nan)),
                       steps_per_cycle=steps) == FOLLOWS for k in voters):
            return p
    return None


def judged_orbit(orbit: dict, dc: dict, gauge: dict, voters, sigma: float) -> dict:
    """One realization's verdict from its orbit: the four judges, the gauge's gate and the vote's
    (``decide_state``), and what a regular verdict bounds (``what_regular_bounds``)."""
    precision, ln_gain, steps = dc["precision"], gauge["row_ln_gain_max"], gauge["row_gain_steps_per_cycle"]
    gain_rounding = math.exp(ln_gain) * injected_rounding(precision.rounding, steps)
    judged = four_judges(orbit, dc, sigma, gain_rounding, tangent=True)
    arithmetic = dict.fromkeys(judged, precision)
    follows = indicator_follows(ln_gain, arithmetic, {k: judged[k].get("resolved", math.nan) for k in judged},
                                steps_per_cycle=steps)
    out = decide_state({k: judged[k]["verdict"] for k in judged}, tangent_based=TANGENT_BASED, arithmetic=arithmetic,
                       follows=follows, voters=voters, sigma=sigma)
    out["bound"] = what_regular_bounds(judged, out["verdicts"], sigma)
    return out


def _why_not(vc: dict, eps: float, period: float, vote: dict, arithmetic: Precision | None) -> str:
    """Why a row is not judged ("" when it is)."""
    if eps < vc["eps_min"]:
        return f"eps {eps:.4g} below verdict.eps_min = {vc['eps_min']:g}"
    if not (math.isfinite(period) and period > 0):
        return "no spike period measured on the row's orbit: the audit's cycles cannot be counted"
    if not vote["voters"]:
        return "no judge votes: " + "; ".join(dict.fromkeys(vote["why"].values()))
    if arithmetic is None:
        return (f"no arithmetic of {', '.join(p.value for p in VERDICT_LADDER)} is shown to follow its orbit closely "
                "enough for the judges that vote (its gauge)")
    return ""


def judge_row(p, y, eps: float, vc: dict, record: dict, gauge: dict, period: float, spike_factor: float,
              label: str = "") -> dict:
    """The row's verdict (``ROW_VERDICT_RULE``) from its settled state ``y`` at parameters ``p``, its gauge
    (row_ln_gain_max, row_gain_steps_per_cycle) and its spike period (time). Returns the FLOATS and TEXTS of the
    row and its realization_verdicts."""
    n = int(vc["realizations"])
    vote = stage_vote(record, vote_block(vc), "decisive")
    arithmetic = row_arithmetic(gauge, vote["voters"])
    why = _why_not(vc, eps, period, vote, arithmetic)
    if why:
        return not_judged(why, arithmetic.value if arithmetic else "", n)
    start = time.perf_counter()
    dc = row_dc(vc, arithmetic, cycle_scale(period, record), spike_factor)
    starts = [realization_states([list(y)], vc["realization_rel"], r)[0] for r in range(n)]
    log.info("%s: row verdict: %d realizations in %s over T = %.6g (dt %.3g)", label, n, arithmetic.value, dc["T"],
             dc["dt"])
    each = [judged_orbit(o, dc, gauge, vote["voters"], vc["sigma"]) for o in lane_orbits(p, starts, dc, tangent=True)]
    verdict, agree, reason = over_realizations([e["verdict"] for e in each])
    bounds = [e["bound"] for e in each]
    regular = verdict == REGULAR
    log.info("%s: row verdict %s (%s)", label, verdict, reason)
    return {"row_verdict": verdict, "row_verdict_arithmetic": arithmetic.value,
            "row_verdict_reason": f"{reason}; realization 0: {each[0]['reason']}" + (
                f"; {bounds[0]['text']}" if regular else ""),
            "row_verdict_agree": float(agree),
            "row_lambda_max": max(b["lambda_max"] for b in bounds) if regular else math.nan,
            "row_bound_T": min(b["T"] for b in bounds) if regular else math.nan,
            "row_verdict_wall_s": time.perf_counter() - start, "realization_verdicts": [e["verdict"] for e in each]}
