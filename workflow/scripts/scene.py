"""Compute one scene's dataset: config block in, netCDF out (Snakemake script)."""

from sleighsim import io, scenes
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    ds = scenes.SCENES[sm.wildcards.scene](sm.params.cfg, scene=sm.wildcards.scene)
    io.write_dataset(ds, sm.output.nc)
