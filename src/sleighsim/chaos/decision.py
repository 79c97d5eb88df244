"""The decision sequence one state's verdict goes through, in one place for the verdict stages and the
judge-power audit: the gauge (``rule.faithful_gate``: set aside what was judged in an arithmetic not shown
to follow the orbit; fails closed), the vote (``rule.vote_gate``: set aside what does not vote), the
decision (``rule.decide``), the consistency of the rates (``rule.consistent``, when rates are given) and,
over realizations, their agreement (``rule.agree``)."""

from __future__ import annotations

from sleighsim.chaos.rule import agree, consistent, decide, faithful_gate, vote_gate

#: The sequence, as the datasets and records keep it.
SEQUENCE = ("gauge (chaos.rule.faithful_gate, fails closed), vote (chaos.rule.vote_gate), decide "
            "(chaos.rule.decide), consistency of the rates (chaos.rule.consistent), agreement of the realizations "
            "(chaos.rule.agree)")


def decide_state(verdicts: dict, *, tangent_based, arithmetic: dict, follows: dict, voters,
                 rates: tuple | None = None, sigma: float = 3.0) -> dict:
    """One state's verdict from its indicators' (verdict, reason) pairs (the stage's verdict names):
    gauge, vote, decide, and with ``rates`` = (rate, stderr, {name: (rate, stderr)}) the consistency check.
    Returns verdict, reason, verdicts (after the gates) and the names set aside by the gauge and the vote."""
    v = dict(verdicts)
    by_gauge = faithful_gate(v, arithmetic, follows)
    by_vote = vote_gate(v, set(voters))
    verdict, reason, _ = decide(v, tangent_based)
    if rates is not None:
        verdict, reason = consistent(verdict, reason, rates[0], rates[1], rates[2], sigma)
    return {"verdict": verdict, "reason": reason, "verdicts": v, "set_aside_gauge": by_gauge, "set_aside_vote": by_vote}


def over_realizations(verdicts) -> tuple[str, int, str]:
    """The realizations' one answer (``rule.agree``)."""
    return agree(verdicts)
