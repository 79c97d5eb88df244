"""The chaos verdict from the exponent spectrum and the 0-1 test (Snakemake script)."""

from sleighsim import chaos, io
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    io.write_dataset(chaos.verdict(sm.input.spectrum, sm.input.poincare, sm.params.cfg), sm.output.nc)
