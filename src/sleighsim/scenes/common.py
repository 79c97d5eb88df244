"""Helpers shared by the scene modules: reading config blocks into engine arguments, and ragged
records into arrays."""

from __future__ import annotations

import numpy as np

from ..integrators import EPSILON, precision_flags
from ..params import Params
from ..symmetries import state_at_label


def initial_state(cfg: dict, params: Params) -> np.ndarray:
    """The configured y0, rescaled to ``energy_label`` when one is given."""
    y0 = np.asarray(cfg["y0"], dtype=float)
    if cfg.get("energy_label") is not None:
        y0 = state_at_label(y0, params, cfg["energy_label"])
    return y0


def nan_padded(rows, min_width: int = 0) -> np.ndarray:
    """Rows of different lengths as one float array, each padded with NaN to the longest (at least
    ``min_width`` columns: 1 keeps a netCDF dimension from being empty)."""
    rows = [np.asarray(r, float) for r in rows]
    width = max(min_width, *(r.size for r in rows)) if rows else min_width
    return np.array([np.r_[r, np.full(width - r.size, np.nan)] for r in rows])


def steady_arithmetic(cfg: dict) -> dict:
    """The arithmetic of a scene's steady-state part: the block's ``precision`` (double, the paper's
    arithmetic, when unset) at the block's ``tol`` in double, else at that precision's machine
    epsilon. The transient before it always runs in double at ``tol``, so every precision of a
    scene's ladder starts from the same settled point. Returns {"precision", "tol"}."""
    precision = cfg.get("precision", "double")
    precision_flags(precision)
    return {"precision": precision, "tol": cfg["tol"] if precision == "double" else EPSILON[precision]}
