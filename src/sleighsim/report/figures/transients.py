"""Figures of the transient section: one attractor per level (F4), the series against the exact flow (F5), its
terms (F6), transient length against eps, and the hierarchy's convergence and secular growth."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np

from sleighsim.io.netcdf import read_dataset
from sleighsim.report.figures.common import LABELS, SYMBOLS, UNITS, WIDTH, finish, subplots
from sleighsim.report.figures.figure import Figure


def fig4(sources):
    """omega aligned at the first spike after the transient, per energy level (mapped onto the
    first level by the time-scaling law), coloured by spike-interval group; the long-horizon
    spike intervals of one representative per group.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    levels = sorted(set(ds.level.values.tolist()))
    ncols = min(3, len(levels) + 1)
    nrows = -(-(len(levels) + 1) // ncols)
    fig, axes = subplots(WIDTH, 4.4 * nrows, nrows, ncols, squeeze=False)
    axes = axes.ravel()
    for ax in axes[len(levels) + 1:]:
        ax.set_visible(False)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    labels = np.atleast_1d(ds.attrs["labels"])
    for li, ax in zip(levels, axes):
        members: dict[int, list[str]] = {}
        for r in np.flatnonzero(ds.level.values == li):
            if not ds.reached.values[r]:
                continue
            g = int(ds.group.values[r])
            members.setdefault(g, []).append(f"{int(ds.state_index[r])}{'m' if ds.mirrored[r] else ''}")
            ax.plot(ds.tau, ds.omega_aligned_smooth[r], lw=0.8, color=colours[g % len(colours)])
        for g, states in members.items():  # one legend entry per group, below the axes (off the curves)
            ax.plot([], [], lw=0.8, color=colours[g % len(colours)], label=f"group {g}: states {', '.join(states)}")
        ax.set_title(f"({'ab'[li] if li < 2 else li}) E = {labels[li]:g}: "
                     f"{ds.attrs[f'level{li}_n_groups']} interval group(s)", loc="left")
        ax.set_xlabel(r"$\tau$ after the first spike (level-0 time units)")
        ax.set_ylabel(r"$\omega / c$, running mean (rad/level-0 time unit)")
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), title="m: mirrored state", frameon=False)
    ax = axes[len(levels)]
    for k, g in enumerate(ds.group_id.values):
        sp = ds.long_spike_time.values[k]
        sp = sp[np.isfinite(sp)]
        ax.plot(sp[1:], np.diff(sp), ".-", ms=3, lw=0.6, color=colours[int(g) % len(colours)], label=f"group {int(g)}")
    ax.set_xlabel("$t$ (level-0 time units)")
    ax.set_ylabel("spike interval (level-0 time units)")
    ax.set_title(f"long run of one state per group, t <= {ds.attrs['long_check_t_end']:g}", loc="left")
    ax.legend()
    return finish(fig, ds.attrs)


def fig5(sources):
    """Exact (solid) against u0 + eps u1 + eps^2 u2 (dashed) for u, Omega, omega, and relative errors.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig, axes = subplots(WIDTH, 6.5, 2, 3, sharex=True)
    for k, v in enumerate(("u", "Omega", "omega")):
        ax = axes[0, k]
        ax.plot(ds.time, ds[f"{v}_exact"], color="k", lw=1.0, label="exact")
        ax.plot(ds.time, ds[f"{v}_series"], "--", color="tab:red", lw=1.0, label=f"orders 0..{ds.attrs['order']}")
        ax.set_ylabel(LABELS[v])
        ax.set_title(f"({'abc'[k]})", loc="left")
        ax.legend()
        ax = axes[1, k]
        ax.semilogy(ds.time, np.maximum(ds[f"{v}_rel_error"], 1e-17), lw=0.8, color="tab:blue")
        ax.set_xlabel(LABELS["t"])
        ax.set_ylabel(f"error of ${SYMBOLS[v]}$ / max |exact| so far (relative)")
        ax.set_title(f"at t = {ds.attrs['t_end']:g}: {100 * ds.attrs[f'{v}_rel_error_at_t_end']:.3g}%")
    return finish(fig, ds.attrs)


def fig6(sources):
    """u0, u2, Omega0, Omega2, omega0, omega2, with the fitted numbers of C08-C10.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    a = ds.attrs
    fig, axes = subplots(WIDTH, 8, 3, 2, sharex=True)
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
        ax.set_ylabel(f"${SYMBOLS[base]}_{v[-1]}$ ({UNITS[base]})")
        ax.set_title(f"({'abcdef'[k]}) {notes[v]}", loc="left")
    for ax in axes[-1]:
        ax.set_xlabel("$t$ (time units; grey: fit window)")
    fig.suptitle(f"order-1 terms: max |x1| = {a['order1_max_abs']:.1g}")
    return finish(fig, a)


def transients(sources):
    """End of the sleigh-like phase and first spike against eps (log-log, fitted slope).
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    a = ds.attrs
    fig, ax = subplots(6.5, 4.8)
    eps = ds.eps.values
    ax.loglog(eps, ds.first_spike, "o", label="first Omega spike (end of the second transient)")
    ax.loglog(eps, ds.spike_interval_mean, "s", label="steady spike interval")
    ax.loglog(eps, ds.sleigh_phase_end, "^", label="end of the sleigh-like phase")
    e = np.geomspace(eps.min(), eps.max(), 20)
    if np.isfinite(a["first_spike_slope"]):
        ax.loglog(e, a["first_spike_prefactor"] * e ** a["first_spike_slope"], "--", color="tab:blue",
                  label=f"fit: slope {a['first_spike_slope']:.2f} (transients last 1/eps^2: -2)")
    ax.set_xlabel(r"$\epsilon$ (unitless)")
    ax.set_ylabel("time (time units)")
    ax.legend()
    ax.set_title("from (" + ", ".join(f"{a[f'y0_{n}']:g}" for n in ("u", "Omega", "omega", "delta")) + "), "
                 f"K2 = 1 + {a['kappa']:g} eps")
    return finish(fig, a)


def perturbation(sources):
    """(a) error of the truncated series against eps (short window); (b) growth of orders 2 and 4.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    fig5_ds, audit_ds = read_dataset(sources[0]), read_dataset(sources[1])
    fig, axes = subplots(WIDTH, 4.5, 1, 2)
    ax = axes[0]
    eps = fig5_ds.eps_study.values
    for name in fig5_ds.data_vars:
        if name.startswith("convergence_error_order"):
            o = name.removeprefix("convergence_error_order")
            ax.loglog(eps, fig5_ds[name], "o-",
                      label=f"order {o}: slope {fig5_ds.attrs[f'convergence_slope_order{o}']:.2f}"
                      f" (predicted {fig5_ds.attrs[f'convergence_predicted_order{o}']})")
    ax.set_xlabel(r"$\epsilon$ (unitless)")
    ax.set_ylabel(f"max error on [0, {fig5_ds.attrs['convergence_window']:g}] (units of u, Omega, omega, delta)")
    ax.legend()
    ax.set_title("(a) truncated series against the exact flow", loc="left")
    ax = axes[1]
    t = audit_ds.time.values
    n = max(1, int(round(audit_ds.attrs["growth_block"] / (t[1] - t[0]))))
    m = t.size // n
    tb = t[: m * n].reshape(m, n).mean(axis=1)
    for v, colour in (("u", "tab:blue"), ("Omega", "tab:green"), ("omega", "tab:red")):
        for k, ls in ((2, "-"), (4, "--")):
            env = np.abs(audit_ds[f"{v}{k}"].values[: m * n]).reshape(m, n).max(axis=1)
            ax.loglog(tb, env, ls, color=colour, lw=1.0,
                      label=f"|{v}{k}| (growth exponent {audit_ds.attrs[f'growth_exponent_{v}{k}'] + 0.0:.2f})")
    ax.axvline(audit_ds.attrs.get("late_start", np.nan), color="0.7", lw=0.8)
    ax.set_xlabel(f"$t$ (time units; block maxima over {audit_ds.attrs['growth_block']:g})")
    ax.set_ylabel("block maximum of the term (units of its variable)")
    ax.legend()
    ax.set_title(f"(b) {audit_ds.attrs['order4_n_secular']} of {audit_ds.attrs['order4_n_terms']} order-4 "
                 f"forcing terms secular; order 3 max {audit_ds.attrs['order3_max_abs_along_solution']:.1g}",
                 loc="left")
    return finish(fig, fig5_ds.attrs)



def basins(sources):
    """Basin fractions on the energy level with their intervals, and the steady spike interval of
    every sampled run coloured by its group (the reference states' intervals as lines).
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig, (ax, bx) = subplots(WIDTH, 5, 1, 2, width_ratios=[1, 1.4])
    groups = [str(g) for g in ds.group.values]
    x = np.arange(len(groups))
    f = ds.fraction.values
    ax.bar(x, f, color=[f"C{i}" for i in x], alpha=0.7)
    ax.errorbar(x, f, yerr=[f - ds.ci_low.values, ds.ci_high.values - f], fmt="none", ecolor="k", capsize=4)
    for i, (c, m) in enumerate(zip(ds["count"].values, ds.mirrored.values)):
        text = f"{c:.0f}\n({100 * m:.0f}% mirrored)" if np.isfinite(m) else f"{c:.0f}"
        ax.text(i, ds.ci_high.values[i] + 0.01, text, ha="center", va="bottom", fontsize=8)
    ax.set_xticks(x, groups, rotation=20)
    ax.set_ylim(0, 1.12)
    ax.set_ylabel(f"fraction of {ds.attrs['n_samples']} samples (unitless; {100 * ds.attrs['confidence']:.0f}% Wilson "
                  "interval)")
    ax.set_title(f"steady states reached on E label {ds.attrs['energy_label']:g}\nsampling: "
                 + textwrap.fill(ds.attrs["measure"], 70), fontsize=8)
    order = np.argsort(np.nan_to_num(ds.interval.values, nan=np.inf))
    for i, g in enumerate(groups):
        sel = ds.group_of.values[order] == g
        bx.plot(np.flatnonzero(sel), ds.interval.values[order][sel], "o", ms=3, color=f"C{i}", label=g)
    for name, interval in zip(ds.reference.values, ds.reference_interval.values):
        if np.isfinite(interval):
            bx.axhline(interval, color="0.4", ls=":", lw=0.8)
            bx.text(0, interval, f" {name}", fontsize=8, va="bottom", color="0.3")
    bx.set_xlabel("sampled run (count, sorted by interval)")
    bx.set_ylabel("steady spike interval (time units)")
    bx.legend()
    bx.set_title(f"group: the first reference within {100 * ds.attrs['group_rel_tol']:.0f}% of the interval\n"
                 f"unsettled: transient not over by {ds.attrs['max_rounds']} x {ds.attrs['t_round']:g}; no spike "
                 f"interval: settled, < {ds.attrs['min_spikes']} spikes", fontsize=8)
    return finish(fig, ds.attrs)


FIG4 = Figure("fig4", fig4, ("fig4",), "F4", ("C06",))
FIG5 = Figure("fig5", fig5, ("fig5",), "F5", ("C11",))
FIG6 = Figure("fig6", fig6, ("fig6",), "F6", ("C07", "C08", "C09", "C10"))
TRANSIENTS = Figure("transients", transients, ("transients", "fig3"), title="Transient length against eps (C03-C05)",
                    section="sec:simulation")
PERTURBATION = Figure("perturbation", perturbation, ("fig5", "pert_audit"),
                      title="Perturbation hierarchy: convergence as eps -> 0 and secular growth (C12)",
                      section="sec:transient")
BASINS = Figure("basins", basins, ("basins",), title="Basin fractions on the energy level (C06 made quantitative)",
                section="sec:simulation")
