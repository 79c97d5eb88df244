"""Figures. Each plot function reads datasets (never integrates) and returns the matplotlib Figure,
which :func:`draw` saves as PNG (for the report) and PDF (for a paper); every figure carries a
footer with the numbers that say how its data were made. Which datasets a figure reads is
declared in :data:`sleighsim.ops.registry.FIGURES`."""

from __future__ import annotations

from sleighsim.ops.registry import plot_name
from sleighsim.report.figures.audit import audit
from sleighsim.report.figures.bench import bench
from sleighsim.report.figures.chaos import chaos
from sleighsim.report.figures.common import save_figure
from sleighsim.report.figures.exponents import drift, fig10, fig11, lyapunov, regimes
from sleighsim.report.figures.precision import precision, trigger
from sleighsim.report.figures.steady_state import fig9, fig12, psd
from sleighsim.report.figures.trajectories import fig1, fig2, fig3, fig7, fig8
from sleighsim.report.figures.transients import basins, fig4, fig5, fig6, perturbation, transients

PLOTS = {f.__name__: f for f in (fig1, fig2, fig3, fig4, fig5, fig6, fig7, fig8, fig9, fig10, fig11, fig12, psd,
                                  transients, perturbation, lyapunov, chaos, audit, bench, regimes, basins,
                                  drift, precision, trigger)}


def build(figure: str, source):
    """The Figure of ``figure`` from its datasets (a list of paths) or, for a schematic, its config block."""
    return PLOTS[plot_name(figure)](source)


def draw(figure: str, source, png, pdf) -> None:
    """Draw ``figure`` (see :func:`build`) into ``png`` and ``pdf``."""
    save_figure(build(figure, source), png, pdf)
