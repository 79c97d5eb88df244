# The claims ledger and the self-contained reproduction report: the final rules. Each names
# every file it reads.


rule claims:
    input:
        data=expand(f"{R}/data/{{name}}.nc", name=CLAIMS_DATA),
        figures=expand(f"{R}/figures/{{fig}}.png", fig=FIGURES_BUILT),
        claims_md=CLAIMS_MD,
    output:
        csv=report(
            f"{R}/claims.csv",
            caption="../report/claims.rst",
            category=sections.LEDGER,
            labels={"file": "claims ledger"},
        ),
        nc=f"{R}/claims.nc",
    log:
        f"{R}/logs/report/claims.log",
    benchmark:
        f"{R}/benchmarks/report/claims.tsv"
    conda:
        "../envs/sleighsim.yaml"
    params:
        # a changed label judges the run against the paper, or not (sleighsim.claims.fidelity)
        label=config["label"],
    script:
        "../scripts/claims.py"


rule report:
    input:
        **POWER_RECORD,
        **CLUSTER_RECORD,
        claims=f"{R}/claims.nc",
        figures=expand(f"{R}/figures/{{fig}}.png", fig=FIGURES_BUILT),
        data=expand(f"{R}/data/{{name}}.nc", name=REPORT_DATA),
        benchmarks=[t for ts in REPORT_BENCHMARKS.values() for t in ts],
        tex=PAPER_TEX,
        claims_md=CLAIMS_MD,
    output:
        html=f"{R}/report/index.html",
        md=f"{R}/report/README.md",
        finding=f"{R}/report/finding.yaml",
        standalone=report(
            f"{R}/report/standalone.html",
            caption="../report/report.rst",
            category=sections.LEDGER,
            labels={"file": "reproduction report"},
        ),
    log:
        f"{R}/logs/report/report.log",
    benchmark:
        f"{R}/benchmarks/report/report.tsv"
    conda:
        "../envs/sleighsim.yaml"
    params:
        label=config["label"],  # the report's first line
        figures=FIGURES_BUILT,
        data=REPORT_DATA,
        kinds={name: block["kind"] for name, block in SCENES.items()},
        benchmarks=REPORT_BENCHMARKS,
    script:
        "../scripts/report.py"
