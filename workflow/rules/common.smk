# Names the rules share, all derived from the config, the scene kinds (sleighsim.scenes.catalog), the
# figures (sleighsim.report.figures.catalog) and the report's tables (nothing listed here).
import re

from sleighsim.io import layout
from sleighsim.precision import Precision
from sleighsim.report.figures import catalog as figure_catalog
from sleighsim.report.tables import TABLES
from sleighsim.scenes import catalog as scene_catalog
from sleighsim.scenes.paper_setup import PAPER_SETUP

R = config["results"]
SCENES = config["scenes"]
# Datasets and figures of the full run, and with the on-request ones (built when asked for).
DATASETS = scene_catalog.datasets(config)
ALL_DATASETS = scene_catalog.datasets(config, on_request=True)
FIGURES_BUILT = figure_catalog.figures_built(config)
ALL_FIGURES = figure_catalog.figures_built(config, on_request=True)
SCHEMATICS = [f for f in ALL_FIGURES if figure_catalog.FIGURES[f].schematic]
CHUNKED = [n for n in ALL_DATASETS if scene_catalog.KINDS[SCENES[n]["kind"]].chunked]
FIRST = [
    n
    for n in ALL_DATASETS
    if n not in CHUNKED and SCENES[n].get("schedule_first", False)
]
PLAIN = [n for n in ALL_DATASETS if n not in CHUNKED and n not in FIRST]
# Chunked scenes whose block asks to start first: their chunk jobs outrank every other job (the chaos
# verdict's decisive stage is the run's longest job and waits for its first stage).
CHUNKED_FIRST = [n for n in CHUNKED if SCENES[n].get("schedule_first", False)]
# Scenes run in several precisions from one settled point ({scene: precisions}), the datasets of
# their finer precisions and their ladders (sleighsim.analysis.observables), by name under data/.
LADDERED = scene_catalog.laddered(config, on_request=True)
# Those whose finer-precision variants run as chunk jobs: the chunked scenes', and those of a kind
# computed in one job in double whose block asks for more than one job in a finer precision
# (sleighsim.scenes.kind.SceneKind.variants_chunked).
LADDERED_CHUNKED = [
    s
    for s in LADDERED
    if s in CHUNKED
    or (
        scene_catalog.KINDS[SCENES[s]["kind"]].variants_chunked
        and scene_catalog.chunk_count(SCENES[s]) > 1
    )
]
TAG_PRECISION = {p.tag: p for ps in LADDERED.values() for p in ps[1:]}
# Scenes run again from perturbed start states ({scene: realizations}) and those datasets by name.
REALIZED = scene_catalog.realized(config, on_request=True)
# Runtime resource (minutes) of a scene job whose block sets no runtime_min (the SLURM profile's default).
SCENE_RUNTIME_MIN = 60
# Every dataset of the default run: the scenes, their finer precisions, ladders and realizations.
CLAIMS_DATA = scene_catalog.run_datasets(config)
LADDER_DATA = [n for n in CLAIMS_DATA if layout.is_finer(n) or layout.is_ladder(n)]
REALIZATION_DATA = [n for n in CLAIMS_DATA if layout.is_realization(n)]
# What the report reads: the datasets of the figures shown and of the tables built.
REPORT_DATA = sorted(
    {d for f in FIGURES_BUILT for d in figure_catalog.FIGURES[f].data}
    | {t.data for t in TABLES.values() if t.data in DATASETS}
    | set(LADDER_DATA)
    | set(
        scene_catalog.scenes_of(config, PAPER_SETUP, on_request=False)
    )  # the findings' setup paragraph
)


def canonical(value):
    """Config values with mapping keys sorted, so reordering a YAML file does not count
    as a parameter change (Snakemake compares params in order)."""
    if isinstance(value, dict):
        return {k: canonical(value[k]) for k in sorted(value)}
    if isinstance(value, list):
        return [canonical(v) for v in value]
    return value


SCENE_CFG = {
    name: canonical(scene_catalog.scene_config(config, name)) for name in SCENES
}


def alternatives(names):
    """A wildcard constraint matching exactly these names, each taken literally (nothing when there
    are none)."""
    return "|".join(re.escape(n) for n in names) or "(?!)"


def figure_files(figs):
    return expand(f"{R}/figures/{{fig}}.{{ext}}", fig=figs, ext=("png", "pdf"))


def figure_inputs(wildcards):
    """The figure's datasets, then (for a figure drawn beside its finer precisions) those of its
    laddered scenes in every finer precision."""
    fig = figure_catalog.FIGURES[wildcards.fig]
    beside = [
        layout.variant(s, p)
        for s in (fig.data if fig.beside else ())
        for p in LADDERED.get(s, ())[1:]
    ]
    return [f"{R}/data/{s}.nc" for s in (*fig.data, *beside)]


def ladder_gain(scene):
    """The faithfulness gauge of a laddered scene (its block's ``gain``), None without one."""
    block, cfg = SCENES[scene], SCENE_CFG[scene]
    if "gain" not in block:
        return None
    return {
        **block["gain"],
        "params": cfg["params"],
        "spike_factor": cfg["transient"]["spike_factor"],
        "tol": cfg["tol"],
    }


def realization_cfg(wildcards):
    """The block of realization k of a scene: its start states perturbed at its realization_rel."""
    from sleighsim.scenes.common import realization_config

    rel = SCENES[wildcards.scene]["realization_rel"]
    return realization_config(SCENE_CFG[wildcards.scene], rel, int(wildcards.k))


def ladder_inputs(wildcards):
    return [
        f"{R}/data/{layout.variant(wildcards.scene, p)}.nc"
        for p in LADDERED[wildcards.scene]
    ]


def scene_inputs(wildcards):
    """The datasets a scene's block names (role -> path), the paper's claims table (role
    ``claims_md``) for a kind that reads it (SceneKind.reads_paper), and the benchmark record of
    measured prices it cites (``price_record``: role price)."""
    block = SCENES[wildcards.scene]
    paper = (
        {"claims_md": CLAIMS_MD}
        if scene_catalog.KINDS[block["kind"]].reads_paper
        else {}
    )
    price = (
        {"price": str(ROOT / block["price_record"])} if "price_record" in block else {}
    )
    return {
        **{
            role: f"{R}/data/{source}.nc"
            for role, source in block.get("inputs", {}).items()
        },
        **paper,
        **price,
    }


def chunk_folder(wildcards):
    """The folder under chunks/ of a chunked scene, or of its variant in a finer precision (wildcard ``tag``)."""
    if "tag" in wildcards.keys():
        return layout.chunk_folder(wildcards.scene, TAG_PRECISION[wildcards.tag])
    return layout.chunk_folder(wildcards.scene, Precision.DOUBLE)


def chunk_reads(wildcards):
    """The chunk files of the same scene (or variant) that a later-stage chunk job reads (the kind's
    ``chunk_reads``; none for most)."""
    reads = scene_catalog.chunk_reads(SCENES[wildcards.scene], int(wildcards.chunk))
    return expand(f"{R}/chunks/{chunk_folder(wildcards)}/{{k}}.nc", k=reads)


def chunk_inputs(wildcards):
    """A chunk job's inputs: the chunks of its scene it reads (``reads``), the datasets its block names
    (``inputs``: role -> dataset) and the judge-power record it votes by (``vote_record``: role power).
    """
    block = SCENES[wildcards.scene]
    record = (
        {"power": str(ROOT / block["vote_record"])} if "vote_record" in block else {}
    )
    return {"reads": chunk_reads(wildcards), **scene_inputs(wildcards), **record}


def chunk_files(wildcards):
    """The chunk files of a chunked scene, or of its variant in a finer precision (wildcard ``tag``)."""
    n = scene_catalog.chunk_count(SCENES[wildcards.scene])
    return expand(f"{R}/chunks/{chunk_folder(wildcards)}/{{k}}.nc", k=range(n))


def benchmark_files(datasets, figures):
    """{"data/<name>" or "figure/<name>": the Snakemake benchmark files of the jobs that made it}."""
    out = {}
    for name in datasets:
        # a chunked scene, or a chunked variant precision/<tag>/<scene> (not its ladder)
        scene = layout.scene_of(name)
        if (scene in CHUNKED and name == scene) or (
            scene in LADDERED_CHUNKED and layout.is_finer(name)
        ):
            chunks = expand(
                f"{R}/benchmarks/chunk/{name}/{{k}}.tsv",
                k=range(scene_catalog.chunk_count(SCENES[scene])),
            )
            out[f"data/{name}"] = [f"{R}/benchmarks/gather/{name}.tsv"] + chunks
        else:
            out[f"data/{name}"] = [f"{R}/benchmarks/scene/{name}.tsv"]
    for name in figures:
        out[f"figure/{name}"] = [f"{R}/benchmarks/figure/{name}.tsv"]
    return out


def chunk_products(scene):
    """The chunk files of a chunked scene and of its chunked finer-precision variants."""
    finer = LADDERED.get(scene, [])[1:] if scene in LADDERED_CHUNKED else []
    folders = [scene] * (scene in CHUNKED) + [
        layout.chunk_folder(scene, p) for p in finer
    ]
    n = scene_catalog.chunk_count(SCENES[scene])
    return [f"{R}/chunks/{f}/{k}.nc" for f in folders for k in range(n)]


# Every netCDF file the config's rules write (on-request ones too): the datasets, their variants,
# ladders and realizations, the chunks and the ledgers. The set-aside step looks at these only.
PRODUCTS = sorted(
    {
        *(
            f"{R}/data/{n}.nc"
            for n in [
                *ALL_DATASETS,
                *(layout.variant(s, p) for s, ps in LADDERED.items() for p in ps),
                *(layout.ladder(s) for s in LADDERED),
                *(
                    layout.realization(s, k)
                    for s, count in REALIZED.items()
                    for k in range(1, count)
                ),
            ]
        ),
        *(f for s in {*CHUNKED, *LADDERED_CHUNKED} for f in chunk_products(s)),
        f"{R}/claims.nc",
        f"{R}/stability/verdicts.nc",
    }
)
REPORT_BENCHMARKS = benchmark_files(REPORT_DATA + REALIZATION_DATA, FIGURES_BUILT)
# The repository: the workflow's parent directory (workflow.basedir is where workflow/Snakefile lies).
ROOT = Path(workflow.basedir).parent
PAPER_TEX = str(ROOT / "paper" / "fedonyuk-tallapragada-sleigh-rotor.tex")
CLAIMS_MD = str(ROOT / "paper" / "CLAIMS.md")
# The judge-power record a scene votes by (its table and the deciding judges' power in the report).
# A chaos verdict measured with another config (ops.verdictrecord writes it), cited on the report's first
# screen when there is one; the default run decides its own states, so the repository keeps none.
CLUSTER_RECORD = {
    "cluster_record": str(path)
    for path in [ROOT / "benchmarks" / "cluster_verdict.yaml"]
    if path.exists()
}
POWER_RECORD = {
    "power_record": str(ROOT / b["vote_record"])
    for b in SCENES.values()
    if "vote_record" in b
}
