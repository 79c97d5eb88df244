"""The rules every judge of the ledger uses: the verdicts (:data:`VERDICT_RULES`, written verbatim into the
claims dataset's ``rules`` attribute) and how numbers are compared."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from sleighsim.chaos.rule import FRAGILE  # a claim whose realizations disagree, as a state's verdict does

#: What a judgement holds: the verdicts, as the claims dataset records them (attribute ``rules``).
VERDICT_RULES = (
    "The rules every judge of the ledger uses: what a judgement holds, and how numbers are compared.\n"
    "\n"
    'Verdicts: "reproduced", "reproduced only in double precision" (the ledger\'s, when the claim\'s\n'
    "datasets were also computed in a finer arithmetic and only double reproduces the paper),\n"
    "\"differs slightly\", \"differs\", \"differs greatly\" (by the relative difference from the paper's value:\n"
    "below 0.25, from 0.25 to 0.5 or not measured, from 0.5 on),\n"
    "\"fragile\" (the ledger's, when realizations of the claim's datasets from start states\n"
    "perturbed at the rounding level give different verdicts), \"check failed\" (a figure whose own process\n"
    "check failed in this run, such as its steady state not shown settled: the run's, not the paper's),\n"
    "\"cannot be reproduced\" (only from a computed rule, such as a measured cost above a\n"
    "stated budget, or a run that reached its stated cap without resolving the number), \"not yet\n"
    "computed\" (the dataset is missing, or does not determine the number: NaN), \"not a reproduction\"\n"
    "(the ledger's, for every row of a run whose config is not at the paper's fidelity, such as the smoke\n"
    "run: its own data's verdict stands in the column run_verdict)."
)
REPRODUCED, DIFFERS, CANNOT, NOT_YET = "reproduced", "differs", "cannot be reproduced", "not yet computed"
#: A paper number that double precision reproduces and the finest arithmetic computed does not.
DOUBLE_ONLY = "reproduced only in double precision"
#: A difference by its size (:func:`severity`): the relative difference from the paper's value.
DIFFERS_SLIGHTLY, DIFFERS_GREATLY = "differs slightly", "differs greatly"
#: A figure whose own process check (its steady state shown settled) failed in this run.
CHECK_FAILED = "check failed"
#: Every row of a run whose config is not at the paper's fidelity (:mod:`sleighsim.claims.fidelity`).
NOT_A_REPRODUCTION = "not a reproduction"
#: The verdicts that say the paper's value is not what we measure, mildest first.
DIFFERING = (DIFFERS_SLIGHTLY, DIFFERS, DIFFERS_GREATLY)
VERDICTS = (REPRODUCED, DOUBLE_ONLY, *DIFFERING, FRAGILE, CHECK_FAILED, CANNOT, NOT_YET, NOT_A_REPRODUCTION)
#: What each verdict means, in one line (the report's legend).
MEANINGS = {
    REPRODUCED: "our value agrees with the paper's (within 10% or 2 standard errors; a stated criterion holds)",
    DOUBLE_ONLY: "double reproduces the paper's value; the finer arithmetic, which follows the orbit, does not",
    DIFFERS_SLIGHTLY: "beyond the tolerance, by less than a quarter of the paper's value",
    DIFFERS: "by a quarter to a half of the paper's value, or a qualitative claim that does not hold",
    DIFFERS_GREATLY: "by half the paper's value or more (a factor 1.5 above or 2 below, or more)",
    FRAGILE: "realizations perturbed at the rounding level give different verdicts",
    CHECK_FAILED: "this run's own process check failed (the steady state not shown settled): not the paper's fault",
    CANNOT: "a computed rule says it cannot be reproduced (cost over budget, capped run)",
    NOT_YET: "the dataset is missing or does not determine the number",
    NOT_A_REPRODUCTION: "the run's config is not at the paper's fidelity (smoke): nothing is judged against the paper",
}
REL_TOL = 0.1  # a number is reproduced within 10% of the paper's value ...
K_SIGMA = 2.0  # ... or within 2 of our standard errors
#: The size of a difference (relative to the paper's value): slight below SLIGHT, great from GREAT.
SLIGHT, GREAT = 0.25, 0.5


def severity(verdict: str, difference: float) -> str:
    """The word for ``verdict`` by the size of its relative ``difference`` (|ours - paper| / |paper|):
    "differs" split into DIFFERS_SLIGHTLY (below SLIGHT), DIFFERS (SLIGHT to GREAT, or not measured: NaN)
    and DIFFERS_GREATLY (GREAT on); any other verdict as it is."""
    if verdict != DIFFERS or not finite(difference):
        return verdict
    return DIFFERS_SLIGHTLY if difference < SLIGHT else DIFFERS_GREATLY if difference >= GREAT else DIFFERS


@dataclass
class Judgement:
    """What a judge returns: the verdict, what was measured (text composed from the data), the rule,
    and optionally the uncertainty, units, the reason (from measured numbers only), a note on the
    evidence beyond the datasets, and the relative size of the largest difference (for ranking)."""

    verdict: str
    measured: str
    rule: str
    reason: str = ""
    uncertainty: str = ""
    units: str = ""
    note: str = ""
    difference: float = math.nan


def finite(*values) -> bool:
    """Whether every one of ``values`` (numbers or None) is a finite number."""
    return all(v is not None and math.isfinite(float(v)) for v in values)


def number(paper: float, ours: float, uncertainty: float = 0.0, rel_tol: float = REL_TOL) -> str:
    """reproduced if |ours - paper| <= max(K_SIGMA * uncertainty, rel_tol * |paper|); NaN: not yet computed."""
    if not finite(ours, uncertainty):
        return NOT_YET
    return REPRODUCED if abs(ours - paper) <= max(K_SIGMA * abs(uncertainty), rel_tol * abs(paper)) else DIFFERS


def band_tolerance(band, resolution: float) -> float:
    """How far a band edge may lie from the paper's ``band`` (low, high) and still reproduce it: REL_TOL of
    the paper's band width or ``resolution`` (one frequency bin), whichever is larger (frequency units)."""
    return max(REL_TOL * (band[1] - band[0]), resolution)


def digits(paper_text: str, ours: float, uncertainty: float = 0.0) -> str:
    """reproduced if |ours - paper| <= max(K_SIGMA * uncertainty, one unit of the paper's last printed digit)."""
    if not finite(ours, uncertainty):
        return NOT_YET
    decimals = len(paper_text.split(".")[1]) if "." in paper_text else 0
    return REPRODUCED if abs(ours - float(paper_text)) <= max(K_SIGMA * abs(uncertainty), 10.0**-decimals) else DIFFERS


def relative(paper: float, ours: float) -> float:
    """|ours - paper| / |paper| (NaN when either is)."""
    return abs(ours - paper) / abs(paper) if finite(ours, paper) and paper else math.nan


def all_of(verdicts) -> str:
    """A claim made of several parts: differs if any part differs, else not yet computed if any part is
    undetermined, else cannot be reproduced if any part is, else reproduced."""
    verdicts = list(verdicts)
    for v in (DIFFERS, NOT_YET, CANNOT):
        if v in verdicts:
            return v
    return REPRODUCED


def fmt(x, digits_: int = 4) -> str:
    """``x`` (a number, or a list or array of numbers) as text with ``digits_`` significant digits;
    what is not a number as str(x)."""
    if isinstance(x, (list, tuple)) or (hasattr(x, "ndim") and getattr(x, "ndim", 0) > 0):
        return "[" + ", ".join(fmt(v, digits_) for v in x) + "]"
    try:
        return f"{float(x):.{digits_}g}"
    except (TypeError, ValueError):
        return str(x)


#: The text a judge wrote for a number it could not compute ("nan"), as a word.
NOT_COMPUTED_TEXT = "not computed"
_NAN = re.compile(r"(?<![A-Za-z0-9_.])nan(?![A-Za-z0-9_])", re.IGNORECASE)


def readable(text: str) -> str:
    """``text`` with every number a judge could not compute ("nan", as Python formats NaN) written as
    NOT_COMPUTED_TEXT, so that no ledger column or page shows a bare NaN."""
    return _NAN.sub(NOT_COMPUTED_TEXT, text)
