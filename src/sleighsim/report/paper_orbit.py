"""What the paper's own orbit does, in one sentence for the first screen and the finding, from the trigger-law
dataset (:data:`sleighsim.scenes.trigger.TRIGGER_LAW`): when its second transient ends as the integration error
falls, and the torus it lands on after each escape, in the arithmetic that follows it."""

from __future__ import annotations

import numpy as np

from sleighsim.chaos.faithfulness import FOLLOWS
from sleighsim.claims.faithful import finest_range
from sleighsim.io.netcdf import read_dataset
from sleighsim.report.findings import of_kind
from sleighsim.scenes.trigger import TRIGGER_LAW


def paper_orbit(datasets: dict, kinds: dict) -> str:
    """The sentence from the run's trigger-law dataset (``datasets`` {name: path}, ``kinds`` {scene: kind name}),
    or "" when the run has none."""
    path = of_kind(datasets, kinds, TRIGGER_LAW)
    return describe(read_dataset(path, verified=False)) if path else ""


def _start(ds) -> str:
    return "(" + ", ".join(f"{float(ds.attrs[f'y0_{c}']):g}" for c in ("u", "Omega", "omega", "delta")) + ")"


def describe(ds) -> str:
    """The sentence from a trigger-law dataset ``ds``: the first spike's range over the unsaturated runs and its
    slope at the finest range (time units per decade of integration error), then the landed tori."""
    ok = ds.saturated.values == 0
    first, tol = ds.first_spike.values[ok], ds.tol.values[ok]
    slope, err, label, moving = finest_range(ds)
    text = (f"From the paper's own start {_start(ds)} the second transient ends at the first spike, t = "
            f"{np.nanmin(first):.0f} to {np.nanmax(first):.0f} as the integration error goes from {tol.max():.0e} to "
            f"{tol.min():.0e} ({ok.sum()} runs), "
            + (f"still moving {abs(slope):.0f} +- {err:.0f} time units per decade at the finest range "
               f"({label}): the integration error decides when the orbit escapes."
               if moving else f"no longer moving at the finest range ({label})."))
    if "landed_interval" not in ds:
        return text
    followed = ds.landed_follows.values[ok] == FOLLOWS
    classes = ", ".join(sorted(set(map(str, ds.landed_class.values[ok]))))
    where = ", ".join(sorted(set(map(str, ds.landed_arithmetic.values[ok][followed])))) or "no arithmetic"
    return text + (f" Each escape lands on a torus ({classes}) whose spike interval depends on that error: "
                   f"{np.nanmin(ds.landed_interval.values[ok]):.0f} to {np.nanmax(ds.landed_interval.values[ok]):.0f}, "
                   f"{followed.sum()} of {ok.sum()} followed in {where}.")
