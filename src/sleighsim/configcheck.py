"""Checks the JSON schema cannot express, run at workflow start (before any job).

Each error names the config key and the admissible range."""

from __future__ import annotations

from . import model
from .scenes import SCENES


class ConfigError(ValueError):
    """A config value is out of its admissible range."""


def check(config: dict) -> None:
    """Raise :class:`ConfigError` naming the first offending key."""
    for name, cfg in config["scenes"].items():
        if "params" in cfg:
            try:
                model.Params.from_config(cfg["params"])
            except ValueError as err:
                raise ConfigError(f"scenes.{name}.params: {err}") from None
        if SCENES.get(name) is SCENES["fig3"]:  # trajectory scenes
            start, end = cfg.get("t_sample_start", 0.0), cfg["t_end"]
            if start > end:
                raise ConfigError(f"scenes.{name}.t_sample_start = {start} must lie in [0, t_end = {end}]")
            if cfg["dt"] > end - start and end > start:
                raise ConfigError(f"scenes.{name}.dt = {cfg['dt']} must lie in (0, t_end - t_sample_start = {end - start}]")
        if "spectrum" in cfg:
            if cfg["check_duration"] > cfg["duration"]:
                raise ConfigError(f"scenes.{name}.check_duration = {cfg['check_duration']} must lie in "
                                  f"(0, duration = {cfg['duration']}]")
            for key, span in (("segment", cfg["duration"]), ("check_segment", cfg["check_duration"])):
                if cfg["spectrum"][key] > span:
                    raise ConfigError(f"scenes.{name}.spectrum.{key} = {cfg['spectrum'][key]} must lie in (0, {span}]")
    scenes = config["scenes"]
    lo, hi = scenes["fig6"]["fit_window"]
    if not 0 <= lo < hi <= scenes["fig6"]["t_end"]:
        raise ConfigError(f"scenes.fig6.fit_window = [{lo}, {hi}] must be increasing within [0, t_end = "
                          f"{scenes['fig6']['t_end']}]")
    f4 = scenes["fig4"]
    for key in ("chunk", "compare_window"):
        if f4[key] >= f4["t_max"]:
            raise ConfigError(f"scenes.fig4.{key} = {f4[key]} must lie in (0, t_max = {f4['t_max']})")
    if f4["smooth"] >= f4["compare_window"]:
        raise ConfigError(f"scenes.fig4.smooth = {f4['smooth']} must lie in (0, compare_window = {f4['compare_window']})")
    grid = config["lyap_grid"]
    for key in ("eps_range", "b_range"):
        lo, hi = grid[key]
        if not lo <= hi:
            raise ConfigError(f"lyap_grid.{key} = [{lo}, {hi}] must be increasing")
    if grid["n_chunks"] > grid["n_eps"]:
        raise ConfigError(f"lyap_grid.n_chunks = {grid['n_chunks']} must lie in [1, n_eps = {grid['n_eps']}] "
                          "(a chunk holds whole eps rows)")
    lo, hi = grid["eps_range"]
    if not lo <= grid["reference_eps"] <= hi:
        raise ConfigError(f"lyap_grid.reference_eps = {grid['reference_eps']} must lie in eps_range [{lo}, {hi}]")
    portrait = config["scenes"]["fig2"]["portrait"]
    for key in ("u_range", "Omega_range"):
        lo, hi = portrait[key]
        if not lo < hi:
            raise ConfigError(f"scenes.fig2.portrait.{key} = [{lo}, {hi}] must be increasing")
