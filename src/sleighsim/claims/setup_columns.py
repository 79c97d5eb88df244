"""The ledger's ``paper_setup_value`` and ``paper_setup_verdict`` columns: each claim's numbers under the
setup the paper_setup scene inferred jointly from all the paper's numbers
(:mod:`sleighsim.scenes.paper_setup`), judged by the ledger's own tolerance
(:func:`sleighsim.claims.rules.number`: REL_TOL or K_SIGMA measured uncertainties; a band's edges
as the spectra judge does: REL_TOL of the paper's band width or one frequency bin)."""

from __future__ import annotations

import numpy as np

from sleighsim.claims.causes import NONE
from sleighsim.claims.rules import REPRODUCED, all_of, band_tolerance, number

NOT_APPLICABLE = "not applicable"
NOT_INFERRED = "not yet computed: no setup determines every scored number"
#: The verdicts' openings: the claim holds under both setups, only under the paper's, only under ours, neither.
BOTH, PAPER_ONLY = "reproduced (under both)", "reproduced under the paper's setup"
SAME_ELEMENTS = "its elements at the run's own: the sweeps' value, not the claim's dataset, reproduces it"
CONVERGED_ONLY, NEITHER = "reproduced under converged physics only", "differs under both"


def _band_part(paper_lo, paper_hi, ours, paper, sd) -> str:
    """An edge of a band judged as the spectra judge does (one bin: the measured sd)."""
    return REPRODUCED if abs(ours - paper) <= band_tolerance((paper_lo, paper_hi), sd) else "differs"


def _parts(numbers) -> list[str]:
    """The verdict of each of a claim's numbers under the best setup (``numbers``: paper_setup rows)."""
    papers = {str(n): float(p) for n, p in zip(numbers.name.values, numbers.paper.values)}
    out = []
    for name, paper, best, sd in zip(numbers.name.values, numbers.paper.values, numbers.best.values,
                                     numbers.best_sd.values):
        if str(name).startswith("band_"):
            out.append(_band_part(papers["band_low"], papers["band_high"], best, paper, sd))
        else:
            out.append(number(float(paper), float(best), float(sd)))
    return out


def columns(claim_id: str, verdict: str, setup) -> tuple[str, str]:
    """(value, verdict) of a ledger row (its id and converged ``verdict``) under the inferred setup
    ``setup`` (the paper_setup dataset; None: not built, with the reason in the verdict)."""
    if setup is None:
        return "", f"{NOT_APPLICABLE}: no paper_setup dataset in this run"
    rows = np.flatnonzero(setup.claim.values == claim_id)
    numbers = setup[["name", "paper", "best", "best_sd", "moved_by", "changed_by"]].isel(paper_number=rows)
    if rows.size == 0:
        return "", f"{NOT_APPLICABLE}: the setup moves none of its numbers"
    if "best_K2" not in setup.attrs:
        return "", NOT_INFERRED
    value = "; ".join(f"{n} {b:.4g}" for n, b in zip(numbers.name.values, numbers.best.values))
    changed = sorted({c for cs in numbers.changed_by.values for c in str(cs).split("; ") if c})
    moved = sorted({m for ms in numbers.moved_by.values for m in str(ms).split(", ") if m})
    setup_ok = all_of(_parts(numbers)) == REPRODUCED
    if verdict == REPRODUCED and setup_ok:
        return value, BOTH
    if setup_ok:
        return value, f"{PAPER_ONLY} ({'; '.join(changed) or SAME_ELEMENTS})"
    if verdict == REPRODUCED:
        return value, f"{CONVERGED_ONLY} (differs under the paper's setup: {'; '.join(changed)})"
    return value, f"{NEITHER} (tried: {', '.join(moved) or 'no element moves it'})"


def cause_with_setup(cause: str, setup_verdict: str) -> str:
    """A cause text that says "not explained by the causes tested", told that the joint setup was tried too."""
    if not cause.startswith(NONE) or setup_verdict.startswith(NOT_APPLICABLE):
        return cause
    return f"{cause}; also tried under the joint setup (paper_setup.nc): {setup_verdict}"
