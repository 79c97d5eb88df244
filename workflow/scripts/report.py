"""Build results/report/index.html and README.md from the ledger, figures and datasets (Snakemake script)."""

from pathlib import Path

from sleighsim.claims import fidelity
from sleighsim.claims import ledger as claims
from sleighsim.io.claims_table import parse_claims
from sleighsim.io.netcdf import write_text
from sleighsim.ops.runlog import logging_to
from sleighsim.report import build as report
from sleighsim.report.figures.catalog import FIGURES
from sleighsim.report.standalone import inline_images

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    rows = claims.read(sm.input.claims)
    labels = {f: c.paper_value for f in FIGURES for c in parse_claims(sm.input.claims_md)
              if c.id == FIGURES[f].paper}
    report.build(rows, out_dir=Path(sm.output.html).parent, tex_path=sm.input.tex, labels=labels,
                 figures=dict(zip(sm.params.figures, sm.input.figures)),
                 datasets=dict(zip(sm.params.data, sm.input.data)), kinds=sm.params.kinds,
                 benchmarks=sm.params.benchmarks, identity=fidelity.identity(sm.config),
                 power_record=sm.input.get("power_record"), cluster_record=sm.input.get("cluster_record"))
    write_text(sm.output.standalone, inline_images(sm.output.html))
