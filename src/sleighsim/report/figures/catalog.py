"""Every figure, in the report's order: the declarations of the figure modules (each beside the
function that draws it), and which of them a config builds."""

from __future__ import annotations

from sleighsim.report.figures import (
    audit,
    bench,
    chaos,
    exponents,
    precision,
    steady_state,
    torus,
    trajectories,
    transients,
    trigger,
)
from sleighsim.report.figures.figure import Figure
from sleighsim.scenes import catalog as scene_catalog

#: Figure name -> declaration, in the order the report shows them (and the figure list names them).
FIGURES: dict[str, Figure] = {f.name: f for f in (
    trajectories.FIG1, trajectories.FIG2, trajectories.FIG3, transients.FIG4, transients.FIG5, transients.FIG6,
    transients.TRANSIENTS, transients.PERTURBATION, trajectories.FIG7, trajectories.FIG8, steady_state.FIG9,
    steady_state.FIG12, steady_state.FIG13, steady_state.FIG14, exponents.FIG10, exponents.FIG11, exponents.LYAPUNOV,
    chaos.CHAOS, exponents.REGIMES, transients.BASINS, torus.TORUS, precision.PRECISION, trigger.TRIGGER,
    trigger.FATE, exponents.DRIFT, audit.AUDIT, bench.BENCH,
)}

#: The atlas (on request: snakemake -c2 atlas): the figures of the large chaos surveys.
ATLAS = ("regimes", "basins", "drift")


def figures_built(config: dict, *, on_request: bool = False) -> list[str]:
    """The names of the figures whose datasets (or schematic block) ``config`` builds, in the order
    of :data:`FIGURES`; with ``on_request`` also those built only when asked for."""
    built = set(scene_catalog.datasets(config, on_request=on_request))
    drawn = {n for n, block in config["scenes"].items() if on_request or not block.get("on_request", False)}
    return [name for name, f in FIGURES.items()
            if set(f.data) <= built and (not f.schematic or f.schematic in drawn)]
