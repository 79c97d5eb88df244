"""Cross-field constraints of scene blocks that the JSON schema cannot express, shared by the kinds'
declared checks (:attr:`sleighsim.scenes.kind.SceneKind.checks`). Each error names the config key and
the admissible range."""

from __future__ import annotations

#: The block length (time units) of the spike rule (sleighsim.engine.transient.spike_times' default
#: ``block``): a record it judges holds two blocks at least.
SPIKE_BLOCK = 50.0


class ConfigError(ValueError):
    """A config value is out of its admissible range."""


def increasing(where: str, pair, strict: bool = True) -> None:
    """The pair [lo, hi] at ``where`` increasing (non-decreasing unless ``strict``)."""
    lo, hi = pair
    if not (lo < hi if strict else lo <= hi):
        raise ConfigError(f"{where} = [{lo}, {hi}] must be increasing")


def within(where: str, value, lo_name: str, lo, hi_name: str, hi) -> None:
    """``value`` in (lo, hi]."""
    if not lo < value <= hi:
        raise ConfigError(f"{where} = {value} must lie in ({lo_name} = {lo}, {hi_name} = {hi}]")


def multiple(where: str, value, of_name: str, of, least: int = 1) -> None:
    """``value`` a whole multiple (at least ``least``) of ``of``."""
    n = value / of
    if not (abs(n - round(n)) < 1e-9 * max(1.0, n) and round(n) >= least):
        raise ConfigError(f"{where} = {value} must be a multiple (at least {least}) of {of_name} = {of}")


def blocks(w, cfg, horizon: str):
    """Benettin's blocks: ``horizon`` holds n_blocks renormalisation intervals tau at least."""
    need = cfg["n_blocks"] * cfg["tau"]
    if cfg[horizon] < need:
        raise ConfigError(f"{w}.{horizon} = {cfg[horizon]} must be at least n_blocks x tau = {need:g} "
                          "(one renormalisation per block)")
