"""Checks the JSON schema cannot express, run at workflow start (before any job).

- every number is finite (YAML's .nan and .inf pass the schema's bounds);
- every tolerance (heyoka ``tol``, SciPy rtols, relative tolerances) lies in (0, 1) (the schema
  holds each to its arithmetic's machine epsilon);
- every integer field is written as an integer (JSON schema counts 3.0 as an integer);
- cross-field constraints of each kind (a window inside its span, increasing ranges, ...), as the
  kind declares them (:class:`sleighsim.scenes.kind.SceneKind`), and each declared pre-run's window;
- scene names match the documented pattern and are not reserved (sleighsim.ops.names);
- labelled start states can be rescaled, sweeps list each eps once, pre-runs hold two spike-rule
  blocks (sleighsim.ops.plancheck);
- every sampling step is shorter than the horizon it samples;
- the datasets a scene reads (``inputs``) are scenes of the config;
- the records a scene holds in memory fit in this machine's memory (an estimate per kind,
  declared by each kind, sleighsim.scenes.memory), its jobs are few enough to plan (:data:`MAX_SCENE_JOBS`)
  and each finishes within
  :data:`MAX_JOB_CPU_DAYS` (the time units it integrates, sleighsim.ops.workmodel).

Each error (:class:`sleighsim.scenes.checks.ConfigError`) names the config key and the admissible
range. The kinds come from :data:`sleighsim.scenes.catalog.KINDS`, so this module imports the scene stack.
"""

from __future__ import annotations

import math
import os

from sleighsim.ops.config import REPO
from sleighsim.ops.names import check_scene_names
from sleighsim.ops.plancheck import (
    check_distinct_eps,
    check_labelled_states,
    check_magnitudes,
    check_pre_run,
    check_window_gain,
)
from sleighsim.ops.workmodel import chunk_work, work
from sleighsim.precision import Precision
from sleighsim.scenes.catalog import KINDS, scene_config
from sleighsim.scenes.checks import ConfigError, within
from sleighsim.scenes.workload import HORIZON_KEYS

#: Bytes held per sampled value: the samples, the energy check and the Dataset copy, in float64.
BYTES_PER_VALUE = 8 * 4
#: CPU seconds per time unit of the cheapest integration, the double flow at the reference state
#: (benchmarks/precision_cost.yaml: 1.2e-5 s); tangent, extended-precision and SciPy runs cost more.
SECONDS_PER_TIME_UNIT = 1.2e-5
#: A job whose integration alone would take longer than this (CPU days, one core) is refused.
MAX_JOB_CPU_DAYS = 30.0
#: Jobs one scene may add (chunks, realizations): Snakemake plans every job before the first starts.
MAX_SCENE_JOBS = 1000

#: Keys the schema types as integers (tests/test_bad_inputs.py checks this set against the schema).
INTEGER_KEYS = frozenset({
    "chunk_runtime_min", "directions", "jobs", "loop_knn", "loschmidt_n", "max_intervals", "max_rounds",
    "max_stored_pi2", "megno_samples", "min_intervals", "min_spikes", "n", "n_b", "n_blocks", "n_chunks", "n_eps",
    "n_field",
    "n_samples", "n_top", "order", "orders", "precision_chunks", "realizations", "repeats", "replicas", "runtime_min",
    "samples", "scipy_repeats", "seed", "spikes_after", "splits", "steady_blocks", "stream", "warmup"})


def _walk(node, path):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _walk(v, f"{path}.{k}" if path else str(k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _walk(v, f"{path}[{i}]")
    else:
        yield path, node


def _is_tolerance(path: str) -> bool:
    """Keys read as a tolerance: tol, *_tol, *tols, *rtol(s), and the rtol lists of the SciPy methods."""
    parts = [p.split("[")[0] for p in path.split(".")]
    leaf = parts[-1]
    return (leaf == "tol" or leaf.endswith(("_tol", "tols", "rtol", "rtols"))
            or any(p.startswith("scipy") for p in parts[:-1]))


def check_numbers(config: dict) -> None:
    """Every number finite; every tolerance in (0, 1); every integer field an int."""
    for path, value in _walk(config, ""):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        if not math.isfinite(value):
            raise ConfigError(f"{path} = {value} is not a finite number")
        if _is_tolerance(path) and not 0 < value < 1:
            raise ConfigError(f"{path} = {value} is a tolerance and must lie in (0, 1)")
        if isinstance(value, float) and path.split(".")[-1].split("[")[0] in INTEGER_KEYS:
            write = f"write {value:.0f}, " if value.is_integer() else ""
            raise ConfigError(f"{path} = {value} must be an integer ({write}without a decimal point)")


def _records(kind: str, cfg: dict) -> list[tuple[str, float, int]]:
    """(what, samples, variables) of the largest records a scene of ``kind`` holds in memory."""
    return [(s.what, s.samples, s.variables) for s in KINDS[kind].records(cfg)]


def check_sampling(name: str, kind: str, cfg: dict) -> None:
    """Every sampling step shorter than the horizon it samples (one sample would make no record)."""
    for s in KINDS[kind].records(cfg):
        if s.step and not 0 < s.step[1] < s.horizon[1]:
            raise ConfigError(f"scenes.{name}.{s.step[0]} = {s.step[1]} must lie in (0, {s.horizon[0]} = "
                              f"{s.horizon[1]:g}): a sampling step shorter than its horizon")


def machine_memory() -> float:
    """Physical memory of this machine in bytes."""
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


def check_memory(name: str, kind: str, cfg: dict, available: float) -> None:
    """Refuse a scene whose records would not fit in ``available`` bytes, saying how much they need."""
    for what, samples, variables in _records(kind, cfg):
        need = samples * variables * BYTES_PER_VALUE
        if need > available:
            raise ConfigError(f"scenes.{name}: {what} = {samples:.3g} samples of {variables} variables would need "
                              f"about {need / 2**30:.3g} GiB in memory; this machine has {available / 2**30:.3g} GiB")


def check_jobs(name: str, kind: str, cfg: dict) -> None:
    """Refuse a scene block that would add more than :data:`MAX_SCENE_JOBS` jobs (its chunks, its
    realizations)."""
    declared = KINDS[kind]
    counts = {"n_chunks": (cfg["n_chunks"], declared.chunk_count(cfg)) if declared.chunked else (1, 1),
              "realizations": (cfg.get("realizations", 1),) * 2 if declared.realizable else (1, 1)}
    for key, (n, jobs) in counts.items():
        if jobs > MAX_SCENE_JOBS:
            raise ConfigError(f"scenes.{name}.{key} = {n} would make {jobs} jobs; at most {MAX_SCENE_JOBS} "
                              "(Snakemake plans every job before the first starts)")


def _longest_horizon(cfg: dict) -> tuple[str, float]:
    """The (dotted key, value) of the longest horizon of a scene block (sleighsim.scenes.workload.HORIZON_KEYS)."""
    horizons = [(p, v) for p, v in _walk(cfg, "") if p.split(".")[-1].split("[")[0] in HORIZON_KEYS
                and p.split(".")[-1] != "max_rounds" and isinstance(v, (int, float))]
    return max(horizons, key=lambda h: h[1], default=("(no horizon)", 0.0))


def check_runtime(name: str, kind: str, cfg: dict) -> None:
    """Refuse a scene one of whose jobs would integrate longer than :data:`MAX_JOB_CPU_DAYS` at
    :data:`SECONDS_PER_TIME_UNIT` (time units integrated: sleighsim.ops.workmodel; a chunked kind's
    largest chunk). A lower estimate of the cost, so only runs that cannot finish are refused."""
    units = max(chunk_work(cfg)) if KINDS[kind].chunked else work(kind, cfg)
    days = units * SECONDS_PER_TIME_UNIT / 86400
    if days > MAX_JOB_CPU_DAYS:
        key, value = _longest_horizon(cfg)
        fix = (f"more chunks (n_chunks = {cfg.get('n_chunks', 1)}) or shorter horizons (the longest: {key} = {value:g})"
               if KINDS[kind].chunked else f"its longest horizon {key} = {value:g} must be shorter")
        raise ConfigError(f"scenes.{name}: about {units:.3g} time units integrated in one job would take at least "
                          f"{days:.3g} CPU days (limit {MAX_JOB_CPU_DAYS:g}); {fix}")


def _precisions(w, cfg):
    """A scene's precision ladder runs coarse to fine (by rounding), from double."""
    given = [Precision.parse(p) for p in cfg.get("precisions", [])]
    if given and (given[0] is not Precision.DOUBLE or sorted(given, key=lambda p: -p.rounding) != given):
        raise ConfigError(f"{w}.precisions = {[p.value for p in given]}: list them coarse to fine, starting with "
                          f"double (of {[p.value for p in Precision]})")


def _scene(name: str, cfg: dict, scenes: dict) -> None:
    """The checks of one scene block that need no estimate (after the memory check, which refuses
    counts too large for the cross-field checks to build)."""
    from sleighsim.model.params import Params

    w, kind = f"scenes.{name}", KINDS[cfg["kind"]]
    if "params" in cfg:
        try:
            Params.from_config(cfg["params"])
        except (TypeError, ValueError) as err:
            raise ConfigError(f"{w}.params: {err}") from None
    for role, source in cfg.get("inputs", {}).items():
        if source not in scenes or not KINDS[scenes[source]["kind"]].dataset:
            raise ConfigError(f"{w}.inputs.{role} = {source!r} is not a scene of the config that makes a dataset")
    if "vote_record" in cfg:
        from sleighsim.ops.powerrecord import problems

        bad = problems(REPO / cfg["vote_record"])
        if bad:
            raise ConfigError(f"{w}.vote_record = {cfg['vote_record']!r}: {'; '.join(bad)}")
    if "price_record" in cfg:
        from sleighsim.scenes.trigger_price import problems as price_problems

        bad = price_problems(REPO / cfg["price_record"])
        if bad:
            raise ConfigError(f"{w}.price_record = {cfg['price_record']!r}: {'; '.join(bad)}")
    check_jobs(name, kind.name, cfg)
    kind.checks(w, cfg)
    check_distinct_eps(w, cfg)
    check_pre_run(w, cfg)
    check_window_gain(w, cfg)
    _precisions(w, cfg)
    if kind.pre_run and "transient" in cfg and cfg.get(kind.pre_run, 0) > 0:
        t = cfg[kind.pre_run]
        within(f"{w}.transient.window", cfg["transient"]["window"], "0", 0, f"{kind.pre_run} / 2", t / 2)


def check(config: dict, available_memory: float | None = None) -> None:
    """Raise :class:`ConfigError` naming the first offending key."""
    check_scene_names(config)
    check_magnitudes(config)
    check_numbers(config)
    available = machine_memory() if available_memory is None else available_memory
    scenes = config["scenes"]
    for name, cfg in scenes.items():
        block = scene_config(config, name)
        check_memory(name, cfg["kind"], block, available)
        _scene(name, cfg, scenes)
        check_labelled_states(f"scenes.{name}", block)
        check_sampling(name, cfg["kind"], block)
        check_runtime(name, cfg["kind"], block)
