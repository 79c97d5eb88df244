"""The decision rule: one verdict per state from the indicators' verdicts, and the state's class.

``decide`` combines the judges' (verdict, reason) pairs by ``DECISION_RULE``, telling the
tangent-based indicators (``TANGENT_BASED``, ``tangent``) from those without tangent dynamics
(``orbits``, ``frequency``); ``precision_gate`` and ``consistent`` can only turn a chaotic verdict
undecided; ``classify`` names the class of a state of the reversible system. Rates in 1/time (the
flow's own time unit); ``sigma`` counts standard errors.
"""

from __future__ import annotations

import math

from sleighsim.chaos.faithfulness import FOLLOWS
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED, VERDICTS

# written into the chaos_verdict dataset (attribute rule, with ``consistent``'s docstring)
DECISION_RULE = (
    "chaotic (regular) only if at least one tangent-based indicator and at least one indicator "
    "without tangent dynamics say chaotic (regular) and no indicator says regular (chaotic); "
    "otherwise undecided; the 0-1 test is not part of this rule"
)

# names under which the 0-1 test might be handed to ``decide``; it is excluded by the rule
_ZERO_ONE_NAMES = {"0-1", "01", "0_1", "zero_one", "zero-one", "zeroone", "z01", "01test", "0-1 test",
                   "zero_one_test", "0-1-test", "test01", "test_01"}

INDICATORS = ("benettin", "ftle", "megno", "two_trajectory", "loschmidt", "frequency")
TANGENT_BASED = ("benettin", "ftle", "megno", "section_megno")


def decide(verdicts, tangent_based):
    """Combine per-indicator verdicts by ``DECISION_RULE``.

    ``verdicts``: {name: (verdict, reason)}; ``tangent_based``: names of the indicators
    that use tangent dynamics (all others count as indicators without). The 0-1 test is
    refused. Returns (verdict, reason, DECISION_RULE)."""
    if not isinstance(verdicts, dict) or not verdicts:
        raise ValueError("verdicts must be a non-empty dict {name: (verdict, reason)}")
    tangent_based = set(tangent_based)
    by = {CHAOTIC: [], REGULAR: [], UNDECIDED: []}
    for name, item in verdicts.items():
        key = str(name).strip().lower().replace(" ", "")
        if key in {z.replace(" ", "") for z in _ZERO_ONE_NAMES}:
            raise ValueError(f"verdicts: {name!r} looks like the 0-1 test, which is not part of this rule")
        try:
            v, _reason = item
        except (TypeError, ValueError):
            raise ValueError(f"verdicts[{name!r}] must be a (verdict, reason) pair") from None
        if v not in VERDICTS:
            raise ValueError(f"verdicts[{name!r}] = {v!r} is not one of {VERDICTS}")
        by[v].append(name)

    def names(lst):
        return ", ".join(sorted(map(str, lst))) or "none"

    tail = f"undecided: {names(by[UNDECIDED])}"
    if by[CHAOTIC] and by[REGULAR]:
        return (UNDECIDED, f"indicators disagree: chaotic: {names(by[CHAOTIC])}; regular: {names(by[REGULAR])}; {tail}",
                DECISION_RULE)
    for v in (CHAOTIC, REGULAR):
        if not by[v]:
            continue
        tan = [k for k in by[v] if k in tangent_based]
        non = [k for k in by[v] if k not in tangent_based]
        if tan and non:
            return v, (f"{v}: tangent-based {names(tan)}; without tangent dynamics {names(non)}; "
                       f"none says otherwise; {tail}"), DECISION_RULE
        missing = "a tangent-based indicator" if not tan else "an indicator without tangent dynamics"
        return UNDECIDED, f"only {names(by[v])} say {v}; missing: {missing} saying {v}; {tail}", DECISION_RULE
    return UNDECIDED, f"no indicator reached a verdict ({tail})", DECISION_RULE


def precision_gate(verdicts: dict, ld: dict) -> None:
    """Turn the tangent-based chaotic verdicts (``TANGENT_BASED``) in ``verdicts`` undecided, in place,
    unless the long-double precision check ``ld`` confirmed exponential growth (``ld["check"]``)."""
    if ld["check"] != "confirmed":
        for k in TANGENT_BASED:
            if k in verdicts and verdicts[k][0] == CHAOTIC:
                verdicts[k] = (UNDECIDED, f"{ld['reason']}; in double precision: {verdicts[k][1]}")


#: What ``faithful_gate`` does (the text a dataset records for the rule).
FAITHFUL_RULE = (
    "every indicator's verdict is set aside (becomes undecided, naming the arithmetic) unless the faithfulness "
    "gauge shows that the arithmetic it was judged in follows the state's orbit closely enough for it (G x the "
    "rounding injected per cycle below the indicator's limit, chaos.faithfulness.indicator_limit); a gauge that "
    "measured nothing (unknown) or gave no answer for the indicator sets it aside too"
)


def faithful_gate(verdicts: dict, arithmetic: dict, follows: dict) -> list[str]:
    """Set aside, in place, every indicator whose verdict was judged in an arithmetic not shown to follow
    the state's orbit closely enough for that indicator (the faithfulness gauge,
    ``sleighsim.chaos.faithfulness``: G x the rounding injected per spike cycle below the indicator's own
    limit, ``faithfulness.indicator_limit``): a chaotic or regular verdict becomes undecided, naming the
    arithmetic, unless the gauge's answer for it is "follows". The gauge fails closed: "unknown" (no
    complete cycle measured) and a missing answer set the verdict aside too. ``arithmetic``: indicator ->
    the arithmetic its verdict was judged in; ``follows``: indicator -> the gauge's answer for it. Returns
    the names set aside."""
    aside = []
    for name, (v, reason) in list(verdicts.items()):
        answer = follows.get(name, "no answer")
        if v != UNDECIDED and answer != FOLLOWS:
            verdicts[name] = (UNDECIDED, f"set aside: judged in {arithmetic.get(name, 'an unnamed arithmetic')}, "
                                         f"which the faithfulness gauge does not show to follow this orbit closely "
                                         f"enough for {name} ({answer}); it said {v}: {reason}")
            aside.append(name)
    return aside


#: What ``vote_gate`` does (the text a dataset records for the rule).
VOTE_RULE = (
    "only a judge that votes at the run's horizon counts: one whose wrong-verdict rate, measured by the "
    "judge-power audit on independent orbits of known class with the same estimator and settings at an audited "
    "horizon no longer than the run's, has a one-sided 95% Clopper-Pearson upper bound of at most 5% on tori and "
    "on chaotic orbits alike (chaos.power.stage_vote); every other indicator's verdict becomes undecided"
)


def vote_gate(verdicts: dict, voters: set) -> list[str]:
    """Set aside, in place, the verdict of every indicator that does not vote (``voters``, from
    ``sleighsim.chaos.power.stage_vote``: the judge-power audit measured its wrong-verdict rate, on
    independent orbits of known class with the same estimator and settings at an audited horizon no longer
    than the run's, with a one-sided 95% upper bound of at most 5% on tori and on chaotic orbits alike): a
    chaotic or regular verdict of any other indicator (one the audit did not measure included) becomes
    undecided, naming why. Returns the names set aside."""
    aside = []
    for name, (v, reason) in list(verdicts.items()):
        if v != UNDECIDED and name not in voters:
            verdicts[name] = (UNDECIDED, f"does not vote (the judge-power record does not bound its wrong-verdict "
                                         f"rate by 5% on every class at this horizon, or did not audit this "
                                         f"estimator); it said {v}: {reason}")
            aside.append(name)
    return aside


#: What ``consistent`` does (the text a dataset records for the rule; its docstring says the same).
CONSISTENCY_RULE = (
    'Indicators that agree on "chaotic" must also agree on the rate: when the tangent-based lambda_1 (a) and the '
    'rate of an indicator without tangent dynamics that says chaotic (others: name -> (rate, stderr)) differ by '
    'more than sigma combined standard errors and by more than a factor 2, the verdict is "undecided" (one of '
    'them is biased).'
)


def consistent(verdict: str, reason: str, rate_a: float, err_a: float, others: dict, sigma: float) -> tuple[str, str]:
    """Indicators that agree on "chaotic" must also agree on the rate: when the tangent-based lambda_1
    (a) and the rate of an indicator without tangent dynamics that says chaotic (others: name ->
    (rate, stderr)) differ by more than sigma combined standard errors and by more than a factor 2,
    the verdict is "undecided" (one of them is biased)."""
    if verdict != CHAOTIC:
        return verdict, reason
    for name, (rate_b, err_b) in others.items():
        gap = abs(rate_a - rate_b)
        if gap > sigma * math.hypot(err_a, err_b) and max(rate_a, rate_b) > 2 * min(rate_a, rate_b):
            return UNDECIDED, (f"the indicators say chaotic but disagree on the rate: lambda_1 = {rate_a:.3g} "
                               f"+- {err_a:.2g} against {rate_b:.3g} +- {err_b:.2g} from {name}; {reason}")
    return verdict, reason


#: What ``classify`` does (the text a dataset records for the rule; its docstring says the same).
CLASS_RULE = (
    'The class of a state of a reversible system: regular; chaotic with the sum of exponents resolved negative ->'
    ' "strange attractor" (its R-image a repeller when R sends it away), with the sum within sigma stderr of 0 '
    'and lambda_1 about -lambda_4 -> "conservative-type chaos" when its R-image stays on the state\'s image, '
    '"mixed dynamics" when it leaves; "undetermined" otherwise.'
)


def classify(verdict: str, sum_all: float, sum_err: float, l1: float, l4: float, r_image: str, sigma: float) -> str:
    """The class of a state of a reversible system: regular; chaotic with the sum of exponents resolved
    negative -> "strange attractor" (its R-image a repeller when R sends it away), with the sum within
    sigma stderr of 0 and lambda_1 about -lambda_4 -> "conservative-type chaos" when its R-image stays
    on the state's image, "mixed dynamics" when it leaves; "undetermined" otherwise."""
    if verdict == REGULAR:
        return "regular"
    if verdict != CHAOTIC or not all(math.isfinite(v) for v in (sum_all, sum_err, l1, l4)):
        return "undetermined"
    if sum_all + sigma * sum_err < 0:
        return "strange attractor"
    if abs(sum_all) <= sigma * sum_err and abs(l1 + l4) <= 0.5 * abs(l1):
        return "conservative-type chaos" if r_image == "stays" else "mixed dynamics"
    return "undetermined"


#: The verdict of a state whose realizations of the rounding disagree.
FRAGILE = "fragile"


#: What ``agree`` does (the text a dataset records for the rule; its docstring says the same).
AGREE_RULE = (
    'One answer from the realizations of a verdict (the same computation from initial states perturbed at the '
    'rounding level): the common answer when every realization gives it, else "fragile". Returns (answer, how '
    'many realizations give the most common answer, reason naming the count of each answer).'
)


def agree(verdicts) -> tuple[str, int, str]:
    """One answer from the realizations of a verdict (the same computation from initial states
    perturbed at the rounding level): the common answer when every realization gives it, else
    "fragile". Returns (answer, how many realizations give the most common answer, reason naming
    the count of each answer)."""
    verdicts = [str(v) for v in verdicts]
    if not verdicts:
        raise ValueError("no realizations to agree on")
    counts = {v: verdicts.count(v) for v in dict.fromkeys(verdicts)}
    top = max(counts.values())
    spread = ", ".join(f"{v} {n}" for v, n in counts.items())
    if len(counts) == 1:
        return verdicts[0], top, f"all {top} realizations agree" if top > 1 else "one realization (none to agree with)"
    return FRAGILE, top, f"realizations disagree: {spread} of {len(verdicts)}"
