"""One chunk of a chunked scene (Snakemake script)."""

from sleighsim.claims.fidelity import identity
from sleighsim.io import netcdf
from sleighsim.ops.runlog import logging_to
from sleighsim.scenes import catalog

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    inputs = {role: path for role, path in sm.input.items() if role != "reads"}
    ds = catalog.chunk(sm.wildcards.scene, sm.params.cfg, int(sm.wildcards.chunk), list(sm.input.reads), inputs)
    ds.attrs.update(identity(sm.config))  # the run's configuration: its label and hash
    netcdf.write_dataset(ds, sm.output.nc, **catalog.writing(sm.params.cfg))
