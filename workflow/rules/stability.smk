# On request (`snakemake -c2 stability`): the ledger rerun with perturbed initial states and a
# looser tolerance (sleighsim.ops.stability), and the table of verdicts that change.


rule stability:
    input:
        claims=f"{R}/claims.nc",
    output:
        csv=f"{R}/stability/verdicts.csv",
        nc=f"{R}/stability/verdicts.nc",
    log:
        f"{R}/logs/report/stability.log",
    conda:
        "../envs/sleighsim.yaml"
    # the nested runs use this many cores; Snakemake lowers it to --cores (a fixed number, not
    # workflow.cores, so that `snakemake --unlock` and other core-less commands still parse)
    threads: 64
    script:
        "../scripts/stability.py"
