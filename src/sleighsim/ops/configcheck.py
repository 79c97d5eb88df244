"""Checks the JSON schema cannot express, run at workflow start (before any job).

- every number is finite (YAML's .nan and .inf pass the schema's bounds);
- every tolerance (heyoka ``tol``, SciPy rtols, relative tolerances) lies in (0, 1) (the schema
  holds each to its arithmetic's machine epsilon);
- every integer field is written as an integer (JSON schema counts 3.0 as an integer);
- cross-field constraints of each kind (a window inside its span, increasing ranges, ...);
- every sampling step is shorter than the horizon it samples;
- the datasets a scene reads (``inputs``) are scenes of the config;
- the records a scene holds in memory fit in this machine's memory (an estimate per kind,
  :data:`RECORDS`), its jobs are few enough to plan (:data:`MAX_SCENE_JOBS`) and each finishes within
  :data:`MAX_JOB_CPU_DAYS` (the time units it integrates, sleighsim.ops.workmodel).

Each error names the config key and the admissible range. Only the parameter check imports the
model; nothing here imports the scene stack (the grid's row layout aside).
"""

from __future__ import annotations

import math
import os
from typing import NamedTuple

from sleighsim.ops.registry import KINDS

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
    "chunk_runtime_min", "loop_knn", "loschmidt_n", "max_rounds", "max_stored_pi2", "megno_samples", "min_spikes",
    "n_b", "n_blocks", "n_chunks", "n_eps", "n_field", "n_samples", "order", "orders", "realizations", "repeats",
    "replicas", "runtime_min", "scipy_repeats", "seed", "spikes_after", "splits", "steady_blocks", "warmup"})


class ConfigError(ValueError):
    """A config value is out of its admissible range."""


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


def _increasing(where: str, pair, strict: bool = True) -> None:
    lo, hi = pair
    if not (lo < hi if strict else lo <= hi):
        raise ConfigError(f"{where} = [{lo}, {hi}] must be increasing")


def _within(where: str, value, lo_name: str, lo, hi_name: str, hi) -> None:
    if not lo < value <= hi:
        raise ConfigError(f"{where} = {value} must lie in ({lo_name} = {lo}, {hi_name} = {hi}]")


def _trajectory(w, cfg):
    start, end = cfg.get("t_sample_start", 0.0), cfg["t_end"]
    if start >= end:
        raise ConfigError(f"{w}.t_sample_start = {start} must lie in [0, t_end = {end})")


def _psd(w, cfg):
    if cfg["check_duration"] > cfg["duration"]:
        raise ConfigError(f"{w}.check_duration = {cfg['check_duration']} must lie in (0, duration = {cfg['duration']}]")
    for key, span in (("segment", cfg["duration"]), ("check_segment", cfg["check_duration"])):
        if cfg["welch"][key] > span:
            raise ConfigError(f"{w}.welch.{key} = {cfg['welch'][key]} must lie in (0, {span}]")


def _hierarchy_terms(w, cfg):
    lo, hi = cfg["fit_window"]
    if not 0 <= lo < hi <= cfg["t_end"]:
        raise ConfigError(f"{w}.fit_window = [{lo}, {hi}] must be increasing within [0, t_end = {cfg['t_end']}]")


def _attractor_levels(w, cfg):
    for key in ("chunk", "compare_window"):
        if cfg[key] >= cfg["t_max"]:
            raise ConfigError(f"{w}.{key} = {cfg[key]} must lie in (0, t_max = {cfg['t_max']})")
    if cfg["smooth"] >= cfg["compare_window"]:
        raise ConfigError(f"{w}.smooth = {cfg['smooth']} must lie in (0, compare_window = {cfg['compare_window']})")


def _lyapunov_grid(w, cfg):
    _increasing(f"{w}.eps_range", cfg["eps_range"], strict=False)
    _increasing(f"{w}.b_range", cfg["b_range"], strict=False)
    if cfg["n_chunks"] > cfg["n_eps"]:
        raise ConfigError(f"{w}.n_chunks = {cfg['n_chunks']} must lie in [1, n_eps = {cfg['n_eps']}] "
                          "(a chunk holds whole eps rows)")
    lo, hi = cfg["eps_range"]
    if not lo <= cfg["reference_eps"] <= hi:
        raise ConfigError(f"{w}.reference_eps = {cfg['reference_eps']} must lie in eps_range [{lo}, {hi}]")
    from sleighsim.scenes.grid import elsewhere

    try:
        elsewhere(cfg)
    except ValueError as bad:
        raise ConfigError(f"{w}.{bad}") from None


def _formal_exponents(w, cfg):
    both = sorted(set(cfg["eps"]) & set(cfg.get("elsewhere", {}).get("eps", [])))
    if both:
        raise ConfigError(f"{w}.elsewhere.eps: {both} also in {w}.eps (a row is computed here or elsewhere, not both)")


def _basins(w, cfg):
    if cfg["n_chunks"] > cfg["n_samples"]:
        raise ConfigError(f"{w}.n_chunks = {cfg['n_chunks']} must lie in [1, n_samples = {cfg['n_samples']}]")


def _sleigh0(w, cfg):
    for key in ("u_range", "Omega_range"):
        _increasing(f"{w}.portrait.{key}", cfg["portrait"][key])


def _blocks(w, cfg, horizon: str):
    """Benettin's blocks: ``horizon`` holds n_blocks renormalisation intervals tau at least."""
    need = cfg["n_blocks"] * cfg["tau"]
    if cfg[horizon] < need:
        raise ConfigError(f"{w}.{horizon} = {cfg[horizon]} must be at least n_blocks x tau = {need:g} "
                          "(one renormalisation per block)")


def _lyapunov_protocol(w, cfg):
    _blocks(w, cfg, "T")
    _blocks(w, dict(cfg, tau=max(cfg["tau"], cfg["paper_tau"])), "tau_check")


def _multiple(where: str, value, of_name: str, of, least: int = 1) -> None:
    """``value`` a whole multiple (at least ``least``) of ``of``."""
    n = value / of
    if not (abs(n - round(n)) < 1e-9 * max(1.0, n) and round(n) >= least):
        raise ConfigError(f"{where} = {value} must be a multiple (at least {least}) of {of_name} = {of}")


def _drift_windows(w, cfg):
    _multiple(f"{w}.window", cfg["window"], "tau", cfg["tau"], least=2)
    _multiple(f"{w}.T", cfg["T"], "window", cfg["window"])


def _precision_ladder(w, cfg):
    _multiple(f"{w}.separation_every", cfg["separation_every"], "dt", cfg["dt"])


CROSS_FIELD = {"trajectory": _trajectory, "psd": _psd, "hierarchy_terms": _hierarchy_terms,
               "attractor_levels": _attractor_levels, "lyapunov_grid": _lyapunov_grid, "sleigh0": _sleigh0,
               "basins": _basins, "formal_exponents": _formal_exponents, "lyapunov_protocol": _lyapunov_protocol,
               "lyapunov_energy": lambda w, cfg: _blocks(w, cfg, "T"), "drift_windows": _drift_windows,
               "precision_ladder": _precision_ladder}

#: Kinds with a checked pre-run, and the key of its length: the settling window must fit twice.
PRE_RUN = {"poincare": "t_settle", "psd": "t_settle", "lyapunov_spectrum": "t_transient", "lyapunov_grid": "t_pre",
           "lyapunov_energy": "t_transient", "trajectory": "t_sample_start", "chaos_verdict": "t_transient",
           "formal_exponents": "t_transient", "basins": "t_round"}


class Span(NamedTuple):
    """A record a scene holds: ``horizon`` sampled every ``step`` (each a (key, value) pair; no step:
    ``horizon`` is a count of samples), ``variables`` per sample, ``lanes`` such records at once."""

    horizon: tuple[str, float]
    step: tuple[str, float] | None
    variables: int = 4
    lanes: tuple[str, float] = ("", 1)

    @property
    def what(self) -> str:
        out = self.horizon[0] + (f" / {self.step[0]}" if self.step else "")
        return out + (f" x {self.lanes[0]}" if self.lanes[0] else "")

    @property
    def samples(self) -> float:
        return self.horizon[1] / (self.step[1] if self.step else 1) * self.lanes[1]


def _key(cfg: dict, key):
    """(dotted key, its value) in a scene block; a (name, value) pair or None as it is."""
    if not isinstance(key, str):
        return key
    value = cfg
    for k in key.split("."):
        value = value[k]
    return key, value


def _span(cfg, horizon, step, variables=4, lanes=("", 1)) -> Span:
    """A :class:`Span` from dotted keys of ``cfg`` (or (name, value) pairs)."""
    return Span(_key(cfg, horizon), _key(cfg, step), variables, lanes)


def _count(cfg, key: str) -> tuple[str, int]:
    """("len(key)", the length of the list or mapping at ``key``): lanes held at once."""
    return f"len({key})", len(_key(cfg, key)[1])


def _pre_run(cfg, horizon: str) -> list[Span]:
    """The pre-run record: ``horizon`` sampled every transient.dt (when the block has a pre-run)."""
    dt = cfg.get("transient", {}).get("dt")
    return [_span(cfg, horizon, "transient.dt")] if dt is not None and cfg.get(horizon, 0) > 0 else []


def _benettin(cfg, variables: int) -> list[Span]:
    """The replicas' renormalisation records: T_round / tau per round, one lane per replica and round."""
    return [_span(cfg, "T_round", "tau", variables, ("replicas x max_rounds", cfg["replicas"] * cfg["max_rounds"]))]


def _hierarchy(cfg, prefix=""):
    return [_span(cfg, f"{prefix}t_end", f"{prefix}dt", 20)]


def _series(cfg, prefix, order):
    return [_span(cfg, f"{prefix}t_end", f"{prefix}dt", 4 * (order + 2))]


#: The records each kind holds (its memory and sampling estimate): kind -> spans of a scene block.
RECORDS = {
    "schematic": lambda c: [],  # drawn from its block
    "attractor_scaling": lambda c: [],  # reads two poincare datasets, integrates nothing
    "sleigh0": lambda c: [_span(c, "portrait.n_samples", None, 4, _count(c, "portrait.states")),
                          _span(c, ("portrait.n_field^2", c["portrait"]["n_field"] ** 2), None, 4),
                          _span(c, "path.t_end", "path.dt", 7)],
    "trajectory": lambda c: [_span(c, ("(t_end - t_sample_start)", c["t_end"] - c.get("t_sample_start", 0.0)), "dt", 7),
                             *_pre_run(c, "t_sample_start")],
    "attractor_levels": lambda c: [_span(c, "t_max", "dt"), _span(c, "long_check.t_end", "long_check.dt"),
                                   _span(c, "compare_window", "compare_dt")],
    "transient_scaling": lambda c: [_span(c, ("t_scale / min(eps)^2", c["t_scale"] / min(c["eps"]) ** 2), "dt")],
    "series_vs_exact": lambda c: [*_series(c, "", c["order"]),
                                  *_series(c, "convergence.", max(c["convergence"]["orders"]))],
    "hierarchy_terms": _hierarchy,
    "hierarchy_audit": _hierarchy,
    "poincare": lambda c: [*_pre_run(c, "t_settle"), _span(c, "attractor_span", "attractor_dt")],
    "psd": lambda c: [*_pre_run(c, "t_settle"), _span(c, "duration", "dt"), _span(c, "check_duration", "check_dt")],
    "lyapunov_spectrum": lambda c: [*_pre_run(c, "t_transient"), *_benettin(c, 8)],
    "formal_exponents": lambda c: [*_pre_run(c, "t_transient"), *_benettin(c, 8)],
    "chaos_verdict": lambda c: [*_pre_run(c, "t_transient"), *_benettin(c, 8),
                                _span(c, "frequency.T", "frequency.dt", 4 * max(c["frequency"]["splits"])),
                                _span(c, "megno_samples", None, 2)],
    "lyapunov_grid": lambda c: [*_pre_run(c, "t_pre"), *_benettin(c, 5),
                                _span(c, ("n_eps x n_b", c["n_eps"] * c["n_b"]), None, 20)],
    "lyapunov_protocol": lambda c: [_span(c, "T", "tau"), _span(c, "tau_check", "paper_tau")],
    "lyapunov_energy": lambda c: [*_pre_run(c, "t_transient"), _span(c, "T", "tau", 5, _count(c, "labels"))],
    "small_eps_cost": lambda c: [_span(c, ("max(horizons)", max(c["horizons"])), "dt")],
    "drift_windows": lambda c: [*_pre_run(c, "t_transient"), _span(c, "window", "tau", 2)],
    "precision_ladder": lambda c: [*_pre_run(c, "t_transient"),
                                   _span(c, "T", "dt", 4, _count(c, "precisions"))],
    "trigger_law": lambda c: [_span(c, "t_end", "dt")],
    "basins": lambda c: [*_pre_run(c, "t_round"), _span(c, "T_measure", "dt_measure"), _span(c, "n_samples", None, 8)],
    "printed_model": lambda c: [_span(c, "t_end", "dt", 8), _span(c, "spikes.t_end", "spikes.dt")],
    "k2_sweep": lambda c: [_span(c, "t_end", "dt"), *_hierarchy(c, "hierarchy."),
                           *_series(c, "series.", c["series"]["order"]), _span(c, "psd.t_settle", "psd.transient.dt"),
                           _span(c, "psd.duration", "psd.dt")],
    "integration_error": lambda c: [_span(c, "t_end", "dt"), *_series(c, "series.", c["series"]["order"]),
                                    _span(c, "lyapunov.T", "lyapunov.tau")],
    "hardcases": lambda c: [_span(c, "T_long", ("T_long / 100", c["T_long"] / 100))],
    "bench": lambda c: [_span(c, "t_long", "dt_long")],
}


def _records(kind: str, cfg: dict) -> list[tuple[str, float, int]]:
    """(what, samples, variables) of the largest records a scene of ``kind`` holds in memory."""
    return [(s.what, s.samples, s.variables) for s in RECORDS[kind](cfg)]


def check_sampling(name: str, kind: str, cfg: dict) -> None:
    """Every sampling step shorter than the horizon it samples (one sample would make no record)."""
    for s in RECORDS[kind](cfg):
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
    counts = {"n_chunks": cfg.get("n_chunks", 1) if KINDS[kind].chunked else 1,
              "realizations": cfg.get("realizations", 1) if KINDS[kind].realizable else 1}
    per_chunk = len(cfg["states"]) if kind == "chaos_verdict" else 1  # a verdict's chunk is one state
    for key, n in counts.items():
        jobs = n * (per_chunk if key == "n_chunks" else 1)
        if jobs > MAX_SCENE_JOBS:
            raise ConfigError(f"scenes.{name}.{key} = {n} would make {jobs} jobs; at most {MAX_SCENE_JOBS} "
                              "(Snakemake plans every job before the first starts)")


def _longest_horizon(cfg: dict) -> tuple[str, float]:
    """The (dotted key, value) of the longest horizon of a scene block (sleighsim.ops.workmodel.HORIZON_KEYS)."""
    from sleighsim.ops.workmodel import HORIZON_KEYS

    horizons = [(p, v) for p, v in _walk(cfg, "") if p.split(".")[-1].split("[")[0] in HORIZON_KEYS
                and p.split(".")[-1] != "max_rounds" and isinstance(v, (int, float))]
    return max(horizons, key=lambda h: h[1], default=("(no horizon)", 0.0))


def check_runtime(name: str, kind: str, cfg: dict) -> None:
    """Refuse a scene one of whose jobs would integrate longer than :data:`MAX_JOB_CPU_DAYS` at
    :data:`SECONDS_PER_TIME_UNIT` (time units integrated: sleighsim.ops.workmodel; a chunked kind's
    largest chunk). A lower estimate of the cost, so only runs that cannot finish are refused."""
    from sleighsim.ops.workmodel import chunk_work, work

    units = max(chunk_work(cfg)) if KINDS[kind].chunked else work(kind, cfg)
    days = units * SECONDS_PER_TIME_UNIT / 86400
    if days > MAX_JOB_CPU_DAYS:
        key, value = _longest_horizon(cfg)
        fix = (f"more chunks (n_chunks = {cfg.get('n_chunks', 1)}) or shorter horizons (the longest: {key} = {value:g})"
               if KINDS[kind].chunked else f"its longest horizon {key} = {value:g} must be shorter")
        raise ConfigError(f"scenes.{name}: about {units:.3g} time units integrated in one job would take at least "
                          f"{days:.3g} CPU days (limit {MAX_JOB_CPU_DAYS:g}); {fix}")


def _precisions(w, cfg):
    """A scene's precision ladder runs coarse to fine, from double."""
    order = ["double", "long double", "quad"]
    given = cfg.get("precisions", [])
    if given and (given[0] != "double" or sorted(given, key=order.index) != list(given)):
        raise ConfigError(f"{w}.precisions = {given}: list them coarse to fine, starting with double "
                          f"(of {order})")


def _scene(name: str, cfg: dict, scenes: dict) -> None:
    """The checks of one scene block that need no estimate (after the memory check, which refuses
    counts too large for the cross-field checks to build)."""
    from sleighsim.model.params import Params

    w, kind = f"scenes.{name}", cfg["kind"]
    if "params" in cfg:
        try:
            Params.from_config(cfg["params"])
        except (TypeError, ValueError) as err:
            raise ConfigError(f"{w}.params: {err}") from None
    for role, source in cfg.get("inputs", {}).items():
        if source not in scenes or not KINDS[scenes[source]["kind"]].dataset:
            raise ConfigError(f"{w}.inputs.{role} = {source!r} is not a scene of the config that makes a dataset")
    check_jobs(name, kind, cfg)
    if kind in CROSS_FIELD:
        CROSS_FIELD[kind](w, cfg)
    _precisions(w, cfg)
    if kind in PRE_RUN and "transient" in cfg and cfg.get(PRE_RUN[kind], 0) > 0:
        t = cfg[PRE_RUN[kind]]
        _within(f"{w}.transient.window", cfg["transient"]["window"], "0", 0, f"{PRE_RUN[kind]} / 2", t / 2)


def check(config: dict, available_memory: float | None = None) -> None:
    """Raise :class:`ConfigError` naming the first offending key."""
    from sleighsim.ops.registry import scene_config

    check_numbers(config)
    available = machine_memory() if available_memory is None else available_memory
    scenes = config["scenes"]
    for name, cfg in scenes.items():
        block = scene_config(config, name)
        check_memory(name, cfg["kind"], block, available)
        _scene(name, cfg, scenes)
        check_sampling(name, cfg["kind"], block)
        check_runtime(name, cfg["kind"], block)
