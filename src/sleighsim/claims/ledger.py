"""The claims ledger: one row per id of paper/CLAIMS.md, judged by code from the datasets.

A claim (C.., D..) is judged by its function in :mod:`sleighsim.claims.judges` from the paper's
values (the ``value`` column of CLAIMS.md, parsed) and the datasets of
:data:`sleighsim.claims.evidence.EVIDENCE`; a row that differs is then tested against its likely causes
(:mod:`sleighsim.claims.causes`, datasets of :data:`sleighsim.claims.evidence.CAUSES`); every row
is then set beside the setup the paper_setup scene inferred jointly from all the paper's numbers
(columns ``paper_setup_value``, ``paper_setup_verdict``: :mod:`sleighsim.claims.setup_columns`). A figure row
(F..) counts when its figure (the ledger is handed the figures of
:data:`sleighsim.report.figures.catalog.FIGURES`) was built, every steady-state dataset it shows carries a passed
transient check ("check failed" otherwise), and no claim it illustrates differs
(:mod:`sleighsim.claims.figure_rows`).

Rules: see :mod:`sleighsim.claims.rules` (a number is reproduced within max(2 standard errors,
10%) of the paper's value; a qualitative claim when its stated criterion holds; a difference worded
by its size; "cannot be reproduced" only from a computed rule; a missing dataset or check gives "not
yet computed"). A run whose config is not at the paper's fidelity (its ``label``,
:mod:`sleighsim.claims.fidelity`: the smoke run) judges nothing against the paper: every row reads
"not a reproduction", its own data's verdict in ``run_verdict``; the ledger records the config's label
and hash.

Which finer-precision variants and realizations a claim is judged on is what the run's config
declares (:func:`sleighsim.scenes.catalog.laddered`, :func:`sleighsim.scenes.catalog.realized`), never which
files lie in the data directory: a declared one that was not built gives "not yet computed", a
stale one from an older config is not read.

Command line (re-judges a results tree in seconds, no Snakemake; ``--config`` names the config
files the tree was run with, merged onto config/config.yaml as ``snakemake --configfile`` does):
``sleighsim claims --data results/data --figures results/figures --out results/claims.csv``
(add ``--config config/smoke.yaml`` for a smoke run's tree; :mod:`sleighsim.cli.claims`).
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import astuple, dataclass, fields
from pathlib import Path

import numpy as np
import xarray as xr

from sleighsim.chaos.faithfulness import FOLLOWS, UNKNOWN
from sleighsim.chaos.rule import agree
from sleighsim.claims import fidelity, rules
from sleighsim.claims.causes import CAUSE_TESTS
from sleighsim.claims.evidence import CAUSES, EVIDENCE, FAITHFUL
from sleighsim.claims.faithful import FAITHFUL_JUDGES, FAITHFUL_RULE, IN_LADDER, OWN
from sleighsim.claims.figure_rows import figure_from_claims, files, judge_figure
from sleighsim.claims.judges import JUDGES
from sleighsim.claims.rules import CANNOT, DIFFERS, DOUBLE_ONLY, FRAGILE, NOT_YET, REPRODUCED, VERDICTS
from sleighsim.claims.setup_columns import cause_with_setup, columns
from sleighsim.io import cf, layout
from sleighsim.io.claims_table import Claim, parse_claims
from sleighsim.io.netcdf import read_dataset, write_dataset, write_text
from sleighsim.precision import Precision
from sleighsim.scenes.catalog import laddered, realized, scenes_of
from sleighsim.scenes.paper_setup import PAPER_SETUP

PRECISIONS = tuple(p.value for p in Precision)  # coarse to fine
#: The cause of a row reproduced only in double: double's rounding, which the finer arithmetic does not share.
ARITHMETIC = "the arithmetic (double's rounding picks the orbit; the finer arithmetic does not follow it)"


@dataclass
class Row:
    """A row of the ledger: the claim, what the datasets measure, the verdict and why (the columns of
    claims.csv)."""

    id: str
    statement: str
    paper_value: str
    measured: str = ""
    uncertainty: str = ""
    units: str = ""
    verdict: str = NOT_YET
    evidence: str = ""
    reason: str = ""
    rule: str = ""
    cause: str = ""
    difference: float = math.nan
    precision: str = ""
    double_value: str = ""
    faithful_value: str = ""
    faithful_arithmetic: str = ""
    faithful_verdict: str = ""
    realizations: str = ""
    paper_setup_value: str = ""
    paper_setup_verdict: str = ""
    run_verdict: str = ""


class MissingDataset(KeyError):
    """A dataset the ledger needs was not built, or cannot be read (args: name[, why])."""

    def __str__(self) -> str:
        return f"dataset {self.args[0]} " + (self.args[1] if len(self.args) > 1 else "not built")


class _Datasets:
    """The datasets of one data directory, each read once; MissingDataset naming a missing one.
    Names are paths under the directory without .nc (a scene, or its variant in a finer precision,
    ``sleighsim.io.layout.variant``, or a realization, ``sleighsim.io.layout.realization``).
    Which variants and realizations exist is what the config declares, never which files are
    there: ``ladders`` {scene: precisions, coarse to fine} (``catalog.laddered``), ``realized``
    {scene: number of realizations} (``catalog.realized``)."""

    def __init__(self, data_dir: Path, ladders: dict[str, list[str]], realized: dict[str, int]):
        self.dir, self.cache = Path(data_dir), {}
        self.ladders, self.realized = dict(ladders), dict(realized)

    def __call__(self, names) -> list:
        for name in names:
            if name not in self.cache:
                path = self.dir / f"{name}.nc"
                if not path.exists():
                    raise MissingDataset(name)
                try:
                    self.cache[name] = read_dataset(path)
                except OSError as err:
                    raise MissingDataset(name, f"unreadable ({err})") from err
        return [self.cache[n] for n in names]

    def finest(self, names) -> str:
        """The finest precision the config ladders every one of ``names`` in (double when any is
        not laddered, or when ``names`` is empty)."""
        if not names or any(n not in self.ladders for n in names):
            return Precision.DOUBLE
        common = set.intersection(*(set(self.ladders[n]) for n in names))
        return max(common, key=PRECISIONS.index, default=Precision.DOUBLE)

    def variants(self, names, precision: str) -> list[str]:
        """Each of ``names`` in ``precision`` where the config ladders it in that precision, else as is."""
        return [layout.variant(n, precision) if precision in self.ladders.get(n, ()) else n for n in names]

    def realizations(self, names) -> list[list[str]]:
        """The evidence of realizations k = 1 .. n-1 of ``names`` (n: the fewest realizations the
        config asks of any of them that is realized): each realized name replaced by its realization
        k (empty when none is realized). Loading a declared realization that was not built raises
        MissingDataset."""
        realized = [n for n in names if n in self.realized]
        n = min((self.realized[r] for r in realized), default=1)
        return [[layout.realization(m, k) if m in realized else m for m in names] for k in range(1, n)]

    def ladder_status(self, names) -> str:
        """The converged precision of each of ``names`` the config ladders (data/ladder/<name>.nc), and
        whether double follows its orbit where the ladder measured the gauge."""
        out = []
        for n in names:
            if n not in self.ladders:
                continue
            ds = self([layout.ladder(n)])[0]
            c = ds.attrs["converged_precision"]
            text = f"{n}: " + (f"converged in {c}" if c != "not converged" else c)
            if "follows_orbit" in ds:
                f = str(ds.follows_orbit.sel(precision=Precision.DOUBLE).values)
                text += ((", double " + f) if f != UNKNOWN
                         else ", double's faithfulness not measured (no full spike cycle)")
            out.append(text)
        return "; ".join(out)


def _judged(claim: Claim, datasets: list):
    j = JUDGES[claim.id](claim.values, *datasets)
    if j.verdict not in VERDICTS or j.verdict == DOUBLE_ONLY:
        raise ValueError(f"{claim.id}: judge returned {j.verdict!r}")
    return j


#: Written into the ledger (attribute precision_rule).
IN_PRECISION_RULE = (
    "The verdict of a claim whose datasets were computed in double and in a finer ``precision``: the finer "
    "arithmetic's verdict, except \"reproduced only in double precision\" when double reproduces the paper's "
    "value and the finer arithmetic does not. Returns (verdict, reason)."
)


def in_precision(double, finest, precision: str):
    """Applies :data:`IN_PRECISION_RULE`, the rule as the datasets record it (just above)."""
    if double.verdict == REPRODUCED and finest.verdict in (DIFFERS, CANNOT):
        return DOUBLE_ONLY, (f"double reproduces the paper ({double.measured}); {precision} does not "
                             f"({finest.measured}){': ' + finest.reason if finest.reason else ''}")
    return finest.verdict, finest.reason


def judge_claim(row: Row, claim: Claim, load: _Datasets) -> None:
    """A claim row from its judge, in the finest precision the config ladders all its datasets in
    (beside double's value), then, if it differs, its cause tests (on the datasets of that precision
    where the config ladders them in it)."""
    names = EVIDENCE.get(claim.id, ())
    row.precision = precision = load.finest(names)
    j = j_double = _judged(claim, load(names))
    row.verdict, row.reason = j.verdict, j.reason
    if row.precision != Precision.DOUBLE:
        j = _judged(claim, load(load.variants(names, precision)))
        row.verdict, row.reason = in_precision(j_double, j, row.precision)
        row.double_value = j_double.measured
        status = load.ladder_status(names)
        row.precision += f" ({status})" if status else ""
    judge_realizations(row, claim, names, load, j_double, judged_in=precision)
    row.measured, row.rule = j.measured, j.rule
    row.uncertainty, row.units, row.difference = j.uncertainty, j.units, float(j.difference)
    row.evidence = files(names) + (" " + j.note if names and j.note.startswith("(") else
                                    "; " + j.note if names and j.note else j.note)
    if row.verdict == DOUBLE_ONLY:
        row.cause = f"{ARITHMETIC}: {row.reason}"
    if row.verdict == DIFFERS and claim.id.startswith("D"):
        row.cause = ("the paper's model as printed (found by the derivation, no run involved): "
                     + (j.reason or j.measured))
    if row.verdict == DIFFERS and claim.id in CAUSE_TESTS:
        needed = load.variants(CAUSES[claim.id], precision)  # the arithmetic the verdict was judged in
        try:
            row.cause = CAUSE_TESTS[claim.id](j, claim.values, *load(needed))
            row.evidence += "; causes: " + files(needed)
        except MissingDataset as missing:
            row.cause = f"causes not yet computed: {missing}"


def judge_realizations(row: Row, claim: Claim, names, load: _Datasets, first,
                       judged_in: Precision = Precision.DOUBLE) -> None:
    """The claim judged again on every realization of its datasets (``_Datasets.realizations``;
    ``first`` is the judgement of realization 0 in double): the row keeps its verdict when all agree,
    else it is "fragile" with the count of each verdict (``chaos.rule.agree``). Realizations run in
    double: a claim judged in a finer precision (``judged_in``, one run) keeps that verdict, and its
    column says how the double realizations agree."""
    sets = load.realizations(names)
    if not sets:
        return
    verdicts = [first.verdict] + [_judged(claim, load(s)).verdict for s in sets]
    answer, _, why = agree(verdicts)
    if judged_in != Precision.DOUBLE:
        row.realizations = f"in double: {why}; {judged_in}: one run"
        return
    row.realizations = why
    if answer == FRAGILE:
        row.verdict, row.reason = FRAGILE, f"{why}; realization 0: {row.reason or first.measured}"


def ledger(claims_md, data_dir, figures_dir, config: dict, figures: dict) -> list[Row]:
    """The rows of every id of CLAIMS.md (path ``claims_md``), judged once each, in file order, from
    the datasets in ``data_dir`` that ``config`` (the workflow's merged config) declares: its
    precision ladders and realizations, on-request scenes included. ``figures`` {name: Figure}
    (:data:`sleighsim.report.figures.catalog.FIGURES`) says which figure in ``figures_dir`` each
    figure row (F..) is, what it shows and which claims it illustrates."""
    fidelity.label(config)  # a run that names no label is refused before anything is judged
    by_paper_id = {f.paper: f for f in figures.values() if f.paper}
    load = _Datasets(data_dir, laddered(config, on_request=True), realized(config, on_request=True))
    rows = []
    claims = {c.id: c for c in parse_claims(claims_md)}
    for claim in claims.values():
        row = Row(claim.id, claim.statement, claim.paper_value)
        try:
            if claim.id in by_paper_id:
                judge_figure(row, by_paper_id[claim.id], load, Path(figures_dir))
            elif claim.id in JUDGES:
                judge_claim(row, claim, load)
            else:
                row.reason = "no judge for this id"
        except MissingDataset as missing:
            row.verdict, row.reason = NOT_YET, str(missing)
            row.measured = row.uncertainty = ""
        rows.append(row)
    with_setup(rows, load, config)  # before the figure rows quote their claims' causes
    for row in rows:
        if row.id not in by_paper_id:
            row.verdict = rules.severity(row.verdict, row.difference)
    judged = {r.id: r for r in rows}
    for row in rows:
        if row.id in FAITHFUL_JUDGES:
            judge_faithful(row, claims[row.id], load)
    for row in rows:
        if row.id in by_paper_id:
            figure_from_claims(row, judged, by_paper_id[row.id].claims)
            faithful_figure(row, judged, by_paper_id[row.id].claims)
    for_run(rows, config)
    return rows


def judge_faithful(row: Row, claim: Claim, load: _Datasets) -> None:
    """The row's faithful columns (:mod:`sleighsim.claims.faithful`, :data:`FAITHFUL_RULE`) from the datasets
    of evidence.FAITHFUL; OWN becomes the row's own verdict; a missing dataset gives "not yet computed"."""
    try:
        if FAITHFUL_JUDGES[claim.id] is IN_LADDER:
            return faithful_in_ladder(row, claim, load)
        f = FAITHFUL_JUDGES[claim.id](claim.values, *load(FAITHFUL[claim.id]))
    except MissingDataset as missing:
        row.faithful_value, row.faithful_verdict = f"not computed: {missing}", NOT_YET
        return
    row.faithful_value, row.faithful_arithmetic = f.value, f.arithmetic
    row.faithful_verdict = row.verdict if f.verdict == OWN else f.verdict


def faithful_in_ladder(row: Row, claim: Claim, load: _Datasets) -> None:
    """The faithful columns of a claim judged again by its own judge on the finest precision its laddered datasets
    are laddered in, when each ladder's gauge says that arithmetic follows its orbit (:class:`IN_LADDER`); a dataset
    of its evidence that is not laddered (derived from others in double) is passed to the judge as None."""
    names = EVIDENCE[claim.id]
    laddered = [n for n in names if n in load.ladders]
    precision = load.finest(laddered)
    gauges = [load([layout.ladder(n)])[0] for n in laddered]
    follows = [str(g.follows_orbit.sel(precision=precision).values) if "follows_orbit" in g else UNKNOWN
               for g in gauges]
    gain = ", ".join(f"10^{float(g.log10_gain_rounding.sel(precision=precision)):.1f}" for g in gauges
                     if "log10_gain_rounding" in g)
    row.faithful_arithmetic = f"{precision} (G x rounding {gain or 'not measured'})"
    if precision == Precision.DOUBLE or not follows or any(f != FOLLOWS for f in follows):
        row.faithful_value = (f"not computed: the finest arithmetic of its ladder ({precision}) "
                              f"{'is not shown to follow' if precision != Precision.DOUBLE else 'is double'} "
                              f"({', '.join(follows) or 'no gauge'}); ladder it in one the gauge accepts")
        row.faithful_verdict = NOT_YET
        return
    found = dict(zip(laddered, load(load.variants(laddered, precision))))
    j = _judged(claim, [found.get(n) for n in names])
    left = [n for n in names if n not in found]
    row.faithful_value = j.measured + (f" (judged without {', '.join(left)}, which is not laddered)" if left else "")
    row.faithful_verdict = rules.severity(j.verdict, float(j.difference))


def faithful_figure(row: Row, judged: dict, claims) -> None:
    """A figure row's faithful columns: those of the claims it illustrates that have them, the verdict the
    least favourable of theirs (VERDICTS order past "reproduced")."""
    mine = [judged[c] for c in claims if c in judged and judged[c].faithful_verdict]
    if not mine:
        return
    row.faithful_value = "; ".join(f"{c.id}: {c.faithful_value}" for c in mine)
    row.faithful_arithmetic = "; ".join(sorted({c.faithful_arithmetic for c in mine}))
    row.faithful_verdict = max((c.faithful_verdict for c in mine), key=VERDICTS.index)


def for_run(rows: list[Row], config: dict) -> None:
    """Each row for the run of ``config`` (:data:`sleighsim.claims.fidelity.FIDELITY_RULE`): its texts made
    :func:`sleighsim.claims.rules.readable` (no bare NaN), its own data's verdict in ``run_verdict``; a run not
    at the paper's fidelity reads "not a reproduction", its reason naming the config and that verdict."""
    against_paper, ident = fidelity.reproduction(config), fidelity.identity(config)
    for row in rows:
        for f in fields(Row):
            if isinstance(getattr(row, f.name), str):
                setattr(row, f.name, rules.readable(getattr(row, f.name)))
        row.run_verdict = row.verdict
        if not against_paper:
            row.faithful_verdict = rules.NOT_A_REPRODUCTION if row.faithful_verdict else ""
            row.verdict = rules.NOT_A_REPRODUCTION
            row.reason = (f"a {ident['config_label']} run ({fidelity.describe(ident)}), not at the paper's fidelity: "
                          f"on its own data, {row.run_verdict}" + (f" ({row.reason})" if row.reason else ""))


def with_setup(rows: list[Row], load: _Datasets, config: dict) -> None:
    """Each row's value and verdict under the setup inferred jointly (the config's paper_setup scene,
    :mod:`sleighsim.claims.setup_columns`); an unexplained cause is told the setup was tried."""
    names = scenes_of(config, PAPER_SETUP)
    try:
        setup = load(names[:1])[0] if names else None
    except MissingDataset:
        setup = None
    for row in rows:
        row.paper_setup_value, row.paper_setup_verdict = columns(row.id, row.verdict, setup)
        row.cause = cause_with_setup(row.cause, row.paper_setup_verdict)


#: What the ledger's dataset is (its CF title).
TITLE = "the claims ledger: every claim of the paper judged from the datasets (paper/CLAIMS.md)"


def write(rows: list[Row], csv_path, nc_path, identity: dict | None = None) -> None:
    """Write the ledger ``rows`` as CSV (one row per claim) to ``csv_path`` and as a netCDF dataset to
    ``nc_path``; ``identity``: the run's config (:func:`sleighsim.claims.fidelity.identity`), recorded in the
    dataset's attributes (None: a ledger of no run, such as a test's)."""
    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow([f.name for f in fields(Row)])
    writer.writerows(astuple(r) for r in rows)
    write_text(csv_path, buf.getvalue())
    ds = to_dataset(rows)
    ds.attrs.update(identity or {})
    write_dataset(ds, nc_path, what=TITLE, vocabulary=VOCABULARY)


def read(nc_path) -> list[Row]:
    """The rows of the ledger written by :func:`write` to the netCDF file ``nc_path``."""
    ds = read_dataset(nc_path)
    names = [f.name for f in fields(Row) if f.name != "id" and f.name in ds.data_vars]
    return [Row(id=str(i), **{k: (float(ds[k].values[j]) if k == "difference" else str(ds[k].values[j]))
                              for k in names}) for j, i in enumerate(ds.id.values)]


#: The ledger's own variables (sleighsim.io.cf): the verdicts as CF flags, beside their text.
VOCABULARY = {"run_verdict": ("the verdict the rules give on this run's own datasets", "text"),
              "verdict_flag": ("the verdict as a flag (flag_meanings: the verdicts, spaces as _)", "1"),
              "run_verdict_flag": ("run_verdict as a flag (flag_meanings: the verdicts, spaces as _)", "1")}


def _flag(name: str, verdicts) -> tuple:
    """The verdicts as the CF flag variable ``name`` along ``id`` (``io.cf.flags``: their indices in VERDICTS,
    int8, with flag_values and flag_meanings; its long_name the ledger's VOCABULARY's)."""
    return cf.flags("id", list(verdicts), VERDICTS, VOCABULARY[name][0])


def to_dataset(rows: list[Row]) -> xr.Dataset:
    """The ledger ``rows`` as a netCDF-ready dataset: one variable per column along ``id``, the verdict
    columns also as CF flags (``verdict_flag``, ``run_verdict_flag``), the counts per verdict and the rules
    as attributes."""
    names = [f.name for f in fields(Row) if f.name != "id"]
    data = {n: ("id", np.array([getattr(r, n) for r in rows], dtype=float) if n == "difference"
                else np.array([str(getattr(r, n)) for r in rows], dtype=object)) for n in names}
    ds = xr.Dataset(data, coords={"id": [r.id for r in rows]})
    ds["verdict_flag"] = _flag("verdict_flag", (r.verdict for r in rows))
    ds["run_verdict_flag"] = _flag("run_verdict_flag", (r.run_verdict or r.verdict for r in rows))
    ds.attrs.update({f"n_{v.replace(' ', '_')}": sum(r.verdict == v for r in rows) for v in VERDICTS})
    ds.attrs.update(rel_tol=rules.REL_TOL, k_sigma=rules.K_SIGMA, slight=rules.SLIGHT, great=rules.GREAT,
                    rules=rules.VERDICT_RULES, precision_rule=IN_PRECISION_RULE, faithful_rule=FAITHFUL_RULE,
                    fidelity_rule=fidelity.FIDELITY_RULE)
    return ds


def summary(rows: list[Row]) -> dict[str, int]:
    """{verdict: number of ``rows`` with it}, every verdict listed."""
    return {v: sum(r.verdict == v for r in rows) for v in VERDICTS}
