"""The records a scene holds in memory: :class:`Span` (a horizon sampled at a step, in lanes) and
the builders the kinds' memory estimates share. Each kind declares its records
(:attr:`sleighsim.scenes.kind.SceneKind.records`); :mod:`sleighsim.ops.configcheck` refuses a block
whose records would not fit in memory or whose sampling step is not shorter than its horizon."""

from __future__ import annotations

from typing import NamedTuple


class Span(NamedTuple):
    """A record a scene holds: ``horizon`` sampled every ``step`` (each a (key, value) pair; no step:
    ``horizon`` is a count of samples), ``variables`` per sample, ``lanes`` such records at once."""

    horizon: tuple[str, float]
    step: tuple[str, float] | None
    variables: int = 4
    lanes: tuple[str, float] = ("", 1)

    @property
    def what(self) -> str:
        """The record's name: its horizon key, "/ step key" and "x lanes key" when there are such."""
        out = self.horizon[0] + (f" / {self.step[0]}" if self.step else "")
        return out + (f" x {self.lanes[0]}" if self.lanes[0] else "")

    @property
    def samples(self) -> float:
        """The number of samples held: horizon / step (or horizon itself without a step) times lanes."""
        return self.horizon[1] / (self.step[1] if self.step else 1) * self.lanes[1]


def _key(cfg: dict, key):
    """(dotted key, its value) in a scene block; a (name, value) pair or None as it is."""
    if not isinstance(key, str):
        return key
    value = cfg
    for k in key.split("."):
        value = value[k]
    return key, value


def span(cfg, horizon, step, variables=4, lanes=("", 1)) -> Span:
    """A :class:`Span` from dotted keys of ``cfg`` (or (name, value) pairs)."""
    return Span(_key(cfg, horizon), _key(cfg, step), variables, lanes)


def count(cfg, key: str) -> tuple[str, int]:
    """("len(key)", the length of the list or mapping at ``key``): lanes held at once."""
    return f"len({key})", len(_key(cfg, key)[1])


def pre_run(cfg, horizon: str) -> list[Span]:
    """The pre-run record: ``horizon`` sampled every transient.dt (when the block has a pre-run)."""
    dt = cfg.get("transient", {}).get("dt")
    return [span(cfg, horizon, "transient.dt")] if dt is not None and cfg.get(horizon, 0) > 0 else []


def benettin(cfg, variables: int) -> list[Span]:
    """The replicas' renormalisation records: T_round / tau per round, one lane per replica and round."""
    return [span(cfg, "T_round", "tau", variables, ("replicas x max_rounds", cfg["replicas"] * cfg["max_rounds"]))]


def hierarchy(cfg, prefix=""):
    """The perturbation hierarchy's terms: t_end / dt samples of 20 variables."""
    return [span(cfg, f"{prefix}t_end", f"{prefix}dt", 20)]


def series(cfg, prefix, order):
    """The perturbation series to ``order``: t_end / dt samples of 4 (order + 2) variables."""
    return [span(cfg, f"{prefix}t_end", f"{prefix}dt", 4 * (order + 2))]
