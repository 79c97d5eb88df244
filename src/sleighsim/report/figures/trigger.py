"""What triggers the steady state and where it leads: the first spike against the injected error with its local
slopes (figure ``trigger``), and the torus each escape lands on (figure ``fate``); both from the trigger_law
dataset alone."""

from __future__ import annotations

import numpy as np

from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import ARITHMETIC_COLOUR, finish, subplots
from sleighsim.report.figures.figure import Figure

TOL_LABEL = "Taylor tolerance: the injected error (relative, unitless)"


def _first_spikes(ax, ds) -> None:
    """The first spike per run, coloured by its arithmetic; open: not in the slopes (saturated marked x)."""
    for p in dict.fromkeys(ds.precision.values):
        colour = ARITHMETIC_COLOUR[Precision.parse(str(p))]
        sel = ds.precision.values == p
        for mask, kw in ((ds.in_slopes.values == 1, {"label": f"{p}"}), (ds.in_slopes.values == 0, {"mfc": "none"})):
            ax.semilogx(ds.tol.values[sel & mask], ds.first_spike.values[sel & mask], "o", color=colour, **kw)
        sat = sel & (ds.saturated.values == 1)
        ax.semilogx(ds.tol.values[sat], ds.first_spike.values[sat], "x", color=colour, ms=9,
                    label=f"{p}: saturated" if sat.any() else None)
    ax.set_xlabel(TOL_LABEL)
    ax.set_ylabel("first spike (time units)")


def _slopes(ax, ds) -> None:
    """Each range's local slope as a segment through its runs' mean, labelled with its value (and its standard
    error where the pooled scatter has a degree of freedom)."""
    ok = ds.in_slopes.values == 1
    tol, first = ds.tol.values[ok], ds.first_spike.values[ok]
    for r in range(ds.sizes["range"]):
        hi, lo = float(ds.range_tol_max.values[r]), float(ds.range_tol_min.values[r])
        inside = (tol <= hi * 1.0001) & (tol >= lo * 0.9999)
        x = np.log10(tol[inside])
        y0, slope = float(np.mean(first[inside])), float(ds.range_slope.values[r])
        ends = np.array([np.log10(hi), np.log10(lo)])
        ax.semilogx(10.0**ends, y0 + slope * (ends - x.mean()), "k-", lw=0.8)
        err = float(ds.range_slope_stderr.values[r])
        ax.annotate(f"{slope:.0f}" + (f" +- {err:.0f}" if np.isfinite(err) else ""), (10.0 ** ends.mean(), y0),
                    textcoords="offset points", xytext=(0, 8), ha="center", fontsize=8)


def trigger(sources):
    """The first spike per run against the injected error, saturated runs marked, and the local slopes (time units
    per decade, +- their standard errors). ``sources``: the paths of its datasets, in the order of its declaration.
    Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig, ax = subplots(8, 5.5)
    _first_spikes(ax, ds)
    _slopes(ax, ds)
    ax.set_title(f"Local slopes per range (time units per decade; {ds.attrs['slopes_dof']} degrees of freedom); "
                 "open: not in the slopes")
    ax.legend()
    return finish(fig, ds.attrs)


def fate(sources):
    """Top: the refined spike interval of the torus each escape lands on against the injected error (marker: the
    arithmetic it was followed in; filled where that arithmetic follows the torus and a twin confirms the landing,
    open otherwise; x where its train is not strictly periodic); bottom: the first spike. ``sources``: the paths
    of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig, (ax, bx) = subplots(8, 8, 2, 1, sharex=True)
    sure = (ds.landed_follows.values == "follows") & (ds.landing_confirmed.values == 1)
    for arith, m in {"double-double": "o", "triple-double": "s"}.items():
        for ok, kw in ((True, {}), (False, {"mfc": "none"})):
            pick = (ds.landed_arithmetic.values == arith) & (sure == ok)
            if pick.any():
                ax.errorbar(ds.tol.values[pick], ds.landed_interval.values[pick],
                            yerr=ds.landed_interval_scatter.values[pick], fmt=m, color="tab:green",
                            label=f"{arith}" + ("" if ok else ": not followed, or landing not confirmed"), **kw)
    odd = ds.landed_class.values == "not strictly periodic"
    ax.semilogx(ds.tol.values[odd], ds.landed_interval.values[odd], "x", color="k", ms=10,
                label="not strictly periodic" if odd.any() else None)
    ax.set_ylabel("landed torus: refined spike interval (time units)")
    ax.set_title("The torus each escape lands on, and the arithmetic that followed it there")
    ax.legend()
    _first_spikes(bx, ds)
    bx.set_title("The escape: first spike (open: not in the slopes)")
    bx.legend()
    return finish(fig, ds.attrs)


TRIGGER = Figure("trigger", trigger, ("trigger_law",),
                 title="What triggers the steady state? The first spike against the size of the injected error, "
                       "with its local slopes (C04)", section="sec:simulation")
FATE = Figure("fate", fate, ("trigger_law",), title="Where the paper's orbit goes: the torus each escape lands on, "
                                                    "against the injected error that triggered it",
              section="sec:simulation")
