"""The report's precision findings, composed from the datasets (never typed by hand): for each
steady state, what the paper claims, what double precision shows, what the finer arithmetic shows,
and the mechanism (how much one spike cycle amplifies rounding). Data for the report's templates."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from sleighsim.analysis.observables import SEPARATED
from sleighsim.claims import setup_columns
from sleighsim.claims.rules import REPRODUCED
from sleighsim.io import layout
from sleighsim.io.netcdf import read_dataset
from sleighsim.model.symmetries import REFERENCE_STATE
from sleighsim.report.page import Table
from sleighsim.scenes.ladder import PRECISION_LADDER
from sleighsim.scenes.paper_setup import PAPER_SETUP
from sleighsim.scenes.verdict import CHAOS_VERDICT


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
        out.append(f"The {pair} orbits " + (f"separate ({SEPARATED:g}) at t = {t:g}." if math.isfinite(t)
                                            else f"stay within {SEPARATED:g} over the whole run."))
    if verdict is not None and st in verdict.state.values and "ln_gain_max" in verdict:
        i = list(verdict.state.values).index(st)
        g = float(verdict.ln_gain_max.values[i])
        if math.isfinite(g):
            cells = [f"{a} {verdict.follows_orbit.values[i, j]} "
                     f"(G x rounding 10^{verdict.log10_gain_rounding.values[i, j]:.1f})"
                     for j, a in enumerate(verdict.arithmetic.values)]
            out.append(f"Mechanism: one spike cycle amplifies errors by up to e^{g:.1f}; " + "; ".join(cells) + ".")
        out.append(f"Chaos verdict: {verdict.verdict.values[i]} ({verdict.reason.values[i].split(';')[0]}).")
    return out


def _cell(value: float, uncertainty: float) -> str:
    return f"{value:.6g}" if uncertainty == 0 else f"{value:.6g} +- {uncertainty:.2g}"


def scene_ladders(datasets: dict) -> Table | None:
    """The ladders of the steady-state scenes (datasets ``ladder/<scene>``): each key observable per
    precision with its stated uncertainty and the precision it converges in, then one row per scene
    saying when the sampled orbits separate and which arithmetic follows them. None when no scene
    was laddered."""
    names = sorted(n for n in datasets if layout.is_ladder(n))
    if not names:
        return None
    rows = []
    for name in names:
        ds = read_dataset(datasets[name])
        scene = layout.scene_of(name)
        for k, obs in enumerate(ds.observable.values):
            cells = "; ".join(f"{p}: {_cell(float(ds.value.values[j, k]), float(ds.uncertainty.values[j, k]))}"
                              for j, p in enumerate(ds.precision.values))
            rows.append([scene, str(obs), cells, str(ds.converged_precision_of.values[k])])
        rows.append([scene, "the scene", _ladder_summary(ds), str(ds.attrs["converged_precision"])])
    return Table(["scene", "observable", "values per precision", "converged in"], rows,
                 note="Steady-state scenes, each computed in every precision from one settled point (value +- the "
                      "uncertainty each observable states, sleighsim.analysis.observables).")


def _ladder_summary(ds) -> str:
    """When a scene ladder's orbits separate, and which arithmetic follows them (faithfulness gauge)."""
    sep = ([f"{pair}: " + (f"separate ({SEPARATED:g}) at t = {t:g} after the settled point" if math.isfinite(t)
                           else f"within {SEPARATED:g} over the sampled stretch")
            for pair, t in zip(ds.pair.values, ds.t_separated.values)] if "t_separated" in ds else [])
    out = f"orbits {'; '.join(sep)}" if sep else "no orbit comparison"
    if "follows_orbit" in ds and math.isfinite(ds.attrs["ln_gain_max"]):
        span = ds.attrs.get("gain_span", "one spike cycle")
        out += (f"; over {span} the flow amplifies errors by up to e^{ds.attrs['ln_gain_max']:.1f}: "
                + ", ".join(f"{p} {f}" for p, f in zip(ds.precision.values, ds.follows_orbit.values)))
    elif "follows_orbit" in ds:
        out += f"; no complete spike cycle within T_gain = {ds.attrs['T_gain']:g}: faithfulness unknown"
    return out


def of_kind(datasets: dict, kinds: dict, kind) -> Path | None:
    """The path of the first of ``datasets`` (name -> path) whose scene is of ``kind`` (a SceneKind;
    ``kinds``: scene -> its kind's name, from the config), None when there is none."""
    return next((path for name, path in datasets.items() if kinds.get(name) == kind.name), None)


def precision_findings(rows: list, datasets: dict, kinds: dict) -> dict:
    """The findings: per state of the verdict states' precision ladder (``states``: [(state,
    sentences)]; empty and ``missing`` true when it was not run), then the steady-state scenes'
    ladders (``ladders``, a Table or None), and the paragraph on the paper's inferred setup (``setup``).
    ``kinds``: scene -> its kind's name (the config's), which finds each dataset by its kind."""
    ladder_path = of_kind(datasets, kinds, PRECISION_LADDER)
    out = {"states": [], "missing": ladder_path is None, "ladders": scene_ladders(datasets),
           "setup": setup_paragraph(rows, of_kind(datasets, kinds, PAPER_SETUP))}
    if out["missing"]:
        return out
    ladder = read_dataset(ladder_path)
    verdict_path = of_kind(datasets, kinds, CHAOS_VERDICT)
    verdict = read_dataset(verdict_path) if verdict_path is not None else None
    paper = next((r.paper_value for r in rows if r.id == "C05"), "not stated")
    for k, st in enumerate(ladder.state.values):
        from_reference = np.array_equal(ladder.start.values[k], np.asarray(REFERENCE_STATE, float))
        claim = f"{paper} (C05)" if from_reference else "no value for this state"
        out["states"].append((str(st), _state_sentences(ladder, verdict, k, claim)))
    return out


SETUP_ELEMENTS = ("K2", "integrator", "psd", "energy", "lyapunov")


def _holds_under_setup(verdict: str) -> bool:
    """Whether a ledger row's paper_setup_verdict says the claim holds under the inferred setup."""
    return verdict.startswith((setup_columns.BOTH, setup_columns.PAPER_ONLY))


def setup_counts(rows: list) -> dict:
    """The rows the inferred setup moves (``ids``), those that hold under it (``setup``) and under
    converged physics (``converged``), and the whole ledger's reproduced counts under each."""
    moved = [r for r in rows if r.paper_setup_verdict and not r.paper_setup_verdict.startswith(
        (setup_columns.NOT_APPLICABLE, setup_columns.NOT_INFERRED))]
    setup = [r.id for r in moved if _holds_under_setup(r.paper_setup_verdict)]
    converged = [r.id for r in moved if r.verdict == REPRODUCED]
    total_conv = sum(r.verdict == REPRODUCED for r in rows)
    return {"ids": [r.id for r in moved], "setup": setup, "converged": converged, "n_rows": len(rows),
            "total_converged": total_conv, "total_setup": total_conv - len(converged) + len(setup)}


def setup_paragraph(rows: list, path) -> str:
    """One paragraph from the paper-setup dataset at ``path`` and the ledger: the setup the paper's numbers
    fit, its gaps to the runners-up, and how many claims hold under it and under converged physics (""
    without the dataset, ``path`` None)."""
    if path is None:
        return ""
    ds = read_dataset(path)
    a = ds.attrs
    if "best_K2" not in a:
        return f"The paper's setup is not inferred in this run: {a.get('n_setups_note', 'no setup ranked')}."
    c = setup_counts(rows)
    elements = "; ".join(
        f"{e} {a[f'best_{e}']:.6g} (within 1 of the least deviance: {a['best_K2_low']:.6g} to {a['best_K2_high']:.6g};"
        f" with the sigmas inflated by the misfit, x {a['misfit_scale']:.3g}: {a['best_K2_low_scaled']:.6g} to "
        f"{a['best_K2_high_scaled']:.6g}; this run {a['baseline_K2']:.4g})" if e == "K2" else
        f"{e}: {a[f'best_{e}']} (next: {a[f'runner_up_{e}']}, deviance +{a[f'gap_{e}']:.3g})" for e in SETUP_ELEMENTS)
    pulls = ds.where(ds.scored == 1, drop=True)
    order = np.argsort(-np.abs(pulls.best_residual.values))[:3]
    pull_text = ", ".join(f"{pulls.paper_number.values[i]} ({pulls.best_residual.values[i]:+.3g} sigma)"
                          for i in order)
    return (f"The paper's numbers fit this setup best (deviance {a['deviance_best']:.4g}, against "
            f"{a['deviance_baseline']:.4g} for this run's own setup; {a['n_ranked']} of {a['n_setups']} setups "
            f"ranked): {elements}. Under it, {len(c['setup'])} of the {len(c['ids'])} claims whose numbers it moves "
            f"hold ({', '.join(c['setup']) or 'none'}); under converged physics, {len(c['converged'])} hold "
            f"({', '.join(c['converged']) or 'none'}); over the whole ledger, {c['total_setup']} of {c['n_rows']} rows "
            f"against {c['total_converged']}. The numbers that pull hardest against it: {pull_text}. "
            f"{_start_sentence(a)} Separability: {a['separability']}")


def _start_sentence(a) -> str:
    """Which start the paper ran (paper_setup's start test), with the T1 a rescaled start would give."""
    if "start" not in a:
        return ""
    T1, res = np.asarray(a["start_T1"], float), np.asarray(a["start_T1_residual"], float)
    return (f"Start: {a['start']} (C08's T1 {T1[0]:.4g}, {res[0]:+.2g} sigma; a start rescaled to the paper's energy "
            f"label under the audit's normalisations would give T1 from {T1[1:].min():.4g} to {T1[1:].max():.4g}, "
            f"{np.abs(res[1:]).min():.3g} sigma or more).")
