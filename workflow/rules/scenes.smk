# One dataset per scene: config block in, netCDF out.


rule scene:
    output:
        nc=f"{R}/data/{{scene}}.nc",
    params:
        cfg=lambda w: canonical(config["scenes"][w.scene]),
    log:
        f"{R}/logs/scene/{{scene}}.log",
    benchmark:
        f"{R}/benchmarks/scene/{{scene}}.tsv"
    wildcard_constraints:
        scene="|".join(s for s in SCENES if s not in LONG_SCENES),
    script:
        "../scripts/scene.py"


# The longest jobs start first, so the rest of the workflow runs beside them.
use rule scene as scene_long with:
    priority: 50
    wildcard_constraints:
        scene="|".join(LONG_SCENES),


rule attractor_scaling:
    input:
        ref=f"{R}/data/fig9_ref.nc",
        high=f"{R}/data/fig9_highE.nc",
    output:
        nc=f"{R}/data/fig9_scaling.nc",
    log:
        f"{R}/logs/analysis/fig9_scaling.log",
    benchmark:
        f"{R}/benchmarks/analysis/fig9_scaling.tsv"
    script:
        "../scripts/analysis.py"
