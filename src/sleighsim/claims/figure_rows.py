"""The ledger's figure rows (F..): a figure counts when it was built from its datasets, every steady-state
dataset it shows carries a passed transient check (a failed one is this run's process check: "check
failed", not a difference from the paper), and no claim it illustrates differs (the figure then takes
the most severe word of its differing claims)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from sleighsim.claims.rules import CHECK_FAILED, DIFFERING, DIFFERS, DOUBLE_ONLY, FRAGILE, NOT_YET, REPRODUCED
from sleighsim.claims.setup_columns import NOT_APPLICABLE

if TYPE_CHECKING:  # the ledger's row type; the ledger imports this module
    from sleighsim.claims.ledger import Row


def files(names) -> str:
    """The datasets ``names`` as file names, comma separated."""
    return ", ".join(f"{n}.nc" for n in names)


def transient_checked(ds) -> tuple[bool, str]:
    """(passed, text): the dataset's transient check, an attribute or a per-row variable; a missing
    check is not a passed one."""
    if "transient_over" in ds.data_vars:
        v = np.asarray(ds.transient_over.values)
        return bool(v.size and np.all(v == 1)), f"{int(np.sum(v == 1))} of {v.size} rows settled"
    if "transient_over" in ds.attrs:
        return ds.attrs["transient_over"] == 1, "settled" if ds.attrs["transient_over"] == 1 else "not settled"
    return False, "no transient check"


def _number(name: str, value: float, fmt: str) -> str:
    """``name value`` formatted, or "no name" when the value is not a number."""
    return f"{name} {value:{fmt}}" if math.isfinite(value) else f"no {name}"


def transient_cause(name: str, ds) -> str:
    """Why the transient check failed in dataset ``name`` (the cause of a figure row whose check failed):
    our run's pre-run, not the paper. Per row: the rows not settled with their pre-run length and those
    another config computes; else the pre-run's spike count, first spike and spike intervals (those it
    could not measure named as such)."""
    if "transient_over" in ds.data_vars:
        return f"{name}: " + "; ".join(_unsettled_rows(ds))
    a = {k: float(ds.attrs.get(f"transient_{k}", math.nan)) for k in
         ("n_spikes", "first_spike", "spike_interval_mean_first_half", "spike_interval_mean_second_half",
          "settling_time")}
    n = f"{a['n_spikes']:.0f}" if math.isfinite(a["n_spikes"]) else "an unknown number of"
    first = f" (first at {a['first_spike']:.6g})" if math.isfinite(a["first_spike"]) else ""
    intervals = ", ".join(_number(f"spike interval over the {half} half", a[f"spike_interval_mean_{half}_half"],
                                  ".5g") for half in ("first", "second"))
    return (f"{name}: the pre-run holds {n} spikes{first}, {intervals}, "
            f"{_number('settling time', a['settling_time'], '.5g')}: too short to show the transient over")


def _unsettled_rows(ds) -> list[str]:
    """The rows of a per-row transient check not settled (with their pre-run length t_pre) and those
    not computed in this run (NaN; the config that computes them when the dataset names it)."""
    over = np.asarray(ds.transient_over.values, float)
    axis = ds.transient_over.dims[0]
    x = ds[axis].values
    t_pre = ds["t_pre"].values if "t_pre" in ds else np.full(over.size, np.nan)
    parts = [f"{axis} {v:.3g} not settled within its pre-run of {t:.3g}" for v, o, t in zip(x, over, t_pre) if o == 0]
    away = [f"{v:.3g}" for v, o in zip(x, over) if not np.isfinite(o)]
    if away:
        where = ds.attrs.get("elsewhere_config", "")
        parts.append(f"{axis} {', '.join(away)} not computed in this run"
                     + (f" ({where} computes it)" if where else ""))
    return parts


def judge_figure(row: Row, fig, load, figures_dir: Path) -> None:
    """A figure row: the figure ``fig`` (a :class:`sleighsim.report.figures.figure.Figure`: its
    ``name``, ``data`` and ``steady`` datasets) built in ``figures_dir`` from its datasets (``load``: the
    ledger's dataset reader), and every steady-state dataset's transient check passed. Sets the row's
    verdict and texts: "check failed" when a check failed (this run's pre-run, not the paper)."""
    png = Path(figures_dir) / f"{fig.name}.png"
    row.evidence = ", ".join([*(f"{n}.nc" for n in fig.data), png.name])
    row.rule = "the figure is built from its datasets" + (
        f" and the transient check passed in {files(fig.steady)}" if fig.steady else "")
    if not png.exists():
        row.verdict, row.reason = NOT_YET, f"figure {png.name} not built"
        return
    steady = dict(zip(fig.steady, load(fig.steady)))
    checks = {n: transient_checked(ds) for n, ds in steady.items()}
    row.measured = f"figure {png.name}" + "".join(f"; {n}: {text}" for n, (_, text) in checks.items())
    failed = [n for n, (ok, _) in checks.items() if not ok]
    missing = [n for n in failed if checks[n][1] == "no transient check"]
    if missing:
        row.verdict, row.reason = NOT_YET, f"no transient check in {files(missing)}"
    elif failed:
        row.verdict, row.reason = CHECK_FAILED, f"the transient is not shown to be over in {files(failed)}"
        row.cause = "this run's pre-run, not the paper: " + "; ".join(transient_cause(n, steady[n]) for n in failed)
    else:
        row.verdict = REPRODUCED


def _worst(words) -> str:
    """The most severe of differing words (DOUBLE_ONLY counts as DIFFERS)."""
    return max((DIFFERS if w == DOUBLE_ONLY else w for w in words), key=DIFFERING.index)


def figure_from_claims(row: Row, judged: dict, claims: tuple) -> None:
    """A built figure is no better than the claims it illustrates (``judged``: rows by id, their
    verdicts already worded by size): a reproduced figure whose claims differ takes the most severe of
    their words, one whose claims are fragile is fragile; a figure whose check failed says so in its
    reason. Its paper_setup_verdict quotes theirs (a figure has no numbers of its own for the setup to move)."""
    if claims:
        row.rule += "; then no better than the claims it illustrates (" + ", ".join(claims) + ")"
    differing = [c for c in claims if c in judged and judged[c].verdict in (*DIFFERING, DOUBLE_ONLY)]
    fragile = [c for c in claims if c in judged and judged[c].verdict == FRAGILE]
    if row.verdict == REPRODUCED and differing:
        row.verdict = _worst(judged[c].verdict for c in differing)
        row.reason = "its claims differ: " + ", ".join(differing)
        row.cause = "; ".join(f"{c}: {judged[c].cause or 'no cause test yet'}" for c in differing)
    elif row.verdict == REPRODUCED and fragile:
        row.verdict, row.reason = FRAGILE, "its claims are fragile: " + ", ".join(fragile)
    elif row.verdict == CHECK_FAILED and claims:
        row.reason += "; its claims: " + ", ".join(f"{c} {judged[c].verdict}" for c in claims if c in judged)
    tried = [c for c in claims if c in judged and judged[c].paper_setup_verdict
             and not judged[c].paper_setup_verdict.startswith(NOT_APPLICABLE)]
    if tried:
        row.paper_setup_verdict = (f"{NOT_APPLICABLE} to a figure; its claims under the paper's setup: "
                                   + "; ".join(f"{c}: {judged[c].paper_setup_verdict}" for c in tried))
