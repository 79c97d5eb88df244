"""One chunk of a chunked scene (Snakemake script)."""

from sleighsim import io, scenes
from sleighsim.ops.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    io.write_dataset(scenes.chunk(sm.wildcards.scene, sm.params.cfg, int(sm.wildcards.chunk)), sm.output.nc)
