"""Where Snakemake's own report (``snakemake --report report.zip``) files each figure: under the
paper section it belongs to, with labels naming the paper's figure and the claims it shows.

A paper figure's section is the LaTeX ``\\section`` its ``\\label`` lies in; a figure the paper
does not have names the section it extends (``Figure.section``), or none (:data:`METHODS`)."""

from __future__ import annotations

import re
from pathlib import Path

from sleighsim.io.claims_table import parse_claims
from sleighsim.report.figures.catalog import FIGURES

#: The category of a figure that extends no paper section (the methods figures).
METHODS = "Methods beyond the paper"
#: The category of the claims ledger and the project's own report.
LEDGER = "Claims ledger and reproduction report"
#: The subcategories: a figure of the paper, or one this project adds.
PAPER, ADDED = "figures of the paper", "added by this reproduction"

_SECTION = re.compile(r"\\section\*?\{(?P<title>[^}]*)\}(\\label\{(?P<label>[^}]*)\})?")
_LABEL = re.compile(r"\\label\{([^}]*)\}")


def section_of_labels(tex_path) -> tuple[dict[str, str], dict[str, str]]:
    """({section label: "§n title"}, {any label: the "§n title" of the section it lies in}) of the
    LaTeX source, sections numbered in order from 1."""
    text = Path(tex_path).read_text()
    starts = list(_SECTION.finditer(text))
    names = {}
    where = {}
    for n, m in enumerate(starts, start=1):
        name = f"§{n} {m['title'].strip()}"
        end = starts[n].start() if n < len(starts) else len(text)
        if m["label"]:
            names[m["label"]] = name
        for label in _LABEL.findall(text, m.start(), end):
            where[label] = name
    return names, where


def figure_entries(tex_path, claims_md) -> dict[str, dict]:
    """{figure: {"category", "subcategory", "labels"}} for every figure of the catalog: its paper
    section, whether the paper has it, and labels (the figure, the paper's id and LaTeX label, what
    it shows: CLAIMS.md's words or the figure's title, and the claims it illustrates)."""
    sections, where = section_of_labels(tex_path)
    rows = {c.id: c for c in parse_claims(claims_md) if c.id.startswith("F")}
    out = {}
    for name, fig in FIGURES.items():
        if fig.paper:
            row = rows[fig.paper]
            category, sub = where[row.paper_value], PAPER
            paper, shows = f"{fig.paper} ({row.paper_value})", row.statement
        else:
            category, sub = sections[fig.section] if fig.section else METHODS, ADDED
            paper, shows = "-", fig.title
        out[name] = {"category": category, "subcategory": sub,
                     "labels": {"figure": name, "paper": paper, "shows": shows, "claims": " ".join(fig.claims) or "-"}}
    return out
