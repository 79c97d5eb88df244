"""Speed against error: work-precision and the observables against tolerance."""

from __future__ import annotations

import textwrap

import numpy as np

from sleighsim.io.netcdf import read_dataset
from sleighsim.report.figures.common import RATE, WIDTH, finish, subplots
from sleighsim.report.figures.figure import Figure


def bench(sources):
    """Work-precision: wall time against error (short horizon) and energy drift (long), and
    the scene observables against heyoka's tolerance.
    ``sources``: the paths of its datasets, in the order of its declaration. Returns the matplotlib Figure."""
    ds = read_dataset(sources[0])
    fig, axes = subplots(WIDTH, 13, 3, 2)
    axes = axes.ravel()
    keys = sorted({(b, m) for b, m in zip(ds.backend.values, ds.method.values)})
    for b, m in keys:
        sel = (ds.backend.values == b) & (ds.method.values == m)
        name = "heyoka (Taylor)" if b == "heyoka" else f"SciPy {m}"
        axes[0].loglog(ds.error_short.values[sel], ds.wall_short.values[sel], "o-", label=name)
        axes[1].loglog(np.maximum(ds.drift_long.values[sel], 1e-17), ds.wall_long.values[sel], "o-", label=name)
    axes[0].set_xlabel(f"end-state error at t = {ds.attrs['t_short']:g} (state units, vs long-double reference)")
    axes[0].set_ylabel(f"wall time (s), median of {ds.attrs['repeats_heyoka']} (heyoka) / "
                       f"{ds.attrs['repeats_scipy']} (SciPy)")
    axes[1].set_xlabel(f"max |E/E0 - 1| over t <= {ds.attrs['t_long']:g} (relative)")
    axes[1].set_ylabel("wall time (s)")
    axes[0].legend()
    axes[0].set_title(f"reference self-difference {ds.attrs['reference_self_difference']:.1e}")
    _observables(axes[2], ds)
    to = ds.tol_observable.values
    ax = axes[3]
    best = float(ds.lambda_1.values[np.argmin(to)])
    ax.loglog(np.maximum(np.abs(ds.lambda_1.values - best), 1e-12), ds.lambda_1_wall.values, "o-",
              label="heyoka (Taylor)")
    if "lyap_scipy" in ds.dims:
        for m in sorted(set(ds.lyap_scipy_method.values.tolist())):
            sel = ds.lyap_scipy_method.values == m
            ax.loglog(np.abs(ds.lyap_scipy_lambda_1.values[sel] - best), ds.lyap_scipy_wall.values[sel], "s--",
                      label=f"SciPy {m}")
    ax.set_xlabel(f"|lambda_1 - heyoka tightest|, T = {ds.attrs['T_lyapunov']:g} ({RATE}; floor 1e-12)")
    ax.set_ylabel("wall time (s)")
    ax.set_title(f"Lyapunov kernel (heyoka tightest: lambda_1 = {best:.4g})")
    ax.legend()
    _peers(axes[4], ds)
    _lyapunov_peers(axes[5], ds)
    return finish(fig, ds.attrs)


def _observables(ax, ds) -> None:
    """The scene observables against heyoka's tolerance, as the relative deviation from their value at
    the tightest tolerance; the loosest converged tolerance of each in the title."""
    hy = ds.backend.values == "heyoka"
    tol = ds.tol.values[hy]
    for name, vals in (("spike interval", ds.spike_interval.values[hy]), ("first spike", ds.first_spike.values[hy])):
        ax.semilogx(tol, vals / vals[np.argmin(tol)] - 1, "o-", label=name)
    to = ds.tol_observable.values
    for name in ("lambda_1", "rotation_number"):
        v = ds[name].values
        ax.semilogx(to, v / v[np.argmin(to)] - 1, "s--", label=name)
    ax.set_xlabel("heyoka tolerance (relative)")
    ax.set_ylabel("observable / value at the tightest tolerance - 1\n(relative deviation)")
    ax.legend()
    loosest = [f"{k.replace('loosest_converged_tol_', '')} {v:.0e}" for k, v in ds.attrs.items()
               if k.startswith("loosest_converged_tol_")]
    ax.set_title(textwrap.fill("loosest converged tol: " + ", ".join(loosest), 60))


def _peers(ax, ds) -> None:
    """Work-precision of every peer engine beside heyoka's bare propagation, compile times in the legend."""
    engines = list(dict.fromkeys(ds.peer_engine.values.tolist()))
    for name in engines:
        sel = (ds.peer_engine.values == name) & np.isfinite(ds.peer_error.values)
        if not sel.any():
            continue
        compile_s = np.nanmax(ds.peer_compile_s.values[sel]) if np.isfinite(ds.peer_compile_s.values[sel]).any() else 0
        style = dict(color="k", lw=2.5, marker="o") if name.startswith("heyoka") else dict(marker=".", lw=1)
        ax.loglog(ds.peer_error.values[sel], ds.peer_wall.values[sel], label=f"{name} (compile {compile_s:.2g} s)",
                  **style)
    missing = sorted({n for n, e in zip(ds.peer_engine.values, ds.peer_error.values) if not np.isfinite(e)})
    for t in ds.error_target.values:
        ax.axvline(t, color="0.85", lw=0.8, zorder=0)
    ax.set_xlabel(f"end-state error at t = {ds.attrs['t_short']:g} (state units; same reference and metric)")
    ax.set_ylabel(f"wall (s), median of {ds.attrs['peer_repeats']} after {ds.attrs['peer_warmup']} warm-up")
    ax.set_title("peers at rtol " + ", ".join(f"{r:.0e}" for r in sorted(set(ds.peer_rtol.values.tolist())))
                 + (f"\nnot run: {', '.join(missing)}" if missing else ""))
    ax.legend()


def _lyapunov_peers(ax, ds) -> None:
    """lambda_1 and wall time of lyapax and heyoka's Benettin on Lorenz and the sleigh."""
    y = np.arange(ds.sizes["lyap_peer"])
    walls = ds.lyap_peer_wall.values
    ax.barh(y, np.where(np.isfinite(walls), walls, 0), height=0.4, color=["C0" if e.startswith("heyoka") else "C1"
                                                              for e in ds.lyap_peer_engine.values])
    labels = [f"{s}: {e}" for s, e in zip(ds.lyap_peer_system.values, ds.lyap_peer_engine.values)]
    ax.set_yticks(y, labels)
    for k, (lam, c, note) in enumerate(zip(ds.lyap_peer_lambda_1.values, ds.lyap_peer_compile_s.values,
                                           ds.lyap_peer_note.values)):
        text = f"lambda_1 = {lam:.4g}, compile {c:.2g} s" if np.isfinite(lam) else f"not run: {note[:80]}"
        ax.annotate(textwrap.fill(text, 50), (0, k + 0.25), xytext=(3, 0), textcoords="offset points", va="bottom",
                    fontsize=8)
    ax.set_xlabel("wall (s), median of the timed repeats")
    ax.set_title(f"Lyapunov kernel: T = {ds.attrs['lyap_peer_T_lorenz']:g} (Lorenz; literature lambda_1 = "
                 f"{ds.attrs['lorenz_lambda_1_literature']:g}),\n{ds.attrs['lyap_peer_T_sleigh']:g} (sleigh), "
                 f"tau = {ds.attrs['lyap_peer_tau']:g}")


BENCH = Figure("bench", bench, ("bench",), title="Speed against error")
