"""Helpers shared by the scene modules: reading config blocks into engine arguments, and ragged
records into arrays."""

from __future__ import annotations

import math

import numpy as np

from sleighsim.engine import integrators
from sleighsim.model.params import Params
from sleighsim.model.symmetries import state_at_label
from sleighsim.precision import Precision


def initial_state(cfg: dict, params: Params) -> np.ndarray:
    """The configured y0, rescaled to ``energy_label`` when one is given."""
    y0 = np.asarray(cfg["y0"], dtype=float)
    if cfg.get("energy_label") is not None:
        y0 = state_at_label(y0, params, cfg["energy_label"])
    return y0


#: Written into the chaos_verdict dataset (attribute realization_rule, before agree's).
REALIZATION_STATES_RULE = (
    "The start states of realization ``index`` (a dict or list of states): realization 0 as given, realization "
    "k > 0 every component times (1 + rel z), z standard normal from a generator seeded by k, the states in "
    "order (zero components stay zero)."
)


def realization_states(states, rel: float, index: int):
    """Applies :data:`REALIZATION_STATES_RULE`, the rule as the datasets record it (just above)."""
    named = states if isinstance(states, dict) else dict(enumerate(states))
    if index == 0:
        out = {name: list(y) for name, y in named.items()}
    else:
        rng = np.random.default_rng(index)
        out = {name: (np.asarray(y, float) * (1.0 + rel * rng.standard_normal(len(y)))).tolist()
               for name, y in named.items()}
    return out if isinstance(states, dict) else list(out.values())


def realization_config(cfg: dict, rel: float, index: int) -> dict:
    """A scene block with its start states (``y0``, ``states``) those of realization ``index``
    (:func:`realization_states`)."""
    out = dict(cfg)
    if "y0" in cfg:
        out["y0"] = realization_states([cfg["y0"]], rel, index)[0]
    if "states" in cfg:
        out["states"] = realization_states(cfg["states"], rel, index)
    return out


def nan_padded(rows, min_width: int = 0) -> np.ndarray:
    """Rows of different lengths as one float array, each padded with NaN to the longest (at least
    ``min_width`` columns: 1 keeps a netCDF dimension from being empty)."""
    rows = [np.asarray(r, float) for r in rows]
    width = max(min_width, *(r.size for r in rows)) if rows else min_width
    return np.array([np.r_[r, np.full(width - r.size, np.nan)] for r in rows])


def tolerance(cfg: dict, precision: Precision) -> float:
    """The Taylor tolerance of a run in ``precision``: the block's ``tol`` in double, else that
    arithmetic's machine epsilon (a finer run follows the exact orbit as far as its rounding lets it)."""
    return cfg["tol"] if precision is Precision.DOUBLE else precision.epsilon


def steady_arithmetic(cfg: dict) -> dict:
    """The arithmetic of a scene's steady-state part: the block's ``precision`` (double, the paper's
    arithmetic, when unset) at its ``tolerance``. The transient before it always runs in double at
    ``tol``, so every precision of a scene's ladder starts from the same settled point. Returns
    {"precision" (a Precision), "tol"}."""
    precision = cfg.get("precision", Precision.DOUBLE)
    return {"precision": precision, "tol": tolerance(cfg, precision)}


def stored_state(y) -> np.ndarray:
    """A state in the model's variables as the compiled sleigh integrators store it (the engines
    of ``sleighsim.chaos`` take stored states): delta + DELTA_SHIFT in [0, 2 pi)."""
    out = np.array(y, float)
    out[3] = (out[3] + integrators.DELTA_SHIFT) % (2 * math.pi)
    return out
