"""Checks the JSON schema cannot express, run at workflow start (before any job).

- every number is finite (YAML's .nan and .inf pass the schema's bounds);
- every tolerance (heyoka ``tol``, SciPy rtols, relative tolerances) lies in (0, 1);
- cross-field constraints of each kind (a window inside its span, increasing ranges, ...);
- the datasets a scene reads (``inputs``) are scenes of the config;
- the records a scene holds in memory fit in this machine's memory (an estimate per kind).

Each error names the config key. Only the parameter check imports the model; nothing here
imports the scene stack.
"""

from __future__ import annotations

import math
import os

from .registry import KINDS

#: Bytes held per sampled value: the samples, the energy check and the Dataset copy, in float64.
BYTES_PER_VALUE = 8 * 4


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
    """Every number finite; every tolerance in (0, 1)."""
    for path, value in _walk(config, ""):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        if not math.isfinite(value):
            raise ConfigError(f"{path} = {value} is not a finite number")
        if _is_tolerance(path) and not 0 < value < 1:
            raise ConfigError(f"{path} = {value} is a tolerance and must lie in (0, 1)")


def _increasing(where: str, pair, strict: bool = True) -> None:
    lo, hi = pair
    if not (lo < hi if strict else lo <= hi):
        raise ConfigError(f"{where} = [{lo}, {hi}] must be increasing")


def _within(where: str, value, lo_name: str, lo, hi_name: str, hi) -> None:
    if not lo < value <= hi:
        raise ConfigError(f"{where} = {value} must lie in ({lo_name} = {lo}, {hi_name} = {hi}]")


def _trajectory(w, cfg):
    start, end = cfg.get("t_sample_start", 0.0), cfg["t_end"]
    if start > end:
        raise ConfigError(f"{w}.t_sample_start = {start} must lie in [0, t_end = {end}]")
    if end > start and cfg["dt"] > end - start:
        raise ConfigError(f"{w}.dt = {cfg['dt']} must lie in (0, t_end - t_sample_start = {end - start}]")


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
    from .scenes.grid import elsewhere

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
    if cfg["dt_measure"] >= cfg["T_measure"]:
        raise ConfigError(f"{w}.dt_measure = {cfg['dt_measure']} must lie in (0, T_measure = {cfg['T_measure']})")


def _sleigh0(w, cfg):
    for key in ("u_range", "Omega_range"):
        _increasing(f"{w}.portrait.{key}", cfg["portrait"][key])


CROSS_FIELD = {"trajectory": _trajectory, "psd": _psd, "hierarchy_terms": _hierarchy_terms,
               "attractor_levels": _attractor_levels, "lyapunov_grid": _lyapunov_grid, "sleigh0": _sleigh0,
               "basins": _basins, "formal_exponents": _formal_exponents}

#: Kinds with a checked pre-run, and the key of its length: the settling window must fit twice.
PRE_RUN = {"poincare": "t_settle", "psd": "t_settle", "lyapunov_spectrum": "t_transient", "lyapunov_grid": "t_pre",
           "lyapunov_energy": "t_transient", "trajectory": "t_sample_start", "chaos_verdict": "t_transient",
           "formal_exponents": "t_transient", "basins": "t_round"}


def _records(kind: str, cfg: dict) -> list[tuple[str, float, int]]:
    """(what, samples, variables) of the largest records a scene of ``kind`` holds in memory."""
    def span(t, dt, what, n=4):
        return (what, t / dt, n)

    tc = cfg.get("transient", {})
    if kind == "sleigh0":
        pc, path = cfg["portrait"], cfg["path"]
        return [("portrait.n_samples", pc["n_samples"] * len(pc["states"]), 4),
                span(path["t_end"], path["dt"], "path.t_end / path.dt", 7)]
    if kind == "trajectory":
        return [span(cfg["t_end"] - cfg.get("t_sample_start", 0.0), cfg["dt"], "(t_end - t_sample_start) / dt", 7)]
    if kind == "attractor_levels":
        return [span(cfg["t_max"], cfg["dt"], "t_max / dt"),
                span(cfg["long_check"]["t_end"], cfg["long_check"]["dt"], "long_check.t_end / long_check.dt")]
    if kind == "transient_scaling":
        return [span(cfg["t_scale"] / min(cfg["eps"]) ** 2, cfg["dt"], "t_scale / min(eps)^2 / dt")]
    if kind == "series_vs_exact":
        return [span(cfg["t_end"], cfg["dt"], "t_end / dt", 4 * (cfg["order"] + 2))]
    if kind in ("hierarchy_terms", "hierarchy_audit"):
        return [span(cfg["t_end"], cfg["dt"], "t_end / dt", 20)]
    if kind == "poincare":
        return [span(cfg["t_settle"], tc["dt"], "t_settle / transient.dt"),
                span(cfg["attractor_span"], cfg["attractor_dt"], "attractor_span / attractor_dt")]
    if kind == "psd":
        return [span(cfg["t_settle"], tc["dt"], "t_settle / transient.dt"), span(cfg["duration"], cfg["dt"], "duration / dt"),
                span(cfg["check_duration"], cfg["check_dt"], "check_duration / check_dt")]
    if kind in ("lyapunov_spectrum", "chaos_verdict", "formal_exponents"):
        steps = cfg["T_round"] * cfg["max_rounds"] / cfg["tau"] * cfg["replicas"]
        out = [span(cfg["t_transient"], tc["dt"], "t_transient / transient.dt"),
               ("T_round x max_rounds / tau x replicas", steps, 8)]
        if kind == "chaos_verdict":
            from .frequencies import MIN_SAMPLES

            fc = cfg["frequency"]
            out.append(span(fc["T"], fc["dt"], "frequency.T / frequency.dt", MIN_SAMPLES * max(fc["splits"])))
        return out
    if kind == "lyapunov_grid":
        steps = cfg["T_round"] * cfg["max_rounds"] / cfg["tau"] * cfg["replicas"]
        return [span(cfg["t_pre"], tc["dt"], "t_pre / transient.dt"),
                ("T_round x max_rounds / tau x replicas", steps, 5)]
    if kind == "basins":
        return [span(cfg["t_round"], tc["dt"], "t_round / transient.dt"),
                span(cfg["T_measure"], cfg["dt_measure"], "T_measure / dt_measure")]
    if kind == "small_eps_cost":
        return [span(max(cfg["horizons"]), cfg["dt"], "max(horizons) / dt")]
    if kind == "printed_model":
        return [span(cfg["t_end"], cfg["dt"], "t_end / dt", 8)]
    if kind == "bench":
        return [span(cfg["t_long"], cfg["dt_long"], "t_long / dt_long")]
    return []


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


def _precisions(w, cfg):
    """A scene's precision ladder runs coarse to fine, from double."""
    order = ["double", "long double", "quad"]
    given = cfg.get("precisions", [])
    if given and (given[0] != "double" or sorted(given, key=order.index) != list(given)):
        raise ConfigError(f"{w}.precisions = {given}: list them coarse to fine, starting with double "
                          f"(of {order})")


def check(config: dict, available_memory: float | None = None) -> None:
    """Raise :class:`ConfigError` naming the first offending key."""
    from .params import Params

    check_numbers(config)
    available = machine_memory() if available_memory is None else available_memory
    scenes = config["scenes"]
    for name, cfg in scenes.items():
        w = f"scenes.{name}"
        kind = cfg["kind"]
        if "params" in cfg:
            try:
                Params.from_config(cfg["params"])
            except ValueError as err:
                raise ConfigError(f"{w}.params: {err}") from None
        for role, source in cfg.get("inputs", {}).items():
            if source not in scenes or not KINDS[scenes[source]["kind"]].dataset:
                raise ConfigError(f"{w}.inputs.{role} = {source!r} is not a scene of the config that makes a dataset")
        if kind in CROSS_FIELD:
            CROSS_FIELD[kind](w, cfg)
        _precisions(w, cfg)
        if kind in PRE_RUN and "transient" in cfg and cfg.get(PRE_RUN[kind], 0) > 0:
            t = cfg[PRE_RUN[kind]]
            _within(f"{w}.transient.window", cfg["transient"]["window"], "0", 0, f"{PRE_RUN[kind]} / 2", t / 2)
        check_memory(name, kind, cfg, available)
