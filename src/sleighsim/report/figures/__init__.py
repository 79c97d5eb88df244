"""Figures. Each plot function reads datasets (never integrates) and returns the matplotlib Figure,
which :func:`draw` saves as PNG (for the report) and PDF (for a paper); every figure carries a
footer with the numbers that say how its data were made. Each figure module declares its figures
(:class:`sleighsim.report.figures.figure.Figure`: the datasets a plot function reads, the paper's id,
the claims) beside their plot functions; :data:`sleighsim.report.figures.catalog.FIGURES` collects
them."""

from __future__ import annotations

from sleighsim.report.figures.catalog import FIGURES
from sleighsim.report.figures.common import save_figure


def build(figure: str, source):
    """The matplotlib Figure of the figure named ``figure`` from its datasets (``source``: a list of
    paths) or, for a schematic, its config block (``source``: a dict)."""
    return FIGURES[figure].plot(source)


def draw(figure: str, source, png, pdf) -> None:
    """Draw the figure named ``figure`` (see :func:`build`) into the files ``png`` and ``pdf``."""
    save_figure(build(figure, source), png, pdf)
