"""The reproduction report: results/report/index.html and README.md.

Per figure of :data:`sleighsim.registry.FIGURES`: our figure (copied beside the page), the
paper's caption (parsed from the LaTeX source), parameters and numerical settings, accuracy
and run time, read from the datasets and Snakemake benchmark files; then the claims ledger,
the figures with no counterpart in the paper, speed against error and the tables of
:data:`sleighsim.registry.TABLES`. Every file it reads is passed in explicitly.
"""

from __future__ import annotations

import csv
import html
import re
import shutil
from pathlib import Path

import latex2mathml.converter
import numpy as np
import yaml

from ..ops import plots
from ..io import read_dataset
from ..registry import FIGURES, TABLES
from .claims import Row
from .findings import precision_findings

COLOURS = {"reproduced": "#d4edda", "reproduced only in double precision": "#ffe0b2", "differs": "#fff3cd",
           "fragile": "#e1d5f0", "cannot be reproduced": "#f8d7da", "not yet computed": "#e2e3e5"}
OUTCOME_COLOURS = {"reliable": COLOURS["reproduced"], "degraded": COLOURS["differs"],
                   "refused": COLOURS["not yet computed"]}
SETTINGS = ("param_eps", "param_b", "param_K2", "energy_label", "energy_physical", "backend", "method", "tol",
            "steps", "t_end", "T", "transient_over")


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
    facts = []
    for name in names:
        a = read_dataset(datasets[name]).attrs
        settings = ", ".join(f"{k.replace('param_', '')} = {a[k]:.4g}" if isinstance(a[k], float) else f"{k} = {a[k]}"
                             for k in SETTINGS if k in a)
        acc = f"max |dE/E| = {a['energy_max_rel_drift']:.2g}" if "energy_max_rel_drift" in a else ""
        facts.append(f"{name}: {settings}; {acc}; wall {a.get('wall_time_s', float('nan')):.3g} s; "
                     f"commit {str(a.get('git_commit', '?'))[:12]}")
    return facts


def _embed(png: Path, out_dir: Path, name: str, h: list, md: list) -> None:
    """Copy the figure beside the page and reference it, or say it is not yet computed."""
    if png.exists():
        shutil.copy2(png, out_dir / png.name)
        h.append(f"<img src='{png.name}' alt='{name}'>")
        md.append(f"![{name}]({png.name})")
    else:
        h.append("<p><b>not yet computed</b></p>")
        md.append("**not yet computed**")


def _table(ds, key, cols, colour_of=None) -> tuple[list[str], list[str]]:
    """HTML and Markdown tables of a dataset's variables ``cols`` along ``key`` (first column)."""
    h = [f"<table><tr><th>{key}</th>" + "".join(f"<th>{c}</th>" for c in cols) + "</tr>"]
    md = [f"| {key} | " + " | ".join(cols) + " |", "|" + "---|" * (len(cols) + 1)]
    for i, first in enumerate(ds[key].values):
        vals = [ds[c].values[i] for c in cols]
        txt = [f"{v:.3g}" if isinstance(v, float) else str(v) for v in vals]
        style = f" style='background:{colour_of(vals)}'" if colour_of else ""
        h.append(f"<tr{style}><td>{html.escape(str(first))}</td>"
                 + "".join(f"<td>{html.escape(t)}</td>" for t in txt) + "</tr>")
        md.append(f"| {first} | " + " | ".join(t.replace("|", "/") for t in txt) + " |")
    h.append("</table>")
    return h, md


def math_html(text: str) -> str:
    """HTML of caption text: ``$...$`` rendered as MathML (latex2mathml, offline), the rest escaped."""
    parts = re.split(r"(\$[^$]+\$)", text)
    out = []
    for part in parts:
        if len(part) > 2 and part[0] == part[-1] == "$":
            try:
                out.append(latex2mathml.converter.convert(part[1:-1]))
            except Exception:  # noqa: BLE001 - a formula the converter rejects is shown as text, without $
                out.append(html.escape(part[1:-1]))
        else:
            out.append(html.escape(part))
    return "".join(out)


def _badge(verdict: str) -> str:
    return f"<span class='badge' style='background:{COLOURS.get(verdict, '#fff')}'>{html.escape(verdict)}</span>"


def chaos_answers(datasets: dict) -> list[tuple[str, str, str]]:
    """(state, verdict, reason) from every dataset that carries a chaos verdict: per state (a
    ``state`` dimension with ``verdict`` and ``reason``) or one verdict in the attributes."""
    out = []
    for name, path in datasets.items():
        ds = read_dataset(path)
        if "verdict" in ds.data_vars and "state" in ds.dims:
            for i, st in enumerate(ds.state.values):
                reason = str(ds.reason.values[i]) if "reason" in ds.data_vars else ""
                out.append((f"{name}: {st}", str(ds.verdict.values[i]),
                            reason + _arithmetic_note(ds, i) + _tori_note(ds, i)))
        elif "verdict" in ds.attrs and "chaotic" in str(ds.attrs.get("rule", "")) + str(ds.attrs["verdict"]):
            out.append((name, str(ds.attrs["verdict"]), str(ds.attrs.get("rule", ""))))
    return out


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
        return ". Faithfulness gauge: no complete spike cycle within T_gain, so which arithmetic follows the orbit is unknown"
    cells = [f"{a}: {ds.follows_orbit.values[i, k]} (G x rounding = 10^{ds.log10_gain_rounding.values[i, k]:.1f})"
             for k, a in enumerate(ds.arithmetic.values)]
    return f". Rounding amplified by ln G = {float(ds.ln_gain_max.values[i]):.1f} per spike cycle: " + "; ".join(cells)


def decisive_cost(precision_cost, cluster_config) -> str:
    """What the quad frequency run the default config leaves to the cluster config costs: its horizon
    there (chaos_verdict.frequency.quad_T) times quad's measured cost per time unit (the flow in
    compact mode, benchmarks/precision_cost.yaml; one core), per state and realization."""
    cost = yaml.safe_load(Path(precision_cost).read_text())
    per_tu = next(r["cost_s_per_tu"] for r in cost["rows"]
                  if (r["system"], r["precision"], r["compact_mode"], r["high_accuracy"]) == ("flow", "quad", True, False))
    quad_T = yaml.safe_load(Path(cluster_config).read_text())["scenes"]["chaos_verdict"]["frequency"]["quad_T"]
    return (f"The decisive computation left to {Path(cluster_config).name}, frequency analysis in quad over quad_T = "
            f"{quad_T:g} time units, costs {per_tu:.2g} s per time unit on one core of the measuring machine "
            f"({cost['machine']['cpu_model']}, {str(cost['date'])[:10]}; benchmarks/precision_cost.yaml): about "
            f"{quad_T * per_tu / 60:.0f} min per state and realization.")


def _answers(rows: list[Row], datasets: dict, n_largest: int = 5, decisive: str = "") -> tuple[list[str], list[str]]:
    """The report's first section: is the steady state chaotic (with ``decisive``, what the run that
    would decide an undecided state costs, when a verdict says its quad run was not made), how many
    claims are reproduced, the largest differences with their tested causes."""
    counts = {v: sum(r.verdict == v for r in rows) for v in COLOURS}
    claims_only = [r for r in rows if r.id[0] in "CD"]
    reproduced = sum(r.verdict == "reproduced" for r in claims_only)
    differs = sorted((r for r in rows if r.verdict == "differs" and np.isfinite(r.difference)),
                     key=lambda r: -r.difference)[:n_largest]
    chaos = chaos_answers(datasets)
    h = ["<section id='answers'><h2>Answers</h2><h3>Is the steady state chaotic?</h3>"]
    md = ["## Answers", "", "### Is the steady state chaotic?", ""]
    if chaos:
        h.append("<table><tr><th>steady state</th><th>verdict</th><th>evidence</th></tr>" + "".join(
            f"<tr><td>{html.escape(st)}</td><td>{_badge(v)}</td><td>{html.escape(why)}</td></tr>" for st, v, why in chaos)
            + "</table>")
        md += [f"- **{st}**: {v}. {why}" for st, v, why in chaos]
        if decisive and any("quad run not made" in why for _, _, why in chaos):
            h.append(f"<p>{html.escape(decisive)}</p>")
            md += ["", decisive]
    else:
        h.append("<p>not yet computed (no chaos-verdict dataset in this run)</p>")
        md.append("not yet computed (no chaos-verdict dataset in this run)")
    h.append(f"<h3>How many claims are reproduced?</h3><p>{reproduced} of {len(claims_only)} claims and model "
             "items; all rows: " + ", ".join(f"{_badge(v)} {n}" for v, n in counts.items()) + "</p>")
    md += ["", "### How many claims are reproduced?", "",
           f"{reproduced} of {len(claims_only)} claims and model items; all rows: "
           + ", ".join(f"{v}: {n}" for v, n in counts.items()), "", "### The largest differences and their tested causes", ""]
    h.append("<h3>The largest differences and their tested causes</h3><table><tr><th>id</th><th>relative "
             "difference</th><th>ours</th><th>tested causes</th></tr>")
    for r in differs:
        h.append(f"<tr><td><a href='#{r.id}'>{r.id}</a></td><td>{r.difference:.3g}</td><td>{html.escape(r.measured)}"
                 f"</td><td>{html.escape(r.cause or 'no cause test for this claim')}</td></tr>")
        md.append(f"- **{r.id}** (relative difference {r.difference:.3g}): {r.measured} Causes: "
                  f"{r.cause or 'no cause test for this claim'}")
    h.append("</table></section>")
    return h, md


_STYLE = ("<style>body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}img{max-width:100%;"
          "border:1px solid #ccc}table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #bbb;"
          "padding:3px;vertical-align:top}.cap{font-style:italic;color:#444}.facts{font-size:12px;color:#333}"
          ".badge{padding:1px 6px;border-radius:8px;border:1px solid #999;font-size:12px;white-space:nowrap}</style>")

#: A script that counts the page's images that did not load (read by the rendered-report test).
_IMAGE_CHECK = ("<div id='image-check'></div><script>window.addEventListener('load',function(){var im=document.images,"
                "bad=0;for(var i=0;i<im.length;i++){if(!(im[i].complete&&im[i].naturalWidth>0))bad++;}"
                "document.getElementById('image-check').textContent='images: '+im.length+' broken: '+bad;});</script>")


def build(rows: list[Row], *, out_dir, tex_path, labels: dict, figures: dict, datasets: dict,
          benchmarks: dict, precision_cost=None, cluster_config=None) -> None:
    """Write index.html and README.md into ``out_dir`` with the figures copied beside them: the
    answers first, a table of contents, the paper's figures (each with its verdict and the claims it
    illustrates), the ledger, the figures with no counterpart in the paper and the tables.

    labels: {figure: paper LaTeX label}; figures: {figure: PNG path} of the figures built;
    datasets: {dataset: netCDF path}; benchmarks: {"data/<dataset>" or "figure/<figure>": [Snakemake
    benchmark files]}; precision_cost, cluster_config: benchmarks/precision_cost.yaml and
    config/cluster.yaml, for the cost of the computation an undecided verdict leaves to the cluster."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paper_figs = [f for f in figures if FIGURES[f].paper]
    other_figs = [f for f in figures if not FIGURES[f].paper]
    h = ["<!doctype html><html><head><meta charset='utf-8'><title>sleighsim reproduction report</title>",
         _STYLE, "</head><body><h1>sleighsim: reproduction of Fedonyuk &amp; Tallapragada</h1>"]
    md = ["# sleighsim reproduction report", ""]
    decisive = decisive_cost(precision_cost, cluster_config) if precision_cost and cluster_config else ""
    ah, am = _answers(rows, datasets, decisive=decisive)
    fh, fm = precision_findings(rows, datasets)
    h += ah + fh
    md += am + [""] + fm
    for section in (_contents(paper_figs, other_figs),
                    _paper_figures(paper_figs, rows, out_dir=out_dir, tex_path=tex_path, labels=labels,
                                   figures=figures, datasets=datasets, benchmarks=benchmarks),
                    _ledger(rows), _other_figures(other_figs, out_dir, figures, datasets), _tables(datasets),
                    _run_cost(benchmarks, out_dir)):
        h += section[0]
        md += section[1]
    h += [_IMAGE_CHECK, "</body></html>"]
    (out_dir / "index.html").write_text("\n".join(h))
    (out_dir / "README.md").write_text("\n".join(md) + "\n")


def _contents(paper_figs: list, other_figs: list) -> tuple[list[str], list[str]]:
    """The table of contents, in the order the sections follow."""
    toc = [("answers", "Answers"), *((f, f"{FIGURES[f].paper}: {f}") for f in paper_figs), ("ledger", "Claims ledger"),
           *((f, FIGURES[f].title) for f in other_figs), *((f"table{i}", t) for i, t in enumerate(TABLES)),
           ("costs", "Run cost")]
    h = ["<nav id='contents'><h2>Contents</h2><ol>" + "".join(
        f"<li><a href='#{a}'>{html.escape(t)}</a></li>" for a, t in toc) + "</ol></nav>"]
    return h, ["## Contents", ""] + [f"- {t}" for _, t in toc] + ["", "## Figures", ""]


def _paper_figures(paper_figs: list, rows: list[Row], *, out_dir, tex_path, labels, figures, datasets,
                   benchmarks) -> tuple[list[str], list[str]]:
    """The paper's figures, each with the paper's caption, its verdict, the claims it illustrates,
    the facts of its datasets and its run time."""
    caps = captions(tex_path)
    by_id = {r.id: r for r in rows}
    h, md = ["<h2>Figures</h2>"], []
    for fig in paper_figs:
        names = list(FIGURES[fig].data)
        cap = caps.get(labels.get(fig, ""), "(no counterpart in the paper)")
        row = by_id.get(FIGURES[fig].paper)
        verdict = row.verdict if row else "not yet computed"
        illustrated = [by_id[c] for c in FIGURES[fig].claims if c in by_id]
        h.append(f"<h3 id='{fig}'>{FIGURES[fig].paper}: {fig} {_badge(verdict)}</h3>"
                 f"<p class='cap'>Paper: {math_html(cap)}</p>")
        if illustrated:
            h.append("<p>Claims: " + ", ".join(f"<a href='#{c.id}'>{c.id}</a> {_badge(c.verdict)}" for c in illustrated)
                     + "</p>")
        md += [f"### {FIGURES[fig].paper}: {fig} ({verdict})", "", f"*Paper:* {cap}", ""]
        if illustrated:
            md += ["Claims: " + ", ".join(f"{c.id} ({c.verdict})" for c in illustrated), ""]
        _embed(Path(figures[fig]), out_dir, fig, h, md)
        facts = _scene_facts(datasets, names)
        run = _runtime(t for key in [f"data/{n}" for n in names] + [f"figure/{fig}"] for t in benchmarks.get(key, []))
        h.append("<ul class='facts'>" + "".join(f"<li>{html.escape(f)}</li>" for f in facts)
                 + f"<li>run time (Snakemake benchmarks): {run:.1f} s</li></ul>")
        md += [""] + [f"- {f}" for f in facts] + [f"- run time (Snakemake benchmarks): {run:.1f} s", ""]
    return h, md


def _ledger(rows: list[Row]) -> tuple[list[str], list[str]]:
    """The claims ledger, one row per claim, coloured by verdict."""
    h = ["<h2 id='ledger'>Claims ledger</h2><table><tr><th>id</th><th>claim</th><th>paper</th><th>ours</th>"
         "<th>uncertainty</th><th>units</th><th>precision</th><th>in double</th><th>verdict</th><th>realizations</th>"
         "<th>evidence</th>"
         "<th>reason</th><th>cause</th><th>rule</th></tr>"]
    md = ["## Claims ledger", "", "| id | paper | ours | precision | verdict | reason | cause |",
          "|---|---|---|---|---|---|---|"]
    for r in rows:
        cells = [r.id, r.statement, r.paper_value, r.measured, r.uncertainty, r.units, r.precision,
                 r.double_value or ("the same" if r.precision == "double" else ""), r.verdict, r.realizations,
                 r.evidence, r.reason, r.cause, r.rule]
        h.append(f"<tr id='{r.id}' style='background:{COLOURS[r.verdict]}'>"
                 + "".join(f"<td>{html.escape(str(c))}</td>" for c in cells) + "</tr>")
        md.append("| " + " | ".join(str(c).replace("|", "/") for c in (r.id, r.paper_value, r.measured, r.precision,
                                                                          r.verdict, r.reason, r.cause)) + " |")
    h.append("</table>")
    return h, md


def _other_figures(other_figs: list, out_dir, figures, datasets) -> tuple[list[str], list[str]]:
    """The figures with no counterpart in the paper, with the speed tables of the datasets that have them."""
    h, md = [], []
    for fig in other_figs:
        title = FIGURES[fig].title
        h.append(f"<h2 id='{fig}'>{html.escape(title)}</h2>")
        md += ["", f"## {title}", ""]
        _embed(Path(figures[fig]), out_dir, fig, h, md)
        speed = [read_dataset(datasets[n]) for n in FIGURES[fig].data]
        for ds in (d for d in speed if any(k.startswith("fastest_at_") for k in d.attrs)):
            th, tm = _fastest_table(ds)
            h += th
            md += tm
        for ds in (d for d in speed if "peer_ratio" in d):
            th, tm = _peer_table(ds)
            h += th
            md += tm
    return h, md


def _tables(datasets) -> tuple[list[str], list[str]]:
    """The registry's tables, or where each would be computed."""
    h, md = [], []
    for i, (title, table) in enumerate(TABLES.items()):
        h.append(f"<h2 id='table{i}'>{html.escape(title)}</h2>")
        md += ["", f"## {title}", ""]
        if table.data in datasets:
            ds = read_dataset(datasets[table.data])
            colour = (lambda vals, k=table.columns.index(table.colour_by): OUTCOME_COLOURS.get(str(vals[k]), "#fff")
                      ) if table.colour_by else None
            th, tm = _table(ds, table.key, table.columns, colour)
            h += th
            md += tm
        else:
            h.append(f"<p><b>not yet computed</b> (on request: <code>snakemake -c2 {table.data}</code>)</p>")
            md.append(f"**not yet computed** (on request: `snakemake -c2 {table.data}`)")
    return h, md


def _run_cost(benchmarks: dict, out_dir: Path) -> tuple[list[str], list[str]]:
    """The run's cost per job from Snakemake's benchmark records (the figure written beside the page)."""
    h, md = ["<h2 id='costs'>Run cost</h2>"], ["", "## Run cost", ""]
    jobs = plots.job_costs(benchmarks)
    if jobs:
        plots.plot_job_costs(jobs, out_dir / "costs.png")
        h.append("<img src='costs.png' alt='costs'>")
        md.append("![costs](costs.png)")
    else:
        (out_dir / "costs.png").unlink(missing_ok=True)  # no stale figure from an earlier run
        h.append("<p><b>not yet computed</b> (no benchmark records)</p>")
        md.append("**not yet computed** (no benchmark records)")
    return h, md


def _fastest_table(ds) -> tuple[list[str], list[str]]:
    """The fastest method per error target and its speed ratio to the fastest SciPy method."""
    a = ds.attrs
    rows_b = [(k.removeprefix("fastest_at_"), a[k], a.get("speedup_vs_scipy_at_" + k.removeprefix("fastest_at_")))
              for k in sorted(a) if k.startswith("fastest_at_")]
    rows_b = [(t, f, f"{r:.0f}x" if np.isfinite(r) else "no SciPy run reaches it") for t, f, r in rows_b]
    h = [f"<h3>Fastest method per error target</h3><table><tr><th>error target (t = {a['t_short']:g})</th>"
         "<th>fastest</th><th>speed ratio to the fastest SciPy method</th></tr>"
         + "".join(f"<tr><td>{t}</td><td>{html.escape(str(f))}</td><td>{r}</td></tr>" for t, f, r in rows_b)
         + f"</table><p>engine overhead over a bare propagation: {a['overhead_overhead_ratio']:.2f}</p>"]
    md = ["", "### Fastest method per error target", "", "| error target | fastest | ratio to fastest SciPy |",
          "|---|---|---|"]
    md += [f"| {t} | {f} | {r} |" for t, f, r in rows_b]
    md += ["", f"Engine overhead over a bare propagation: {a['overhead_overhead_ratio']:.2f}"]
    return h, md


def _peer_table(ds) -> tuple[list[str], list[str]]:
    """Each peer's fastest wall reaching each error target over heyoka's, compile times beside."""
    peers, targets = [str(p) for p in ds.peer.values], ds.error_target.values
    compile_s = ds.peer_engine_compile_s.values

    def cell(r):
        return f"{r:.3g}x" if np.isfinite(r) else "not reached"

    head = ["error target"] + [f"{p} (compile {c:.2g} s)" for p, c in zip(peers, compile_s)]
    rows = [[f"{t:.0e}"] + [cell(r) for r in ds.peer_ratio.values[i]] for i, t in enumerate(targets)]
    rule = html.escape(ds.attrs["peer_ratio_rule"])
    h = ["<h3>Speed ratio of each peer to heyoka</h3><table><tr>" + "".join(f"<th>{html.escape(c)}</th>" for c in head)
         + "</tr>" + "".join("<tr>" + "".join(f"<td>{c}</td>" for c in row) + "</tr>" for row in rows)
         + f"</table><p>{rule}; versions: {html.escape(ds.attrs['peer_versions'])}</p>"]
    md = ["", "### Speed ratio of each peer to heyoka", "", "| " + " | ".join(head) + " |",
          "|" + "---|" * len(head)] + ["| " + " | ".join(row) + " |" for row in rows]
    md += ["", f"{ds.attrs['peer_ratio_rule']}; versions: {ds.attrs['peer_versions']}"]
    return h, md
