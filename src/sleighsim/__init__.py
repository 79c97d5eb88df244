"""sleighsim: computational companion to "Chaotic dynamics of the Chaplygin sleigh
with a passive internal rotor" (Fedonyuk and Tallapragada).

Layout: engines with plain arguments live in this package's top-level modules (mechanics,
params, model, symmetries, integrate, poincare, lyapunov, transient, spectra, fits, ...);
:mod:`sleighsim.scenes` turns config blocks into datasets, one module per analysis stage;
:mod:`sleighsim.outputs` draws the figures, judges the claims and writes the report; what the
workflow builds is declared once in :mod:`sleighsim.registry`.
"""

from .integrate import IntegrationError, final_state, integrate, sample_grid
from .lyapunov import benettin, mean_divergence, tangent_integrator
from .mechanics import derive
from .model import energy, jacobian, rhs
from .params import Params
from .symmetries import REFERENCE_LABEL, REFERENCE_STATE, energy_label, reverse, state_at_label

__version__ = "0.1.0"
__all__ = ["IntegrationError", "Params", "REFERENCE_LABEL", "REFERENCE_STATE", "benettin", "derive", "energy",
           "energy_label", "final_state", "integrate", "jacobian", "mean_divergence", "reverse", "rhs",
           "sample_grid", "state_at_label", "tangent_integrator"]
