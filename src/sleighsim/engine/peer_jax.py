"""JAX peers of the sleigh: its rhs as a JAX function (:func:`sleigh_jax`, and Lorenz's, :func:`lorenz_jax`)
and diffrax's jit-compiled adaptive solve (:func:`diffrax_solver`, :func:`diffrax_run`)."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from sleighsim.engine.peers import Y0_REFERENCE, derivation, lambdified, param_tuple, require


def jax_x64():
    """jax and jax.numpy with float64 enabled (a process-wide JAX setting)."""
    jax = require("jax")
    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    return jax, jnp


def sleigh_jax(param_values=None) -> Callable:
    """The sleigh's rhs as a JAX function of the state: ``rhs(y) -> (4,)`` with the parameters
    bound, or ``rhs(y, p)`` when ``param_values`` is None (SymPy lambdified with modules="jax")."""
    _, jnp = jax_x64()
    lam = lambdified("jax")
    if param_values is None:
        def rhs(y, p):
            return jnp.stack(lam(y[0], y[1], y[2], y[3], *(p[i] for i in range(p.shape[0]))))

        return rhs
    _, _, _, n_par = derivation()
    p = param_tuple(param_values, n_par)

    def rhs(y):
        return jnp.stack(lam(y[0], y[1], y[2], y[3], *p))

    return rhs


@dataclass
class JaxSolve:
    """A compiled diffrax solve: ``fn(y0, p)`` returns (end state, accepted steps, rejected steps,
    success flag) as JAX arrays; ``compile_s`` is its trace + lower + XLA compile time."""

    fn: Callable
    compile_s: float
    solver: str
    rtol: float
    atol: float
    t_end: float
    max_steps: int

    def __call__(self, y0, param_values):
        """Solve from ``y0`` with ``param_values``: (end state, accepted steps, rejected steps)."""
        _, jnp = jax_x64()
        out = self.fn(jnp.asarray(y0, dtype=jnp.float64), jnp.asarray(param_values, dtype=jnp.float64))
        y, n_acc, n_rej, ok = (np.asarray(o) for o in out)  # np.asarray blocks until ready
        if not bool(ok):
            raise RuntimeError(f"diffrax {self.solver} (rtol={self.rtol:g}) did not reach t = {self.t_end:g} "
                               f"(accepted {int(n_acc)} + rejected {int(n_rej)} steps of max_steps = {self.max_steps})")
        return y, int(n_acc), int(n_rej)


#: Generous: on the sleigh, t_end = 100 at rtol 1e-12 takes about 2.9e3 Tsit5 steps (5.3e2 Dopri8).
DIFFRAX_MAX_STEPS = 2**20


@lru_cache(maxsize=32)
def diffrax_solver(t_end: float, rtol: float, atol: float, solver: str = "Dopri8",
                   max_steps: int = DIFFRAX_MAX_STEPS) -> JaxSolve:
    """Compile (ahead of time, once per process and setting) a diffrax solve of the sleigh from
    0 to ``t_end`` with a PID step-size controller; the parameters and y0 are run-time inputs."""
    diffrax = require("diffrax")
    jax, jnp = jax_x64()
    solvers = {"Dopri8": diffrax.Dopri8, "Tsit5": diffrax.Tsit5, "Dopri5": diffrax.Dopri5}
    if solver not in solvers:
        raise ValueError(f"solver must be one of {sorted(solvers)}; got {solver!r}")
    rhs = sleigh_jax(None)
    term = diffrax.ODETerm(lambda t, y, p: rhs(y, p))
    controller = diffrax.PIDController(rtol=rtol, atol=atol)

    def solve(y0, p):
        sol = diffrax.diffeqsolve(term, solvers[solver](), 0.0, float(t_end), None, y0, args=p,
                                  stepsize_controller=controller, saveat=diffrax.SaveAt(t1=True),
                                  max_steps=max_steps, throw=False, adjoint=diffrax.ForwardMode())
        ok = sol.result == diffrax.RESULTS.successful
        return sol.ys[-1], sol.stats["num_accepted_steps"], sol.stats["num_rejected_steps"], ok

    n_par = derivation()[3]
    start = time.perf_counter()
    fn = jax.jit(solve).lower(jnp.zeros(len(Y0_REFERENCE)), jnp.zeros(n_par)).compile()
    return JaxSolve(fn, time.perf_counter() - start, solver, rtol, atol, float(t_end), max_steps)


def diffrax_run(param_values, y0, t_end: float, rtol: float, atol: float, solver: str = "Dopri8") -> np.ndarray:
    """End state of the sleigh from y0 over [0, t_end] by diffrax (``solver`` "Dopri8" or
    "Tsit5", PID controller at rtol/atol, float64). The jit-compiled solve is built on the first
    call for each (t_end, rtol, atol, solver) and reused: its compile time is
    ``diffrax_solver(t_end, rtol, atol, solver).compile_s``; later calls time the run only."""
    require("diffrax")
    require("jax")
    _, _, _, n_par = derivation()
    return diffrax_solver(float(t_end), float(rtol), float(atol), solver)(y0, param_tuple(param_values, n_par))[0]


def lorenz_jax(sigma: float = 10.0, rho: float = 28.0, beta: float = 8.0 / 3.0) -> Callable:
    """Lorenz's rhs as a JAX function of the state (lambda_1 about 0.906 at the defaults)."""
    _, jnp = jax_x64()

    def rhs(s):
        x, y, z = s[0], s[1], s[2]
        return jnp.stack([sigma * (y - x), x * (rho - z) - y, x * y - beta * z])

    return rhs

