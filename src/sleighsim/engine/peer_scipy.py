"""SciPy peers of the sleigh: ``solve_ivp`` with a Python right-hand side (:func:`numpy_rhs`: the SymPy
expressions lambdified to NumPy) or with a compiled one (:func:`compiled_rhs`: numba's ``njit`` of the same
lambdified code, or heyoka's ``cfunc``), run by :func:`scipy_run`."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from sleighsim.engine.peers import Y0_REFERENCE, derivation, lambdified, param_tuple, require


def numpy_rhs(param_values) -> Callable:
    """The "Python right-hand side": f(t, y) -> ndarray (4,) for SciPy, the SymPy rhs lambdified
    to NumPy (with common subexpressions), the parameters bound."""
    _, _, _, n_par = derivation()
    p = param_tuple(param_values, n_par)
    lam = lambdified("numpy")

    def f(t, y):
        return np.array(lam(*y, *p))

    f.compile_s = 0.0
    f.how = "numpy"
    return f


def compiled_rhs(param_values, how: str = "numba") -> Callable:
    """A compiled f(t, y) -> ndarray (4,) for SciPy: ``how="numba"`` jit-compiles the
    lambdified NumPy code (with common subexpressions) with ``numba.njit``; ``how="heyoka"``
    compiles the SymPy rhs with ``heyoka.cfunc``. The compile / JIT time [s] (including a first
    call, which numba needs to compile) is ``f.compile_s``."""
    _, _, n_state, n_par = derivation()
    p = param_tuple(param_values, n_par)
    y_probe = np.array(Y0_REFERENCE, dtype=float)
    if how == "numba":
        numba = require("numba")
        lam = lambdified("numpy")
        start = time.perf_counter()
        core = numba.njit(lam)

        # The parameters are frozen into the compiled code as constants (closure variables).
        if n_state != 4:  # pragma: no cover - the sleigh's state is 4-D
            raise NotImplementedError("compiled_rhs(how='numba') is written for a 4-D state")

        @numba.njit
        def f(t, y):
            r = core(y[0], y[1], y[2], y[3], *p)
            out = np.empty(4)
            out[0] = r[0]
            out[1] = r[1]
            out[2] = r[2]
            out[3] = r[3]
            return out

        f(0.0, y_probe)  # compile for (float, float64[:])
        f.compile_s = time.perf_counter() - start  # numba dispatchers take attributes: SciPy calls f itself
        f.how = "numba"
        return f
    if how == "heyoka":
        hy = require("heyoka")
        exprs, symbols, _, _ = derivation()
        start = time.perf_counter()
        hv = [hy.make_vars(str(s)) for s in symbols[:n_state]]
        smap = {s: v for s, v in zip(symbols[:n_state], hv)}
        # The parameters as numbers, like numba's constants: a cfunc called with pars=... costs
        # about 5 microseconds more per call (argument handling), doubling SciPy's time.
        smap.update({s: hy.expression(v) for s, v in zip(symbols[n_state:], p)})
        cf = hy.cfunc([hy.from_sympy(e, smap) for e in exprs], vars=hv)
        cf(y_probe)
        compile_s = time.perf_counter() - start

        def f(t, y):
            return cf(y)

        f.compile_s = compile_s
        f.how = "heyoka"
        return f
    raise ValueError(f"how must be 'numba' or 'heyoka'; got {how!r}")


def rhs_function(param_values, how: str) -> Callable:
    """f(t, y) for SciPy by name: "numpy", "numba" or "heyoka"."""
    return numpy_rhs(param_values) if how == "numpy" else compiled_rhs(param_values, how)



def scipy_run(f, y0, t_end: float, method: str = "DOP853", rtol: float = 1e-10, atol: float = 1e-13):
    """``solve_ivp(f, (0, t_end), y0, method, rtol, atol)`` without dense output.

    Returns (end state (n,), number of rhs evaluations). Raises RuntimeError when SciPy reports
    a failure (its message says which: e.g. a step size below the spacing of t)."""
    from scipy.integrate import solve_ivp

    sol = solve_ivp(f, (0.0, float(t_end)), np.asarray(y0, dtype=float), method=method, rtol=rtol, atol=atol,
                    dense_output=False)
    if not sol.success:
        raise RuntimeError(f"solve_ivp({method}, rtol={rtol:g}) failed at t = {sol.t[-1]:.6g}: {sol.message}")
    return sol.y[:, -1].copy(), int(sol.nfev)
