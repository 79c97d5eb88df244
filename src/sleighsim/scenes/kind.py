"""A scene kind, declared once beside the function that computes it: :class:`SceneKind`.

Each scene module holds its kind(s) as module-level constants; :mod:`sleighsim.scenes.catalog`
collects them. Everything the workflow, the config checks and the cost estimate need to know about a
kind is here: how it runs, what it reads, which observables its precision ladder compares, what it
holds in memory, how much it integrates and which cross-field constraints its config block obeys.
The estimates and checks are pure functions of the kind's config block (as
:func:`sleighsim.scenes.catalog.scene_config` gives it)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from sleighsim.scenes.workload import HORIZON_KEYS, horizon_work


def n_chunks(cfg: dict) -> int:
    """The chunk jobs of a chunked block: its ``n_chunks``."""
    return cfg["n_chunks"]


def equal_chunks(cfg: dict) -> list[float]:
    """Work of each chunk job when the chunks share the block's horizons equally."""
    n = cfg["n_chunks"]
    return [horizon_work(cfg) / n] * n


def reads_none(cfg: dict, index: int) -> list[int]:
    """A chunk job that reads no other chunk of its scene."""
    return []


def horizon_key(leaf: str) -> bool:
    """Whether the horizon work model (:func:`sleighsim.scenes.workload.horizon_work`) reads ``leaf``."""
    return leaf in HORIZON_KEYS


def no_checks(where: str, cfg: dict) -> None:
    """A kind without cross-field constraints."""


@dataclass(frozen=True, kw_only=True)
class SceneKind:
    """A scene kind.

    - ``name``: the ``kind`` of a config block; ``title``: what a dataset of this kind is, in words (the
      heart of its CF title; a block's own ``title`` says it for that scene); ``vocabulary``: the
      (long_name, kind of quantity) of the variables only this kind writes (``sleighsim.io.cf``; the
      shared names are ``sleighsim.io.vocabulary``'s, and a name means one thing in every dataset);
    - ``compute(cfg, [inputs,] scene=)``: its dataset (None for a chunked or dataset-free kind);
    - ``chunk(cfg, index, scene=)`` and ``gather(paths, cfg, scene=)``: a chunked kind's chunk jobs
      and its dataset from their files; ``chunk_count(cfg)``: how many chunk jobs (a kind with both
      ``compute`` and ``chunk`` is computed in one job in double and chunked in a finer precision);
      ``chunk_reads(cfg, index)``: the indices of the scene's own chunks that chunk ``index`` reads (a
      later stage; its ``chunk`` then takes their paths as ``reads=``);
    - ``inputs``: the roles of the datasets it reads (named in the block's ``inputs``);
      ``reads_paper``: it also reads the paper's claims table (paper/CLAIMS.md, role ``claims_md``);
    - ``dataset``: False for a kind drawn from its config block alone; ``integrates``: it takes the
      config's ``defaults`` (the tolerance) unless its block sets them; ``realizable``: its claims rest
      on a sensitive quantity, so its block may ask for ``realizations``;
    - ``observables``: the key observables its precision ladder compares (none: it is not laddered);
    - ``records(cfg)``: the records it holds in memory (:class:`sleighsim.scenes.records.Span`);
    - ``work(cfg)``: the time units its jobs integrate; ``chunk_work(cfg)``: those of each chunk job;
      ``modelled(leaf)``: whether the work model reads a config key;
    - ``chunk_holds(cfg, k)``: what chunk k holds, for the cost estimate's report (None: not told);
    - ``checks(where, cfg)``: its cross-field constraints (raise
      :class:`sleighsim.scenes.checks.ConfigError`); ``pre_run``: the key of its checked pre-run."""

    name: str
    title: str
    records: Callable[[dict], list]
    vocabulary: dict = field(default_factory=dict)
    compute: Callable | None = None
    chunk: Callable | None = None
    gather: Callable | None = None
    chunk_count: Callable[[dict], int] = n_chunks
    chunk_reads: Callable[[dict, int], list[int]] = reads_none
    inputs: tuple[str, ...] = ()
    reads_paper: bool = False
    dataset: bool = True
    integrates: bool = True
    realizable: bool = False
    observables: tuple[str, ...] = ()
    work: Callable[[dict], float] = horizon_work
    chunk_work: Callable[[dict], list[float]] = equal_chunks
    modelled: Callable[[str], bool] = horizon_key
    chunk_holds: Callable[[dict, int], list] | None = None
    checks: Callable[[str, dict], None] = no_checks
    pre_run: str = ""

    @property
    def chunked(self) -> bool:
        """Whether it runs as independent chunk jobs gathered by one job, in every precision."""
        return self.chunk is not None and self.compute is None

    @property
    def variants_chunked(self) -> bool:
        """Whether its finer-precision variants run as chunk jobs gathered by one job: a chunked
        kind's, and those of a kind computed in one job in double (SIMD lanes) whose lanes a finer
        precision runs one after another."""
        return self.chunk is not None
