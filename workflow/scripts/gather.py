"""A chunked scene's dataset from its chunks (Snakemake script)."""

from sleighsim.claims.fidelity import identity
from sleighsim.io import netcdf
from sleighsim.ops.runlog import logging_to
from sleighsim.scenes import catalog

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    ds = catalog.gather(sm.wildcards.scene, sm.params.cfg, sm.input.chunks)
    ds.attrs.update(identity(sm.config))  # the run's configuration: its label and hash
    netcdf.write_dataset(ds, sm.output.nc, **catalog.writing(sm.params.cfg))
