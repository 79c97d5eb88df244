# The (eps, b) Lyapunov grid: independent chunk jobs gathered by one rule, so
# `snakemake -c2` runs it here and `--profile profiles/slurm` runs it wide.
# Then the chaos verdict from the spectrum and the P_2pi iterates.

GRID_CHUNKS = list(range(config["lyap_grid"]["n_chunks"]))
# What the grid computes; the runtime resource is scheduling only and must not force a rerun.
GRID_CFG = canonical({k: v for k, v in config["lyap_grid"].items() if k != "chunk_runtime_min"})


rule lyap_grid_chunk:
    output:
        nc=f"{R}/lyapunov/grid_chunk{{chunk}}.nc",
    params:
        cfg=GRID_CFG,
    threads: 1
    resources:
        runtime=config["lyap_grid"]["chunk_runtime_min"],
        mem_mb=1500,
    log:
        f"{R}/logs/lyap_grid_chunk/{{chunk}}.log",
    benchmark:
        f"{R}/benchmarks/lyap_grid_chunk/{{chunk}}.tsv"
    wildcard_constraints:
        chunk=r"\d+",
    script:
        "../scripts/grid_chunk.py"


rule lyap_grid:
    input:
        chunks=expand(f"{R}/lyapunov/grid_chunk{{chunk}}.nc", chunk=GRID_CHUNKS),
    output:
        nc=f"{R}/data/fig11_grid.nc",
    params:
        cfg=GRID_CFG,
    log:
        f"{R}/logs/analysis/fig11_grid.log",
    benchmark:
        f"{R}/benchmarks/analysis/fig11_grid.tsv"
    script:
        "../scripts/grid_gather.py"


rule chaos_verdict:
    input:
        spectrum=f"{R}/data/lyap_spectrum.nc",
        poincare=f"{R}/data/fig9_ref.nc",
    output:
        nc=f"{R}/data/chaos_verdict.nc",
    params:
        cfg=canonical(config["chaos_verdict"]),
    log:
        f"{R}/logs/analysis/chaos_verdict.log",
    benchmark:
        f"{R}/benchmarks/analysis/chaos_verdict.tsv"
    script:
        "../scripts/verdict.py"
