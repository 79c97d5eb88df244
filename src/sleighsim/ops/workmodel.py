"""Work models of scene blocks: how much a scene's jobs integrate, in time units, as a function
of its config block. :mod:`sleighsim.ops.estimate` scales measured CPU seconds by the ratio of
these measures between two configs."""

from __future__ import annotations

#: Keys of a scene block (at any depth) that are integration horizons in time units; a list (of
#: horizons, one per case) counts as its sum. T_round counts T_round x max_rounds (the cap on rounds).
HORIZON_KEYS = ("T", "t_end", "t_map", "duration", "check_duration", "t_max", "t_settle", "t_transient",
                "t_pre", "t_scale", "t_half", "horizons", "T_long", "t_long", "t_short", "T_eps", "T_scaling",
                "T_lyapunov", "T_round", "max_rounds", "T_gain")

#: Keys the lyapunov_grid model reads (everything else of such a block is outside the model).
GRID_KEYS = ("eps_range", "n_eps", "n_chunks", "reference_eps", "t_pre", "t_pre_min", "replicas",
             "replica_spacing", "t_align", "T_round", "max_rounds", "poincare_span", "b_check", "eps")


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


def grid_rows(cfg: dict) -> list[tuple[float, float]]:
    """(eps, work) of every row of a lyapunov_grid block, following sleighsim.scenes.grid.row, in time
    units integrated at slow time s = reference_eps / eps:

    - pre-run: max(t_pre_min, t_pre s^2) (one trajectory);
    - replica sampling: replicas x replica_spacing x s (one trajectory through the replicas' states);
    - tangent batch: (t_align + T_round x max_rounds) x s, counted once: the replicas are the SIMD
      lanes of one batch (the brief's n_b / batch_size), and max_rounds is the cap (rows that converge
      earlier cost less; target_rel is not modelled);
    - Poincare crossings: poincare_span x s;
    - the reference row also runs one round per b_check value: len(b_check) x (t_align + T_round) x s.

    n_b costs nothing: b is an exact symmetry and every row is computed once at b = 1; a row left to
    another config (``elsewhere``) costs nothing here."""
    from sleighsim.scenes.grid import axes, elsewhere, pre_run, reference_row, slow_time

    eps_all, _ = axes(cfg)
    ref, away = reference_row(cfg), elsewhere(cfg)
    rows = []
    for i, eps in enumerate(eps_all):
        if away[i]:  # left to another config: no work here
            rows.append((float(eps), 0.0))
            continue
        s = slow_time(cfg, eps)
        w = pre_run(cfg, eps) + cfg["replicas"] * cfg["replica_spacing"] * s
        w += (cfg["t_align"] + cfg["T_round"] * cfg["max_rounds"]) * s + cfg.get("poincare_span", 0.0) * s
        if i == ref:
            w += len(cfg.get("b_check") or ()) * (cfg["t_align"] + cfg["T_round"]) * s
        rows.append((float(eps), float(w)))
    return rows


def chunk_work(cfg: dict) -> list[float]:
    """Work of each chunk job of a chunked block: a lyapunov_grid's chunk k computes rows k,
    k + n_chunks, ...; a chaos_verdict's chunk is one state of one realization of the scene (a block without
    n_chunks, measured before the verdict ran realizations, is one); any other kind's chunks share
    its horizons equally."""
    n = cfg.get("n_chunks", 1) if cfg["kind"] == "chaos_verdict" else cfg["n_chunks"]
    if cfg["kind"] == "lyapunov_grid":
        rows = grid_rows(cfg)
        return [sum(w for _, w in rows[k::n]) for k in range(n)]
    if cfg["kind"] == "chaos_verdict":
        states = len(cfg["states"])
        return [horizon_work(cfg) / states] * (n * states)
    return [horizon_work(cfg) / n] * n


def work(kind: str, cfg: dict) -> float:
    """The work measure of a scene block (as :func:`sleighsim.ops.registry.scene_config` gives it)."""
    if kind == "lyapunov_grid":
        return sum(w for _, w in grid_rows(cfg))
    if kind == "chaos_verdict":
        return sum(chunk_work(cfg))
    return horizon_work(cfg)


def is_modelled(kind: str, key: str) -> bool:
    """Whether the work model of ``kind`` reads the (dotted) config key."""
    leaf = key.split(".")[-1]
    if kind == "lyapunov_grid":
        return leaf in GRID_KEYS
    return leaf in HORIZON_KEYS or (kind == "chaos_verdict" and leaf == "n_chunks")
