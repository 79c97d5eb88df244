"""``sleighsim claims``: re-judge the claims ledger from a results tree without Snakemake,
reading the precision ladders and realizations its config files (``--config``, default
config/config.yaml) declare (``--help`` lists the options). It hands the ledger the figures of
:mod:`sleighsim.report.figures.catalog` (the figure rows of CLAIMS.md), as the workflow's claims
job does. The ledger records the config's label and hash as the workflow's does: the config files merged,
then the schema's defaults set, as the Snakefile sets them (:func:`run_config`); a run that is not at the
paper's fidelity (the smoke run: ``--config config/smoke.yaml``) is judged against nothing
(:mod:`sleighsim.claims.fidelity`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from sleighsim.claims import fidelity
from sleighsim.claims.ledger import ledger, summary, write
from sleighsim.io.claims_table import parse_claims
from sleighsim.io.integrity import ProductError, valid
from sleighsim.ops.config import BASE_CONFIG, REPO, merged_config
from sleighsim.report.figures.catalog import FIGURES, figures_built
from sleighsim.scenes.catalog import run_datasets


def _parser(prog: str = "sleighsim claims") -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog=prog,
                                 description="Judge every claim of CLAIMS.md from a results tree; write the ledger.")
    ap.add_argument("--claims", default=str(REPO / "paper" / "CLAIMS.md"),
                    help="the claims list (default: the project's paper/CLAIMS.md)")
    ap.add_argument("--data", default="results/data", help="directory of the datasets (default results/data)")
    ap.add_argument("--figures", default="results/figures", help="directory of the figures (default results/figures)")
    ap.add_argument("--out", default="results/claims.csv",
                    help="the ledger as CSV; the netCDF copy goes beside it (default results/claims.csv)")
    ap.add_argument("--config", nargs="+", default=[], metavar="FILE",
                    help="the run's config files, merged in order onto config/config.yaml as snakemake "
                         "--configfile merges them: which precision ladders and realizations were asked for "
                         f"(default: {BASE_CONFIG} alone)")
    return ap


def _checked(ap: argparse.ArgumentParser, argv) -> argparse.Namespace:
    """The parsed arguments, after refusing (with a usage error) a path that cannot be what it names."""
    a = ap.parse_args(argv)
    if Path(a.out).suffix != ".csv":
        ap.error(f"--out {a.out}: give a .csv path")
    for f in a.config:
        if not Path(f).is_file():
            ap.error(f"--config {f}: no such file")
    for flag, d in (("--data", a.data), ("--figures", a.figures)):
        if not Path(d).is_dir():
            ap.error(f"{flag} {d}: no such directory")
    try:
        n_claims = len(parse_claims(a.claims))
    except (OSError, UnicodeDecodeError) as err:  # /bin/ls: not UTF-8 text
        ap.error(f"--claims {a.claims}: {getattr(err, 'strerror', None) or 'not a UTF-8 text file'}")
    if not n_claims:
        ap.error(f"--claims {a.claims}: no claim rows (table rows whose first cell is an id such as F1, C01, D1)")
    return a


def main(argv=None, prog: str = "sleighsim claims") -> int:
    """Judge the claims of a results tree and write the ledger (``argv``: the command line without the
    program, default sys.argv). Returns the exit status: 0, or 3 when products of the run are missing."""
    a = _checked(_parser(prog), argv)
    out = Path(a.out)
    config = run_config(a.config)
    rows = ledger(a.claims, a.data, a.figures, config, FIGURES)
    ident = fidelity.identity(config)
    write(rows, out, out.with_suffix(".nc"), identity=ident)
    print(f"{fidelity.describe(ident)}" + ("" if fidelity.reproduction(config) else " (not a reproduction)") + ": "
          + ", ".join(f"{v}: {n}" for v, n in summary(rows).items() if n), f"-> {out}, {out.with_suffix('.nc')}")
    absent = missing_products(a.data, a.figures, config)
    if absent:
        print(f"error: {len(absent)} product(s) of the run the config declares are missing or unreadable "
              "(their claims read 'not yet computed'): " + ", ".join(absent), file=sys.stderr)
        return 3
    return 0


def run_config(files) -> dict:
    """The config a workflow run of ``files`` (overlays on config/config.yaml) hands its jobs: merged, then
    the schema's defaults set (snakemake.utils.validate, as the Snakefile calls it), so that its hash is the
    workflow's."""
    from snakemake.utils import validate

    config = merged_config(files)
    validate(config, schema=str(REPO / "workflow" / "schemas" / "config.schema.yaml"), set_default=True)
    return config


def missing_products(data_dir, figures_dir, config: dict) -> list[str]:
    """The datasets (``scenes.catalog.run_datasets``) and figures (``figures_built``) of the default run of
    ``config`` that are absent from the directories ``data_dir`` / ``figures_dir`` or cannot be opened,
    as paths."""
    data = [Path(data_dir) / f"{name}.nc" for name in run_datasets(config)]
    figures = [Path(figures_dir) / f"{f}.png" for f in figures_built(config)]
    return [str(p) for p in data if not _opens(p)] + [str(p) for p in figures if not p.is_file()]


def _opens(path: Path) -> bool:
    """Whether the dataset ``path`` exists and netCDF4 opens it (a permission, lock or I/O error counts
    as not)."""
    try:
        return path.is_file() and valid(path)
    except ProductError:
        return False


if __name__ == "__main__":
    raise SystemExit(main())
