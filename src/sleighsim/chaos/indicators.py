"""The registry of chaos indicators: one entry per estimator that can vote, used by the judge-power audit
(``chaos.power_audit``) and by the vote (``chaos.power.stage_vote``), and meant for the verdict scenes'
one pipeline, so that the estimator audited is the estimator that votes.

An :class:`Indicator` names its stage ("first": the chaos verdict's first stage, in double and long
double; "decisive": the decisive stage, on one orbit in an arithmetic that follows it), the name the
stage's verdict table gives it, whether it is tangent-based, its estimator (a one-line text naming the
functions and settings; the judge-power record stores it, and a record whose text differs is refused:
it audited another estimator), the stage's settings key of its horizon and the other settings it reads
(a run whose settings differ from the audited ones votes by nothing), and ``judged``: the function that
computes its value and verdict from the stage's orbit record (None: not audited yet, votes by nothing).

Decisive stage's orbit record (``DecisiveOrbit`` keys): t (0, dt, ..., T), log_norm (one tangent
vector's ln |v(t)|), x (the frequency component), crossings (the section's times), obs (the Birkhoff
observables, samples x observables, without the last sample), dt, T, precision (its name) and
gain_rounding (G x the rounding the arithmetic injects per cycle); settings: megno_samples, splits,
min_cycles, sigma.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from sleighsim.chaos import decisive

FIRST, DECISIVE = "first", "decisive"
STAGES = (FIRST, DECISIVE)


@dataclass(frozen=True)
class Indicator:
    """One estimator with its judge (module docstring)."""

    name: str
    stage: str
    verdict_name: str
    tangent_based: bool
    estimator: str
    horizon: str
    settings: tuple
    judged: Callable | None = None


def _megno(o: dict, s: dict) -> dict:
    return decisive.megno_judged(o["t"], o["log_norm"], s["megno_samples"], o["T"], s["sigma"])


def _section(o: dict, s: dict) -> dict:
    return decisive.section_megno_judged(o["t"], o["log_norm"], o["crossings"], o["T"], s["sigma"])


def _frequency(o: dict, s: dict) -> dict:
    return decisive.frequency_judged(o["x"], o["dt"], s["splits"], s["min_cycles"], o["precision"], s["sigma"])


def _birkhoff(o: dict, s: dict) -> dict:
    return decisive.birkhoff_judged(o["obs"], o["dt"], s["splits"], o["gain_rounding"])


_FIRST_NOTE = "; not yet audited on independent orbits (votes by nothing)"

#: name -> Indicator
REGISTRY: dict[str, Indicator] = {i.name: i for i in (
    Indicator("megno_log_norm", DECISIVE, "megno", True,
              "chaos.decisive.megno_judged: megno.megno_from_log_norm (trapezoid on the log-norm sampled every dt, "
              "megno_samples points) and megno.judge_megno_run over T", "T", ("dt", "megno_samples", "sigma"), _megno),
    Indicator("section_megno", DECISIVE, "section_megno", True,
              "chaos.decisive.section_megno_judged: section_megno.section_megno at the section crossings of the "
              "log-norm sampled every dt, judge_section_megno", "T", ("dt", "sigma"), _section),
    Indicator("frequency_orbit", DECISIVE, "frequency", False,
              "chaos.decisive.frequency_judged: frequency.drift of the component sampled every dt over windows "
              "T / splits (min_cycles), judge_frequency on that one run", "T", ("dt", "splits", "min_cycles", "sigma"),
              _frequency),
    Indicator("birkhoff", DECISIVE, "birkhoff", False,
              "chaos.decisive.birkhoff_judged: birkhoff.digits of the observables sampled every dt over windows "
              "T / splits, judge_birkhoff with G x injected rounding", "T", ("dt", "splits"), _birkhoff),
    Indicator("benettin", FIRST, "benettin", True,
              "benettin.replica_exponents over the replicas, tangent.judge_benettin" + _FIRST_NOTE, "T_round",
              ("tau", "replicas", "replica_spacing", "max_rounds", "target_rel", "t_align", "regular_floor", "sigma")),
    Indicator("ftle", FIRST, "ftle", True,
              "tangent.finite_time_exponents of the first replica's vector, tangent.judge_ftle" + _FIRST_NOTE,
              "T_round", ("tau", "ftle_windows", "sigma")),
    Indicator("megno", FIRST, "megno", True,
              "megno.megno (heyoka's quadratures) over T_megno, judge_megno_run, under the long-double precision "
              "check" + _FIRST_NOTE, "T_megno", ("tau", "megno_samples", "T_long_double", "sigma")),
    Indicator("two_trajectory", FIRST, "two_trajectory", False,
              "two_trajectory.two_trajectory_indicator at each d0" + _FIRST_NOTE, "T_two", ("tau", "d0", "t_align",
                                                                                          "sigma")),
    Indicator("loschmidt", FIRST, "loschmidt", False,
              "loschmidt.loschmidt_indicator (double and long double)" + _FIRST_NOTE, "loschmidt_T",
              ("loschmidt_n", "sigma")),
    Indicator("frequency", FIRST, "frequency", False,
              "scenes.verdict_frequency.frequency_indicator (double, long double, quad)" + _FIRST_NOTE, "frequency",
              ("sigma",)),
)}


def of_stage(stage: str) -> list[Indicator]:
    """The indicators of ``stage``, in registry order."""
    if stage not in STAGES:
        raise ValueError(f"stage {stage!r}: choose one of {STAGES}")
    return [i for i in REGISTRY.values() if i.stage == stage]


def audited(stage: str) -> list[Indicator]:
    """The indicators of ``stage`` the audit runs (those with a ``judged`` function)."""
    return [i for i in of_stage(stage) if i.judged is not None]


def record_names(stage: str) -> dict[str, str]:
    """{verdict name: registry name (the judge-power record's)} of the stage's indicators."""
    return {i.verdict_name: i.name for i in of_stage(stage)}


def tangent_based(stage: str) -> set[str]:
    """The verdict names of the stage's tangent-based indicators (``rule.decide``'s second argument)."""
    return {i.verdict_name for i in of_stage(stage) if i.tangent_based}


def judge_orbit(orbit: dict, settings: dict, names=None) -> dict:
    """{name: the indicator's judged dict} of the decisive stage's audited indicators (``names``: a subset)
    on one orbit record."""
    return {i.name: i.judged(orbit, settings) for i in audited(DECISIVE) if names is None or i.name in names}
