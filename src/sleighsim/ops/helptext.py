"""Command-line help from a module's docstring: its first paragraph with the reStructuredText markup the
docs render (``code``, :mod:`name`, :func:`name`, ...) reduced to plain text, as a terminal shows it."""

from __future__ import annotations

import re

_ROLE = re.compile(r":\w+:`~?([^`]+)`")
_LITERAL = re.compile(r"``([^`]+)``")


def plain(text: str) -> str:
    """``text`` without reStructuredText roles and literal markup."""
    return _LITERAL.sub(r"\1", _ROLE.sub(r"\1", text))


def summary(doc: str) -> str:
    """The first paragraph of a docstring as plain text."""
    return plain(doc.split("\n\n")[0])
