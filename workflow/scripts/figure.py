"""Draw one figure from its datasets (or, for a schematic, its config block) (Snakemake script)."""

from sleighsim.ops.runlog import logging_to
from sleighsim.report import figures

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    source = list(sm.input.nc) if "nc" in sm.input.keys() else sm.params.cfg
    figures.draw(sm.params.fig, source, sm.output.png, sm.output.pdf)
