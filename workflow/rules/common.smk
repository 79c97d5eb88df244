# Shared names: which scenes compute a dataset, which datasets each figure reads.

# Every scene key except the schematic computes one dataset (sleighsim.scenes.SCENES).
SCENES = [s for s in config["scenes"] if s != "fig1"]
# Datasets made from other datasets, and every dataset the claims ledger may read.
DERIVED = ["fig9_scaling", "fig11_grid", "chaos_verdict"]
ALL_DATA = SCENES + DERIVED

# Figure -> the datasets it reads (fig1 is a schematic drawn from its config block).
FIGURE_INPUTS = {
    "fig2": ["fig2"],
    "fig3": ["fig3"],
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
}
FIGURES = ["fig1"] + list(FIGURE_INPUTS)


def figure_files(figs):
    return expand(f"{R}/figures/{{fig}}.{{ext}}", fig=figs, ext=("png", "pdf"))


def figure_inputs(wildcards):
    return [f"{R}/data/{s}.nc" for s in FIGURE_INPUTS[wildcards.fig]]
