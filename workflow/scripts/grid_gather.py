"""Gather the Lyapunov grid chunks (Snakemake script)."""

from sleighsim import chaos, io
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    io.write_dataset(chaos.grid_gather(list(sm.input.chunks), sm.params.cfg), sm.output.nc)
