"""Draw one figure from its dataset (or, for the schematic, its config block)."""

from sleighsim import plots
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    source = list(sm.input.nc) if "nc" in sm.input.keys() else sm.params.cfg
    plots.FIGURES[sm.params.fig](source, sm.output.png, sm.output.pdf)
