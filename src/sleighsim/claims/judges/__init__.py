"""One judge per claim of paper/CLAIMS.md, grouped by the paper's sections. A judge takes the paper's
values (the ``value`` column, parsed) and the datasets named for it in
:data:`sleighsim.claims.evidence.EVIDENCE`, in that order, and returns a
:class:`~sleighsim.claims.rules.Judgement` whose texts are composed from measured numbers."""

from __future__ import annotations

from sleighsim.claims.judges import (
    lyapunov,
    perturbation,
    sleigh0,
    slips,
    spectra,
    steady_state,
    transients,
)

#: Claim id -> judge.
JUDGES = {
    "C01": sleigh0.c01,
    "C02": sleigh0.c02,
    "C03": transients.c03,
    "C04": transients.c04,
    "C05": transients.c05,
    "C06": transients.c06,
    "C07": perturbation.c07,
    "C08": perturbation.c08,
    "C09": perturbation.c09,
    "C10": perturbation.c10,
    "C11": perturbation.c11,
    "C12": perturbation.c12,
    "C13": steady_state.c13,
    "C14": steady_state.c14,
    "C15": steady_state.c15,
    "C16": steady_state.c16,
    "C17": steady_state.c17,
    "C18": lyapunov.c18,
    "C19": lyapunov.c19,
    "C20": lyapunov.c20,
    "C21": lyapunov.c21,
    "C22": steady_state.c22,
    "C23": spectra.c23,
    "C24": spectra.c24,
    "C25": lyapunov.c25,
    "C26": lyapunov.c26,
    "C27": lyapunov.c27,
    "D1": slips.d1,
    "D2": slips.d2,
    "D3": slips.d3,
    "D4": slips.d4,
    "D5": slips.d5,
    "D6": slips.d6,
}
