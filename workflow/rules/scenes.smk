# One dataset per scene: config block (and the datasets it reads) in, netCDF out.


rule scene:
    input:
        unpack(scene_inputs),
    output:
        nc=f"{R}/data/{{scene}}.nc",
    log:
        f"{R}/logs/scene/{{scene}}.log",
    benchmark:
        f"{R}/benchmarks/scene/{{scene}}.tsv"
    wildcard_constraints:
        scene=alternatives(PLAIN),
    conda:
        "../envs/sleighsim.yaml"
    resources:
        runtime=lambda w: SCENES[w.scene].get("runtime_min", SCENE_RUNTIME_MIN),
    params:
        cfg=lambda w: SCENE_CFG[w.scene],
    script:
        "../scripts/scene.py"


# A laddered scene in a finer precision: the same block, its steady-state part in that arithmetic.
rule scene_in_precision:
    output:
        nc=f"{R}/data/{layout.FINER}.nc",
    log:
        f"{R}/logs/scene/{layout.FINER}.log",
    benchmark:
        f"{R}/benchmarks/scene/{layout.FINER}.tsv"
    wildcard_constraints:
        scene=alternatives([s for s in LADDERED if s not in LADDERED_CHUNKED]),
        tag=alternatives(TAG_PRECISION),
    conda:
        "../envs/sleighsim.yaml"
    resources:
        runtime=lambda w: SCENES[w.scene].get("runtime_min", SCENE_RUNTIME_MIN),
    params:
        cfg=lambda w: {**SCENE_CFG[w.scene], "precision": TAG_PRECISION[w.tag]},
    script:
        "../scripts/scene.py"


# A realized scene again from its start states perturbed at the rounding level (realization k >= 1).
rule scene_realization:
    input:
        unpack(scene_inputs),
    output:
        nc=f"{R}/data/{layout.REALIZED}.nc",
    log:
        f"{R}/logs/scene/{layout.REALIZED}.log",
    benchmark:
        f"{R}/benchmarks/scene/{layout.REALIZED}.tsv"
    wildcard_constraints:
        scene=alternatives(REALIZED),
        k=r"[1-9]\d*",
    conda:
        "../envs/sleighsim.yaml"
    resources:
        runtime=lambda w: SCENES[w.scene].get("runtime_min", SCENE_RUNTIME_MIN),
    params:
        cfg=realization_cfg,
        attrs=lambda w: {
            "realization": int(w.k),
            "realization_rel": SCENES[w.scene]["realization_rel"],
        },
    script:
        "../scripts/scene.py"


# Its ladder: the key observables in every precision and the precision they converge in.
rule ladder:
    input:
        runs=ladder_inputs,
    output:
        nc=f"{R}/data/{layout.LADDER_OF}.nc",
    log:
        f"{R}/logs/scene/{layout.LADDER_OF}.log",
    benchmark:
        f"{R}/benchmarks/scene/{layout.LADDER_OF}.tsv"
    wildcard_constraints:
        scene=alternatives(LADDERED),
    conda:
        "../envs/sleighsim.yaml"
    params:
        kind=lambda w: SCENES[w.scene]["kind"],
        what=lambda w: scene_catalog.writing(SCENE_CFG[w.scene])["what"],
        precisions=lambda w: LADDERED[w.scene],
        gain=lambda w: ladder_gain(w.scene),
    script:
        "../scripts/ladder.py"


# Long jobs start first, so the rest of the workflow runs beside them.
use rule scene as scene_first with:
    wildcard_constraints:
        scene=alternatives(FIRST),
    priority: 50


# A chunked scene: independent chunk jobs (scaled out on a cluster), gathered into its dataset.
rule chunk:
    input:
        unpack(chunk_inputs),
    output:
        nc=f"{R}/chunks/{{scene}}/{{chunk}}.nc",
    log:
        f"{R}/logs/chunk/{{scene}}/{{chunk}}.log",
    benchmark:
        f"{R}/benchmarks/chunk/{{scene}}/{{chunk}}.tsv"
    wildcard_constraints:
        scene=alternatives([n for n in CHUNKED if n not in CHUNKED_FIRST]),
        chunk=r"\d+",
    # after the scheduled-first scenes, before the rest: the grid's small-eps chunks are long
    priority: 40
    conda:
        "../envs/sleighsim.yaml"
    threads: 1
    resources:
        runtime=lambda w: SCENES[w.scene].get(
            "chunk_runtime_min", SCENES[w.scene].get("runtime_min", SCENE_RUNTIME_MIN)
        ),
        mem_mb=1500,
    params:
        cfg=lambda w: SCENE_CFG[w.scene],
    script:
        "../scripts/chunk.py"


# The chunks of a chunked scene scheduled first, before every other job: its last stage is the run's longest.
use rule chunk as chunk_first with:
    wildcard_constraints:
        scene=alternatives(CHUNKED_FIRST),
        chunk=r"\d+",
    priority: 60


rule gather:
    input:
        chunks=chunk_files,
    output:
        nc=f"{R}/data/{{scene}}.nc",
    log:
        f"{R}/logs/gather/{{scene}}.log",
    benchmark:
        f"{R}/benchmarks/gather/{{scene}}.tsv"
    wildcard_constraints:
        scene=alternatives(CHUNKED),
    conda:
        "../envs/sleighsim.yaml"
    params:
        cfg=lambda w: SCENE_CFG[w.scene],
    script:
        "../scripts/gather.py"


# A laddered scene chunked in a finer precision: its chunks' steady-state parts in that arithmetic.
use rule chunk as chunk_in_precision with:
    output:
        nc=f"{R}/chunks/{layout.FINER}/{{chunk}}.nc",
    log:
        f"{R}/logs/chunk/{layout.FINER}/{{chunk}}.log",
    benchmark:
        f"{R}/benchmarks/chunk/{layout.FINER}/{{chunk}}.tsv"
    wildcard_constraints:
        scene=alternatives(LADDERED_CHUNKED),
        tag=alternatives(TAG_PRECISION),
        chunk=r"\d+",
    params:
        cfg=lambda w: {**SCENE_CFG[w.scene], "precision": TAG_PRECISION[w.tag]},


use rule gather as gather_in_precision with:
    output:
        nc=f"{R}/data/{layout.FINER}.nc",
    log:
        f"{R}/logs/gather/{layout.FINER}.log",
    benchmark:
        f"{R}/benchmarks/gather/{layout.FINER}.tsv"
    wildcard_constraints:
        scene=alternatives(LADDERED_CHUNKED),
        tag=alternatives(TAG_PRECISION),
    params:
        cfg=lambda w: {**SCENE_CFG[w.scene], "precision": TAG_PRECISION[w.tag]},
