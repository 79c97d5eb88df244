"""Dataset attributes shared by every scene: variable names and units, and the run's
parameters, initial state and energy (physical and as the paper's label)."""

from __future__ import annotations

import numpy as np

from sleighsim.io import cf
from sleighsim.model.equations import STATE_NAMES, energy
from sleighsim.model.params import Params
from sleighsim.model.symmetries import energy_label

#: name -> (long_name, units) of the state and kinematic variables (CF, :mod:`sleighsim.io.cf`: units
#: "1" or "rad", the model unit in the long_name).
UNITS = {n: (a["long_name"], a["units"]) for n, a in (
    ("u", cf.attrs("runner longitudinal speed u", "speed")),
    ("Omega", cf.attrs("sleigh angular velocity Omega", "angular_velocity")),
    ("omega", cf.attrs("rotor angular velocity omega", "angular_velocity")),
    ("delta", cf.attrs("relative angle delta = theta - beta", "angle")),
    ("theta", cf.attrs("sleigh heading theta", "angle")),
    ("x", cf.attrs("centre C, x", "length")),
    ("y", cf.attrs("centre C, y", "length")),
)}


def state_attrs(params: Params, y0) -> dict:
    """Parameters, initial state, physical energy and label of a run from y0."""
    y0 = np.asarray(y0, dtype=float)
    out = params.attrs()
    out.update({f"y0_{n}": float(v) for n, v in zip(STATE_NAMES, y0)})
    out.update(energy_physical=float(energy(y0[:4], params)), energy_label=float(energy_label(y0[:4], params)))
    return out
