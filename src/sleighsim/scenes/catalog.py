"""Every scene kind, collected from the scene modules that declare them (:data:`KINDS`), and the
names of the datasets a config builds.

Scenes live in the config: each block under ``scenes`` names its ``kind``; the dataset is
``results/data/<scene>.nc``, computed by the kind's declared function (:class:`sleighsim.scenes.kind.SceneKind`).
A scene may also run in several precisions (a ladder, coarse to fine from double) and from perturbed
start states (realizations); where each of those lies is :mod:`sleighsim.io.layout`'s. The Snakefile, the
config checks, the cost estimate and the claims ledger derive what they build from here.

Importing this module imports every scene module (about 1.1 CPU-s, once per job: farm-bench, median
of 10; scipy.signal, .stats and .optimize are imported where used, 0.8 CPU-s less)."""

from __future__ import annotations

import xarray as xr

from sleighsim.io import layout
from sleighsim.precision import Precision, parsed
from sleighsim.scenes import (
    audit,
    basins,
    bench,
    causes,
    drift,
    energy_sweep,
    exponents,
    formal,
    grid,
    hardcases,
    hierarchy,
    judge_power,
    ladder,
    paper_setup,
    schematic,
    steady_state,
    torus_stability,
    trajectories,
    transients,
    trigger,
    verdict,
)
from sleighsim.scenes.kind import SceneKind

#: Every scene kind by its name.
KINDS: dict[str, SceneKind] = {k.name: k for k in (
    schematic.SCHEMATIC, trajectories.SLEIGH0, trajectories.TRAJECTORY, transients.ATTRACTOR_LEVELS,
    transients.TRANSIENT_SCALING, hierarchy.SERIES_VS_EXACT, hierarchy.HIERARCHY_TERMS, hierarchy.HIERARCHY_AUDIT,
    steady_state.POINCARE, steady_state.PSD, steady_state.ATTRACTOR_SCALING, exponents.LYAPUNOV_SPECTRUM,
    exponents.LYAPUNOV_PROTOCOL, energy_sweep.LYAPUNOV_ENERGY, formal.SMALL_EPS_COST, formal.FORMAL_EXPONENTS,
    grid.LYAPUNOV_GRID, verdict.CHAOS_VERDICT, ladder.PRECISION_LADDER, trigger.TRIGGER_LAW, drift.DRIFT_WINDOWS,
    basins.BASINS, audit.PRINTED_MODEL, causes.K2_SWEEP, causes.INTEGRATION_ERROR, hardcases.HARDCASES, bench.BENCH,
    judge_power.JUDGE_POWER,
    torus_stability.TORUS_STABILITY, paper_setup.PAPER_SETUP,
)}

#: Keys of a scene block that schedule its jobs and do not change what it computes.
SCHEDULING = ("on_request", "schedule_first", "chunk_runtime_min", "runtime_min")


def compute(scene: str, cfg: dict, inputs: dict | None = None) -> xr.Dataset:
    """The dataset of ``scene`` from its config block; ``inputs`` maps the kind's roles (and
    ``claims_md`` for a kind that reads the paper's claims table) to paths."""
    kind = KINDS[cfg["kind"]]
    if kind.inputs:
        roles = kind.inputs + (("claims_md",) if kind.reads_paper else ())
        return kind.compute(cfg, {role: inputs[role] for role in roles}, scene=scene)
    return kind.compute(cfg, scene=scene)


def chunk(scene: str, cfg: dict, index: int, reads=(), inputs: dict | None = None) -> xr.Dataset:
    """Chunk ``index`` of a chunked scene (see the kind's module); ``reads``: the paths of the chunks
    it reads (``chunk_reads``), for a kind that reads any; ``inputs``: the kind's roles -> dataset paths,
    for a kind that reads datasets."""
    kind = KINDS[cfg["kind"]]
    extra = {"reads": list(reads)} if kind.chunk_reads(cfg, index) else {}
    if kind.inputs:
        extra["inputs"] = {role: inputs[role] for role in kind.inputs}
    return kind.chunk(cfg, index, scene=scene, **extra)


def chunk_reads(cfg: dict, index: int) -> list[int]:
    """The indices of the chunks of the same scene that chunk ``index`` reads."""
    return KINDS[cfg["kind"]].chunk_reads(cfg, index)


def gather(scene: str, cfg: dict, paths) -> xr.Dataset:
    """A chunked scene's dataset from its chunk files."""
    return KINDS[cfg["kind"]].gather(list(paths), cfg, scene=scene)


def writing(cfg: dict) -> dict:
    """How a dataset of the scene block ``cfg`` is written (``sleighsim.io.netcdf.write_dataset``'s
    keywords): the arithmetic it was computed in, what it is (the block's ``title``, else its kind's) and
    its kind's vocabulary."""
    kind = KINDS[cfg["kind"]]
    return {"precision": cfg.get("precision", Precision.DOUBLE), "what": cfg.get("title", kind.title),
            "vocabulary": kind.vocabulary}


def chunk_count(cfg: dict) -> int:
    """The number of chunk jobs of a chunked scene block."""
    return KINDS[cfg["kind"]].chunk_count(cfg)


def laddered(config: dict, *, on_request: bool = False) -> dict[str, list[Precision]]:
    """{scene: its precisions, coarse to fine from double} for the scenes of ``config`` that run in more
    than one precision (among those :func:`datasets` builds)."""
    scenes = config["scenes"]
    return {name: parsed(scenes[name])["precisions"] for name in datasets(config, on_request=on_request)
            if KINDS[scenes[name]["kind"]].observables and len(scenes[name].get("precisions", ())) > 1}


def realized(config: dict, *, on_request: bool = False) -> dict[str, int]:
    """{scene: its number of realizations} for the scenes of ``config`` (among those :func:`datasets`
    builds) whose realizable block asks for more than one."""
    scenes = config["scenes"]
    return {name: int(scenes[name]["realizations"]) for name in datasets(config, on_request=on_request)
            if KINDS[scenes[name]["kind"]].realizable and scenes[name].get("realizations", 1) > 1}


def run_datasets(config: dict) -> list[str]:
    """Every dataset the config's default run builds, by name under data/: its scenes, their
    finer-precision variants and precision ladders, and their realizations (on-request scenes not)."""
    lad = laddered(config)
    return (datasets(config) + [layout.variant(s, p) for s, ps in lad.items() for p in ps[1:]]
            + [layout.ladder(s) for s in lad]
            + [layout.realization(s, k) for s, n in realized(config).items() for k in range(1, n)])


def scene_config(config: dict, scene: str) -> dict:
    """The block of ``scene`` as its function reads it: the config's ``defaults`` filled in where
    the kind integrates and the block sets no value, the scheduling keys removed (and a laddered
    kind's ``precisions`` and ``gain``: each precision's job adds its own ``precision``, and the
    ladder's job reads the gauge; a realizable kind's ``realizations`` and ``realization_rel``: each
    realization's job perturbs its start states itself), every arithmetic it names parsed into a
    Precision (``sleighsim.precision.parsed``: the one place a scene's precisions are parsed)."""
    block = config["scenes"][scene]
    kind = KINDS[block["kind"]]
    defaults = config.get("defaults", {}) if kind.integrates else {}
    laddering = ("precisions", "gain") if kind.observables else ()  # the ladder's, by its own jobs
    realizing = ("realizations", "realization_rel") if kind.realizable else ()
    return parsed({**defaults, **{k: v for k, v in block.items() if k not in SCHEDULING + laddering + realizing}})


def scenes_of(config: dict, kind: SceneKind, *, on_request: bool = True) -> list[str]:
    """The scenes of ``config`` of ``kind`` (a declaration, never its name as a string) that make a
    dataset (:func:`datasets`; with ``on_request`` also those built only when asked for)."""
    return [n for n in datasets(config, on_request=on_request) if config["scenes"][n]["kind"] == kind.name]


def datasets(config: dict, *, on_request: bool = False) -> list[str]:
    """The scenes of ``config`` that make a dataset: those built in the full run, or with
    ``on_request`` also those built only when asked for."""
    return [name for name, block in config["scenes"].items()
            if KINDS[block["kind"]].dataset and (on_request or not block.get("on_request", False))]
