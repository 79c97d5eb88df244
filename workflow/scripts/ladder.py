"""Compare a laddered scene's key observables across its precisions (Snakemake script)."""

from sleighsim.analysis import observables
from sleighsim.claims.fidelity import identity
from sleighsim.io import netcdf
from sleighsim.ops.runlog import logging_to
from sleighsim.scenes.catalog import KINDS

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    runs = [netcdf.read_dataset(p) for p in sm.input.runs]
    ds = observables.ladder(sm.params.kind, KINDS[sm.params.kind].observables, runs, list(sm.params.precisions),
                            scene=sm.wildcards.scene, gain=sm.params.gain)
    ds.attrs.update(identity(sm.config))  # the run's configuration: its label and hash
    netcdf.write_dataset(ds, sm.output.nc, what=sm.params.what)
