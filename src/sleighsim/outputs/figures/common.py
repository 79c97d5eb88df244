"""What every figure shares: axis labels, the provenance footer, layout and atomic saving."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ...io import atomic_path  # noqa: E402

LABELS = {"u": r"$u$", "Omega": r"$\Omega$", "omega": r"$\omega$", "theta": r"$\theta$", "delta": r"$\delta$"}


def save_figure(fig, *paths) -> None:
    """Save to every path atomically (the format from its suffix), then close."""
    for path in map(Path, paths):
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=150, format=path.suffix[1:])
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



#: Line styles of the precisions drawn beside double (the paper's arithmetic).
PRECISION_STYLE = {"double": {"color": "tab:blue"}, "long double": {"color": "tab:red", "alpha": 0.7},
                   "quad": {"color": "black", "alpha": 0.6}}


def finer_precisions(datasets: list) -> dict:
    """{(scene, precision): dataset} of the datasets computed in a precision finer than double
    (a figure drawn beside its finer precisions receives them after its own datasets)."""
    return {(d.attrs["scene"], d.attrs["precision"]): d for d in datasets
            if d.attrs.get("precision", "double") != "double"}
