"""The measured price of the arithmetic a landed torus would need, from the multiple-precision benchmark's record
(benchmarks/multiprec.yaml, schema sleighsim.multiprec/1: per candidate arithmetic its unit roundoff and median
CPU seconds per time unit on one core), for the trigger law's fate (sleighsim.scenes.trigger_fate).

Conventions: CPU seconds per time unit of one orbit, on the machine and at the commit the record names; a cycle
is the landed torus' refined interval.
"""

from __future__ import annotations

import math
from pathlib import Path

import yaml

SCHEMA = "sleighsim.multiprec/1"
ROW_KEYS = ("candidate", "rounding", "cpu_s_per_tu")


def problems(path) -> list[str]:
    """What makes the record at ``path`` unusable as a price record (missing, not YAML, another schema, a
    candidate without its rounding or cost); empty when usable."""
    path = Path(path)
    if not path.is_file():
        return ["no such file in the repository (write it with python benchmarks/multiprec.py)"]
    try:
        rec = yaml.safe_load(path.read_text())
    except yaml.YAMLError as err:
        return [f"not YAML: {err}"]
    if not isinstance(rec, dict) or rec.get("schema") != SCHEMA:
        return [f"not a {SCHEMA} record"]
    rows = rec.get("rows") or []
    bad = [str(i) for i, r in enumerate(rows) if not all(k in r for k in ROW_KEYS)]
    return ([] if rows else ["no candidate rows"]) + ([f"rows {', '.join(bad)} lack {ROW_KEYS}"] if bad else [])


def load(path) -> dict:
    """The record at ``path`` (checked by :func:`problems`; ValueError naming them)."""
    bad = problems(path)
    if bad:
        raise ValueError(f"{path}: {'; '.join(bad)}")
    return yaml.safe_load(Path(path).read_text())


#: Written into the trigger_law dataset (attribute price_rule).
PRICE_RULE = (
    "Where the last arithmetic tried does not follow the landed torus, the arithmetic it would need: the rounding "
    "below which the gauge would accept one (FAITHFUL_MAX / (G x steps), from that torus' G and steps), and the "
    "cheapest candidate of the price record (price_record: the multiple-precision benchmark) whose rounding lies "
    "below it, with its measured CPU seconds per time unit and per cycle of the torus (its refined interval); "
    "none when no candidate's rounding is fine enough."
)


def log10_needed(log10_gain_rounding: float, rounding: float, limit: float) -> float:
    """log10 of the unit roundoff below which G x steps x rounding < ``limit``, from an arithmetic's log10 G x
    steps x rounding and its unit roundoff ``rounding`` (NaN when unknown)."""
    return math.log10(limit) - (log10_gain_rounding - math.log10(rounding))


def price(record: dict, rounding: float, interval: float) -> str:
    """Applies :data:`PRICE_RULE` for a torus needing unit roundoff below ``rounding`` with spike interval
    ``interval``: the text naming the candidate and its price, or that none is fine enough."""
    fine = [r for r in record["rows"] if r["rounding"] < rounding]
    where = f"benchmarks/multiprec.yaml at {str(record.get('git_commit', '?'))[:7]}"
    if not fine:
        return f"no candidate of {where} rounds below {rounding:.1e}"
    best = min(fine, key=lambda r: r["cpu_s_per_tu"])
    per_cycle = best["cpu_s_per_tu"] * interval if math.isfinite(interval) else math.nan
    return (f"{best['candidate']} (rounding {best['rounding']:.1e}) would: {best['cpu_s_per_tu']:.3g} CPU-s per time "
            f"unit, {per_cycle:.3g} per cycle ({where})")
