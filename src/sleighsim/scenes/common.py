"""Helpers shared by the scene modules: reading config blocks into engine arguments."""

from __future__ import annotations

import numpy as np

from ..params import Params
from ..symmetries import state_at_label


def initial_state(cfg: dict, params: Params) -> np.ndarray:
    """The configured y0, rescaled to ``energy_label`` when one is given."""
    y0 = np.asarray(cfg["y0"], dtype=float)
    if cfg.get("energy_label") is not None:
        y0 = state_at_label(y0, params, cfg["energy_label"])
    return y0
