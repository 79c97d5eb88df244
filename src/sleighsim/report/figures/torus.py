"""The torus family around the main state (sleighsim.scenes.torus_stability): each perturbed orbit's period
difference and spike-point offset against the perturbation's size a, one line per seeded direction, with
the fitted laws."""

from __future__ import annotations

import math

import numpy as np

from sleighsim.analysis.torus import NOT_SHOWN
from sleighsim.io.netcdf import read_dataset
from sleighsim.report.figures.common import WIDTH, finish, subplots
from sleighsim.report.figures.figure import Figure


def _law(a: dict, name: str, what: str) -> str:
    """A law's attributes as a title line."""
    if not a.get(f"{name}_directions", 0):
        return f"{what}: not fitted"
    err = a[f"{name}_err"]
    return f"{what} {a[name]:.3g}" + (f" +- {err:.2g}" if math.isfinite(err) else "") + \
        f" ({a[f'{name}_directions']} directions)"


def torus_family(sources):
    """Left: period minus the reference's (time units) against a; right: the spike point's relative offset
    (log scale) against a; filled markers for orbits shown to be on tori, open ones for the rest.
    ``sources``: the path of the torus_stability dataset. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig, (ax, bx) = subplots(WIDTH, 4.5, 1, 2)
    a = ds.amplitude.values
    for k in np.unique(ds.direction.values[1:]):
        sel = np.flatnonzero(ds.direction.values == k)
        sel = sel[np.argsort(a[sel])]
        torus = ds.torus_class.values[sel] != NOT_SHOWN
        for axis, y in ((ax, ds.period_difference.values[sel]), (bx, ds.spike_point_offset.values[sel])):
            line, = axis.plot(a[sel], y, "-", color=f"C{k % 10}", lw=0.8, label=f"direction {k}")
            axis.plot(a[sel][torus], y[torus], "o", color=line.get_color(), ms=4)
            axis.plot(a[sel][~torus], y[~torus], "o", mfc="none", color=line.get_color(), ms=4)
    for axis in (ax, bx):
        axis.set_xscale("log")
        axis.set_xlabel("relative size a of the start's perturbation (unitless)")
    bx.set_yscale("log")
    ax.set_ylabel("period minus the reference's (time units)")
    bx.set_ylabel("spike-point offset from the reference's (unitless)")
    ax.legend(fontsize=8)
    attrs = ds.attrs
    ax.set_title(f"reference period {attrs['reference_period']:.10g}\n"
                 + _law(attrs, "period_law_slope", "time units per decade of a:"), fontsize=9)
    bx.set_title("filled: shown to be on a torus; open: not\n"
                 + _law(attrs, "offset_law_exponent", "offset ~ a to the power"), fontsize=9)
    return finish(fig, attrs)


TORUS = Figure("torus", torus_family, ("torus_stability",),
               title="The torus family around the main state: period and spike point against the perturbation (C06)",
               section="sec:simulation")
