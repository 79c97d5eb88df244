"""Figures. Each plot function reads datasets (never integrates) and returns the matplotlib Figure,
which :func:`draw` saves as PNG (for the report) and PDF (for a paper); every figure carries a
footer with the numbers that say how its data were made. Which datasets a figure reads is
declared in :data:`sleighsim.registry.FIGURES`."""

from __future__ import annotations

from ...registry import plot_name
from .audit import audit
from .bench import bench
from .chaos import chaos
from .common import save_figure
from .exponents import drift, fig10, fig11, lyapunov, regimes
from .precision import precision, trigger
from .steady_state import fig9, fig12, psd
from .trajectories import fig1, fig2, fig3, fig7, fig8
from .transients import basins, fig4, fig5, fig6, perturbation, transients

PLOTS = {f.__name__: f for f in (fig1, fig2, fig3, fig4, fig5, fig6, fig7, fig8, fig9, fig10, fig11, fig12, psd,
                                  transients, perturbation, lyapunov, chaos, audit, bench, regimes, basins,
                                  drift, precision, trigger)}


def build(figure: str, source):
    """The Figure of ``figure`` from its datasets (a list of paths) or, for a schematic, its config block."""
    return PLOTS[plot_name(figure)](source)


def draw(figure: str, source, png, pdf) -> None:
    """Draw ``figure`` (see :func:`build`) into ``png`` and ``pdf``."""
    save_figure(build(figure, source), png, pdf)
