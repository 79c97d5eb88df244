"""A chunked scene's dataset from its chunks (Snakemake script)."""

from sleighsim import io, scenes
from sleighsim.ops.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    io.write_dataset(scenes.gather(sm.wildcards.scene, sm.params.cfg, sm.input.chunks), sm.output.nc)
