"""Compiled heyoka integrators: one cache per process.

An integrator is compiled once per process for its structure (system, tolerance, mode) and
reused; parameters are runtime par[] and states are set per run. heyoka also keeps compiled
code in its on-disk cache (heyoka.llvm_state), so a new process reuses earlier compilations.
"""

from __future__ import annotations

import time
from typing import Callable

_CACHE: dict = {}


def compiled(key: tuple, build: Callable):
    """(integrator, compile seconds) for ``key``: built by ``build()`` on first use in this process."""
    if key not in _CACHE:
        start = time.perf_counter()
        ta = build()
        _CACHE[key] = (ta, time.perf_counter() - start)
    return _CACHE[key]


def flow(kinematics: bool, tol: float):
    """The sleigh (with (theta, x, y) when ``kinematics``). Returns (integrator, compile seconds)."""

    def build():
        import heyoka as hy

        from .model import heyoka_system
        from .params import Params

        n = 7 if kinematics else 4
        return hy.taylor_adaptive(heyoka_system(kinematics), [0.0, 0.1, 1.0, 0.0] + [0.0] * (n - 4),
                                  pars=list(Params.paper(eps=0.1).values), tol=tol)

    return compiled(("flow", kinematics, tol), build)
