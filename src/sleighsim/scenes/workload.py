"""Work of a scene block: how much its jobs integrate, in time units, as a function of its config
block. :mod:`sleighsim.ops.estimate` scales measured CPU seconds by the ratio of these measures
between two configs; a kind with a model of its own declares it (:class:`sleighsim.scenes.kind.SceneKind`)."""

from __future__ import annotations

#: Keys of a scene block (at any depth) that are integration horizons in time units; a list (of
#: horizons, one per case) counts as its sum. T_round counts T_round x max_rounds (the cap on rounds).
HORIZON_KEYS = ("T", "t_end", "t_map", "duration", "check_duration", "t_max", "t_settle", "t_transient",
                "t_pre", "t_scale", "t_half", "horizons", "T_long", "t_long", "t_short", "T_eps", "T_scaling",
                "T_lyapunov", "T_round", "max_rounds", "T_gain")


def horizon_work(block: dict) -> float:
    """Work of a scene without a model of its own: the sum of its horizons (:data:`HORIZON_KEYS`, at
    any depth; T_round times max_rounds). A linear model: cost proportional to time integrated, with
    the number of cases (states, sweeps, lanes) and the step sizes taken as unchanged."""
    total = 0.0
    for key, value in block.items():
        if isinstance(value, dict):
            total += horizon_work(value)
        elif key == "T_round":
            total += float(value) * float(block.get("max_rounds", 1))
        elif key == "max_rounds":
            continue
        elif key in HORIZON_KEYS:
            if isinstance(value, (list, tuple)):
                total += sum(float(v) for v in value if isinstance(v, (int, float)))
            elif isinstance(value, (int, float)) and not isinstance(value, bool):
                total += float(value)
    return total
