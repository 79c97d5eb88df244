"""Scenes: one module per analysis stage; each function takes its config block (and the paths
of the datasets it reads, by role) and returns one Dataset. :func:`function` imports the function
of each kind (:data:`sleighsim.ops.registry.KINDS` says how the kind runs), so a job loads only the
module it needs and a reader can follow a kind to its code."""

from __future__ import annotations

from collections.abc import Callable

import xarray as xr

from sleighsim.ops.registry import KINDS


def function(kind: str) -> Callable[..., xr.Dataset]:
    """The function that computes a scene of ``kind`` (a chunked kind: see :func:`chunk_functions`)."""
    match kind:
        case "sleigh0":
            from sleighsim.scenes.trajectories import sleigh0 as f
        case "trajectory":
            from sleighsim.scenes.trajectories import trajectory as f
        case "attractor_levels":
            from sleighsim.scenes.transients import attractor_levels as f
        case "transient_scaling":
            from sleighsim.scenes.transients import transient_scaling as f
        case "series_vs_exact":
            from sleighsim.scenes.hierarchy import series_vs_exact as f
        case "hierarchy_terms":
            from sleighsim.scenes.hierarchy import hierarchy_terms as f
        case "hierarchy_audit":
            from sleighsim.scenes.hierarchy import hierarchy_audit as f
        case "poincare":
            from sleighsim.scenes.steady_state import poincare_maps as f
        case "psd":
            from sleighsim.scenes.steady_state import psd as f
        case "attractor_scaling":
            from sleighsim.scenes.steady_state import attractor_scaling as f
        case "lyapunov_spectrum":
            from sleighsim.scenes.exponents import spectrum as f
        case "lyapunov_protocol":
            from sleighsim.scenes.exponents import protocol as f
        case "lyapunov_energy":
            from sleighsim.scenes.exponents import energy_sweep as f
        case "small_eps_cost":
            from sleighsim.scenes.exponents import small_eps_cost as f
        case "formal_exponents":
            from sleighsim.scenes.exponents import formal_exponents as f
        case "precision_ladder":
            from sleighsim.scenes.ladder import precision_ladder as f
        case "trigger_law":
            from sleighsim.scenes.trigger import trigger_law as f
        case "drift_windows":
            from sleighsim.scenes.drift import drift_windows as f
        case "printed_model":
            from sleighsim.scenes.audit import printed_model as f
        case "k2_sweep":
            from sleighsim.scenes.causes import k2_sweep as f
        case "integration_error":
            from sleighsim.scenes.causes import integration_error as f
        case "hardcases":
            from sleighsim.scenes.hardcases import hardcases as f
        case "bench":
            from sleighsim.scenes.bench import bench as f
        case _:
            raise KeyError(f"scene kind {kind!r} has no function here (chunked or drawn without a dataset?)")
    return f


def chunk_functions(kind: str) -> tuple[Callable[..., xr.Dataset], Callable[..., xr.Dataset]]:
    """(chunk, gather) of a chunked kind: chunk k of the scene, and the dataset from its chunk files."""
    match kind:
        case "lyapunov_grid":
            from sleighsim.scenes.grid import chunk, gather
        case "basins":
            from sleighsim.scenes.basins import chunk, gather
        case "chaos_verdict":
            from sleighsim.scenes.verdict import chunk, gather
        case _:
            raise KeyError(f"scene kind {kind!r} is not chunked")
    return chunk, gather


def chunk_count(cfg: dict) -> int:
    """The number of chunk jobs of a chunked scene block: a verdict's one per realization and state,
    any other kind's ``n_chunks``."""
    if cfg["kind"] == "chaos_verdict":  # verdict.chunk: job k is state k % n_states of realization k // n_states
        return cfg["n_chunks"] * len(cfg["states"])
    return cfg["n_chunks"]


def compute(scene: str, cfg: dict, inputs: dict | None = None) -> xr.Dataset:
    """The dataset of ``scene`` from its config block; ``inputs`` maps the kind's roles to paths."""
    kind = KINDS[cfg["kind"]]
    fn = function(cfg["kind"])
    if kind.inputs:
        return fn(cfg, {role: inputs[role] for role in kind.inputs}, scene=scene)
    return fn(cfg, scene=scene)


def chunk(scene: str, cfg: dict, index: int) -> xr.Dataset:
    """One chunk of a chunked scene (see the kind's module)."""
    return chunk_functions(cfg["kind"])[0](cfg, index, scene=scene)


def gather(scene: str, cfg: dict, paths) -> xr.Dataset:
    """A chunked scene's dataset from its chunk files."""
    return chunk_functions(cfg["kind"])[1](list(paths), cfg, scene=scene)
