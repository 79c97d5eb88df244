"""Lyapunov exponents by Benettin's method on heyoka's variational equations (the integrators
are built in ``engine.integrators``; the 0-1 test is ``chaos.zero_one``).

Benettin: k tangent vectors (the first-order variational equations of
``var_ode_sys`` with respect to the first k initial conditions; their values
are overwritten after every renormalisation) are propagated with the flow; every
``tau`` time units they are QR-decomposed, log|R_ii| is accumulated and the
vectors are replaced by Q. An alignment phase (renormalised, not accumulated)
removes the bias of the arbitrary initial directions. The standard error comes
from ``n_blocks`` equal, consecutive blocks of the accumulation window.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np

from sleighsim.engine import integrators
from sleighsim.engine.integrate import check_tol
from sleighsim.precision import Precision

log = logging.getLogger("sleighsim")


class LaneLoop:
    """B lanes run one after another through one scalar tangent integrator, with the part of a batch
    integrator's interface :func:`batch_benettin` uses (``batch_size``, ``state`` (n + n k, B),
    ``pars``, ``set_time``, ``propagate_for``, ``propagate_res``): the batch method in any precision
    heyoka's scalar integrators have (long double, real128), which its SIMD batch mode lacks. Each
    lane keeps its own state in ``state``; every lane restarts its clock at 0 (autonomous flow)."""

    def __init__(self, ta, batch_size: int):
        self.ta, self.batch_size = ta, batch_size
        self.state = np.repeat(np.array(ta.state)[:, None], batch_size, axis=1)
        self.propagate_res: list = []
        integrators.copy_angles(ta, self)

    @property
    def pars(self):
        """The scalar integrator's parameters (shared by every lane)."""
        return self.ta.pars

    def set_time(self, times) -> None:
        """Lanes start every propagation at t = 0 (the flow is autonomous); ``times`` must be zeros."""
        if np.any(np.asarray(times) != 0):
            raise ValueError("LaneLoop runs autonomous lanes from t = 0 only")

    def propagate_for(self, taus, callback=None):
        """Each lane over its tau (``callback`` is the scalar integrator's own angle reducer)."""
        self.propagate_res = []
        fp = self.state.dtype.type
        for j, tau in enumerate(np.broadcast_to(taus, (self.batch_size,))):
            self.ta.time = fp(0)
            self.ta.state[:] = self.state[:, j]
            self.propagate_res.append(self.ta.propagate_for(fp(tau), callback=integrators.bounded(self.ta)))
            self.state[:, j] = self.ta.state


def sleigh_tangent_lanes(batch_size: int, tol: float, compact: bool, k: int = 1,
                         precision: Precision = Precision.DOUBLE):
    """``batch_size`` lanes of the sleigh plus k tangent vectors for :func:`batch_benettin` and
    :func:`replica_exponents`: SIMD lanes (``integrators.sleigh_tangent_batch``) in double, else a
    :class:`LaneLoop` over one scalar integrator in ``precision``. Returns (lanes, compile_s)."""
    if precision is Precision.DOUBLE:
        return integrators.sleigh_tangent_batch(batch_size, tol, compact, k=k)
    ta, compile_s = integrators.sleigh_tangent(k, tol, compact, precision)
    return LaneLoop(ta, batch_size), compile_s


def mean_divergence(params, y0, T, tol) -> float:
    """(1/T) integral of trace J along the sleigh's orbit from y0 over [0, T] (T > 0, in double at tol)."""
    if not (math.isfinite(T) and T > 0):
        raise ValueError(f"T = {T} is outside the admissible range (0, inf): the mean is over [0, T]")
    check_tol(tol)
    ta = integrators.divergence(tol)
    ta.time = 0.0
    y = np.array([*np.asarray(y0, float), 0.0])
    y[3] %= 2.0 * math.pi
    integrators.load(ta, y)
    integrators.set_pars(ta, params)
    ta.propagate_until(float(T), callback=integrators.bounded(ta))
    return float(ta.state[4] / T)


def initial_directions(n, k, seed):
    """k orthonormal random directions in n dimensions (columns), from ``seed``."""
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(n, k)))
    return q


def benettin(ta, n: int, k: int, y0, *, t_align: float, T: float, tau: float, n_blocks: int = 10,
             n_record: int = 60, seed: int = 0, label: str = "", progress_every: float = 30.0) -> dict:
    """Run Benettin's method from ``y0`` (the integrator's pars must already be set).

    Phases: alignment over t_align (renormalised, not accumulated), then T
    accumulated in steps of tau. Returns exponents (k,), their standard error
    from n_blocks blocks, block estimates, finite-time estimates on a log-spaced
    grid of accumulation times, the log growth of each vector in each interval
    (n_steps, k) (the convergence history), the final state and wall time."""
    if not (tau > 0 and T >= n_blocks * tau and t_align >= 0):
        raise ValueError(f"need tau > 0, T >= n_blocks * tau and t_align >= 0 (tau={tau}, T={T}, t_align={t_align})")
    start = time.perf_counter()
    callback = integrators.bounded(ta)
    fp = ta.state.dtype.type  # float, or the extended type of a long double or quad integrator
    ta.time = fp(0)
    integrators.load(ta, np.asarray(y0, float))
    ta.state[n:] = initial_directions(n, k, seed).ravel()
    n_steps = int(round(T / tau))
    n_align = int(math.ceil(t_align / tau))
    record_at = np.unique(np.geomspace(1, n_steps, n_record).astype(int))
    running = np.empty((len(record_at), k))
    block_of = np.minimum((np.arange(n_steps) * n_blocks) // n_steps, n_blocks - 1)
    blocks = np.zeros((n_blocks, k))
    total = np.zeros(k)
    log_growth = np.empty((n_steps, k))
    r = 0
    last_log = time.perf_counter()
    for i in range(-n_align, n_steps):
        rr = _renormalised_leg(ta, n, k, fp(tau), callback, label)
        if i < 0:
            continue
        growth = np.log(np.abs(np.diag(rr)))
        log_growth[i] = growth
        total += growth
        blocks[block_of[i]] += growth
        if r < len(record_at) and i + 1 == record_at[r]:
            running[r] = total / ((i + 1) * tau)
            r += 1
        if time.perf_counter() - last_log > progress_every:
            last_log = time.perf_counter()
            log.info("%s: Lyapunov t = %.4g / %.4g, lambda_1 ~ %.4g", label, (i + 1) * tau, T,
                     total[0] / ((i + 1) * tau))
    block_len = np.bincount(block_of, minlength=n_blocks) * tau
    block_est = blocks / block_len[:, None]
    exps = total / (n_steps * tau)
    return {
        "exponents": exps,
        "stderr": block_est.std(axis=0, ddof=1) / math.sqrt(n_blocks),
        "block_estimates": block_est,
        "T_grid": record_at * tau,
        "running": running,
        "log_growth": log_growth,
        "final_state": integrators.read(ta, n).astype(float),
        "wall_time_s": time.perf_counter() - start,
    }


def _renormalised_leg(ta, n: int, k: int, tau, callback, label: str) -> np.ndarray:
    """One leg of ``benettin``: the flow and its k tangent vectors propagated over tau (in the
    integrator's type), the clock reset to 0, the vectors replaced by Q of their QR decomposition
    (in double). Returns R (k, k); RuntimeError if the leg fails."""
    import heyoka as hy  # local: heyoka takes seconds to import

    res = ta.propagate_for(tau, callback=callback)
    if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(ta.state)):
        raise RuntimeError(f"{label}: Lyapunov run failed at t = {ta.time:.6g}: heyoka outcome {res[0].name}")
    ta.time = ta.state.dtype.type(0)  # autonomous: keep the clock small
    V = ta.state[n:].reshape(n, k).astype(float)  # QR in double (numpy's has no extended precision)
    q, rr = np.linalg.qr(V)
    ta.state[n:] = q.ravel()
    return rr


def batch_benettin(ta, n: int, k: int, y0s, taus, *, n_steps: int, t_align_steps: int = 0, seed: int = 0,
                   resume: bool = False, label: str = "", progress_every: float = 30.0) -> dict:
    """Benettin's method for several systems or replicas in lock-step, one per SIMD lane (``ta``
    from ``integrators.tangent_integrator_batch`` with k vectors, pars already set): lane j renormalises
    every taus[j] (QR of its k vectors); t_align_steps steps align the vectors (not accumulated),
    then n_steps are accumulated. With ``resume`` the lanes continue from the integrator's state
    (y0s and the vectors are not reset). Returns the log growth of every step, vector and lane
    (n_steps, k, B), the state at every renormalisation (n_steps, n, B), the final states (B, n)
    (all in double, whatever the lanes' arithmetic) and the wall time."""
    import heyoka as hy

    B = ta.batch_size
    taus = np.asarray(taus, float)
    if taus.shape != (B,) or np.any(taus <= 0) or n_steps < 1:
        raise ValueError(f"need {B} positive taus and n_steps >= 1; got taus {taus.shape}, n_steps = {n_steps}")
    start = time.perf_counter()
    callback = integrators.bounded(ta)
    if not resume:
        y0s = np.atleast_2d(np.asarray(y0s, float))
        if y0s.shape != (B, n):
            raise ValueError(f"need {B} states of {n} components; got {y0s.shape}")
        integrators.load(ta, y0s.T)
        ta.state[n:] = np.repeat(initial_directions(n, k, seed)[:, :, None], B, axis=2).reshape(n * k, B)
    growth = np.empty((n_steps, k, B))
    states = np.empty((n_steps, n, B))
    last_log = time.perf_counter()
    for i in range(-t_align_steps, n_steps):
        ta.set_time(np.zeros(B))
        ta.propagate_for(taus, callback=callback)
        if any(r[0] != hy.taylor_outcome.time_limit for r in ta.propagate_res) or not np.all(np.isfinite(ta.state)):
            raise RuntimeError(f"{label}: batch Lyapunov run failed: {[r[0].name for r in ta.propagate_res]}")
        V = np.moveaxis(ta.state[n:].reshape(n, k, B), 2, 0).astype(float)  # (B, n, k); QR in double
        q, r = np.linalg.qr(V)
        ta.state[n:] = np.moveaxis(q, 0, 2).reshape(n * k, B)
        if i >= 0:
            growth[i] = np.log(np.abs(np.diagonal(r, axis1=1, axis2=2))).T
            states[i] = integrators.read(ta, n)
        if time.perf_counter() - last_log > progress_every:
            last_log = time.perf_counter()
            log.info("%s: batch Lyapunov step %d / %d, running lambda_1 %s", label, i + 1, n_steps,
                     np.array2string(growth[: max(i + 1, 1), 0].sum(axis=0) / (max(i + 1, 1) * taus), precision=3))
    return {"log_growth": growth, "states": states, "final_state": integrators.read(ta, n).T.astype(float),
            "wall_time_s": time.perf_counter() - start}


def replica_exponents(ta, n: int, k: int, y0s, tau: float, *, T_round: float, max_rounds: int, target_rel: float,
                      regular_floor: float, t_align: float = 0.0, sigma: float = 3.0, degree: float = 2.0,
                      seed: int = 0, label: str = "") -> dict:
    """The first k Lyapunov exponents from independent replicas, one per SIMD lane: y0s are
    points along one settled orbit, many decorrelation times apart. The lanes run in rounds of
    T_round; after each round the estimate is the mean over replicas of each replica's
    cumulative exponents and its standard error the replicas' spread / sqrt(B), an honest
    uncertainty that assumes no independence within a run. Stops when lambda_1 is resolved
    (stderr <= target_rel lambda_1: "converged"), when lambda_1 + sigma stderr lies below the
    rate polynomial growth can fake, degree ln(T / tau) / T, and that rate is itself below
    ``regular_floor`` (any exponent above the floor would have been resolved: "regular"), or after
    max_rounds ("capped"). Returns the exponents, their standard errors, the per-replica exponents (B, k),
    the horizon per replica, the status and rule, the history per round (T, lambdas, stderrs),
    the log growth per step, vector and lane (steps, k, B; for finite-time statistics), the
    states at the renormalisations (for steadiness checks), the final states and the wall time."""
    from sleighsim.chaos.verdicts import polynomial_rate_bound

    B = ta.batch_size
    if B < 2:
        raise ValueError("replica_exponents needs at least 2 lanes (replicas) for an uncertainty")
    steps = int(round(T_round / tau))
    if steps < 1 or max_rounds < 1:
        raise ValueError(f"need T_round >= tau and max_rounds >= 1 (T_round = {T_round}, tau = {tau})")
    taus = np.full(B, tau)
    growth, states, history = [], [], []
    start, status = time.perf_counter(), "capped"
    for rnd in range(max_rounds):
        r = batch_benettin(ta, n, k, y0s, taus, n_steps=steps,
                           t_align_steps=int(math.ceil(t_align / tau)) if rnd == 0 else 0,
                           seed=seed, resume=rnd > 0, label=f"{label} round {rnd + 1}")
        growth.append(r["log_growth"])
        states.append(r["states"])
        T = (rnd + 1) * steps * tau
        per_replica = np.concatenate(growth).sum(axis=0).T / T  # (B, k)
        lam, err = per_replica.mean(axis=0), per_replica.std(axis=0, ddof=1) / math.sqrt(B)
        history.append((T, *lam, *err))
        log.info("%s: T = %.4g per replica, lambda = %s +- %s", label, T, np.array2string(lam, precision=3),
                 np.array2string(err, precision=2))
        if err[0] <= target_rel * lam[0]:
            status = "converged"
            break
        fake = polynomial_rate_bound(T, tau, degree)
        if lam[0] + sigma * err[0] < fake <= regular_floor:
            status = "regular"
            break
    return {"exponents": lam, "stderr": err, "per_replica": per_replica, "T": T, "status": status,
            "rule": f"replicas in rounds of {T_round:g}: converged when stderr <= {target_rel:g} lambda_1; regular "
                    f"when lambda_1 + {sigma:g} stderr < {degree:g} ln(T / tau) / T <= {regular_floor:g}; capped after "
                    f"{max_rounds} rounds",
            "history": np.array(history), "log_growth": np.concatenate(growth),
            "states": np.concatenate(states), "final_state": r["final_state"],
            "wall_time_s": time.perf_counter() - start}


def scipy_benettin(params, y0, k: int, *, T: float, tau: float, method: str, rtol: float, atol: float,
                   t_align: float = 0.0, compiled: bool = True, seed: int = 0) -> dict:
    """Benettin's method with a SciPy solver on the flow plus k tangent vectors (the variational
    equations compiled by heyoka, or with ``compiled=False`` J(y) V from the lambdified Jacobian),
    integrated in segments of tau, QR-renormalised after each; delta reduced by whole turns between
    segments. The same initial directions as :func:`benettin`. Returns exponents (k,), the final
    state and the wall time."""
    from scipy.integrate import solve_ivp

    from sleighsim.model import equations

    if compiled:
        f = integrators.rhs_function(k=k, params=params)
        rhs = lambda t, z: f(z)  # noqa: E731
    else:
        def rhs(t, z):
            V = z[4:].reshape(4, k)
            return np.concatenate([equations.rhs(z[:4], params), (equations.jacobian(z[:4], params) @ V).ravel()])
    z = np.r_[np.asarray(y0, float), initial_directions(4, k, seed).ravel()]
    total, n_align, n = np.zeros(k), int(math.ceil(t_align / tau)), int(round(T / tau))
    start = time.perf_counter()
    for i in range(-n_align, n):
        sol = solve_ivp(rhs, (0.0, tau), z, method=method, rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(f"SciPy {method} Lyapunov run failed: {sol.message}")
        z = sol.y[:, -1]
        z[3] %= 2.0 * math.pi  # an exact symmetry: delta stays bounded
        q, r = np.linalg.qr(z[4:].reshape(4, k))
        z[4:] = q.ravel()
        if i >= 0:
            total += np.log(np.abs(np.diag(r)))
    return {"exponents": total / (n * tau), "final_state": z[:4].copy(), "wall_time_s": time.perf_counter() - start}
