# Figures read datasets only; each figure is also a named target (snakemake -c2 fig3).


rule figure:
    input:
        nc=figure_inputs,
    output:
        png=report(f"{R}/figures/{{fig}}.png", caption="../report/figure.rst", category="Figures"),
        pdf=f"{R}/figures/{{fig}}.pdf",
    params:
        fig=lambda w: w.fig,
    log:
        f"{R}/logs/figure/{{fig}}.log",
    benchmark:
        f"{R}/benchmarks/figure/{{fig}}.tsv"
    wildcard_constraints:
        fig="|".join(FIGURE_INPUTS),
    script:
        "../scripts/figure.py"


rule figure_schematic:
    output:
        png=report(f"{R}/figures/fig1.png", caption="../report/figure.rst", category="Figures"),
        pdf=f"{R}/figures/fig1.pdf",
    params:
        fig="fig1",
        cfg=canonical(config["scenes"]["fig1"]),
    log:
        f"{R}/logs/figure/fig1.log",
    benchmark:
        f"{R}/benchmarks/figure/fig1.tsv"
    script:
        "../scripts/figure.py"


for _fig in FIGURES:

    rule:
        name:
            _fig
        input:
            figure_files([_fig]),
        localrule: True
