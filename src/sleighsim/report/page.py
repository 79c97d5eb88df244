"""The report's page model and its rendering: plain data (tables, figures, answers) filled in by
:mod:`sleighsim.report.build` and rendered by the Jinja2 templates of ``report/templates``
(the HTML page autoescaped, its Markdown twin not)."""

from __future__ import annotations

import html
import re
from dataclasses import dataclass, field

import jinja2
import latex2mathml.converter
import nh3
from markupsafe import Markup

#: Each verdict's colour (sleighsim.claims.rules.VERDICTS, a test checks every one has one) ...
COLOURS = {"reproduced": "#d4edda", "reproduced only in double precision": "#ffe0b2", "differs slightly": "#fdf6d8",
           "differs": "#fbe49a", "differs greatly": "#f5b971", "fragile": "#e1d5f0", "check failed": "#cfe2f3",
           "cannot be reproduced": "#f8d7da", "not yet computed": "#e2e3e5", "not a reproduction": "#f3f3f3"}
#: ... and its mark, so that no verdict is told by colour alone.
MARKS = {"reproduced": "\u2713", "reproduced only in double precision": "\u25d0", "differs slightly": "\u2248",
         "differs": "\u2260", "differs greatly": "\u226b", "fragile": "~", "check failed": "!",
         "cannot be reproduced": "\u2717", "not yet computed": "\u2026", "not a reproduction": "\u2205"}
#: Chaos verdicts, in colours of their own (the first screen shows both kinds side by side).
CHAOS_COLOURS = {"chaotic": "#f5b7b1", "regular": "#a9dfbf", "undecided": "#d6dbdf", "fragile": "#d2b4de"}


@dataclass
class Table:
    """A table of text cells; ``colours`` is one background per row ("" for none)."""

    head: list[str]
    rows: list[list[str]]
    colours: list[str] = field(default_factory=list)
    title: str = ""
    note: str = ""


#: The MathML latex2mathml writes: its elements, and the attributes it sets on them (not href or style).
MATHML_TAGS = frozenset({"math", "mrow", "mi", "mn", "mo", "mtext", "mspace", "msup", "msub", "msubsup", "mfrac",
                         "msqrt", "mroot", "mstyle", "mover", "munder", "munderover", "mtable", "mtr", "mtd",
                         "mpadded", "mphantom", "menclose"})
MATHML_ATTRIBUTES = frozenset({"xmlns", "display", "mathvariant", "mathsize", "mathcolor", "mathbackground",
                               "stretchy", "fence", "form", "separator", "lspace", "rspace", "width", "height",
                               "depth", "voffset", "columnalign", "columnlines", "columnspacing", "rowspacing",
                               "displaystyle", "scriptlevel", "accent", "movablelimits", "linethickness", "notation",
                               "minsize", "maxsize", "linebreak", "largeop"})


def mathml(latex: str) -> str:
    """MathML of the formula ``latex`` (latex2mathml), kept to :data:`MATHML_TAGS` and
    :data:`MATHML_ATTRIBUTES` by nh3: latex2mathml copies ``\\text{...}`` into the page raw."""
    raw = latex2mathml.converter.convert(latex)
    return nh3.clean(raw, tags=set(MATHML_TAGS), attributes={t: set(MATHML_ATTRIBUTES) for t in MATHML_TAGS},
                     url_schemes=set(), link_rel=None)


def math_html(text: str) -> Markup:
    """HTML of caption text: ``$...$`` rendered as MathML (latex2mathml, offline, sanitised by
    :func:`mathml`), the rest escaped."""
    out = []
    for part in re.split(r"(\$[^$]+\$)", text):
        if len(part) > 2 and part[0] == part[-1] == "$":
            try:
                out.append(mathml(part[1:-1]))
            except Exception:  # noqa: BLE001 - a formula the converter rejects is shown as text, without $
                out.append(html.escape(part[1:-1]))
        else:
            out.append(html.escape(part))
    return Markup("".join(out))


def md_cell(text) -> str:
    """A Markdown table cell: one line, no column separators."""
    return " ".join(str(text).replace("|", "/").split())


def _environment() -> jinja2.Environment:
    env = jinja2.Environment(loader=jinja2.PackageLoader("sleighsim.report", "templates"),
                             autoescape=jinja2.select_autoescape(["html.j2"]), undefined=jinja2.StrictUndefined,
                             trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=True)
    env.filters.update(math=math_html, md_cell=md_cell)
    env.globals.update(colours=COLOURS, marks=MARKS, chaos_colours=CHAOS_COLOURS)
    return env


def render(template: str, **context) -> str:
    """Render ``templates/<template>`` with ``context``."""
    return _environment().get_template(template).render(**context)
