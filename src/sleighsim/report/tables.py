"""The tables the report shows after the figures, each read from one dataset."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Table:
    """A table of the report: dataset ``data``, one row per value of ``key``, the ``columns`` shown;
    rows coloured by the value of ``colour_by`` (an outcome) when given."""

    data: str
    key: str
    columns: tuple[str, ...]
    colour_by: str = ""


#: Tables the report shows after the figures: section title -> table.
TABLES: dict[str, Table] = {
    "Perturbation hierarchy: terms where the printed equations differ from the derived ones":
        Table("pert_audit", "equation", ("term", "derived", "printed", "derived_with_kappa")),
    "Hard cases": Table("hardcases", "case", ("outcome", "error", "drift", "disagreement", "steps", "wall_s", "detail"),
                        colour_by="outcome"),
}
