# Shared names: which scenes compute a dataset, which figures exist.

# Scenes whose dataset comes from sleighsim.scenes.SCENES (fig1 is a schematic).
SCENES = [s for s in ("fig2", "fig3", "fig7", "fig8") if s in config["scenes"]]
FIGURES = ["fig1"] + SCENES


def figure_files(figs):
    return expand(f"{R}/figures/{{fig}}.{{ext}}", fig=figs, ext=("png", "pdf"))
