"""The report's precision findings, composed from the datasets (never typed by hand): for each
steady state, what the paper claims, what double precision shows, what the finer arithmetic shows,
and the mechanism (how much one spike cycle amplifies rounding)."""

from __future__ import annotations

import html
import math

import numpy as np

from ..io import read_dataset
from ..symmetries import REFERENCE_STATE


def _interval(ds, k: int, j: int) -> str:
    m, s = float(ds.interval_mean.values[k, j]), float(ds.interval_sd.values[k, j])
    return "no spike train within the run" if not math.isfinite(m) else f"{m:.1f} +- {s:.1f}"


def _state_sentences(ladder, verdict, k: int, paper_interval: str) -> list[str]:
    """The findings for state k of the precision ladder (and, when given, the chaos verdict with its gauge)."""
    st = str(ladder.state.values[k])
    precs = [str(p) for p in ladder.precision.values]
    out = [f"Spike interval (mean +- sd of the intervals, from one settled point over T = {ladder.attrs['T']:g}): "
           + "; ".join(f"{p} {_interval(ladder, k, j)}" for j, p in enumerate(precs))
           + f" (the paper: {paper_interval}). Converged precision: {ladder.converged_precision.values[k]}."]
    for i, pair in enumerate(ladder.pair.values):
        t = float(ladder.t_separated.values[k, i])
        out.append(f"The {pair} orbits " + (f"separate (1e-3) at t = {t:g}." if math.isfinite(t)
                                            else "stay within 1e-3 over the whole run."))
    if verdict is not None and st in verdict.state.values and "ln_gain_max" in verdict:
        i = list(verdict.state.values).index(st)
        g = float(verdict.ln_gain_max.values[i])
        if math.isfinite(g):
            cells = [f"{a} {verdict.follows_orbit.values[i, j]} (G x rounding 10^{verdict.log10_gain_rounding.values[i, j]:.1f})"
                     for j, a in enumerate(verdict.arithmetic.values)]
            out.append(f"Mechanism: one spike cycle amplifies errors by up to e^{g:.1f}; " + "; ".join(cells) + ".")
        out.append(f"Chaos verdict: {verdict.verdict.values[i]} ({verdict.reason.values[i].split(';')[0]}).")
    return out


def precision_findings(rows: list, datasets: dict) -> tuple[list[str], list[str]]:
    """The findings section (HTML lines, Markdown lines); a note when the precision ladder was not run."""
    h = ["<section id='findings'><h3>Does the arithmetic decide the steady state?</h3>"]
    md = ["### Does the arithmetic decide the steady state?", ""]
    if "precision_ladder" not in datasets:
        h.append("<p>not yet computed (no precision-ladder dataset in this run)</p></section>")
        return h, md + ["not yet computed (no precision-ladder dataset in this run)", ""]
    ladder = read_dataset(datasets["precision_ladder"])
    verdict = read_dataset(datasets["chaos_verdict"]) if "chaos_verdict" in datasets else None
    paper = next((r.paper_value for r in rows if r.id == "C05"), "not stated")
    for k, st in enumerate(ladder.state.values):
        from_reference = np.array_equal(ladder.start.values[k], np.asarray(REFERENCE_STATE, float))
        claim = f"{paper} (C05)" if from_reference else "no value for this state"
        sentences = _state_sentences(ladder, verdict, k, claim)
        h.append(f"<p><b>{html.escape(str(st))}</b>: " + " ".join(html.escape(s) for s in sentences) + "</p>")
        md += [f"- **{st}**: " + " ".join(sentences)]
    h.append("</section>")
    return h, md + [""]
