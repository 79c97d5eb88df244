"""The transients from the reference state and the time-scaling law between energy levels
(figures F3, F4; C03-C06).

Each judge takes the paper's values and its datasets (:data:`sleighsim.claims.evidence.EVIDENCE`)
and returns a :class:`~sleighsim.claims.rules.Judgement`."""

from __future__ import annotations

import math

import numpy as np

from sleighsim.analysis.torus import CLASSES, IDENTITIES
from sleighsim.claims.rules import (
    DIFFERS,
    K_SIGMA,
    NOT_YET,
    REL_TOL,
    REPRODUCED,
    Judgement,
    finite,
    fmt,
    number,
    relative,
)
from sleighsim.engine.transient import phases


def _phases(fig3):
    return phases(fig3.time.values, fig3.u.values, fig3.Omega.values, fig3.omega.values)


def c03(paper, fig3) -> Judgement:
    """C03, "first transient: sleigh-like motion for t < 100": judged from the paper's values ``paper`` and
    ``fig3``; returns its Judgement."""
    t1 = _phases(fig3)["sleigh_phase_end"]
    limit = paper["sleigh_phase_end_max"]
    verdict = NOT_YET if not finite(t1) else REPRODUCED if t1 <= limit * (1 + REL_TOL) else DIFFERS
    return Judgement(verdict, measured=f"the sleigh-like phase ends at t = {t1:g}", units="time",
                     rule=f"end of the sleigh-like phase (running mean of u first reaches 99% of its maximum before "
                          f"the first spike) at most {limit:g} (+{REL_TOL:.0%})",
                     note="(sleighsim.engine.transient.phases)",
                     difference=max(0.0, t1 / limit - 1) if finite(t1) else math.nan)


def c04(paper, fig3, scaling) -> Judgement:
    """C04, "second transient: u decays, Omega oscillations grow, until the steady state": judged from the
    paper's values ``paper`` and ``fig3``, ``scaling``; returns its Judgement."""
    first = _phases(fig3)["first_spike"]
    want = paper["first_spike"]
    return Judgement(
        number(want, first), units="time", difference=relative(want, first),
        measured=f"{first:.5g}; across eps the first spike scales like eps^{scaling.attrs['first_spike_slope']:.2f}",
        rule=f"number, within {REL_TOL:.0%}", note="(first Omega spike)",
        reason=f"the first spike comes {want - first:.4g} time units earlier" if finite(first) and first < want else "")


def c05(paper, fig3) -> Judgement:
    """C05, "steady state: Omega spikes and theta jumps at regular intervals": judged from the paper's values
    ``paper`` and ``fig3``; returns its Judgement."""
    ph = _phases(fig3)
    mean, std, n = ph["spike_interval_mean"], ph["spike_interval_std"], ph["n_spikes"]
    stderr = std / math.sqrt(n - 2) if n > 2 else math.nan
    want = paper["spike_interval"]
    return Judgement(
        number(want, mean, stderr), units="time", uncertainty=fmt(stderr, 2), difference=relative(want, mean),
        measured=f"{mean:.5g} from {n - 2 if n > 2 else 0} intervals (standard deviation {std:.3g})",
        rule=f"number, within {REL_TOL:.0%} or {K_SIGMA:g} standard errors of the mean interval",
        note="(spike intervals, sleighsim.engine.transient.phases)")


def _law(a: dict, name: str, what: str, fmt_: str) -> str:
    """One of the torus family's laws (attributes of the torus-stability dataset) as text."""
    k = a.get(f"{name}_directions", 0)
    if not k:
        return f"{what}: not fitted (no direction with two amplitudes on tori)"
    err = a[f"{name}_err"]
    return (f"{what} {a[name]:{fmt_}}" + (f" +- {err:.2g}" if math.isfinite(err) else "")
            + f" (standard error over {k} directions; residual about each direction's line "
            f"{a[f'{name}_residual']:.2g})")


def torus_facts(torus) -> str:
    """What the torus-stability scene measured around the main torus (sleighsim.scenes.torus_stability): the
    reference's reversal train, the perturbed orbits' classes and identities, their periods and the family's
    laws against the perturbation's size a, as text."""
    a, sel = torus.attrs, torus.amplitude.values > 0
    cls, ident = torus.torus_class.values[sel], torus.torus_identity.values[sel]
    classes = ", ".join(f"{int(np.sum(cls == c))} {c}" for c in CLASSES if np.any(cls == c))
    idents = ", ".join(f"{int(np.sum(ident == c))} {c}" for c in IDENTITIES[1:] if np.any(ident == c))
    periods = torus.period.values[sel]
    lo, hi = a["law_amplitudes"]
    return (f"torus stability (double-double; the reference from the settled main state over {a['T_reference']:g}: "
            f"{a['reference_class']}, period {a['reference_period']:.12g} +- {a['reference_period_err']:.1g} over "
            f"{a['reference_n_cycles']} reversal intervals; {a['n_perturbed']} orbits started "
            f"{np.min(torus.amplitude.values[sel]):.0e} to {np.max(torus.amplitude.values[sel]):.0e} from it on its "
            f"energy level, over {a['T']:g}): {classes}; {idents}; periods {np.nanmin(periods):.7g} to "
            f"{np.nanmax(periods):.7g}; over a = {lo:.0e} to {hi:.0e} a family whose "
            + _law(a, "period_law_slope", "period changes per decade of a by", ".3g") + ", and whose "
            + _law(a, "offset_law_exponent", "spike point moves like a to the power", ".3g"))


def c06(paper, fig4, torus) -> Judgement:
    """C06, "same energy -> same attractor; different energy -> different attractor": judged from the paper's
    values ``paper`` and ``fig4``; ``torus`` (the torus-stability scene) is reported beside it; returns its
    Judgement."""
    a = fig4.attrs
    levels = sorted(set(fig4.level.values.tolist()))
    ok_runs = fig4.reached.values == 1
    groups = []
    for g in sorted(set(fig4.group.values[ok_runs].tolist())):
        sel = (fig4.group.values == g) & ok_runs
        groups.append(f"group {g}: {sel.sum()} runs, "
                      f"interval {np.mean(fig4.spike_interval_level0_units.values[sel]):.0f}")
    long = []
    for k, g in enumerate(fig4.group_id.values):
        sp = fig4.long_spike_time.values[k]
        d = np.diff(sp[np.isfinite(sp)])
        if d.size >= 2:
            long.append(f"group {int(g)}: intervals {d[0]:.0f} -> {d[-1]:.0f} by t = {sp[np.isfinite(sp)][-1]:.3g}")
    n_groups = [int(a[f"level{li}_n_groups"]) for li in levels]
    one = all(n == 1 for n in n_groups)
    if not ok_runs.any():
        verdict = NOT_YET
    else:
        verdict = REPRODUCED if one else DIFFERS
    return Judgement(
        verdict, units="fraction of mean |omega|",
        measured=f"interval groups per level {n_groups} ({'; '.join(groups)}); omega distance within the main group "
                 f"{max(a[f'level{li}_distance_main_group'] for li in levels):.3g}, across levels after the time "
                 f"scaling {a.get('across_levels_distance_main_group_scaled', math.nan):.3g}, unscaled "
                 f"{a.get('across_levels_distance_main_group_unscaled', math.nan):.3g}; long runs: " + "; ".join(long)
                 + "; " + torus_facts(torus),
        rule=f"one attractor per level: every run on a level falls in one steady spike-interval group (within "
             f"{a['group_rel_tol']:g})",
        reason="" if one else f"{sum(n - 1 for n in n_groups)} extra steady state(s) on the levels: runs keep "
                              "distinct spike intervals (long runs above)")
