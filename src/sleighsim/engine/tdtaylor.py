"""The sleigh's Taylor integrator in triple-double (:mod:`sleighsim.engine.tdarith`, about 159 bits, rounding
below 2^-150): the double-double engine's derived program (:mod:`sleighsim.engine.ddprogram`), order and step rule
(heyoka's), stored angle (delta + pi, reduced into [0, 2 pi) after every step) and optional tangent vector, over
lanes like :class:`sleighsim.engine.ddbatch.DDBatch` (kernels in :mod:`sleighsim.engine.tdlanes`). For orbits that
double-double cannot follow: a spike cycle whose tangent map's gain G reaches e^76 needs rounding well below
1/G ~ 1e-33.

States are triples: arrays [..., 3] of components (value = their sum); states given as numbers (doubles, long
doubles, real128, mpmath numbers, Fractions, decimal strings) are split exactly or to the nearest triple. Times in
the flow's time unit from the initial state; results indexed [lane, time, variable, component].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from functools import cache

import mpmath
import numpy as np

from sleighsim.engine import ddlanes, tdlanes
from sleighsim.engine import tdarith as td
from sleighsim.engine.ddbatch import MAX_LANES, LaneError, block_width, lane_grid, lane_settings
from sleighsim.engine.ddprogram import exact_coefficients, program, taylor_order
from sleighsim.engine.ddtaylor import MAX_STEPS
from sleighsim.model.params import Params, positive

#: Admissible tolerances: from a little below triple-double's rounding to a loose one.
TOL_RANGE = (1e-49, 1e-6)
_WHY = {ddlanes.TOO_MANY_STEPS: "more than max_steps steps", ddlanes.NOT_FINITE: "a non-finite step or state"}


def _triple(v) -> tuple[float, float, float]:
    if isinstance(v, float | int | np.floating) and not isinstance(v, np.longdouble):
        return float(v), 0.0, 0.0
    if isinstance(v, np.longdouble):
        return td.expansion(Fraction(*v.as_integer_ratio()))
    if isinstance(v, mpmath.mpf):
        return td.expansion(v)
    with mpmath.workprec(400):
        return td.expansion(mpmath.mpf(str(v)))


def as_triples(y, n: int = 4, name: str = "y0") -> np.ndarray:
    """States of all lanes as triples, (lanes, n, 3): from an array (lanes, n, 3) of components, or from rows of
    numbers (doubles exactly; long doubles, mpmath numbers, heyoka's real128 and real through their values).
    ValueError naming ``name`` on a wrong shape, a lane count outside [1, MAX_LANES] or a non-finite component."""
    arr = np.asarray(y)
    if arr.ndim == 3 and arr.shape[2] == 3 and arr.dtype == float:
        out = arr.astype(float)
    elif arr.ndim == 2:
        out = np.array([[_triple(v) for v in row] for row in arr], dtype=float).reshape(*arr.shape, 3)
    else:
        raise ValueError(f"{name} must be (lanes, {n}) numbers or (lanes, {n}, 3) components, got shape {arr.shape}")
    if not 1 <= out.shape[0] <= MAX_LANES or out.shape[1] != n:
        raise ValueError(f"{name} must hold the states ({n} components) of 1 to {MAX_LANES} lanes, got {out.shape}")
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{name}: the states must be finite")
    return out


@cache
def _coefficients(tangent: bool, params: Params) -> np.ndarray:
    """The program's coefficients for ``params`` as triples (terms, 3), once per process."""
    return np.array([td.expansion(v) for v in exact_coefficients(program(tangent), params)])


class TDBatch:
    """Lanes of the sleigh integrated in triple-double at tolerance ``tol`` (in TOL_RANGE), as DDBatch does in
    double-double: ``params`` one Params or one per lane, ``step`` "lane" or "common", ``steps`` per lane;
    a lane that exceeds max_steps or meets a non-finite step or state raises LaneError naming it."""

    def __init__(self, params: Params | Sequence[Params], tol: float = 1e-47, *, max_steps: int = MAX_STEPS,
                 step: str = "lane"):
        self.tol, self.per_lane, self.params, self.max_steps = lane_settings(params, tol, TOL_RANGE, step, max_steps)
        self.order, self.step = taylor_order(self.tol), step
        self.steps = np.zeros(0, dtype=np.int64)

    def _states(self, y0, v0):
        y = as_triples(y0)
        if self.per_lane and y.shape[0] != len(self.params):
            raise ValueError(f"y0 holds {y.shape[0]} lanes, params {len(self.params)}")
        if v0 is None:
            return y
        v = as_triples(v0, name="v0")
        if v.shape != y.shape:
            raise ValueError(f"v0 holds {v.shape[0]} lanes, y0 {y.shape[0]}")
        if not np.all(np.any(v[:, :, 0] != 0, axis=1)):
            raise ValueError("every lane's tangent vector v0 must be non-zero")
        return np.concatenate([y, v], axis=1)

    def _setup(self, y, idx, tangent: bool):
        """For a block of lanes ``idx``: the program, X [series, order, component, lane], K [term, component,
        lane] and the stored states [variable, component, lane] (delta + pi reduced into [0, 2 pi))."""
        prog, W = program(tangent), idx.size
        X = np.zeros((prog.n_series, self.order + 1, 3, W))
        X[prog.one, 0, 0] = 1.0
        K = np.array([_coefficients(tangent, self.params[i if self.per_lane else 0]) for i in idx])
        K = np.ascontiguousarray(K.transpose(1, 2, 0))
        ys = np.ascontiguousarray(y[idx].transpose(1, 2, 0))
        for lane in range(W):
            ys[3, :, lane] = td.reduce_angle(*td.sub_expansion(*ys[3, :, lane], td.PI4, -1))
        return prog, X, K, ys

    def _blocks(self, L: int):
        W = block_width(L)
        blocks = [np.arange(start, min(start + W, L)) for start in range(0, L, W)]
        return [np.r_[idx, np.full(W - idx.size, idx[0])] for idx in blocks], W

    def jet(self, y0, v0=None) -> np.ndarray:
        """(lanes, 4 or 8, order + 1, 3): the normalised Taylor coefficients of every lane at its state."""
        y = self._states(y0, v0)
        blocks, W = self._blocks(y.shape[0])
        out = []
        for idx in blocks:
            prog, X, K, ys = self._setup(y, idx, v0 is not None)
            tdlanes.jet(X, prog.ops, prog.lin_src, K, self.order, prog.n_vars, ys, (0.0,) * W)
            out.append(X[: prog.n_vars].transpose(3, 0, 1, 2))
        return np.concatenate(out)[: y.shape[0]].copy()

    def _run(self, y, t_grid, tangent: bool):
        """Every block in turn: out [lane, time, variable, component], the tangent's scale exponents."""
        L = y.shape[0]
        grid = lane_grid(t_grid, L)
        blocks, W = self._blocks(L)
        n_vars = program(tangent).n_vars
        out, out_e = np.empty((L, grid.shape[1], n_vars, 3)), np.empty((L, grid.shape[1]), dtype=np.int64)
        status, self.steps = np.full(L, ddlanes.RUNNING, dtype=np.int64), np.zeros(L, dtype=np.int64)
        for b, idx in enumerate(blocks):
            real = slice(0, min(W, L - b * W))
            lanes = idx[real]
            prog, X, K, ys = self._setup(y, idx, tangent)
            bo, be = np.empty((W, grid.shape[1], n_vars, 3)), np.zeros((W, grid.shape[1]), dtype=np.int64)
            bs, bn, bt = np.full(W, ddlanes.OK, dtype=np.int64), np.zeros(W, dtype=np.int64), np.zeros((3, W))
            bs[real] = ddlanes.RUNNING
            tdlanes.propagate(X, prog.ops, prog.lin_src, K, self.order, ys, np.ascontiguousarray(grid[idx]), bo, be,
                              self.max_steps, self.step == "common", bs, bn, bt, (0.0,) * W)
            status[lanes], self.steps[lanes] = bs[real], bn[real]
            if np.any(bs[real] > ddlanes.RUNNING):
                first = int(np.flatnonzero(bs[real] > ddlanes.RUNNING)[0])
                raise LaneError(int(lanes[first]), float(bt[0, first]), _WHY[int(bs[first])], status,
                                self.steps.copy())
            out[lanes], out_e[lanes] = bo[real], be[real]
        for r in out.reshape(-1, n_vars, 3):
            r[3] = td.sub_expansion(*r[3], td.PI4, 1)
        return out, out_e

    def propagate_grid(self, y0, t_grid) -> np.ndarray:
        """(lanes, n, 4, 3): every lane's states at its grid times (t_grid (n,) or (lanes, n); delta as integrated
        between the step ends, where it is reduced into [-pi, pi))."""
        return self._run(self._states(y0, None), t_grid, tangent=False)[0]

    def propagate(self, y0, T) -> np.ndarray:
        """(lanes, 4, 3): every lane's state a time T after its y0 (T a number or one per lane)."""
        y = self._states(y0, None)
        T = np.broadcast_to(np.asarray(T, dtype=float), (y.shape[0],))
        return self._run(y, np.array([[positive("T", x)] for x in T]), tangent=False)[0][:, 0]

    def propagate_tangent_grid(self, y0, v0, t_grid):
        """Every lane's orbit and tangent vector: states (lanes, n, 4, 3), log_norm (lanes, n) the natural log of
        the tangent vector's norm, direction (lanes, n, 4) the unit tangent vector (doubles)."""
        out, out_e = self._run(self._states(y0, v0), t_grid, tangent=True)
        v = out[:, :, 4:].sum(axis=3)
        norm = np.linalg.norm(v, axis=2)
        return out[:, :, :4], out_e * math.log(2.0) + np.log(norm), v / norm[:, :, None]
