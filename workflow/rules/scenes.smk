# One dataset per scene: config block in, netCDF out.


rule scene:
    output:
        nc=f"{R}/data/{{scene}}.nc",
    params:
        cfg=lambda w: config["scenes"][w.scene],
    log:
        f"{R}/logs/scene/{{scene}}.log",
    benchmark:
        f"{R}/benchmarks/scene/{{scene}}.tsv"
    wildcard_constraints:
        scene="|".join(SCENES),
    script:
        "../scripts/scene.py"
