# The claims ledger and the self-contained reproduction report: the final rules.


rule claims:
    input:
        data=expand(f"{R}/data/{{name}}.nc", name=ALL_DATA),
        figures=figure_files(FIGURES),
        claims_md=str(Path(workflow.basedir) / "paper" / "CLAIMS.md"),
    output:
        csv=report(f"{R}/claims.csv", caption="../report/claims.rst", category="Claims"),
        nc=f"{R}/claims.nc",
    log:
        f"{R}/logs/report/claims.log",
    benchmark:
        f"{R}/benchmarks/report/claims.tsv"
    script:
        "../scripts/claims.py"


rule report:
    input:
        claims=f"{R}/claims.nc",
        figures=figure_files(FIGURES),
        tex=str(Path(workflow.basedir) / "paper" / "fedonyuk-tallapragada-sleigh-rotor.tex"),
        claims_md=str(Path(workflow.basedir) / "paper" / "CLAIMS.md"),
    output:
        html=f"{R}/report/index.html",
        md=f"{R}/report/README.md",
    params:
        figure_inputs={f: FIGURE_INPUTS.get(f, []) for f in FIGURES
                       if f not in ("lyapunov", "audit", "transients", "perturbation")},
        extra={"Transient length against eps (C03-C05)": "transients",
               "Perturbation hierarchy: convergence as eps -> 0 and secular growth (C12)": "perturbation",
               "Lyapunov spectrum and chaos verdict": "lyapunov",
               "The model as printed: energy drift of the printed udot": "audit",
               "Speed against error": "bench"},
    log:
        f"{R}/logs/report/report.log",
    benchmark:
        f"{R}/benchmarks/report/report.tsv"
    script:
        "../scripts/report.py"


rule bench_data:
    output:
        nc=f"{R}/data/bench.nc",
    params:
        cfg=canonical(config["bench"]),
    threads: 1
    log:
        f"{R}/logs/bench/bench.log",
    benchmark:
        f"{R}/benchmarks/bench/bench.tsv"
    script:
        "../scripts/bench.py"


rule bench:
    input:
        figure_files(["bench"]),
    localrule: True


rule hardcases:
    input:
        f"{R}/data/hardcases.nc",
    localrule: True
