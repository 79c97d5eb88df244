"""The paper's model as printed, its slips found by the derivation (D1-D6).

Each judge takes the paper's values and its datasets (:data:`sleighsim.claims.evidence.EVIDENCE`)
and returns a :class:`~sleighsim.claims.rules.Judgement`."""

from __future__ import annotations

import numpy as np

from sleighsim.claims.rules import (
    DIFFERS,
    REL_TOL,
    REPRODUCED,
    Judgement,
    number,
    relative,
)


def d1(paper, audit) -> Judgement:
    """D1, "printed udot equation": judged from the paper's values ``paper`` and ``audit``; returns its
    Judgement."""
    a = audit.attrs
    return Judgement(DIFFERS if a["printed_max_abs_rel_change"] > 1e-6 else REPRODUCED,
                     measured=f"printed: max |E/E0 - 1| = {a['printed_max_abs_rel_change']:.3g}; derived: "
                              f"{a['derived_max_abs_rel_change']:.2g}",
                     rule="the printed equation differs when it changes E by more than 1e-6")


def d2(paper, audit) -> Judgement:
    """D2, "K^2 = 1 + I_r/(m b^2)": judged from the paper's values ``paper`` and ``audit``; returns its
    Judgement."""
    a = audit.attrs
    ic, ir = a["d2_Omegadot_residual_with_Ic"], a["d2_Omegadot_residual_with_Ir"]
    return Judgement(DIFFERS if ic < 1e-12 < ir else REPRODUCED,
                     measured=f"printed Omegadot against the derivation: residual {ic:.1e} with I_c = (K^2 - 1) b^2, "
                              f"{ir:.2g} with I_r",
                     rule="differs when only I_c (not the printed I_r) makes the printed Omegadot hold",
                     reason="the definition must read K^2 = 1 + I_c / (m b^2)" if ic < 1e-12 < ir else "")


def d3(paper, audit) -> Judgement:
    """D3, "locked inertia and its right-hand side": judged from the paper's values ``paper`` and ``audit``;
    returns its Judgement."""
    a = audit.attrs
    return Judgement(DIFFERS if a["d3_n_differences"] else REPRODUCED,
                     measured=f"{a['d3_n_differences']} entries differ: {a['d3_differences']}",
                     rule="symbolic comparison")


def d4(paper, audit) -> Judgement:
    """D4, "Euler-Lagrange equation for beta": judged from the paper's values ``paper`` and ``audit``; returns
    its Judgement."""
    a = audit.attrs
    return Judgement(DIFFERS if a["d4_dL_dbeta"] != "0" else REPRODUCED, measured=f"dL/dbeta = {a['d4_dL_dbeta']}",
                     rule="symbolic: the printed beta equation omits dL/dbeta, which is not zero")


def d5(paper, audit) -> Judgement:
    """D5, "E = 0.1127 for the reference state": judged from the paper's values ``paper`` and ``audit``; returns
    its Judgement."""
    a = audit.attrs
    E = a["d5_reference_energy_physical"]
    want = paper["label"]
    return Judgement(number(want, E), units="energy", difference=relative(want, E),
                     measured=f"{E:.4g} for the reference state at eps = {a['param_eps']:g}",
                     rule=f"number, within {REL_TOL:.0%}")


def d6(paper, audit) -> Judgement:
    """D6, "eps > 20": judged from the paper's values ``paper`` and ``audit``; returns its Judgement."""
    a = audit.attrs
    eps, m_c, det = a["d6_eps"], a["d6_m_c"], a["d6_min_det_M"]
    unphysical, formal_ok = bool(np.all(m_c < 0)), bool(np.all(det > 0))
    return Judgement(
        DIFFERS if unphysical else REPRODUCED,
        measured="; ".join(f"eps {e:g}: m_c = {m:g}, min det M = {d:.3g}" for e, m, d in zip(eps, m_c, det)),
        rule="from the derivation: eps = m_r / m >= 1 makes the sleigh's mass m_c = 1 - eps non-positive; the formal "
             "system is well defined where M(delta) stays positive definite",
        reason=f"eps > {paper['eps']:g} is a formal system (m_c < 0)" + (", whose inertia stays positive definite"
                                                                          if formal_ok else ""))
