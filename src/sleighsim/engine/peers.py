"""Peer engines for a fair speed comparison with the project's Taylor integrator (heyoka): their registry.

What a Python user would pick instead of heyoka for the sleigh's 4-D ODE, one module per family:

* SciPy's ``solve_ivp`` with a Python right-hand side or a compiled one (numba's ``njit`` of the same
  lambdified code, or heyoka's ``cfunc``): :mod:`sleighsim.engine.peer_scipy`;
* diffrax (JAX) with a jit-compiled adaptive solve: :mod:`sleighsim.engine.peer_jax`;
* for the largest Lyapunov exponent, lyapax (JAX, Benettin/QR on the tangent map of a fixed-step
  Runge-Kutta map) against Benettin's method on heyoka's variational equations:
  :mod:`sleighsim.engine.peer_lyapunov`;
* the whole end-state comparison, :func:`sleighsim.engine.peer_table.integration_table`.

This module holds what they share: the peer packages and their versions, :class:`PeerUnavailable` and
:func:`require` (a missing peer raises an ``ImportError`` that says how to install it), the one timer
:func:`timed` (one warm-up call, then the median of ``repeats`` calls; compile / JIT time is always
measured apart from run time), the sleigh's right-hand side every peer evaluates (:func:`derivation`,
:func:`lambdified`) and the error metric :func:`state_error`. Every engine function takes plain
arguments (parameter values in ``mechanics.PHYSICAL`` order, states as sequences) and imports its
optional peer inside the function.
"""

from __future__ import annotations

import importlib
import math
import statistics
import time
from collections.abc import Callable
from functools import cache

import numpy as np

#: Extra that installs every peer (pyproject's ``[project.optional-dependencies] bench``).
INSTALL_HINT = "pip install 'sleighsim[bench]'"
#: Index of the angle delta in the sleigh's state (enters only through sin and cos).
DELTA = 3
#: The reference initial state (u, Omega, omega, delta).
Y0_REFERENCE = (0.0, 0.1, 1.0, 0.0)
#: Peer packages (distribution names) reported by :func:`peer_versions`.
PEERS = ("numpy", "scipy", "sympy", "heyoka", "numba", "llvmlite", "jax", "jaxlib", "equinox", "diffrax", "lyapax")


class PeerUnavailable(ImportError):
    """An optional peer engine is not installed (or cannot be used as the peer modules call it)."""


def require(module: str, package: str | None = None):
    """Import ``module`` or raise :class:`PeerUnavailable` with the install hint; heyoka with its JIT
    cache checked (sleighsim.engine.integrators.guarded_heyoka)."""
    try:
        if module == "heyoka":
            from sleighsim.engine.integrators import guarded_heyoka

            return guarded_heyoka()
        return importlib.import_module(module)
    except ImportError as exc:
        name = package or module.split(".")[0]
        raise PeerUnavailable(f"{name} is not installed: {INSTALL_HINT} ({exc})") from exc


def peer_versions() -> dict:
    """Installed version of every peer package (None when not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for name in PEERS:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            out[name] = None
    return out


# ----------------------------------------------------------------------------- timing


def timed(fn: Callable[[], object], repeats: int = 5, warmup: int = 1):
    """Call ``fn()`` ``warmup`` times untimed, then ``repeats`` (at least 1) times timed.

    Returns (result of the last call, median wall time [s], list of the timed walls [s])."""
    if repeats < 1 or warmup < 0:
        raise ValueError(f"need repeats >= 1 and warmup >= 0 (repeats={repeats}, warmup={warmup})")
    result = None
    for _ in range(warmup):
        result = fn()
    walls = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        walls.append(time.perf_counter() - start)
    return result, statistics.median(walls), walls


# ----------------------------------------------------------------------------- the sleigh's rhs


def derivation():
    """(expressions, symbols, number of states, number of parameters) of the sleigh's rhs in the
    polynomial form heyoka integrates (mechanics.PolynomialForm, its coefficients written out in the
    physical parameters), so every peer evaluates the same formula."""
    from sleighsim.model import mechanics as m

    d = m.derive()
    return d.polynomial.explicit() + [d.rhs[3]], (*m.STATE, *m.PHYSICAL), len(m.STATE), len(m.PHYSICAL)


@cache
def lambdified(modules: str):
    """The sleigh's rhs (:func:`derivation`) lambdified with ``modules`` ("numpy", "jax", "mpmath", ...),
    with common subexpressions: f(u, Omega, omega, delta, *physical parameters) -> tuple of 4."""
    import sympy as sp

    exprs, symbols, _, _ = derivation()
    return sp.lambdify(symbols, tuple(exprs), modules=modules, cse=True)


def param_tuple(param_values, n_expected: int) -> tuple:
    """``param_values`` as a tuple of floats, checked to hold ``n_expected`` values."""
    p = tuple(float(v) for v in param_values)
    if len(p) != n_expected:
        raise ValueError(f"need {n_expected} parameter values (mechanics.PHYSICAL order); got {len(p)}")
    return p


# ----------------------------------------------------------------------------- the error metric


def state_error(a, b, angle_index: int | None = DELTA) -> float:
    """max |a - b| over the components, the angle compared modulo 2 pi."""
    d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    if angle_index is not None:
        d[angle_index] = (d[angle_index] + math.pi) % (2.0 * math.pi) - math.pi
    return float(np.max(np.abs(d)))
