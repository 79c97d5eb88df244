"""Speed against error (Snakemake script): sleighsim.bench.run on the config's bench block."""

from sleighsim import bench, io
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    io.write_dataset(bench.run(sm.params.cfg), sm.output.nc)
