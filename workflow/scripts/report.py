"""Build results/report/index.html and README.md from the ledger, figures and datasets."""

from pathlib import Path

from sleighsim import claims, report
from sleighsim.io import read_dataset
from sleighsim.runlog import logging_to

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logging_to(sm.log[0]):
    ds = read_dataset(sm.input.claims)
    rows = [claims.Row(id=str(i), **{k: str(ds[k].values[j]) for k in ds.data_vars}) for j, i in enumerate(ds.id.values)]
    results = Path(sm.input.claims).parent
    labels = {f"fig{cid[1:]}": label for cid, _, label in claims.parse_claims(sm.input.claims_md) if cid[0] == "F"}
    report.build(rows, out_dir=Path(sm.output.html).parent, figures_dir=results / "figures", data_dir=results / "data",
                 bench_dir=results / "benchmarks", tex_path=sm.input.tex, figure_inputs=sm.params.figure_inputs,
                 labels=labels, extra_figures=sm.params.extra)
