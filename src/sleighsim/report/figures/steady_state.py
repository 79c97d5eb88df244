"""Figures of the steady state: Poincare maps on the attractor (F9), return times (F12), power spectra (F13, F14)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import MaxNLocator

from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import (
    FREQUENCY,
    LABELS,
    PRECISION_STYLE,
    SYMBOLS,
    UNITS,
    WIDTH,
    finer_precisions,
    finish,
    subplots,
)
from sleighsim.report.figures.figure import Figure


def _attractor_panel(ax, ds, title, iterates="ppi2"):
    ax.scatter(ds.attractor_u, ds.attractor_Omega, ds.attractor_omega, s=0.2, c="0.7", alpha=0.3, depthshade=False)
    if iterates == "ppi2":
        for k in range(4):
            sel = ds.ppi2_class.values == k
            ax.scatter(ds.ppi2_u.values[sel], ds.ppi2_Omega.values[sel], ds.ppi2_omega.values[sel], s=2,
                       depthshade=False, label=f"$\\delta = {k}\\pi/2$ mod $2\\pi$")
    else:
        ax.scatter(ds.p2pi_u, ds.p2pi_Omega, ds.p2pi_omega, s=1.5, c=ds.p2pi_time, cmap="viridis", depthshade=False)
    for axis, name in ((ax.xaxis, "u"), (ax.yaxis, "Omega"), (ax.zaxis, "omega")):
        axis.set_label_text(LABELS[name])
        axis.set_major_locator(MaxNLocator(4))
    status = "" if ds.attrs["transient_over"] else "\nTRANSIENT NOT SHOWN OVER"
    ax.set_title(title + status)


def fig9(sources):
    """(a) P_2pi iterates; (b) P_pi/2 iterates on the attractor; (c) higher energy; (d) eps = 0.01.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ref, high, small, scaling = (read_dataset(s) for s in sources)
    fig = plt.figure(figsize=(WIDTH, 10.5), layout="constrained")
    panels = [
        (ref, "p2pi", f"(a) $P_{{2\\pi}}$: {ref.attrs['n_p2pi']} iterates (colour: time)\n"
                      f"rotation number {ref.attrs['rotation_number']:.5g} turns/iterate"),
        (ref, "ppi2", f"(b) $P_{{\\pi/2}}$ on the attractor, E label {ref.attrs['energy_label']:.4g}: "
                      f"{ref.attrs['n_loops']} loops"),
        (high, "ppi2", f"(c) E label {high.attrs['energy_label']:.4g}, $\\epsilon$ = {high.attrs['param_eps']:.3g}: "
                       f"{high.attrs['n_loops']} loops; divided by c = {scaling.attrs['scale_factor_c']:.4g},\n"
                       f"median distance to (b) {scaling.attrs['distance_scaled_median']:.2g} of its size "
                       f"(unscaled {scaling.attrs['distance_unscaled_median']:.2g})"),
        (small, "ppi2", f"(d) $\\epsilon$ = {small.attrs['param_eps']:.3g}, E label {small.attrs['energy_label']:.4g}: "
                        f"{small.attrs['n_loops']} loops"),
    ]
    for i, (ds, kind, title) in enumerate(panels):
        ax = fig.add_subplot(2, 2, i + 1, projection="3d")
        _attractor_panel(ax, ds, title, kind)
        if i == 1:
            ax.legend(markerscale=3, loc="upper left")
    return finish(fig, ref.attrs)


def fig12(sources):
    """Return times t_{n+1} - t_n of P_2pi for two values of eps: double (the paper's arithmetic)
    and, beside it, every finer precision computed from the same settled point.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    data = [read_dataset(s) for s in sources]
    finer = finer_precisions(data[2:])
    fig, axes = subplots(WIDTH, 4.4, 1, 2)
    for ax, ds, tag in zip(axes, data, "ab"):
        ax.plot(ds.return_time, ".", ms=1.2, label=Precision.DOUBLE, **PRECISION_STYLE[Precision.DOUBLE])
        for (scene, precision), other in finer.items():
            if scene == ds.attrs["scene"]:
                ax.plot(other.return_time, ".", ms=1.0, label=precision, **PRECISION_STYLE[precision])
        if len(finer):
            ax.legend(markerscale=6)
        ax.set_xlabel("iterate $n$ (count)")
        ax.set_ylabel("return time $t_{n+1} - t_n$ (time units)")
        ax.set_title(f"({tag}) $\\epsilon$ = {ds.attrs['param_eps']:.3g}, E label {ds.attrs['energy_label']:.4g}: "
                     f"range [{ds.attrs['return_time_min']:.5g}, {ds.attrs['return_time_max']:.5g}],\n"
                     f"min pairwise difference {ds.attrs['return_time_min_pairwise_difference']:.2g}"
                     + ("" if ds.attrs["transient_over"] else "; TRANSIENT NOT SHOWN OVER"))
    return finish(fig, ds.attrs)


def psd(sources):
    """Welch PSD of u and Omega with the band and the peaks near zero (F13, F14): double (the
    paper's arithmetic) and, beside it, every finer precision computed from the same settled point.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds, *others = (read_dataset(s) for s in sources)
    finer = finer_precisions(others)
    fig, axes = subplots(10, 7, 2, 1)
    for ax, v in zip(axes, ("u", "Omega")):
        f, S = ds.frequency.values[1:], ds[f"psd_{v}"].values[1:]
        ax.semilogy(f, S, lw=0.5, label=Precision.DOUBLE, **PRECISION_STYLE[Precision.DOUBLE])
        for (_, precision), other in finer.items():
            ax.semilogy(other.frequency.values[1:], other[f"psd_{v}"].values[1:], lw=0.5, label=precision,
                        **PRECISION_STYLE[precision])
        lo, hi = ds.attrs[f"{v}_band_low"], ds.attrs[f"{v}_band_high"]
        ax.axvspan(lo, hi, color="tab:orange", alpha=0.25, label=f"band [{lo:.4g}, {hi:.4g}]")
        ax.set_xlim(0, min(f[-1], 2.5 * hi))
        ax.set_ylabel(f"PSD of ${SYMBOLS[v]}$ (({UNITS[v]})$^2$ per cycle/time unit)")
        ax.legend(loc="upper right")
        inset = ax.inset_axes([0.08, 0.5, 0.3, 0.45])
        near = f < 20 * max(np.nan_to_num(ds.attrs[f"{v}_lowest_peak"], nan=1e-3), 1e-3)
        inset.semilogy(f[near], S[near], lw=0.6)
        inset.text(0.97, 0.95, f"near f = 0: {ds.attrs[f'{v}_n_peaks_near_zero']} peaks", transform=inset.transAxes,
                   ha="right", va="top", fontsize=8)
        inset.tick_params(labelsize=8)
    axes[-1].set_xlabel(f"frequency $f$ ({FREQUENCY})")
    status = "" if ds.attrs["transient_over"] else "  [TRANSIENT NOT SHOWN OVER]"
    axes[0].set_title(f"$\\epsilon$ = {ds.attrs['param_eps']:.3g}, E label {ds.attrs['energy_label']:.4g}, "
                      f"record {ds.attrs['record_duration']:g} time units at dt = {ds.attrs['sample_dt']:g} after "
                      f"t = {ds.attrs['record_start']:g}{status}")
    return finish(fig, ds.attrs)


FIG9 = Figure("fig9", fig9, ("fig9_ref", "fig9_highE", "fig9_eps001", "fig9_scaling"), "F9", ("C15", "C16", "C17"),
              steady=("fig9_ref", "fig9_highE", "fig9_eps001"))
FIG12 = Figure("fig12", fig12, ("fig9_ref", "fig9_eps001"), "F12", ("C22",), steady=("fig9_ref", "fig9_eps001"),
               beside=True)
FIG13 = Figure("fig13", psd, ("psd_eps01",), "F13", ("C23",), steady=("psd_eps01",), beside=True)
FIG14 = Figure("fig14", psd, ("psd_eps001",), "F14", ("C24",), steady=("psd_eps001",), beside=True)
