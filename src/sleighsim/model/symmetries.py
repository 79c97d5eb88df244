"""The exact symmetries of the sleigh, and the energy labels built on time scaling.

- Time scaling: if y(t) = (u, Omega, omega, delta)(t) solves the system, so does
  (c u, c Omega, c omega, delta)(c t), c > 0. The paper's energy "E = 0.1127" is a label
  for the reference state; another label is the reference state with its velocities
  scaled by sqrt(label / 0.1127).
- Length scale: with K2 fixed, (u / b, Omega, omega, delta) obeys b-free equations
  (:func:`sleighsim.model.mechanics.b_free_form`), so u scales with b.
- Reversibility: R(u, Omega, omega, delta) = (-u, -Omega, -omega, delta); if y(t) is a
  solution, so is R y(-t) (the force terms are quadratic in the velocities).
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.model.equations import energy
from sleighsim.model.params import Params, finite

#: The paper's reference state at eps = 0.1 and the energy label it quotes for it.
REFERENCE_STATE = (0.0, 0.1, 1.0, 0.0)
REFERENCE_LABEL = 0.1127


def energy_label(y, params: Params) -> np.ndarray:
    """The paper's energy label of state y: REFERENCE_LABEL times E(y) / E(reference state)."""
    return REFERENCE_LABEL * energy(y, params) / energy(REFERENCE_STATE, params)


def state_at_label(y, params: Params, label: float) -> np.ndarray:
    """y with its velocities scaled (time-scaling symmetry) so that its energy label is ``label``."""
    label = finite("energy label", label)
    if label <= 0:
        raise ValueError(f"energy label = {label} is outside the admissible range (0, inf)")
    y = np.array(y, dtype=float)
    current = float(energy_label(y, params))
    if current <= 0:
        raise ValueError("cannot rescale a state with zero kinetic energy to a label")
    y[:3] *= math.sqrt(label / current)
    return y


def b_image(y, b_from: float, b_to: float) -> np.ndarray:
    """The state at b_to that the length-scale symmetry maps y (at b_from) to: u scales with b.

    With K2 fixed, (u / b, Omega, omega, delta) obeys b-free equations, so the image of a point
    on the attractor at b_from lies on the attractor at b_to."""
    y = np.array(y, dtype=float)
    y[0] *= b_to / b_from
    return y


def reverse(y) -> np.ndarray:
    """The reversing involution R(u, Omega, omega, delta) = (-u, -Omega, -omega, delta)."""
    y = np.array(y, dtype=float)
    y[..., :3] *= -1.0
    return y

