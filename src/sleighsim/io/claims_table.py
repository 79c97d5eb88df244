"""The paper's claims table, paper/CLAIMS.md, as data: one :class:`Claim` per table row whose first cell
is an id (F.., C.., D..), with the ``value`` column parsed into numbers. The claims ledger
(:mod:`sleighsim.claims.ledger`) and the scenes that read the paper's numbers
(:mod:`sleighsim.scenes.paper_setup`) read the paper's values here, and only here."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

ID = re.compile(r"[FCD]\d+")
PAIR = re.compile(r"\s*(\w+)\s*=\s*(\[[^\]]*\]|[^;]+)")


@dataclass
class Claim:
    """A row of CLAIMS.md: ``values`` are the parsed ``value`` column (numbers or lists of
    numbers), with the numbers' spellings under ``values["_text"]``."""

    id: str
    statement: str
    paper_value: str
    values: dict = field(default_factory=dict)


def parse_values(cell: str) -> dict:
    """``name=number; name=[number, ...]`` -> {name: float or list}, with the spellings in ``_text``."""
    values, text = {}, {}
    for m in PAIR.finditer(cell or ""):
        name, raw = m.group(1), m.group(2).strip()
        if raw.startswith("["):
            items = [s.strip() for s in raw.strip("[]").split(",")]
            values[name], text[name] = [float(s) for s in items], items
        else:
            values[name], text[name] = float(raw), raw
    if values:
        values["_text"] = text
    return values


def parse_claims(path) -> list[Claim]:
    """Every table row of CLAIMS.md whose first cell is an id, in file order. Figure rows: (id, label,
    what it shows); claims: (id, claim, paper value, value); model rows: (id, item, what to show, value)."""
    out = []
    for line in Path(path).read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 3 or not ID.fullmatch(cells[0]):
            continue
        kind = cells[0][0]
        if kind == "F":
            out.append(Claim(cells[0], cells[2], cells[1]))
        else:
            value = cells[3] if len(cells) > 3 else ""
            out.append(Claim(cells[0], cells[1], cells[2], parse_values(value)))
    return out
