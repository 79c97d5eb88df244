"""A chunked scene's dataset from its chunks (Snakemake script)."""

from sleighsim.io import netcdf
from sleighsim.ops.runlog import logging_to
from sleighsim.scenes import catalog

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    netcdf.write_dataset(catalog.gather(sm.wildcards.scene, sm.params.cfg, sm.input.chunks), sm.output.nc,
                         **catalog.writing(sm.params.cfg))
