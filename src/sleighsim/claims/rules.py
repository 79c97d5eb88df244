"""The rules every judge of the ledger uses: the verdicts (:data:`VERDICT_RULES`, written verbatim into the
claims dataset's ``rules`` attribute) and how numbers are compared."""

from __future__ import annotations

import math
from dataclasses import dataclass

from sleighsim.chaos.rule import FRAGILE  # a claim whose realizations disagree, as a state's verdict does

#: What a judgement holds: the verdicts, as the claims dataset records them (attribute ``rules``).
VERDICT_RULES = (
    "The rules every judge of the ledger uses: what a judgement holds, and how numbers are compared.\n"
    "\n"
    'Verdicts: "reproduced", "reproduced only in double precision" (the ledger\'s, when the claim\'s\n'
    "datasets were also computed in a finer arithmetic and only double reproduces the paper),\n"
    "\"differs\", \"fragile\" (the ledger's, when realizations of the claim's datasets from start states\n"
    "perturbed at the rounding level give different verdicts), \"cannot be reproduced\" (only from a computed "
    "rule, such as a measured cost above a\n"
    "stated budget, or a run that reached its stated cap without resolving the number), \"not yet\n"
    "computed\" (the dataset is missing, or does not determine the number: NaN)."
)
REPRODUCED, DIFFERS, CANNOT, NOT_YET = "reproduced", "differs", "cannot be reproduced", "not yet computed"
#: A paper number that double precision reproduces and the finest arithmetic computed does not.
DOUBLE_ONLY = "reproduced only in double precision"
VERDICTS = (REPRODUCED, DOUBLE_ONLY, DIFFERS, FRAGILE, CANNOT, NOT_YET)
REL_TOL = 0.1  # a number is reproduced within 10% of the paper's value ...
K_SIGMA = 2.0  # ... or within 2 of our standard errors


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
