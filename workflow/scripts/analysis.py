"""Combine datasets into a derived one: inputs in order, one netCDF out (Snakemake script)."""

from sleighsim import io, scenes
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    ds = getattr(scenes, sm.rule)(*sm.input)
    io.write_dataset(ds, sm.output.nc)
