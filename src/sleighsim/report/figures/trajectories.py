"""Figures of single runs: the schematic (F1), the eps = 0 sleigh (F2), transients and steady state in time
(F3, F7) and the path (F8)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import patches
from matplotlib.lines import Line2D

from sleighsim.io.netcdf import read_dataset
from sleighsim.precision import Precision
from sleighsim.report.figures.common import LABELS, PRECISION_STYLE, finer_precisions, finish, subplots
from sleighsim.report.figures.figure import Figure


def fig1(cfg: dict):
    """Schematic: sleigh body, centre C, runner P at distance b, rotor at distance a.
    ``cfg``: the scene's config block (a dict). Returns the matplotlib Figure."""
    b, a, th, be = cfg["b"], cfg["a"], cfg["theta"], cfg["beta"]
    fig, ax = subplots(5.5, 4.5)
    ex, ey = np.array([np.cos(th), np.sin(th)]), np.array([-np.sin(th), np.cos(th)])
    C = np.zeros(2)
    P = C - b * ex
    body = patches.Ellipse(C - 0.25 * b * ex, 2.1 * b, 0.9 * b, angle=np.degrees(th), fc="0.92", ec="k")
    ax.add_patch(body)
    R = C + a * np.array([np.cos(be), np.sin(be)])
    ax.add_patch(patches.Circle(C, a, fill=False, ls=":", ec="0.5"))
    ax.plot(*zip(C, R), color="tab:red", lw=2)
    ax.plot(*R, "o", color="tab:red", ms=9)
    ax.plot(*C, "ko", ms=5)
    ax.plot([P[0] - 0.2 * b * ex[0], P[0] + 0.2 * b * ex[0]], [P[1] - 0.2 * b * ex[1], P[1] + 0.2 * b * ex[1]],
            color="tab:blue", lw=5, solid_capstyle="butt")
    for vec, name in ((ex, r"$X_b$"), (ey, r"$Y_b$")):
        ax.annotate("", C + 0.9 * b * vec, C, arrowprops=dict(arrowstyle="->", lw=1.2))
        ax.text(*(C + 0.97 * b * vec), name, fontsize=11)
    ax.annotate("", (1.6 * b, 0), (-1.6 * b, 0), arrowprops=dict(arrowstyle="->", color="0.6"))
    ax.text(1.62 * b, 0, r"$X$", color="0.4")
    ax.text(*(C + np.array([0.05, -0.12]) * b), r"$C$", fontsize=12)
    ax.text(*(P + np.array([-0.05, -0.2]) * b), r"$P$ (runner)", fontsize=11, color="tab:blue")
    ax.text(*(R + np.array([-0.75, 0.12]) * b), r"rotor $m_r, I_r$", fontsize=10, color="tab:red")
    ax.text(*((C + R) / 2 + np.array([-0.12, 0.02]) * b), r"$a$", color="tab:red", fontsize=12)
    ax.text(*((C + P) / 2 + 0.08 * b * ey), r"$b$", fontsize=12)
    ax.add_patch(patches.Arc(C, 0.5 * b, 0.5 * b, theta1=0, theta2=np.degrees(th), color="0.3"))
    ax.text(*(C + 0.3 * b * np.array([np.cos(th / 2), np.sin(th / 2)])), r"$\theta$", fontsize=11)
    ax.add_patch(patches.Arc(C, 0.35 * b, 0.35 * b, theta1=0, theta2=np.degrees(be), color="tab:red"))
    ax.text(*(C + 0.2 * b * np.array([np.cos(be / 2), np.sin(be / 2)])), r"$\beta$", fontsize=11, color="tab:red")
    ax.set_aspect("equal")
    ax.set_xlim(-1.7 * b, 1.8 * b)
    ax.set_ylim(-1.2 * b, 1.3 * b)
    ax.axis("off")
    ax.set_title(r"Chaplygin sleigh with a passive rotor; $\delta = \theta - \beta$", fontsize=10)
    return fig


def fig2(sources):
    """(a) eps = 0 phase portrait with sample trajectories; (b) path from (u, Omega) = (0, 1).
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig, (ax, bx) = subplots(10, 4.6, 1, 2)
    ax.streamplot(ds.u_grid.values, ds.Omega_grid.values, ds.du.values.T, ds.dOmega.values.T,
                  color="0.75", density=0.9, linewidth=0.6, arrowsize=0.7)
    for k in range(ds.sizes["trajectory"]):
        line, = ax.plot(ds.u_closed[k], ds.Omega_closed[k], lw=1.4)
        ax.plot(ds.u_integrated[k][::8], ds.Omega_integrated[k][::8], ".", ms=2.5, color=line.get_color())
    ax.axhline(0, color="k", lw=1.5, label=r"$\Omega = 0$: fixed points")
    ax.set_xlabel(LABELS["u"])
    ax.set_ylabel(LABELS["Omega"])
    ax.set_xlim(ds.u_grid.values[[0, -1]])
    ax.set_ylim(ds.Omega_grid.values[[0, -1]])
    ax.set_title(f"(a) $\\epsilon=0$: closed form (lines), heyoka (dots)\nmax |difference| = "
                 f"{ds.attrs['closed_form_max_abs_error']:.1e}")
    ax.legend(loc="lower left")
    bx.plot(ds.path_x, ds.path_y, color="tab:blue")
    bx.plot(ds.path_x[0], ds.path_y[0], "ko", ms=4)
    bx.set_aspect("equal", adjustable="datalim")
    bx.set_xlabel(LABELS["x"])
    bx.set_ylabel(LABELS["y"])
    bx.set_title(f"(b) path from $u=0$, $\\Omega=1$, $t\\leq{float(ds.path_time[-1]):g}$")
    return finish(fig, ds.attrs)


def _time_panels(axes, ds, names, lw=0.3, finer=None):
    """One panel per variable against time: double, and over it every finer precision in ``finer``
    ({(scene, precision): dataset}, the same window from the same start), named once in a legend above the
    panels (a legend inside would cover the oscillation that fills each panel)."""
    for axk, name in zip(axes, names):
        axk.plot(ds.time, ds[name], lw=lw, label=Precision.DOUBLE, **PRECISION_STYLE[Precision.DOUBLE])
        for (_, precision), other in (finer or {}).items():
            axk.plot(other.time, other[name], lw=lw, label=precision, **PRECISION_STYLE[precision])
        axk.set_ylabel(LABELS[name])
        axk.set_xlabel(LABELS["t"])
    if finer:
        shown = [Precision.DOUBLE, *(precision for _, precision in finer)]
        axes[0].figure.legend(handles=[Line2D([], [], lw=2, label=str(p), **PRECISION_STYLE[p]) for p in shown],
                              loc="outside upper center", ncols=len(shown), frameon=False)


def _first_spike(ds) -> str:
    """Where the run's first Omega spike lies, in words."""
    t = ds.attrs.get("first_spike_time", float("nan"))
    return f"{ds.attrs['precision']}: " + (f"first spike at t = {t:.5g}" if np.isfinite(t) else "no spike in the run")


def fig3(sources):
    """u, Omega, omega, theta through both transients into the steady state, in double (the paper's
    arithmetic) and every finer precision from the same start (the whole run in that arithmetic).
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds, *others = (read_dataset(s) for s in sources)
    finer = finer_precisions(others)
    fig, axes = subplots(11, 6.5, 2, 2)
    _time_panels(axes.ravel(), ds, ["u", "Omega", "omega", "theta"], finer=finer)
    spikes = "; ".join(_first_spike(d) for d in (ds, *finer.values()))
    for axk, tag in zip(axes.ravel(), "abcd"):
        axk.set_title(f"({tag})" + (f" {spikes}" if tag == "b" else ""), loc="left")
    return finish(fig, ds.attrs)


def fig7(sources):
    """Steady-state window: u, Omega, omega, theta and the path over the window.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig = plt.figure(figsize=(11, 9), layout="constrained")
    grid = fig.add_gridspec(3, 2, height_ratios=[1, 1.4, 1])
    axes = [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1]),
            fig.add_subplot(grid[2, 0]), fig.add_subplot(grid[2, 1])]
    _time_panels(axes, ds, ["u", "Omega", "omega", "theta"], lw=0.4)
    for axk, tag in zip(axes, "abde"):
        axk.set_title(f"({tag})", loc="left")
    px = fig.add_subplot(grid[1, :])
    sc = px.scatter(ds.x, ds.y, c=ds.time, s=0.3, cmap="viridis")
    px.plot(ds.x[0], ds.y[0], "ks", ms=5, label=f"t = {float(ds.time[0]):g}")
    px.plot(ds.x[-1], ds.y[-1], "k^", ms=6, label=f"t = {float(ds.time[-1]):g}")
    px.set_aspect("equal", adjustable="datalim")
    px.set_xlabel(LABELS["x"])
    px.set_ylabel(LABELS["y"])
    px.legend()
    px.set_title("(c) path over the window (colour: time)", loc="left")
    fig.colorbar(sc, ax=px, label=LABELS["t"])
    return finish(fig, ds.attrs)


def fig8(sources):
    """Path of the sleigh over a long steady-state window, in double (the paper's arithmetic) and
    every finer precision from the same settled point.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds, *others = (read_dataset(s) for s in sources)
    fig, ax = subplots(7, 6.5)
    ax.plot(ds.x, ds.y, lw=0.4, label=f"double (reach {ds.attrs.get('path_reach', float('nan')):.4g})",
            **PRECISION_STYLE[Precision.DOUBLE])
    for (_, precision), other in finer_precisions(others).items():
        ax.plot(other.x, other.y, lw=0.3,
                label=f"{precision} (reach {other.attrs.get('path_reach', float('nan')):.4g})",
                **PRECISION_STYLE[precision])
    ax.plot(ds.x[0], ds.y[0], "ks", ms=5, label=f"t = {float(ds.time[0]):g}")
    ax.plot(ds.x[-1], ds.y[-1], "r^", ms=6, label=f"t = {float(ds.time[-1]):g}")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(LABELS["x"])
    ax.set_ylabel(LABELS["y"])
    ax.legend()
    ax.set_title(f"Path over {float(ds.time[-1] - ds.time[0]):g} time units after the transient", fontsize=10)
    return finish(fig, ds.attrs)


FIG1 = Figure("fig1", fig1, paper="F1", schematic="fig1")
FIG2 = Figure("fig2", fig2, ("fig2",), "F2", ("C01",))
FIG3 = Figure("fig3", fig3, ("fig3",), "F3", ("C03", "C04", "C05"), beside=True)
FIG7 = Figure("fig7", fig7, ("fig7",), "F7", ("C13",), steady=("fig7",))
FIG8 = Figure("fig8", fig8, ("fig8",), "F8", ("C14",), steady=("fig8",), beside=True)
