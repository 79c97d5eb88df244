# Shared names: which scenes compute a dataset, which datasets each figure reads.

# Every scene key except the schematic computes one dataset (sleighsim.scenes.SCENES);
# the hard cases run on request (`snakemake -c2 hardcases`), not as part of `all`.
SCENES = [s for s in config["scenes"] if s != "fig1"]
ON_REQUEST = ["hardcases"]
# Scenes that take minutes at paper fidelity: scheduled first (rule scene_long).
LONG_SCENES = ["lyap_spectrum"]
# Datasets made from other datasets, and every dataset the claims ledger may read.
DERIVED = ["fig9_scaling", "fig11_grid", "chaos_verdict"]
ALL_DATA = [s for s in SCENES if s not in ON_REQUEST] + DERIVED

# Figure -> the datasets it reads (fig1 is a schematic drawn from its config block).
FIGURE_INPUTS = {
    "fig2": ["fig2"],
    "fig3": ["fig3"],
    "fig4": ["fig4"],
    "fig5": ["fig5"],
    "fig6": ["fig6"],
    "transients": ["transients", "fig3"],
    "perturbation": ["fig5", "pert_audit"],
    "fig7": ["fig7"],
    "fig8": ["fig8"],
    "fig9": ["fig9_ref", "fig9_highE", "fig9_eps001", "fig9_scaling"],
    "fig12": ["fig9_ref", "fig9_eps001"],
    "fig13": ["psd_eps01"],
    "fig14": ["psd_eps001"],
    "fig10": ["lyap_energy"],
    "fig11": ["fig11_grid"],
    "lyapunov": ["lyap_spectrum", "lyap_protocol", "chaos_verdict"],
    "audit": ["audit"],
    "bench": ["bench"],
}
# Figures of `rule all` (the benchmark runs on request: `snakemake -c2 bench`).
FIGURES = ["fig1"] + [f for f in FIGURE_INPUTS if f != "bench"]


def figure_files(figs):
    return expand(f"{R}/figures/{{fig}}.{{ext}}", fig=figs, ext=("png", "pdf"))


def figure_inputs(wildcards):
    return [f"{R}/data/{s}.nc" for s in FIGURE_INPUTS[wildcards.fig]]


def canonical(value):
    """Config values with mapping keys sorted, so reordering a YAML file does not count
    as a parameter change (Snakemake compares params in order)."""
    if isinstance(value, dict):
        return {k: canonical(value[k]) for k in sorted(value)}
    if isinstance(value, list):
        return [canonical(v) for v in value]
    return value
