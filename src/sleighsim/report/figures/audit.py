"""The model as printed: energy drift of the printed udot (D1)."""

from __future__ import annotations

import numpy as np

from sleighsim.io.netcdf import read_dataset
from sleighsim.report.figures.common import LABELS, finish, subplots
from sleighsim.report.figures.figure import Figure


def audit(sources):
    """Energy drift of the printed udot against the derived equations (D1).
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig, ax = subplots(8, 4.5)
    for name in ("printed", "derived"):
        v = np.abs(ds[f"energy_rel_change_{name}"].values[1:])
        ax.semilogy(ds.time.values[1:], np.maximum(v, 1e-17), "-", label=f"{name} equations")
    ax.set_xlabel(LABELS["t"])
    ax.set_ylabel(r"$|E(t)/E(0) - 1|$ (relative)")
    ax.set_title(f"The paper's printed udot does not conserve the energy: max change "
                 f"{ds.attrs['printed_max_abs_rel_change']:.3g} "
                 f"(derived: {ds.attrs['derived_max_abs_rel_change']:.2g})")
    ax.legend()
    return finish(fig, ds.attrs)


AUDIT = Figure("audit", audit, ("audit",), title="The model as printed: energy drift of the printed udot",
               section="sec:eom")
