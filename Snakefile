# sleighsim workflow: every figure of Fedonyuk & Tallapragada, from the mechanics up.
#   snakemake -c2                                  paper fidelity (config/config.yaml)
#   snakemake -c2 --configfile config/smoke.yaml   tiny, for CI
#   snakemake -c2 fig3                             one figure and what it needs
# What is built is derived from the config's scenes and sleighsim.registry.
from pathlib import Path

from snakemake.utils import min_version, validate

from sleighsim.configcheck import check as check_config

min_version("8.0")


configfile: "config/config.yaml"


# Stop before any job on a bad value; the message names the offending key.
validate(config, schema="workflow/schemas/config.schema.yaml", set_default=True)
check_config(config)


include: "workflow/rules/common.smk"
include: "workflow/rules/scenes.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/report.smk"
include: "workflow/rules/stability.smk"


rule all:
    default_target: True
    input:
        figure_files(FIGURES_BUILT),
        f"{R}/report/index.html",
