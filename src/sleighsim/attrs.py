"""Dataset attributes shared by every scene: variable names and units, and the run's
parameters, initial state and energy (physical and as the paper's label)."""

from __future__ import annotations

import numpy as np

from .model import STATE_NAMES, energy
from .params import Params
from .symmetries import energy_label

UNITS = {
    "u": ("runner longitudinal speed", "length/time"),
    "Omega": ("sleigh angular velocity", "rad/time"),
    "omega": ("rotor angular velocity", "rad/time"),
    "delta": ("relative angle theta - beta", "rad"),
    "theta": ("sleigh heading", "rad"),
    "x": ("centre C, x", "length"),
    "y": ("centre C, y", "length"),
}


def state_attrs(params: Params, y0) -> dict:
    """Parameters, initial state, physical energy and label of a run from y0."""
    y0 = np.asarray(y0, dtype=float)
    out = params.attrs()
    out.update({f"y0_{n}": float(v) for n, v in zip(STATE_NAMES, y0)})
    out.update(energy_physical=float(energy(y0[:4], params)), energy_label=float(energy_label(y0[:4], params)))
    return out
