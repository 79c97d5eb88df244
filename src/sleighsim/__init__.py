"""sleighsim: computational companion to "Chaotic dynamics of the Chaplygin sleigh
with a passive internal rotor" (Fedonyuk and Tallapragada).

Layout, in layers whose imports run downward only (docs/layout.md; import-linter contracts in
pyproject.toml): ``io`` (datasets, CF, integrity), ``model`` (mechanics, parameters, equations,
symmetries), ``engine`` (integrators), ``chaos`` (indicators and their judges), ``analysis``
(spectra, fits, windows, observables), ``scenes`` (config blocks to datasets, one module per
kind), ``claims`` (the ledger), ``report`` (figures and the page), ``ops`` (config
checks, costs) and ``cli``.
"""

import importlib

#: The package-level names and the module each comes from, imported on first use (PEP 562), so a
#: job that only draws or reads datasets does not import SymPy (0.6 s). The integrator is
#: sleighsim.engine.integrate.integrate (the package attribute ``integrate`` is its module).
_EXPORTS = {
    "IntegrationError": "engine.integrate", "final_state": "engine.integrate", "sample_grid": "engine.integrate",
    "integrate": "engine.integrate", "benettin": "chaos.benettin", "mean_divergence": "chaos.benettin",
    "tangent_integrator": "engine.integrators", "derive": "model.mechanics", "energy": "model.equations",
    "jacobian": "model.equations", "rhs": "model.equations", "Params": "model.params",
    "REFERENCE_LABEL": "model.symmetries", "REFERENCE_STATE": "model.symmetries", "energy_label": "model.symmetries",
    "reverse": "model.symmetries", "state_at_label": "model.symmetries",
}


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__version__ = "0.1.0"
__all__ = sorted(_EXPORTS)
