"""Judge every claim of CLAIMS.md from the datasets; write claims.csv and claims.nc (Snakemake script)."""

from pathlib import Path

from sleighsim.claims import fidelity
from sleighsim.claims import ledger as claims
from sleighsim.ops.runlog import logging_to
from sleighsim.report.figures.catalog import FIGURES

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]) as log:
    data = Path(sm.input.data[0]).parent if sm.input.data else Path(sm.output.nc).parent / "data"
    figures = Path(sm.output.nc).parent / "figures"
    rows = claims.ledger(sm.input.claims_md, data, figures, sm.config, FIGURES)
    claims.write(rows, sm.output.csv, sm.output.nc, identity=fidelity.identity(sm.config))
    log.info("claims (%s): %s", fidelity.describe(fidelity.identity(sm.config)), claims.summary(rows))
