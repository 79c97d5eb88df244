# One dataset per scene: config block (and the datasets it reads) in, netCDF out.


rule scene:
    input:
        unpack(scene_inputs),
    output:
        nc=f"{R}/data/{{scene}}.nc",
    params:
        cfg=lambda w: SCENE_CFG[w.scene],
    log:
        f"{R}/logs/scene/{{scene}}.log",
    benchmark:
        f"{R}/benchmarks/scene/{{scene}}.tsv"
    conda:
        "../envs/sleighsim.yaml"
    wildcard_constraints:
        scene=alternatives(PLAIN),
    script:
        "../scripts/scene.py"


# Long jobs start first, so the rest of the workflow runs beside them.
use rule scene as scene_first with:
    priority: 50
    wildcard_constraints:
        scene=alternatives(FIRST),


# A chunked scene: independent chunk jobs (scaled out on a cluster), gathered into its dataset.
rule chunk:
    output:
        nc=f"{R}/chunks/{{scene}}/{{chunk}}.nc",
    params:
        cfg=lambda w: SCENE_CFG[w.scene],
    threads: 1
    resources:
        runtime=lambda w: SCENES[w.scene]["chunk_runtime_min"],
        mem_mb=1500,
    log:
        f"{R}/logs/chunk/{{scene}}/{{chunk}}.log",
    benchmark:
        f"{R}/benchmarks/chunk/{{scene}}/{{chunk}}.tsv"
    conda:
        "../envs/sleighsim.yaml"
    wildcard_constraints:
        scene=alternatives(CHUNKED),
        chunk=r"\d+",
    script:
        "../scripts/chunk.py"


rule gather:
    input:
        chunks=chunk_files,
    output:
        nc=f"{R}/data/{{scene}}.nc",
    params:
        cfg=lambda w: SCENE_CFG[w.scene],
    log:
        f"{R}/logs/gather/{{scene}}.log",
    benchmark:
        f"{R}/benchmarks/gather/{{scene}}.tsv"
    conda:
        "../envs/sleighsim.yaml"
    wildcard_constraints:
        scene=alternatives(CHUNKED),
    script:
        "../scripts/gather.py"
