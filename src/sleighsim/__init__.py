"""sleighsim: computational companion to "Chaotic dynamics of the Chaplygin sleigh
with a passive internal rotor" (Fedonyuk and Tallapragada).

Layout: engines with plain arguments live in this package's top-level modules (mechanics,
params, model, symmetries, integrate, poincare, lyapunov, transient, spectra, fits, ...);
:mod:`sleighsim.scenes` turns config blocks into datasets, one module per analysis stage;
:mod:`sleighsim.outputs` draws the figures, judges the claims and writes the report; what the
workflow builds is declared once in :mod:`sleighsim.registry`.
"""

import importlib

#: The package-level names and the module each comes from, imported on first use (PEP 562), so a
#: job that only draws or reads datasets does not import SymPy (0.6 s). The integrator is
#: sleighsim.integrate.integrate (the package attribute ``integrate`` is its module).
_EXPORTS = {
    "IntegrationError": "integrate", "final_state": "integrate", "sample_grid": "integrate",
    "benettin": "lyapunov", "mean_divergence": "lyapunov", "tangent_integrator": "lyapunov", "derive": "mechanics",
    "energy": "model", "jacobian": "model", "rhs": "model", "Params": "params", "REFERENCE_LABEL": "symmetries",
    "REFERENCE_STATE": "symmetries", "energy_label": "symmetries", "reverse": "symmetries",
    "state_at_label": "symmetries",
}


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__version__ = "0.1.0"
__all__ = sorted(_EXPORTS)
