"""Generated blocks of a Markdown file (the README's times table and finding): the text between
``<!-- BEGIN name -->`` and ``<!-- END name -->`` markers, each on a line of its own, is a program's
output; :func:`replaced` writes it, :func:`block` reads it back for a test to compare."""

from __future__ import annotations

import re


def _markers(name: str) -> tuple[str, str]:
    return f"<!-- BEGIN {name}", f"<!-- END {name} -->"


def _span(text: str, name: str) -> tuple[int, int]:
    """Where the block's body lies in ``text``: from the line after its BEGIN marker to its END marker.
    Raises ValueError when the markers are missing, repeated or out of order."""
    begin, end = _markers(name)
    starts = [m.start() for m in re.finditer(re.escape(begin) + r"[ :>]", text)]
    ends = [m.start() for m in re.finditer(re.escape(end), text)]
    if len(starts) != 1 or len(ends) != 1 or ends[0] < starts[0]:
        raise ValueError(f"expected one '{begin} ... -->' line and one later '{end}' line, found {len(starts)} and "
                         f"{len(ends)}")
    body = text.index("\n", starts[0]) + 1
    return body, ends[0]


def block(text: str, name: str) -> str:
    """The body of the generated block ``name`` in ``text`` (its marker lines excluded)."""
    start, stop = _span(text, name)
    return text[start:stop]


def replaced(text: str, name: str, body: str) -> str:
    """``text`` with the body of block ``name`` replaced by ``body`` (ending with a newline)."""
    start, stop = _span(text, name)
    return text[:start] + body.rstrip("\n") + "\n" + text[stop:]
