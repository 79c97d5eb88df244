"""The rotor-free sleigh (eps = 0, figure F2): its closed-form flow and its equilibria (C01, C02).

Each judge takes the paper's values and its datasets (:data:`sleighsim.claims.evidence.EVIDENCE`)
and returns a :class:`~sleighsim.claims.rules.Judgement`."""

from __future__ import annotations

import numpy as np

from sleighsim.claims.rules import (
    DIFFERS,
    REPRODUCED,
    Judgement,
)
from sleighsim.model.equations import rhs
from sleighsim.model.params import Params


def c01(paper, fig2) -> Judgement:
    """C01, "without rotor, E is conserved, Omega -> 0, u -> constant, path -> straight line": judged from the
    paper's values ``paper`` and ``fig2``; returns its Judgement."""
    a = fig2.attrs
    om_end = float(np.max(np.abs(fig2.Omega_closed.values[:, -1])))
    V = float(np.max(np.abs(fig2.u_closed.values[:, -1])))
    th = fig2.path_theta.values
    turning = float(abs(th[-1] - th[int(0.9 * th.size)]))
    ok = a["closed_form_max_abs_error"] < 1e-10 and om_end < 1e-3 * V and turning < 1e-3
    return Judgement(
        REPRODUCED if ok else DIFFERS, units="rad/time",
        measured=f"|Omega(t_end)| = {om_end:.2g} against u -> {V:.4g}; heading turns by {turning:.2g} rad over the "
                 f"last 10% of the path; closed form against heyoka {a['closed_form_max_abs_error']:.1e}",
        rule="integration matches the closed form to 1e-10, |Omega(end)| < 1e-3 u(end) and the heading turns by less "
             "than 1e-3 rad over the last tenth of the path (a straight line)")


def c02(paper) -> Judgement:
    """C02, "only fixed points: Omega = omega = 0": judged from the paper's values ``paper``; returns its
    Judgement."""
    p = Params.paper(eps=0.1)
    rng = np.random.default_rng(0)
    rest = np.c_[rng.uniform(-2, 2, 100), np.zeros(100), np.zeros(100), rng.uniform(-7, 7, 100)]
    moving = np.c_[rng.uniform(-2, 2, 100), rng.uniform(0.01, 1, (100, 2)) * rng.choice([-1, 1], (100, 2)),
                   rng.uniform(-7, 7, 100)]
    at_rest = float(np.max(np.abs(rhs(rest, p))))
    elsewhere = float(np.min(np.max(np.abs(rhs(moving, p)), axis=1)))
    ok = at_rest < 1e-14 and elsewhere > 0
    return Judgement(
        REPRODUCED if ok else DIFFERS,
        measured=f"max |rhs| with Omega = omega = 0: {at_rest:.1e}; smallest max |rhs| at 100 states with Omega, "
                 f"omega != 0: {elsewhere:.2g}",
        rule="the right-hand side vanishes on Omega = omega = 0 and nowhere else sampled (deltadot = Omega - omega, "
             "and Omegadot = omegadot = 0 force Omega = omega = 0)",
        note="sleighsim.model.equations.rhs (derived equations)")
