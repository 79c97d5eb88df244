"""Work models of scene blocks: how much a scene's jobs integrate, in time units, as a function
of its config block, as each kind declares it (:class:`sleighsim.scenes.kind.SceneKind`; the
default, :func:`sleighsim.scenes.workload.horizon_work`, sums the block's horizons).
:mod:`sleighsim.ops.estimate` scales measured CPU seconds by the ratio of these measures between two
configs."""

from __future__ import annotations

from sleighsim.scenes.catalog import KINDS


def chunk_work(cfg: dict) -> list[float]:
    """Work of each chunk job of a chunked block (as its kind declares it)."""
    return KINDS[cfg["kind"]].chunk_work(cfg)


def work(kind: str, cfg: dict) -> float:
    """The work measure of a scene block (as :func:`sleighsim.scenes.catalog.scene_config` gives it)."""
    return KINDS[kind].work(cfg)


def is_modelled(kind: str, key: str) -> bool:
    """Whether the work model of ``kind`` reads the (dotted) config key."""
    return KINDS[kind].modelled(key.split(".")[-1])
