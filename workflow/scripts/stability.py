"""Rerun the ledger's scenes perturbed and at a looser tolerance; tabulate verdict changes (Snakemake script)."""

from sleighsim.ops import stability
from sleighsim.ops.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]) as log:
    ds = stability.run(dict(sm.config), sm.input.claims, sm.output.csv, cores=sm.threads)
    log.info("stability: %d of %d verdicts changed", ds.attrs["n_changed"], ds.sizes["id"])
