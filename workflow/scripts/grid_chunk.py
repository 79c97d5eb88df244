"""One chunk of the Lyapunov grid (Snakemake script)."""

from sleighsim import chaos, io
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    cfg = sm.params.cfg
    io.write_dataset(chaos.grid_chunk(cfg, int(sm.wildcards.chunk), cfg["n_chunks"], scene="lyap_grid"), sm.output.nc)
