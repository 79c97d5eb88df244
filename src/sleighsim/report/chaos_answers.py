"""The chaos answers of the report's first screen: per steady state of every verdict dataset, its verdict,
class and reason, the arithmetic it was decided in, the indicators that decided it with their measured power
(the judge-power record), what would decide a state not yet decided, a verdict measured with another
config, and the judge-power record as a table."""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np

from sleighsim.chaos.indicators import DECISIVE, record_names
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, TORI
from sleighsim.chaos.power import from_counts, record_rates, record_voting
from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.page import Table

#: The judge-power record's name of each decisive judge's verdict name.
RECORD_NAME = record_names(DECISIVE)


class ChaosAnswer(NamedTuple):
    """One steady state's chaos verdict: its name, verdict, why, the arithmetic it was decided in (with
    G x rounding there), its class, the indicators that decided it (with their arithmetic), and, when it
    is not decided, what would decide it and at what measured cost; and what the state is (its start's own
    steady state or a torus the settling arithmetic's rounding selected); for a decided state, what the verdict
    rests on (the exponent bound of its judges and the decision rule's measured wrong rate)."""

    state: str
    verdict: str
    why: str
    arithmetic: str = ""
    klass: str = ""
    decided_by: str = ""
    to_decide: str = ""
    origin: str = ""
    rests_on: str = ""

def chaos_answers(datasets: dict, power: dict | None = None) -> list[ChaosAnswer]:
    """Per state of every dataset with per-state chaos verdicts (a ``state`` dimension with
    ``verdict``): its verdict and class, the arithmetic it was decided in and the orbit's faithfulness,
    the indicators that decided it (with their measured power when the judge-power record ``power`` is
    given), what would decide it when it is not decided, and the reason with the tori its realizations
    reached."""
    return [a for path in datasets.values() for a in dataset_answers(read_dataset(path), power)]


def dataset_answers(ds, power: dict | None = None) -> list[ChaosAnswer]:
    """:func:`chaos_answers` of one dataset (none when it holds no per-state verdict)."""
    if "verdict" not in ds.data_vars or "state" not in ds.dims:
        return []
    out = []
    for i, st in enumerate(ds.state.values):
        reason = str(ds.reason.values[i]) if "reason" in ds.data_vars else ""
        verdict = str(ds.verdict.values[i])
        klass = str(ds.state_class.values[i]) if "state_class" in ds.data_vars else ""
        origin = str(ds.state_origin.values[i]) if "state_origin" in ds.data_vars else ""
        why = reason + _arithmetic_note(ds, i) + _tori_note(ds, i) + _settle_note(ds, i)
        out.append(ChaosAnswer(str(st), verdict, why,
                               _decided_in(ds, i), klass, _decided_by(ds, i, power),
                               _to_decide(ds, i, verdict, power), origin, _rests_on(ds, i, verdict, power)))
    return out


def _decisive_ran(ds, i: int) -> bool:
    """Whether state i of a verdict dataset went through the decisive stage."""
    return "decisive_verdict" in ds.data_vars and str(ds.decisive_verdict.values[i]) != "not run"


def _vote_factor(ds) -> float:
    """The audited horizon factor the decisive stage voted at (1 without the stage or a finite factor)."""
    h = float(ds.attrs.get("decisive_vote_horizon", 1.0))
    return h if np.isfinite(h) else 1.0


def _power_note(power: dict | None, judge: str, verdict: str, factor: float = 1.0) -> str:
    """A judge's (its verdict name) measured power for a verdict at the audited horizon ``factor``, from the
    judge-power record: right on n of N orbits of the class the verdict names, wrong on m of M of the other;
    "" without the record, "; not audited" without the judge there."""
    if power is None:
        return ""
    name = RECORD_NAME.get(judge, judge)
    rows = {r["class"]: r for r in record_rates(power, factor) if r["judge"] == name}
    right, other = (TORI, CHAOTIC_ORBITS) if verdict == "regular" else (CHAOTIC_ORBITS, TORI)
    if right not in rows or other not in rows:
        return "; not audited"
    a, b = rows[right], rows[other]
    return (f"; says {verdict} on {a['correct']} of {a['N']} {right}, wrongly on {b['wrong']} of {b['N']} {other} "
            f"(95% bound {b['wrong_upper95']:.2g})")


def _decided_by(ds, i: int, power: dict | None = None) -> str:
    """The indicators that vote and whose verdict equals state i's (chaotic or regular), with the arithmetic
    each was judged in and its measured power at the horizon voted at (``_power_note``); "" when the state is
    not decided. A dataset that does not record which decisive judges voted names none of them."""
    verdict = str(ds.verdict.values[i])
    if verdict not in ("chaotic", "regular") or "indicator_verdict" not in ds.data_vars:
        return ""
    names = {str(k): Precision.DOUBLE
             for k, v in zip(ds.indicator.values, ds.indicator_verdict.values[i]) if v == verdict}
    factor = 1.0
    if _decisive_ran(ds, i):
        factor = _vote_factor(ds)
        voting = (ds.decisive_voting.values[i] if "decisive_voting" in ds.data_vars  # unrecorded: none voted
                  else np.zeros(ds.sizes["decisive_indicator"], int))
        names = {k: a for k, a in names.items() if k not in set(map(str, ds.decisive_indicator.values))}
        names.update({str(k): ds.attrs["decisive_precision"] for k, v, on in
                      zip(ds.decisive_indicator.values, ds.decisive_indicator_verdict.values[i], voting)
                      if v == verdict and int(on)})
    return ", ".join(f"{k} ({a}{_power_note(power, k, verdict, factor)})" for k, a in sorted(names.items()))


def _rests_on(ds, i: int, verdict: str, power: dict | None = None) -> str:
    """What state i's decided verdict rests on: the exponent bound of its regular tangent-based judges (the
    decisive stage's ``decisive_bound_text``) and the decision rule's own counts at the horizon voted at (the
    judge-power record: right on the verdict's class, wrong on the other, with the 95% bound); "" when not
    decided or neither is known."""
    if verdict not in ("chaotic", "regular"):
        return ""
    parts = []
    if verdict == "regular" and "decisive_bound_text" in ds.data_vars and _decisive_ran(ds, i):
        parts.append(str(ds.decisive_bound_text.values[i]))
    factor = _vote_factor(ds)
    rule = next((v for k, v in (power or {}).get("rule", {}).items() if float(k) == factor), None)
    if rule:
        right, other = (TORI, CHAOTIC_ORBITS) if verdict == "regular" else (CHAOTIC_ORBITS, TORI)
        a, b = from_counts(rule[right]), from_counts(rule[other])
        parts.append(f"the decision rule at audited factor {factor:g} says {verdict} on {a['correct']} of {a['N']} "
                     f"{right} and wrongly on {b['wrong']} of {b['N']} {other} (95% bound {b['wrong_upper95']:.2g})")
    return "; ".join(parts)


def _to_decide(ds, i: int, verdict: str, power: dict | None = None) -> str:
    """For a state not decided (undecided or fragile): what would decide it and its measured cost (the
    decisive stage's own wall time, scaled by the horizon), or that no decisive stage ran for it. With the
    judge-power record, the next audited horizon factor and the judges it would let vote besides."""
    if verdict in ("chaotic", "regular"):
        return ""
    if not _decisive_ran(ds, i):
        return ("no decisive stage ran for this state: name it among the decisive stage's states (decisive.states) "
                "to judge it again in an arithmetic that follows its orbit")
    wall, T = float(ds.decisive_wall_time_s.values[i]), float(ds.attrs["decisive_T"])
    left = "; ".join(f"{k}: {v}" for k, v in zip(ds.decisive_indicator.values, ds.decisive_indicator_verdict.values[i]))
    text = (f"the decisive stage ({ds.attrs['decisive_precision']}, T = {T:g}, {wall:.0f} s per realization on one "
            f"core, measured) left it {verdict} ({left})")
    now = float(ds.attrs.get("decisive_vote_horizon", 1.0))
    if not np.isfinite(now) and ds.attrs.get("decisive_vote_why", ""):
        return (text + f"; no judge votes here at any horizon ({ds.attrs['decisive_vote_why']}): the audit must cover "
                       "it first")
    later = sorted(float(h) for h in (power or {}).get("counts", {}) if float(h) > now)
    if not later:
        return text + f"; its cost grows linearly with T: {2 * T:g} would take about {2 * wall:.0f} s per realization"
    h = later[0]
    gained = sorted(record_voting(power, h) - record_voting(power, now))
    who = ", ".join(gained) or "no other judge"
    orbit_only = not int(ds.attrs.get("decisive_tangent", 1)) and set(gained) & {"megno", "section_megno"}
    more = (" for the orbit alone, more with the tangent vector MEGNO needs (not integrated at this horizon, "
            "where no tangent-based judge of the stage votes)") if orbit_only else ""
    return (text + f"; at {h / now:g} times the horizon the judge-power audit lets {who} vote as well: "
            f"T = {T * h / now:g} (vote_horizon {h:g}; config/cluster.yaml) would take about "
            f"{wall * h / now:.0f} s per realization{more}")


def _settle_note(ds, i: int) -> str:
    """For a state whose pre-run did not end its transient: that, and what comes before any longer horizon ("" for
    the others; the gauge's missing spike cycle is said by the arithmetic note)."""
    if "transient_over" not in ds or int(ds.transient_over.values[i]):
        return ""
    return (". Its transient was not over at the end of the pre-run: a longer pre-run (t_transient, in a "
            "--configfile overlay) comes before any longer horizon")


def _decided_in(ds, i: int) -> str:
    """The arithmetic state i was decided in: the decisive stage's, with G x rounding there, when it ran;
    else those of its indicators (MEGNO's, the frequency analysis') and which arithmetic follows its
    orbit by the faithfulness gauge; "" without them."""
    if _decisive_ran(ds, i):
        log10_gr = float(ds.decisive_log10_gain_rounding.values[i])
        gr = f"10^{log10_gr:.1f}" if np.isfinite(log10_gr) else "unknown (no complete spike cycle)"
        return (f"{ds.attrs['decisive_precision']} (G x rounding = {gr}; decisive stage over "
                f"T = {float(ds.attrs['decisive_T']):g})")
    parts = []
    if "megno_precision" in ds.data_vars:
        parts.append(f"MEGNO: {ds.megno_precision.values[i]}")
    if "frequency_precision" in ds.coords:
        parts.append("frequency analysis: " + ", ".join(str(p) for p in ds.frequency_precision.values))
    if "follows_orbit" in ds.data_vars:
        follow = [str(a) for a, f in zip(ds.arithmetic.values, ds.follows_orbit.values[i]) if f == "follows"]
        parts.append("follows the orbit: " + (", ".join(follow) if follow else
                                              "unknown" if (ds.follows_orbit.values[i] == "unknown").all() else "none"))
    return "; ".join(parts)


def _tori_note(ds, i: int) -> str:
    """The tori state i's realizations reached (their median spike intervals), or "" without them."""
    if "realization_spike_period" not in ds.data_vars:
        return ""
    periods = np.asarray(ds.realization_spike_period.values[:, i], float)
    if not np.isfinite(periods).any():
        return ". Tori reached: no two spikes within T_gain in any realization"
    return (f". Tori reached (median spike interval per realization, to about tau_gain = {ds.attrs['tau_gain']:g}): "
            + ", ".join(f"{p:.0f}" if np.isfinite(p) else "none" for p in periods))


def _arithmetic_note(ds, i: int) -> str:
    """Which arithmetic follows state i's orbit, from the faithfulness gauge (``follows_orbit``), or "" without it."""
    if "follows_orbit" not in ds.data_vars:
        return ""
    if not np.isfinite(ds.ln_gain_max.values[i]):
        return (". Faithfulness gauge: no complete spike cycle within T_gain, so which arithmetic follows the orbit "
                "is unknown")
    cells = [f"{a}: {ds.follows_orbit.values[i, k]} (G x rounding = 10^{ds.log10_gain_rounding.values[i, k]:.1f})"
             for k, a in enumerate(ds.arithmetic.values)]
    return f". Rounding amplified by ln G = {float(ds.ln_gain_max.values[i]):.1f} per spike cycle: " + "; ".join(cells)


def elsewhere(record: dict | None) -> list[str]:
    """The first screen's lines on a chaos verdict measured with another config (its record: per state, how
    many realizations gave each verdict, the arithmetic and horizon, the indicators that decided, the tori
    reached, the measured wall time and the commit)."""
    if not record:
        return []
    out = []
    for state in dict.fromkeys(r["state"] for r in record["realizations"]):
        rs = [r for r in record["realizations"] if r["state"] == state]
        counts = {v: sum(r["verdict"] == v for r in rs) for v in dict.fromkeys(r["verdict"] for r in rs)}
        said = sorted({k for r in rs for k, v in r["indicators"].items() if v == r["verdict"]})
        out.append(f"{state}, with {record['config']} (decisive stage in {rs[0]['precision']} over "
                   f"T = {rs[0]['T']:g}): "
                   + ", ".join(f"{v} in {n} of {len(rs)} realizations" for v, n in counts.items())
                   + f"; indicators saying so: {', '.join(said)}; G x rounding 10^"
                   + "/".join(f"{r['log10_gain_rounding']:.1f}" for r in rs) + "; tori reached (median spike interval) "
                   + ", ".join(f"{r['spike_period']:g}" for r in rs) + "; wall "
                   + ", ".join(f"{r['wall_time_s']:.0f}" for r in rs) + " s per realization; commit "
                   + ", ".join(sorted({r["git_commit"][:12] for r in rs})) + f", {rs[0]['created_utc'][:10]}")
    return out

def power_table(power: dict, path) -> Table:
    """The judge-power record as a table: per audited horizon factor, judge and class of known orbits, N and
    the counts and shares of correct, wrong (with the 95% upper bound) and undecided verdicts, and whether
    the judge votes at that horizon."""
    rows = []
    for h in sorted(float(h) for h in power["counts"]):
        votes = record_voting(power, h)
        rows += [[f"x{h:g}", r["judge"], r["class"], str(r["N"]), f"{r['correct']} ({r['p_correct']:.2f})",
                  f"{r['wrong']} ({r['p_wrong']:.3f}; <= {r['wrong_upper95']:.3f})",
                  f"{r['undecided']} ({r['p_undecided']:.2f})", "yes" if r["judge"] in votes else "no"]
                 for r in record_rates(power, h)]
    sources = "; ".join(f"commit {str(s['git_commit'])[:12]}, {s['created_utc']}" for s in power.get("sources", []))
    return Table(["horizon", "judge", "orbits", "N", "correct", "wrong (95% bound)", "undecided", "votes"], rows,
                 note=f"Measured on orbits of known class by the judge-power audit (scene judge_power; {sources}); "
                      f"record {Path(path).name}. A judge votes only when it is wrong at most 1 time in 100 on "
                      "each class, at the audited horizon (a factor on the chaos verdict's horizons) of the run.")
