"""What a figure is: the declaration each figure module makes beside the function that draws it
(collected, in the report's order, by :mod:`sleighsim.report.figures.catalog`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class Figure:
    """A figure: ``name`` is its file's stem under figures/ (and its Snakemake target); ``plot``
    the function drawing it, which takes the paths of ``data`` (in order), or for a schematic the
    config block of the scene ``schematic`` names, and returns the matplotlib Figure; ``paper`` is
    its id in CLAIMS.md ("" when the paper has no such figure, then ``title`` heads its report
    section); ``claims`` are the claims it illustrates; ``steady`` are the datasets that show a
    steady state, each of which must carry a passed transient check (``transient_over``) for the
    figure to count; ``beside``: the figure also reads its laddered scenes in their finer precisions
    (after ``data``) and draws them beside the paper's arithmetic; ``section``: for a figure the paper
    does not have, the LaTeX label of the paper section it extends ("" for none: methods), which
    Snakemake's report files it under (a paper figure's section is read from the LaTeX)."""

    name: str
    plot: Callable
    data: tuple[str, ...] = ()
    paper: str = ""
    claims: tuple[str, ...] = ()
    title: str = ""
    schematic: str = ""
    steady: tuple[str, ...] = ()
    beside: bool = False
    section: str = ""
