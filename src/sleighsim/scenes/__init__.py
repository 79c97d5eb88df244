"""Scenes: one module per analysis stage; each function takes its config block (and the paths
of the datasets it reads, by role) and returns one Dataset. Which function computes a scene
is declared once, by its ``kind``, in :data:`sleighsim.registry.KINDS`."""

from __future__ import annotations

from importlib import import_module

import xarray as xr

from ..registry import KINDS


def _function(kind: str, name: str | None = None):
    module, function = KINDS[kind].function.split(":")
    return getattr(import_module(f"{__name__}.{module}"), name or function)


def compute(scene: str, cfg: dict, inputs: dict | None = None) -> xr.Dataset:
    """The dataset of ``scene`` from its config block; ``inputs`` maps the kind's roles to paths."""
    kind = KINDS[cfg["kind"]]
    fn = _function(cfg["kind"])
    if kind.inputs:
        return fn(cfg, {role: inputs[role] for role in kind.inputs}, scene=scene)
    return fn(cfg, scene=scene)


def chunk(scene: str, cfg: dict, index: int) -> xr.Dataset:
    """One chunk of a chunked scene (see the kind's module)."""
    return _function(cfg["kind"], "chunk")(cfg, index, scene=scene)


def gather(scene: str, cfg: dict, paths) -> xr.Dataset:
    """A chunked scene's dataset from its chunk files."""
    return _function(cfg["kind"], "gather")(list(paths), cfg, scene=scene)
