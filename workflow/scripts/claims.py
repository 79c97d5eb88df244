"""Judge every claim of CLAIMS.md from the datasets; write claims.csv and claims.nc."""

import csv
import io as _io
from dataclasses import astuple, fields
from pathlib import Path

from sleighsim import claims, io
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]) as log:
    rows = claims.ledger(sm.input.claims_md, Path(sm.output.nc).parent / "data", Path(sm.output.nc).parent / "figures")
    buf = _io.StringIO()
    writer = csv.writer(buf)
    writer.writerow([f.name for f in fields(claims.Row)])
    writer.writerows(astuple(r) for r in rows)
    io.write_text(sm.output.csv, buf.getvalue())
    io.write_dataset(claims.to_dataset(rows), sm.output.nc)
    log.info("claims: %s", {v: sum(r.verdict == v for r in rows) for v in claims.VERDICTS})
