# Figures read datasets only; each figure, and each dataset without a figure of its name, is
# also a named target (snakemake -c2 fig3, snakemake -c2 hardcases).
from sleighsim.report import sections

# Where Snakemake's own report (snakemake --report report.zip) files each figure: its paper section.
FIGURE_REPORT = sections.figure_entries(PAPER_TEX, CLAIMS_MD)


rule figure:
    input:
        nc=figure_inputs,
    output:
        png=report(
            f"{R}/figures/{{fig}}.png",
            caption="../report/figure.rst",
            category=lambda w: FIGURE_REPORT[w.fig]["category"],
            subcategory=lambda w: FIGURE_REPORT[w.fig]["subcategory"],
            labels=lambda w: FIGURE_REPORT[w.fig]["labels"],
        ),
        pdf=f"{R}/figures/{{fig}}.pdf",
    log:
        f"{R}/logs/figure/{{fig}}.log",
    benchmark:
        f"{R}/benchmarks/figure/{{fig}}.tsv"
    wildcard_constraints:
        fig=alternatives([f for f in ALL_FIGURES if f not in SCHEMATICS]),
    conda:
        "../envs/sleighsim.yaml"
    params:
        fig=lambda w: w.fig,
    script:
        "../scripts/figure.py"


rule schematic:
    output:
        png=report(
            f"{R}/figures/{{fig}}.png",
            caption="../report/figure.rst",
            category=lambda w: FIGURE_REPORT[w.fig]["category"],
            subcategory=lambda w: FIGURE_REPORT[w.fig]["subcategory"],
            labels=lambda w: FIGURE_REPORT[w.fig]["labels"],
        ),
        pdf=f"{R}/figures/{{fig}}.pdf",
    log:
        f"{R}/logs/figure/{{fig}}.log",
    benchmark:
        f"{R}/benchmarks/figure/{{fig}}.tsv"
    wildcard_constraints:
        fig=alternatives(SCHEMATICS),
    conda:
        "../envs/sleighsim.yaml"
    params:
        fig=lambda w: w.fig,
        cfg=lambda w: SCENE_CFG[figure_catalog.FIGURES[w.fig].schematic],
    script:
        "../scripts/figure.py"


for _target in ALL_FIGURES:

    rule:
        name:
            _target
        input:
            figure_files([_target]),
        localrule: True


for _target in [d for d in ALL_DATASETS if d not in ALL_FIGURES]:

    rule:
        name:
            _target
        input:
            f"{R}/data/{_target}.nc",
        localrule: True


# The atlas of on-request chaos surveys (sleighsim.report.figures.catalog.ATLAS): snakemake -c2 atlas
rule atlas:
    input:
        figure_files([f for f in figure_catalog.ATLAS if f in ALL_FIGURES]),
    localrule: True
