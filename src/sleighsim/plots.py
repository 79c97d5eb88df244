"""Figures. Each reads datasets (never integrates) and writes PNG and PDF.

Every figure carries a footer with the numbers that say how its data were made.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import patches  # noqa: E402

from .io import read_dataset  # noqa: E402

LABELS = {"u": r"$u$", "Omega": r"$\Omega$", "omega": r"$\omega$", "theta": r"$\theta$", "delta": r"$\delta$"}


def save_figure(fig, *paths) -> None:
    """Save to every path atomically (temporary file, then rename), then close."""
    for path in map(Path, paths):
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
        os.close(fd)
        try:
            fig.savefig(tmp, dpi=150)
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
    plt.close(fig)


def footer(fig, attrs: dict) -> None:
    """Provenance line: parameters, integrator, tolerance, energy drift, commit."""
    parts = []
    if "param_eps" in attrs:
        parts.append(f"eps={attrs['param_eps']:.4g}, b={attrs['param_b']:.4g}, K2={attrs['param_K2']:.4g}")
    if "energy_label" in attrs:
        physical = f" (physical {attrs['energy_physical']:.4g})" if "energy_physical" in attrs else ""
        parts.append(f"E label={attrs['energy_label']:.4g}{physical}")
    if attrs.get("backend") == "heyoka":
        parts.append(f"heyoka tol={attrs['tol']:.2g}")
    elif "backend" in attrs:
        parts.append(f"{attrs['method']} rtol={attrs['rtol']:.2g}")
    if "energy_max_rel_drift" in attrs:
        parts.append(f"max |dE/E|={attrs['energy_max_rel_drift']:.2g}")
    if "git_commit" in attrs:
        parts.append(f"commit {str(attrs['git_commit'])[:12]}")
    fig.text(0.01, 0.005, "; ".join(parts), fontsize=6, color="0.4", ha="left", va="bottom")


def finish(fig, attrs: dict, png, pdf) -> None:
    """Provenance footer, layout, and both files."""
    footer(fig, attrs)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    save_figure(fig, png, pdf)


def fig1(cfg: dict, png, pdf) -> None:
    """Schematic: sleigh body, centre C, runner P at distance b, rotor at distance a."""
    b, a, th, be = cfg["b"], cfg["a"], cfg["theta"], cfg["beta"]
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
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
    save_figure(fig, png, pdf)


def fig2(sources, png, pdf) -> None:
    """(a) eps = 0 phase portrait with sample trajectories; (b) path from (u, Omega) = (0, 1)."""
    ds = read_dataset(sources[0])
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.6))
    U, O = np.meshgrid(ds.u_grid, ds.Omega_grid, indexing="ij")
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
                 f"{ds.attrs['closed_form_max_abs_error']:.1e}", fontsize=9)
    ax.legend(loc="lower left", fontsize=7)
    bx.plot(ds.path_x, ds.path_y, color="tab:blue")
    bx.plot(ds.path_x[0], ds.path_y[0], "ko", ms=4)
    bx.set_aspect("equal", adjustable="datalim")
    bx.set_xlabel("$x$")
    bx.set_ylabel("$y$")
    bx.set_title(f"(b) path from $u=0$, $\\Omega=1$, $t\\leq{float(ds.path_time[-1]):g}$", fontsize=9)
    finish(fig, ds.attrs, png, pdf)


def _time_panels(axes, ds, names, lw=0.3):
    for axk, name in zip(axes, names):
        axk.plot(ds.time, ds[name], lw=lw, color="tab:blue")
        axk.set_ylabel(LABELS[name])
        axk.set_xlabel("$t$")


def fig3(sources, png, pdf) -> None:
    """u, Omega, omega, theta through both transients into the steady state."""
    ds = read_dataset(sources[0])
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5))
    _time_panels(axes.ravel(), ds, ["u", "Omega", "omega", "theta"])
    for axk, tag in zip(axes.ravel(), "abcd"):
        axk.set_title(f"({tag})", fontsize=9, loc="left")
    finish(fig, ds.attrs, png, pdf)


def fig7(sources, png, pdf) -> None:
    """Steady-state window: u, Omega, omega, theta and the path over the window."""
    ds = read_dataset(sources[0])
    fig = plt.figure(figsize=(11, 9))
    grid = fig.add_gridspec(3, 2, height_ratios=[1, 1.4, 1])
    axes = [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1]),
            fig.add_subplot(grid[2, 0]), fig.add_subplot(grid[2, 1])]
    _time_panels(axes, ds, ["u", "Omega", "omega", "theta"], lw=0.4)
    for axk, tag in zip(axes, "abde"):
        axk.set_title(f"({tag})", fontsize=9, loc="left")
    px = fig.add_subplot(grid[1, :])
    sc = px.scatter(ds.x, ds.y, c=ds.time, s=0.3, cmap="viridis")
    px.plot(ds.x[0], ds.y[0], "ks", ms=5, label=f"t = {float(ds.time[0]):g}")
    px.plot(ds.x[-1], ds.y[-1], "k^", ms=6, label=f"t = {float(ds.time[-1]):g}")
    px.set_aspect("equal", adjustable="datalim")
    px.set_xlabel("$x$")
    px.set_ylabel("$y$")
    px.legend(fontsize=7)
    px.set_title("(c) path over the window (colour: time)", fontsize=9, loc="left")
    fig.colorbar(sc, ax=px, label="$t$")
    finish(fig, ds.attrs, png, pdf)


def fig8(sources, png, pdf) -> None:
    """Path of the sleigh over a long steady-state window."""
    ds = read_dataset(sources[0])
    fig, ax = plt.subplots(figsize=(7, 6.5))
    ax.plot(ds.x, ds.y, lw=0.4, color="tab:blue")
    ax.plot(ds.x[0], ds.y[0], "ks", ms=5, label=f"t = {float(ds.time[0]):g}")
    ax.plot(ds.x[-1], ds.y[-1], "r^", ms=6, label=f"t = {float(ds.time[-1]):g}")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("$x$")
    ax.set_ylabel("$y$")
    ax.legend(fontsize=8)
    ax.set_title(f"Path over {float(ds.time[-1] - ds.time[0]):g} time units after the transient", fontsize=10)
    finish(fig, ds.attrs, png, pdf)


def _attractor_panel(ax, ds, title, iterates="ppi2"):
    ax.scatter(ds.attractor_u, ds.attractor_Omega, ds.attractor_omega, s=0.2, c="0.7", alpha=0.3, depthshade=False)
    if iterates == "ppi2":
        for k in range(4):
            sel = ds.ppi2_class.values == k
            ax.scatter(ds.ppi2_u.values[sel], ds.ppi2_Omega.values[sel], ds.ppi2_omega.values[sel], s=2,
                       depthshade=False, label=f"$\\delta = {k}\\pi/2$ mod $2\\pi$")
    else:
        ax.scatter(ds.p2pi_u, ds.p2pi_Omega, ds.p2pi_omega, s=1.5, c=ds.p2pi_time, cmap="viridis", depthshade=False)
    ax.set_xlabel(LABELS["u"])
    ax.set_ylabel(LABELS["Omega"])
    ax.set_zlabel(LABELS["omega"])
    ax.tick_params(labelsize=6)
    status = "" if ds.attrs["transient_over"] else "\nTRANSIENT NOT SHOWN OVER"
    ax.set_title(title + status, fontsize=8)


def fig9(sources, png, pdf) -> None:
    """(a) P_2pi iterates; (b) P_pi/2 iterates on the attractor; (c) higher energy; (d) eps = 0.01."""
    ref, high, small, scaling = (read_dataset(s) for s in sources)
    fig = plt.figure(figsize=(11, 10))
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
            ax.legend(fontsize=6, markerscale=3, loc="upper left")
    finish(fig, ref.attrs, png, pdf)


def fig12(sources, png, pdf) -> None:
    """Return times t_{n+1} - t_n of P_2pi for two values of eps."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, src, tag in zip(axes, sources, "ab"):
        ds = read_dataset(src)
        ax.plot(ds.return_time, ".", ms=1.2)
        ax.set_xlabel("iterate $n$")
        ax.set_ylabel("return time $t_{n+1} - t_n$")
        ax.set_title(f"({tag}) $\\epsilon$ = {ds.attrs['param_eps']:.3g}, E label {ds.attrs['energy_label']:.4g}: "
                     f"range [{ds.attrs['return_time_min']:.5g}, {ds.attrs['return_time_max']:.5g}],\n"
                     f"min pairwise difference {ds.attrs['return_time_min_pairwise_difference']:.2g}"
                     + ("" if ds.attrs["transient_over"] else "; TRANSIENT NOT SHOWN OVER"), fontsize=8)
    finish(fig, ds.attrs, png, pdf)


def _psd_figure(sources, png, pdf) -> None:
    ds = read_dataset(sources[0])
    fig, axes = plt.subplots(2, 1, figsize=(10, 7))
    for ax, v in zip(axes, ("u", "Omega")):
        f, S = ds.frequency.values[1:], ds[f"psd_{v}"].values[1:]
        ax.semilogy(f, S, lw=0.5)
        lo, hi = ds.attrs[f"{v}_band_low"], ds.attrs[f"{v}_band_high"]
        ax.axvspan(lo, hi, color="tab:orange", alpha=0.25, label=f"band [{lo:.4g}, {hi:.4g}]")
        ax.set_xlim(0, min(f[-1], 2.5 * hi))
        ax.set_ylabel(f"PSD of {LABELS[v]}")
        ax.legend(fontsize=7, loc="upper right")
        inset = ax.inset_axes([0.08, 0.5, 0.3, 0.45])
        near = f < 20 * max(np.nan_to_num(ds.attrs[f"{v}_lowest_peak"], nan=1e-3), 1e-3)
        inset.semilogy(f[near], S[near], lw=0.6)
        inset.set_title(f"near f = 0: {ds.attrs[f'{v}_n_peaks_near_zero']} peaks", fontsize=6)
        inset.tick_params(labelsize=5)
    axes[-1].set_xlabel("frequency $f$ (cycles per unit time)")
    status = "" if ds.attrs["transient_over"] else "  [TRANSIENT NOT SHOWN OVER]"
    axes[0].set_title(f"$\\epsilon$ = {ds.attrs['param_eps']:.3g}, E label {ds.attrs['energy_label']:.4g}, "
                      f"record {ds.attrs['record_duration']:g} time units at dt = {ds.attrs['sample_dt']:g} after "
                      f"t = {ds.attrs['record_start']:g}{status}", fontsize=8)
    finish(fig, ds.attrs, png, pdf)


fig13 = fig14 = _psd_figure


def fig10(sources, png, pdf) -> None:
    """Max Lyapunov exponent against energy label, with the time-scaling law."""
    ds = read_dataset(sources[0])
    fig, ax = plt.subplots(figsize=(7, 5))
    lam, err, E = ds.lambda_1.values, ds.stderr.values, ds.label.values
    pos = lam > 0
    ax.errorbar(E[pos], lam[pos], yerr=err[pos], fmt="o", capsize=3, label="direct (Benettin, k = 1)")
    if (~pos).any():
        ax.plot(E[~pos], np.abs(lam[~pos]), "x", color="tab:red", label="|lambda_1| where lambda_1 <= 0")
    ax.loglog(E, np.abs(ds.law.values), "-", color="0.4",
              label=f"law $\\lambda \\propto E^{{1/2}}$ from E = {ds.attrs['reference_label']:g}")
    ax.set_xlabel("energy label $E$")
    ax.set_ylabel(r"max Lyapunov exponent $\lambda_1$")
    ax.set_title(f"$\\epsilon$ = {ds.attrs['param_eps']:.3g}, b = {ds.attrs['param_b']:.3g}: fitted exponent "
                 f"{ds.attrs['fitted_exponent']:.4f} +- {ds.attrs['fitted_exponent_stderr']:.2g} (law: 0.5)\n"
                 f"T = {ds.attrs['T_reference']:g} time units at E = {ds.attrs['reference_label']:g}, scaled by the law",
                 fontsize=8)
    ax.legend(fontsize=7)
    finish(fig, ds.attrs, png, pdf)


def _every_other_tick(axis, values) -> None:
    """Label every other grid value on a log axis, without matplotlib's crowded minor labels."""
    from matplotlib.ticker import NullFormatter

    axis.set_minor_formatter(NullFormatter())
    axis.set_ticks(values[::2], [f"{v:.2g}" for v in values[::2]])


def fig11(sources, png, pdf) -> None:
    """Max Lyapunov exponent on the (eps, b) grid (log colour scale), flagged points marked; and
    lambda_1 against eps (b is a symmetry: every b of a row is the same system)."""
    from matplotlib.colors import LogNorm

    ds = read_dataset(sources[0])
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.8), gridspec_kw={"width_ratios": [1.3, 1]})
    lam = ds.lambda_1.values
    positive = lam[lam > 0]
    mesh = ax.pcolormesh(ds.b.values, ds.eps.values, np.where(lam > 0, lam, np.nan), shading="nearest",
                         cmap="viridis", norm=LogNorm(vmin=positive.min(), vmax=positive.max()))
    fig.colorbar(mesh, ax=ax, label=r"$\lambda_1$ (1/time; non-positive values blank)")
    B, Eps = np.meshgrid(ds.b.values, ds.eps.values)
    flagged = ds.flagged.values.astype(bool)
    ax.plot(B[flagged], Eps[flagged], "wx", ms=5, mew=1.5, label="flagged: transient not over or not converged")
    ax.set_xscale("log")
    ax.set_yscale("log")
    _every_other_tick(ax.xaxis, ds.b.values)
    _every_other_tick(ax.yaxis, ds.eps.values)
    ax.set_xlabel("$b$")
    ax.set_ylabel(r"$\epsilon$")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), facecolor="0.6")
    ax.set_title(f"E label {ds.attrs['energy_label']:g}: {ds.attrs['n_points']} points, "
                 f"{100 * ds.attrs['fraction_flagged']:.0f}% flagged; lambda_1 in "
                 f"[{ds.attrs['min_lambda_1']:.2g}, {ds.attrs['max_lambda_1']:.2g}]", fontsize=8)
    eps = ds.eps.values
    for j in range(ds.sizes["b"]):
        ok = ~flagged[:, j]
        bx.plot(eps[ok], lam[ok, j], ".", color="C0", ms=4, label="points" if j == 0 else None)
        bx.plot(eps[~ok], lam[~ok, j], "x", color="C3", ms=4, label="flagged points" if j == 0 else None)
    bx.errorbar(eps, ds.row_mean.values, yerr=ds.row_stderr.values, fmt="o-", color="k", ms=4, capsize=3,
                label="mean over b, +- mean block stderr")
    bx.axhline(1e-4, color="0.5", ls=":", label="paper: smallest value > 1e-4")
    bx.set_xscale("log")
    bx.set_yscale("log")
    _every_other_tick(bx.xaxis, eps)
    bx.set_xlabel(r"$\epsilon$")
    bx.set_ylabel(r"$\lambda_1$ (1/time; log scale, positive values)")
    bx.legend(fontsize=7)
    bx.set_title(f"reference point (eps {ds.attrs['reference_point_eps']:.3g}): stderr / lambda_1 = "
                 f"{ds.attrs['reference_point_rel_err']:.2f}; spread over b / stderr: "
                 f"{ds.attrs['median_row_spread_over_stderr']:.2f}\n(median over rows with lambda_1 T >= 100)", fontsize=8)
    finish(fig, ds.attrs, png, pdf)


def lyapunov(sources, png, pdf) -> None:
    """lambda_i(T) on log-log axes, the paper-protocol spread, and the verdict."""
    spec, prot, verdict = (read_dataset(s) for s in sources)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [1.6, 1]})
    T = spec["T"].values
    for i in range(4):
        lam = spec.running.values[:, i]
        line, = ax.loglog(T, np.where(lam > 0, lam, np.nan), "-", label=f"$\\lambda_{i + 1}(T) > 0$")
        ax.loglog(T, np.where(lam < 0, -lam, np.nan), "--", color=line.get_color(), label=f"$-\\lambda_{i + 1}(T)$")
    ax.loglog(T, 1.0 / T, ":", color="k", label="$1/T$")
    ax.axhline(abs(spec.attrs["mean_divergence"]), color="0.5", lw=0.8,
               label=f"|mean divergence| = {abs(spec.attrs['mean_divergence']):.2g}")
    ax.set_xlabel("accumulation time $T$")
    ax.set_ylabel(r"$|\lambda_i(T)|$")
    ax.legend(fontsize=6, ncol=2)
    lam = spec.exponent.values
    err = spec.stderr.values
    ax.set_title("exponents at T = %g: %s\n+- %s; verdict: %s (0-1 test K = %.2f)" % (
        spec.attrs["T"], np.array2string(lam, precision=2), np.array2string(err, precision=1),
        verdict.attrs["verdict"], verdict.attrs["zero_one_K"]), fontsize=8)
    for j in range(prot.sizes["state"]):
        bx.plot(np.arange(1, 5), prot.exponent.values[j], "o-", ms=4, label=f"state {j}")
    bx.axhline(0, color="k", lw=0.6)
    bx.set_xticks(range(1, 5))
    bx.set_xlabel("index $i$")
    bx.set_ylabel(r"$\lambda_i$ (paper protocol)")
    bx.set_title(f"paper protocol: T = {prot.attrs['T']:g} after {prot.attrs['t_transient']:g}, tau = "
                 f"{prot.attrs['tau']:g}\nspread of lambda_1 over states: {prot.attrs['spread_lambda_1']:.2g}",
                 fontsize=8)
    bx.legend(fontsize=6)
    finish(fig, spec.attrs, png, pdf)


def audit(sources, png, pdf) -> None:
    """Energy drift of the printed udot against the derived equations (D1)."""
    ds = read_dataset(sources[0])
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for name, style in (("printed", "-"), ("derived", "-")):
        v = np.abs(ds[f"energy_rel_change_{name}"].values[1:])
        ax.semilogy(ds.time.values[1:], np.maximum(v, 1e-17), style, label=f"{name} equations")
    ax.set_xlabel("$t$")
    ax.set_ylabel(r"$|E(t)/E(0) - 1|$")
    ax.set_title(f"The paper's printed udot does not conserve the energy: max change "
                 f"{ds.attrs['printed_max_abs_rel_change']:.3g} (derived: {ds.attrs['derived_max_abs_rel_change']:.2g})",
                 fontsize=9)
    ax.legend()
    finish(fig, ds.attrs, png, pdf)


def bench(sources, png, pdf) -> None:
    """Work-precision: wall time against error (short horizon) and energy drift (long), and
    the scene observables against heyoka's tolerance."""
    ds = read_dataset(sources[0])
    fig, axes = plt.subplots(1, 4, figsize=(20, 4.8))
    keys = sorted({(b, m) for b, m in zip(ds.backend.values, ds.method.values)})
    for b, m in keys:
        sel = (ds.backend.values == b) & (ds.method.values == m)
        name = "heyoka (Taylor)" if b == "heyoka" else f"SciPy {m}"
        axes[0].loglog(ds.error_short.values[sel], ds.wall_short.values[sel], "o-", label=name)
        axes[1].loglog(np.maximum(ds.drift_long.values[sel], 1e-17), ds.wall_long.values[sel], "o-", label=name)
    axes[0].set_xlabel(f"end-state error at t = {ds.attrs['t_short']:g} (vs long-double reference)")
    axes[0].set_ylabel(f"wall time (s), median of {ds.attrs['repeats_heyoka']} (heyoka) / "
                       f"{ds.attrs['repeats_scipy']} (SciPy)")
    axes[1].set_xlabel(f"max |E/E0 - 1| over t <= {ds.attrs['t_long']:g}")
    axes[1].set_ylabel("wall time (s)")
    axes[0].legend(fontsize=7)
    axes[0].set_title(f"reference self-difference {ds.attrs['reference_self_difference']:.1e}", fontsize=8)
    hy = ds.backend.values == "heyoka"
    ax = axes[2]
    tol = ds.tol.values[hy]
    for name, vals in (("spike interval", ds.spike_interval.values[hy]), ("first spike", ds.first_spike.values[hy])):
        ax.semilogx(tol, vals / vals[np.argmin(tol)], "o-", label=name)
    to = ds.tol_observable.values
    for name in ("lambda_1", "rotation_number"):
        v = ds[name].values
        ax.semilogx(to, v / v[np.argmin(to)], "s--", label=name)
    ax.set_xlabel("heyoka tolerance")
    ax.set_ylabel("observable / value at the tightest tolerance")
    ax.legend(fontsize=7)
    ax.set_title("loosest converged tol: " + ", ".join(
        f"{k.replace('loosest_converged_tol_', '')} {v:.0e}" for k, v in ds.attrs.items()
        if k.startswith("loosest_converged_tol_")), fontsize=7)
    ax = axes[3]
    best = float(ds.lambda_1.values[np.argmin(to)])
    ax.loglog(np.maximum(np.abs(ds.lambda_1.values - best), 1e-12), ds.lambda_1_wall.values, "o-",
              label="heyoka (Taylor)")
    if "lyap_scipy" in ds.dims:
        for m in sorted(set(ds.lyap_scipy_method.values.tolist())):
            sel = ds.lyap_scipy_method.values == m
            ax.loglog(np.abs(ds.lyap_scipy_lambda_1.values[sel] - best), ds.lyap_scipy_wall.values[sel], "s--",
                      label=f"SciPy {m}")
    ax.set_xlabel(f"|lambda_1 - heyoka tightest| over T = {ds.attrs['T_lyapunov']:g} (floor 1e-12)")
    ax.set_ylabel("wall time (s)")
    ax.set_title(f"Lyapunov kernel (heyoka tightest: lambda_1 = {best:.4g})", fontsize=8)
    ax.legend(fontsize=7)
    finish(fig, ds.attrs, png, pdf)


def fig4(sources, png, pdf) -> None:
    """omega aligned at the first spike after the transient, per energy level (mapped onto the
    first level by the time-scaling law), coloured by spike-interval group; the long-horizon
    spike intervals of one representative per group."""
    ds = read_dataset(sources[0])
    levels = sorted(set(ds.level.values.tolist()))
    fig, axes = plt.subplots(1, len(levels) + 1, figsize=(5.2 * (len(levels) + 1), 4.2))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    labels = np.atleast_1d(ds.attrs["labels"])
    for li, ax in zip(levels, axes):
        for r in np.flatnonzero(ds.level.values == li):
            if not ds.reached.values[r]:
                continue
            g = int(ds.group.values[r])
            ax.plot(ds.tau, ds.omega_aligned_smooth[r], lw=0.8, color=colours[g % len(colours)],
                    label=f"state {int(ds.state_index[r])}{' (mirrored)' if ds.mirrored[r] else ''}, group {g}")
        ax.set_title(f"({'ab'[li] if li < 2 else li}) E = {labels[li]:g}: "
                     f"{ds.attrs[f'level{li}_n_groups']} interval group(s)", fontsize=9, loc="left")
        ax.set_xlabel(r"$\tau$ after the first spike (level-0 time units)")
        ax.set_ylabel(r"$\omega / c$, running mean")
        ax.legend(fontsize=6)
    ax = axes[-1]
    for k, g in enumerate(ds.group_id.values):
        sp = ds.long_spike_time.values[k]
        sp = sp[np.isfinite(sp)]
        ax.plot(sp[1:], np.diff(sp), ".-", ms=3, lw=0.6, color=colours[int(g) % len(colours)], label=f"group {int(g)}")
    ax.set_xlabel("$t$ (level 0)")
    ax.set_ylabel("spike interval")
    ax.set_title(f"long run of one state per group, t <= {ds.attrs['long_check_t_end']:g}", fontsize=9, loc="left")
    ax.legend(fontsize=7)
    finish(fig, ds.attrs, png, pdf)


def fig5(sources, png, pdf) -> None:
    """Exact (solid) against u0 + eps u1 + eps^2 u2 (dashed) for u, Omega, omega, and relative errors."""
    ds = read_dataset(sources[0])
    fig, axes = plt.subplots(2, 3, figsize=(13, 6.5), sharex=True)
    for k, v in enumerate(("u", "Omega", "omega")):
        ax = axes[0, k]
        ax.plot(ds.time, ds[f"{v}_exact"], color="k", lw=1.0, label="exact")
        ax.plot(ds.time, ds[f"{v}_series"], "--", color="tab:red", lw=1.0, label=f"orders 0..{ds.attrs['order']}")
        ax.set_ylabel(LABELS[v])
        ax.set_title(f"({'abc'[k]})", fontsize=9, loc="left")
        ax.legend(fontsize=7)
        ax = axes[1, k]
        ax.semilogy(ds.time, np.maximum(ds[f"{v}_rel_error"], 1e-17), lw=0.8, color="tab:blue")
        ax.set_xlabel("$t$")
        ax.set_ylabel(f"error / max |exact| so far, {LABELS[v]}")
        ax.set_title(f"at t = {ds.attrs['t_end']:g}: {100 * ds.attrs[f'{v}_rel_error_at_t_end']:.3g}%", fontsize=8)
    finish(fig, ds.attrs, png, pdf)


def fig6(sources, png, pdf) -> None:
    """u0, u2, Omega0, Omega2, omega0, omega2, with the fitted numbers of C08-C10."""
    ds = read_dataset(sources[0])
    a = ds.attrs
    fig, axes = plt.subplots(3, 2, figsize=(11, 8), sharex=True)
    notes = {"u2": f"T1 = {a['T1_u2']:.5g}; 2pi/omega0 = {a['two_pi_over_omega0']:.5g}",
             "Omega2": f"T1 = {a['T1_Omega2']:.5g}, amplitude {a['Omega2_amplitude']:.4g}, "
                       f"phi1 = {a['phi1_over_pi']:.4f} pi",
             "omega2": f"T2 = {a['T2']:.5g}, B = {a['B']:.4g}, growth {a['omega2_growth']:.4g}",
             "omega0": f"omega0 -> {a['omega0_end']:.6g}", "u0": f"u0 -> {a['u0_end']:.6g}", "Omega0": ""}
    for k, (v, base) in enumerate((("u0", "u"), ("u2", "u"), ("Omega0", "Omega"), ("Omega2", "Omega"),
                                   ("omega0", "omega"), ("omega2", "omega"))):
        ax = axes.ravel()[k]
        ax.plot(ds.time, ds[v], lw=0.8, color="tab:blue")
        ax.axvspan(a["fit_window_start"], a["fit_window_end"], color="0.92", zorder=0)
        ax.set_ylabel(LABELS[base][:-1] + "_" + v[-1] + "$")
        ax.set_title(f"({'abcdef'[k]}) {notes[v]}", fontsize=8, loc="left")
    for ax in axes[-1]:
        ax.set_xlabel("$t$ (grey: fit window)")
    fig.suptitle(f"order-1 terms: max |x1| = {a['order1_max_abs']:.1g}", fontsize=9)
    finish(fig, a, png, pdf)


def transients(sources, png, pdf) -> None:
    """End of the sleigh-like phase and first spike against eps (log-log, fitted slope)."""
    ds = read_dataset(sources[0])
    a = ds.attrs
    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    eps = ds.eps.values
    ax.loglog(eps, ds.first_spike, "o", label="first Omega spike (end of the second transient)")
    ax.loglog(eps, ds.spike_interval_mean, "s", label="steady spike interval")
    ax.loglog(eps, ds.sleigh_phase_end, "^", label="end of the sleigh-like phase")
    e = np.geomspace(eps.min(), eps.max(), 20)
    if np.isfinite(a["first_spike_slope"]):
        ax.loglog(e, a["first_spike_prefactor"] * e ** a["first_spike_slope"], "--", color="tab:blue",
                  label=f"fit: slope {a['first_spike_slope']:.2f} (SCIENCE.md: -2)")
    ax.set_xlabel(r"$\epsilon$")
    ax.set_ylabel("time")
    ax.legend(fontsize=7)
    ax.set_title("from (" + ", ".join(f"{a[f'y0_{n}']:g}" for n in ("u", "Omega", "omega", "delta")) + "), "
                 f"K2 = 1 + {a['kappa']:g} eps", fontsize=8)
    finish(fig, a, png, pdf)


def perturbation(sources, png, pdf) -> None:
    """(a) error of the truncated series against eps (short window); (b) growth of orders 2 and 4."""
    fig5_ds, audit_ds = read_dataset(sources[0]), read_dataset(sources[1])
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    ax = axes[0]
    eps = fig5_ds.eps_study.values
    for name in fig5_ds.data_vars:
        if name.startswith("convergence_error_order"):
            o = name.removeprefix("convergence_error_order")
            ax.loglog(eps, fig5_ds[name], "o-", label=f"order {o}: slope {fig5_ds.attrs[f'convergence_slope_order{o}']:.2f}"
                      f" (predicted {fig5_ds.attrs[f'convergence_predicted_order{o}']})")
    ax.set_xlabel(r"$\epsilon$")
    ax.set_ylabel(f"max error on [0, {fig5_ds.attrs['convergence_window']:g}]")
    ax.legend(fontsize=7)
    ax.set_title("(a) truncated series against the exact flow", fontsize=9, loc="left")
    ax = axes[1]
    t = audit_ds.time.values
    n = max(1, int(round(audit_ds.attrs["growth_block"] / (t[1] - t[0]))))
    m = t.size // n
    tb = t[: m * n].reshape(m, n).mean(axis=1)
    for v, colour in (("u", "tab:blue"), ("Omega", "tab:green"), ("omega", "tab:red")):
        for k, ls in ((2, "-"), (4, "--")):
            env = np.abs(audit_ds[f"{v}{k}"].values[: m * n]).reshape(m, n).max(axis=1)
            ax.loglog(tb, env, ls, color=colour, lw=1.0,
                      label=f"|{v}{k}| (growth exponent {audit_ds.attrs[f'growth_exponent_{v}{k}']:.2f})")
    ax.axvline(audit_ds.attrs.get("late_start", np.nan), color="0.7", lw=0.8)
    ax.set_xlabel(f"$t$ (block maxima over {audit_ds.attrs['growth_block']:g})")
    ax.legend(fontsize=6)
    ax.set_title(f"(b) {audit_ds.attrs['order4_n_secular']} of {audit_ds.attrs['order4_n_terms']} order-4 "
                 f"forcing terms secular; order 3 max {audit_ds.attrs['order3_max_abs_along_solution']:.1g}",
                 fontsize=9, loc="left")
    finish(fig, fig5_ds.attrs, png, pdf)


#: Figure name -> plotting function (fig1 takes its config block instead of a dataset).
FIGURES = {"fig1": fig1, "fig2": fig2, "fig3": fig3, "fig4": fig4, "fig5": fig5, "fig6": fig6,
           "transients": transients, "perturbation": perturbation, "fig7": fig7, "fig8": fig8, "fig9": fig9, "fig12": fig12,
           "fig13": fig13, "fig14": fig14, "fig10": fig10, "fig11": fig11, "lyapunov": lyapunov,
           "audit": audit, "bench": bench}
