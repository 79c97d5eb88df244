"""The reproduction report: results/report/index.html and README.md, rendered from the Jinja2
templates of ``report/templates`` (:mod:`sleighsim.report.page`).

The first screen answers a referee's two questions: which of the paper's claims hold (every claim
and model item as a badge by verdict, linked to its ledger row) and whether the steady state is
chaotic (per state, with the arithmetic it was decided in and the figure that shows why). Then the
precision findings, the paper's figures (our figure copied beside the page, the paper's caption
parsed from the LaTeX source, parameters, accuracy and run time from the datasets and Snakemake
benchmark files), the claims ledger, the methods figures with no counterpart in the paper, the
tables of :data:`sleighsim.report.tables.TABLES` and the run's cost. Every file it reads is passed in.
"""

from __future__ import annotations

import csv
import re
import shutil
from functools import partial
from pathlib import Path
from typing import NamedTuple

import numpy as np
import yaml

from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, TORI
from sleighsim.chaos.power import record_rates, record_voting
from sleighsim.claims.ledger import Row
from sleighsim.io.netcdf import atomic_path, read_dataset, write_text
from sleighsim.report.figures import costs as plots
from sleighsim.report.figures.catalog import FIGURES
from sleighsim.report.findings import precision_findings
from sleighsim.report.page import COLOURS, Table, math_html, render
from sleighsim.report.tables import TABLES

OUTCOME_COLOURS = {"reliable": COLOURS["reproduced"], "degraded": COLOURS["differs"],
                   "refused": COLOURS["not yet computed"]}
SETTINGS = ("param_eps", "param_b", "param_K2", "energy_label", "energy_physical", "backend", "method", "tol",
            "steps", "t_end", "T", "transient_over")
#: Groups of the claims grid, by the first letter of an id.
GROUPS = {"F": "Figures", "C": "Claims", "D": "Model as printed"}
#: The figure that shows why a chaos verdict is what it is, in order of preference.
WHY_FIGURES = ("precision", "chaos")

__all__ = ["build", "captions", "chaos_answers", "math_html"]


class ChaosAnswer(NamedTuple):
    """One steady state's chaos verdict: its name, verdict, why, the arithmetic it was decided in (with
    G x rounding there), its class, the indicators that decided it (with their arithmetic), and, when it
    is not decided, what would decide it and at what measured cost."""

    state: str
    verdict: str
    why: str
    arithmetic: str = ""
    klass: str = ""
    decided_by: str = ""
    to_decide: str = ""


def captions(tex_path) -> dict[str, str]:
    """{label: caption text} for every figure of the LaTeX source (balanced braces)."""
    text = Path(tex_path).read_text()
    out = {}
    for m in re.finditer(r"\\caption\{", text):
        depth, i = 1, m.end()
        while depth and i < len(text):
            depth += {"{": 1, "}": -1}.get(text[i], 0)
            i += 1
        body = text[m.end(): i - 1]
        label = re.search(r"\\label\{([^}]*)\}", body) or re.search(r"\\label\{([^}]*)\}", text[i: i + 200])
        if label:
            out[label.group(1)] = " ".join(re.sub(r"\\label\{[^}]*\}", "", body).split())
    return out


def _runtime(tsvs) -> float:
    """Total wall seconds of Snakemake benchmark files."""
    total = 0.0
    for tsv in tsvs:
        with Path(tsv).open() as fh:
            total += float(next(csv.DictReader(fh, delimiter="\t"))["s"])
    return total


def _scene_facts(datasets: dict, names) -> list[str]:
    """Per dataset: its parameters and settings, energy drift, wall time and commit."""
    facts = []
    for name in names:
        a = read_dataset(datasets[name]).attrs
        settings = ", ".join(f"{k.replace('param_', '')} = {a[k]:.4g}" if isinstance(a[k], float) else f"{k} = {a[k]}"
                             for k in SETTINGS if k in a)
        acc = f"max |dE/E| = {a['energy_max_rel_drift']:.2g}" if "energy_max_rel_drift" in a else ""
        facts.append(f"{name}: {settings}; {acc}; wall {a.get('wall_time_s', float('nan')):.3g} s; "
                     f"commit {str(a.get('git_commit', '?'))[:12]}")
    return facts


def _copy_figure(png: Path, out_dir: Path) -> str:
    """Copy the figure beside the page, atomically (a full disk leaves no truncated copy); its file
    name, or "" when it was not built."""
    if not png.exists():
        return ""
    with atomic_path(out_dir / png.name) as tmp:
        shutil.copy2(png, tmp)
    return png.name


def dataset_table(ds, key, cols, colour_of=None) -> Table:
    """A dataset's variables ``cols`` along ``key`` (first column), numbers to 3 digits."""
    rows, colours = [], []
    for i, first in enumerate(ds[key].values):
        vals = [ds[c].values[i] for c in cols]
        rows.append([str(first)] + [f"{v:.3g}" if isinstance(v, float) else str(v) for v in vals])
        colours.append(colour_of(vals) if colour_of else "")
    return Table([key, *cols], rows, colours)


def chaos_answers(datasets: dict, power: dict | None = None) -> list[ChaosAnswer]:
    """Per state of every dataset with per-state chaos verdicts (a ``state`` dimension with
    ``verdict``): its verdict and class, the arithmetic it was decided in and the orbit's faithfulness,
    the indicators that decided it (with their measured power when the judge-power record ``power`` is
    given), what would decide it when it is not decided, and the reason with the tori its realizations
    reached."""
    out = []
    for path in datasets.values():
        ds = read_dataset(path)
        if "verdict" not in ds.data_vars or "state" not in ds.dims:
            continue
        for i, st in enumerate(ds.state.values):
            reason = str(ds.reason.values[i]) if "reason" in ds.data_vars else ""
            verdict = str(ds.verdict.values[i])
            klass = str(ds.state_class.values[i]) if "state_class" in ds.data_vars else ""
            out.append(ChaosAnswer(str(st), verdict, reason + _arithmetic_note(ds, i) + _tori_note(ds, i),
                                   _decided_in(ds, i), klass, _decided_by(ds, i, power),
                                   _to_decide(ds, i, verdict, power)))
    return out


def _decisive_ran(ds, i: int) -> bool:
    """Whether state i of a verdict dataset went through the decisive stage."""
    return "decisive_verdict" in ds.data_vars and str(ds.decisive_verdict.values[i]) != "not run"


def _power_note(power: dict | None, judge: str, verdict: str) -> str:
    """A judge's measured power for a verdict, from the judge-power record: right on n of N orbits of the
    class the verdict names, wrong on m of M of the other; "" without the record or the judge in it."""
    if power is None:
        return ""
    rows = {r["class"]: r for r in record_rates(power, 1.0) if r["judge"] == judge}
    right, other = (TORI, CHAOTIC_ORBITS) if verdict == "regular" else (CHAOTIC_ORBITS, TORI)
    if right not in rows or other not in rows:
        return "; not audited"
    a, b = rows[right], rows[other]
    return (f"; says {verdict} on {a['correct']} of {a['N']} {right}, wrongly on {b['wrong']} of {b['N']} {other} "
            f"(95% bound {b['wrong_upper95']:.2g})")


def _decided_by(ds, i: int, power: dict | None = None) -> str:
    """The indicators whose verdict equals state i's (chaotic or regular), with the arithmetic each was
    judged in and its measured power (``_power_note``); "" when the state is not decided."""
    verdict = str(ds.verdict.values[i])
    if verdict not in ("chaotic", "regular") or "indicator_verdict" not in ds.data_vars:
        return ""
    names = {str(k): "double" for k, v in zip(ds.indicator.values, ds.indicator_verdict.values[i]) if v == verdict}
    if _decisive_ran(ds, i):
        names = {k: a for k, a in names.items() if k not in set(map(str, ds.decisive_indicator.values))}
        names.update({str(k): ds.attrs["decisive_precision"] for k, v in
                      zip(ds.decisive_indicator.values, ds.decisive_indicator_verdict.values[i]) if v == verdict})
    return ", ".join(f"{k} ({a}{_power_note(power, k, verdict)})" for k, a in sorted(names.items()))


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


def answers(rows: list[Row], datasets: dict, figures: dict, power: dict | None = None, n_largest: int = 5,
            cluster: dict | None = None) -> dict:
    """The first screen: the claims grid by group with the verdict counts (one denominator, every
    row), the chaos answer per state with the figure that shows why, and the largest differences with
    their tested causes."""
    chaos = chaos_answers(datasets, power)
    counts = {v: sum(r.verdict == v for r in rows) for v in COLOURS}
    return {
        "groups": [(name, [r for r in rows if r.id[0] == g]) for g, name in GROUPS.items()
                   if any(r.id[0] == g for r in rows)],
        "counts": [(v, n) for v, n in counts.items() if n],
        "n_rows": len(rows),
        "chaos": chaos,
        "elsewhere": elsewhere(cluster),
        "why_figure": next((f for f in WHY_FIGURES if f in figures), ""),
        "differs": sorted((r for r in rows if r.verdict == "differs" and np.isfinite(r.difference)),
                          key=lambda r: -r.difference)[:n_largest],
    }


def build(rows: list[Row], *, out_dir, tex_path, labels: dict, figures: dict, datasets: dict,
          benchmarks: dict, power_record=None, cluster_record=None) -> None:
    """Write index.html and README.md into ``out_dir`` with the figures copied beside them.

    labels: {figure: paper LaTeX label}; figures: {figure: PNG path} of the figures built;
    datasets: {dataset: netCDF path}; benchmarks: {"data/<dataset>" or "figure/<figure>": [Snakemake
    benchmark files]}; power_record: the judge-power record the chaos verdict voted by (its table and the
    deciding judges' power); cluster_record: a chaos verdict measured with another config, cited on the
    first screen (``elsewhere``)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    power = yaml.safe_load(Path(power_record).read_text()) if power_record else None
    context = {
        "answers": answers(rows, datasets, figures, power,
                           cluster=yaml.safe_load(Path(cluster_record).read_text()) if cluster_record else None),
        "findings": precision_findings(rows, datasets),
        "paper_figures": paper_figures(rows, out_dir=out_dir, tex_path=tex_path, labels=labels, figures=figures,
                                       datasets=datasets, benchmarks=benchmarks),
        "ledger": rows,
        "other_figures": other_figures(out_dir, figures, datasets),
        "tables": tables(datasets, power, power_record or ""),
        "costs_image": run_cost(benchmarks, out_dir),
    }
    write_text(out_dir / "index.html", render("report.html.j2", **context))
    write_text(out_dir / "README.md", render("report.md.j2", **context))


def paper_figures(rows: list[Row], *, out_dir, tex_path, labels, figures, datasets, benchmarks) -> list[dict]:
    """The paper's figures, each with the paper's caption, its verdict, the claims it illustrates,
    the facts of its datasets and its run time."""
    caps = captions(tex_path)
    by_id = {r.id: r for r in rows}
    out = []
    for fig in (f for f in figures if FIGURES[f].paper):
        names = list(FIGURES[fig].data)
        row = by_id.get(FIGURES[fig].paper)
        run = _runtime(t for key in [f"data/{n}" for n in names] + [f"figure/{fig}"] for t in benchmarks.get(key, []))
        out.append({"id": fig, "paper": FIGURES[fig].paper, "verdict": row.verdict if row else "not yet computed",
                    "caption": caps.get(labels.get(fig, ""), "(no counterpart in the paper)"),
                    "claims": [by_id[c] for c in FIGURES[fig].claims if c in by_id],
                    "image": _copy_figure(Path(figures[fig]), out_dir), "facts": _scene_facts(datasets, names),
                    "run_s": run})
    return out


def other_figures(out_dir, figures, datasets) -> list[dict]:
    """The methods figures with no counterpart in the paper, with the speed tables of their datasets."""
    out = []
    for fig in (f for f in figures if not FIGURES[f].paper):
        speed = [read_dataset(datasets[n]) for n in FIGURES[fig].data]
        out.append({"id": fig, "title": FIGURES[fig].title, "image": _copy_figure(Path(figures[fig]), out_dir),
                    "tables": [fastest_table(d) for d in speed if any(k.startswith("fastest_at_") for k in d.attrs)]
                    + [peer_table(d) for d in speed if "peer_ratio" in d]})
    return out


def _outcome_colour(k: int, vals) -> str:
    """The colour of a row's outcome, the ``k``-th of its values ``vals`` ("" for no known outcome)."""
    return OUTCOME_COLOURS.get(str(vals[k]), "")


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


def tables(datasets, power: dict | None = None, power_path="") -> list[dict]:
    """The report's tables (:data:`sleighsim.report.tables.TABLES`), or the dataset that would hold each;
    then the judge-power record's (``power_table``) when given."""
    out = [] if power is None else [{"title": "Judges' power and false rates (who votes on chaos)",
                                     "data": "judge_power", "table": power_table(power, power_path)}]
    for title, table in TABLES.items():
        content = None
        if table.data in datasets:
            colour = partial(_outcome_colour, table.columns.index(table.colour_by)) if table.colour_by else None
            content = dataset_table(read_dataset(datasets[table.data]), table.key, table.columns, colour)
        out.append({"title": title, "data": table.data, "table": content})
    return out


def run_cost(benchmarks: dict, out_dir: Path) -> str:
    """The run's cost per job from Snakemake's benchmark records, drawn beside the page; the image's
    file name, or "" (and no stale figure from an earlier run) without records."""
    jobs = plots.job_costs(benchmarks)
    if not jobs:
        for stale in ("costs.png", "costs.pdf"):
            (out_dir / stale).unlink(missing_ok=True)
        return ""
    plots.plot_job_costs(jobs, out_dir / "costs.png")
    return "costs.png"


def fastest_table(ds) -> Table:
    """The fastest method per error target and its speed ratio to the fastest SciPy method."""
    a = ds.attrs
    targets = [k.removeprefix("fastest_at_") for k in sorted(a) if k.startswith("fastest_at_")]
    ratios = [a.get("speedup_vs_scipy_at_" + t) for t in targets]
    return Table([f"error target (t = {a['t_short']:g})", "fastest", "speed ratio to the fastest SciPy method"],
                 [[t, str(a["fastest_at_" + t]), f"{r:.0f}x" if np.isfinite(r) else "no SciPy run reaches it"]
                  for t, r in zip(targets, ratios)],
                 title="Fastest method per error target",
                 note=f"Engine overhead over a bare propagation: {a['overhead_overhead_ratio']:.2f}")


def peer_table(ds) -> Table:
    """Each peer's fastest wall reaching each error target over heyoka's, compile times beside."""
    peers, compile_s = [str(p) for p in ds.peer.values], ds.peer_engine_compile_s.values
    head = ["error target"] + [f"{p} (compile {c:.2g} s)" for p, c in zip(peers, compile_s)]
    rows = [[f"{t:.0e}"] + [f"{r:.3g}x" if np.isfinite(r) else "not reached" for r in ds.peer_ratio.values[i]]
            for i, t in enumerate(ds.error_target.values)]
    return Table(head, rows, title="Speed ratio of each peer to heyoka",
                 note=f"{ds.attrs['peer_ratio_rule']}; versions: {ds.attrs['peer_versions']}")
