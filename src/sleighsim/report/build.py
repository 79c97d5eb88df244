"""The reproduction report: results/report/index.html and README.md, rendered from the Jinja2
templates of ``report/templates`` (:mod:`sleighsim.report.page`).

Its first line names the run's configuration (label and hash, :mod:`sleighsim.claims.fidelity`) and, for a
run not at the paper's fidelity (the smoke run), says that it is not a reproduction; then the finding in one
paragraph (:mod:`sleighsim.report.finding`).
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

import numpy as np
import yaml

from sleighsim.claims import fidelity
from sleighsim.claims.ledger import Row
from sleighsim.claims.rules import DIFFERING, MEANINGS, REPRODUCED, VERDICTS
from sleighsim.io.netcdf import atomic_path, read_dataset, write_text
from sleighsim.io.yamlfile import read_yaml
from sleighsim.report import finding
from sleighsim.report.chaos_answers import chaos_answers, elsewhere, power_table
from sleighsim.report.figures import costs as plots
from sleighsim.report.figures.catalog import FIGURES
from sleighsim.report.findings import precision_findings
from sleighsim.report.page import COLOURS, MARKS, Table, math_html, render
from sleighsim.report.paper_orbit import paper_orbit
from sleighsim.report.tables import TABLES

OUTCOME_COLOURS = {"reliable": COLOURS["reproduced"], "degraded": COLOURS["differs"],
                   "refused": COLOURS["not yet computed"]}
SETTINGS = ("param_eps", "param_b", "param_K2", "energy_label", "energy_physical", "backend", "method", "tol",
            "steps", "t_end", "T", "transient_over")
#: Groups of the claims grid, by the first letter of an id.
GROUPS = {"F": "Figures", "C": "Claims", "D": "Model as printed"}
#: The figure that shows why a chaos verdict is what it is, in order of preference.
WHY_FIGURES = ("precision", "chaos")

__all__ = ["build", "captions", "math_html"]


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
    """Per dataset: its parameters and settings, energy drift, wall time and commit (what a dataset does
    not record is left out)."""
    facts = []
    for name in names:
        a = read_dataset(datasets[name]).attrs
        settings = ", ".join(f"{k.replace('param_', '')} = {a[k]:.4g}" if isinstance(a[k], float) else f"{k} = {a[k]}"
                             for k in SETTINGS if k in a)
        wall = float(a.get("wall_time_s", np.nan))
        drift = float(a.get("energy_max_rel_drift", np.nan))
        parts = [settings, f"max |dE/E| = {drift:.2g}" if np.isfinite(drift) else "",
                 f"wall {wall:.3g} s" if np.isfinite(wall) else "", f"commit {str(a.get('git_commit', '?'))[:12]}"]
        facts.append(f"{name}: " + "; ".join(p for p in parts if p))
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



def answers(rows: list[Row], datasets: dict, figures: dict, power: dict | None = None, n_largest: int = 5,
            cluster: dict | None = None) -> dict:
    """The first screen: the claims grid by group with the verdict counts (one denominator, every
    row), the chaos answer per state with the figure that shows why, and the largest differences with
    their tested causes."""
    chaos = chaos_answers(datasets, power)
    counts = {v: sum(r.verdict == v for r in rows) for v in VERDICTS}
    return {
        "groups": [(name, [r for r in rows if r.id[0] == g]) for g, name in GROUPS.items()
                   if any(r.id[0] == g for r in rows)],
        "counts": [(v, n) for v, n in counts.items() if n],
        "n_rows": len(rows),
        "chaos": chaos,
        "elsewhere": elsewhere(cluster),
        "why_figure": next((f for f in WHY_FIGURES if f in figures), ""),
        "legend": [(v, MARKS[v], MEANINGS[v]) for v in VERDICTS],
        "differs": sorted((r for r in rows if r.verdict in DIFFERING and np.isfinite(r.difference)),
                          key=lambda r: -r.difference)[:n_largest],
        **faithful_screen(rows),
    }


def faithful_screen(rows: list[Row]) -> dict:
    """The first screen's answer to the chaos claims judged in an arithmetic that follows each orbit (the
    ledger's faithful columns, :mod:`sleighsim.claims.faithful`): the claims (C..) with a faithful verdict,
    how many hold ("reproduced") and the count of each verdict."""
    judged = finding.faithful_claims(rows)
    counts = {v: sum(r.faithful_verdict == v for r in judged) for v in VERDICTS}
    return {"faithful": judged, "faithful_hold": counts[REPRODUCED],
            "faithful_counts": [(v, n) for v, n in counts.items() if n]}


def run_line(identity: dict) -> dict:
    """The report's first line: the run's configuration (``identity``: :func:`sleighsim.claims.fidelity.identity`)
    and whether it is judged against the paper (``reproduction``), in words (``text``)."""
    against = fidelity.at_paper_fidelity(identity["config_label"])
    config = fidelity.describe(identity)
    text = (f"A run of {config}, judged against the paper's numbers." if against else
            f"A {identity['config_label']} run ({config}): NOT a reproduction of the paper. Its horizons are not the "
            "paper's; every claim reads \"not a reproduction\", and the verdict its own data give stands beside it "
            "in the ledger (column \"this run's data\"). Run at the paper's fidelity for a reproduction.")
    return {**identity, "reproduction": against, "text": text}


def build(rows: list[Row], *, out_dir, tex_path, labels: dict, figures: dict, datasets: dict, kinds: dict,
          benchmarks: dict, identity: dict, power_record=None, cluster_record=None) -> None:
    """Write index.html and README.md into ``out_dir`` with the figures copied beside them, and the
    finding's facts as finding.yaml (:mod:`sleighsim.report.finding`; its paragraph opens the page).

    identity: the run's configuration (its label and hash, :func:`sleighsim.claims.fidelity.identity`);
    labels: {figure: paper LaTeX label}; figures: {figure: PNG path} of the figures built;
    datasets: {dataset: netCDF path}; kinds: {scene: its kind's name} (the config's); benchmarks:
    {"data/<dataset>" or "figure/<figure>": [Snakemake
    benchmark files]}; power_record: the judge-power record the chaos verdict voted by (its table and the
    deciding judges' power); cluster_record: a chaos verdict measured with another config, cited on the
    first screen (``elsewhere``)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    power = read_yaml(power_record) if power_record else None
    cluster = read_yaml(cluster_record) if cluster_record else None
    first = answers(rows, datasets, figures, power, cluster=cluster)
    found = finding.facts(rows, first["chaos"], cluster, identity, finding.provenance(datasets),
                          orbit=paper_orbit(datasets, kinds))
    write_text(out_dir / "finding.yaml", yaml.safe_dump(found, sort_keys=False, width=120))
    context = {
        "run": run_line(identity),
        "finding": finding.paragraph(found),
        "answers": first,
        "findings": precision_findings(rows, datasets, kinds),
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
                    "reason": (row.reason or row.measured) if row else "no ledger row",
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


def tables(datasets, power: dict | None = None, power_path="") -> list[dict]:
    """The report's tables (:data:`sleighsim.report.tables.TABLES`), or the dataset that would hold each;
    then the judge-power record's (``power_table``) when given."""
    out = [] if power is None else [{"title": "Judges' power and false rates (who votes on chaos)",
                                     "data": Path(power_path).name, "table": power_table(power, power_path)}]
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
