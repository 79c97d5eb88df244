"""Many sleigh orbits at once in double-double: the Taylor engine of :mod:`sleighsim.engine.ddtaylor` over lanes,
the lanes the innermost (vectorised) dimension of its arrays (kernels in :mod:`sleighsim.engine.ddlanes`).

A lane is one orbit (u, Omega, omega, delta), with one tangent vector in the tangent variant: a realization, a
replica, a row of a parameter sweep (each lane may have its own parameters), a start of a stability test.
Each lane performs the scalar engine's arithmetic exactly, so with per-lane steps (the default, ``step="lane"``)
its results are bit for bit DDFlow's from the same state; ``step="common"`` gives every lane the smallest of
their steps (each lane's own heyoka rule, then the minimum), which only adds steps.

Conventions as DDFlow: states (hi, lo) pairs of doubles, delta as the model's angle (reduced into [-pi, pi)
at step ends), times in the flow's time unit from the initial state; arrays are indexed [lane, time, variable].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import cache

import numpy as np

from sleighsim.engine import ddarith as dd
from sleighsim.engine import ddlanes
from sleighsim.engine.ddprogram import coefficients, program, taylor_order
from sleighsim.engine.ddtaylor import MAX_STEPS, TOL_RANGE, as_pair, check_grid, shift_angle
from sleighsim.engine.progress import watched
from sleighsim.model.params import Params, integer, positive

#: Most lanes one batch takes (the series arrays of the tangent program at 1e-34: 71 kB per lane).
MAX_LANES = 1024


def host_vector_doubles() -> int:
    """Doubles in the host CPU's widest vector register: 8 with AVX-512 (avx512f), else 4 (AVX2's 256 bits)."""
    from llvmlite import binding

    return 8 if binding.get_host_cpu_features().get("avx512f") else 4


#: Widest block of lanes evaluated together in vectors: two of the host's vector registers per value (16 doubles
#: with AVX-512, 8 with AVX2, where a block of 16 spills its registers and costs several times one of 8). A lane's
#: numbers do not depend on the width (tested).
MAX_WIDTH = 2 * host_vector_doubles()
#: Step control: each lane its own step, or the smallest of them for every lane.
STEPS = ("lane", "common")
_WHY = {ddlanes.TOO_MANY_STEPS: "more than max_steps steps", ddlanes.NOT_FINITE: "a non-finite step or state"}


@cache
def _coefficients(tangent: bool, params: Params) -> np.ndarray:
    """ddprogram.coefficients of the program (with the tangent or not) for ``params``, once per process."""
    return coefficients(program(tangent), params)


def block_width(lanes: int) -> int:
    """The vector width W of a batch: the power of two at or above ``lanes``, at most MAX_WIDTH; lanes are
    evaluated in blocks of W, the last padded (the padding's results are dropped)."""
    return min(MAX_WIDTH, 1 << (lanes - 1).bit_length())


class LaneError(RuntimeError):
    """A lane failed: ``lane`` its index, ``time`` the time it reached, ``reason``; ``status`` every lane's
    ddlanes status (the others RUNNING when stopped unfinished, OK when done) and ``steps`` theirs."""

    def __init__(self, lane: int, time: float, reason: str, status: np.ndarray, steps: np.ndarray):
        unfinished = int(np.sum(status == ddlanes.RUNNING))
        super().__init__(f"double-double Taylor integration failed in lane {lane} at t = {time:.17g}: {reason} "
                         f"({unfinished} other lanes stopped unfinished)")
        self.lane, self.time, self.reason, self.status, self.steps = lane, time, reason, status, steps


def as_pairs(y, n: int = 4, name: str = "y0") -> tuple[np.ndarray, np.ndarray]:
    """States of all lanes as pairs (hi, lo), each (lanes, n): from a (hi, lo) tuple of such arrays, or from an
    array (lanes, n) of doubles, long doubles or real128 (rows as ddtaylor.as_pair). ValueError naming ``name``
    on a wrong shape, a lane count outside [1, MAX_LANES] or a non-finite component."""
    if isinstance(y, tuple) and len(y) == 2:
        rows = list(zip(*(np.asarray(a, dtype=float) for a in y)))
    else:
        rows = list(np.asarray(y))
    if not 1 <= len(rows) <= MAX_LANES:
        raise ValueError(f"{name} must hold the states of 1 to {MAX_LANES} lanes, got {len(rows)}")
    try:
        pairs = [as_pair(r if isinstance(r, tuple) else np.asarray(r), n) for r in rows]
    except ValueError as err:
        raise ValueError(f"{name}: {err}") from None
    return np.array([a for a, _ in pairs]), np.array([b for _, b in pairs])


def lane_grid(t_grid, lanes: int) -> np.ndarray:
    """The sample times (lanes, n): a grid (n,) shared by all lanes or one per lane (lanes, n), each as
    ddtaylor.check_grid requires (finite, >= 0, non-decreasing, at least one)."""
    grid = np.array(t_grid, dtype=float)
    if grid.ndim == 2 and grid.shape[0] != lanes:
        raise ValueError(f"t_grid has {grid.shape[0]} rows for {lanes} lanes")
    rows = grid if grid.ndim == 2 else [grid] * lanes
    return np.array([check_grid(r) for r in rows])


def lane_settings(params, tol: float, tol_range: tuple, step: str, max_steps: int) -> tuple:
    """A batch engine's settings checked (ValueError naming the setting): (tol within ``tol_range``, whether
    ``params`` is one Params per lane, the lanes' Params as a tuple of 1 to MAX_LANES, max_steps); ``step``
    one of STEPS."""
    tol = positive("tol", tol)
    if not tol_range[0] <= tol <= tol_range[1]:
        raise ValueError(f"tol = {tol:g} is outside the admissible range [{tol_range[0]:g}, {tol_range[1]:g}]")
    if step not in STEPS:
        raise ValueError(f"step = {step!r}: choose one of {STEPS}")
    per_lane = not isinstance(params, Params)
    lanes = tuple(params) if per_lane else (params,)
    if not 1 <= len(lanes) <= MAX_LANES or not all(isinstance(p, Params) for p in lanes):
        raise ValueError(f"params must be a Params or a sequence of 1 to {MAX_LANES} Params (one per lane)")
    return tol, per_lane, lanes, integer("max_steps", max_steps, 1, 2**62)


class DDBatch:
    """Lanes of the sleigh integrated in double-double at tolerance ``tol`` (in TOL_RANGE; heyoka's order and
    step rule), each lane as DDFlow would. ``params``: one Params for every lane, or a sequence of Params, one
    per lane (then it fixes the lane count). ``step``: "lane" (each lane its own step: bit for bit DDFlow) or
    "common". ``steps`` holds each lane's step count of the last propagation. A lane that exceeds max_steps
    or meets a non-finite step or state stops the batch: LaneError naming it and its time."""

    def __init__(self, params: Params | Sequence[Params], tol: float = 1e-32, *, max_steps: int = MAX_STEPS,
                 step: str = "lane"):
        self.tol, self.per_lane, self.params, self.max_steps = lane_settings(params, tol, TOL_RANGE, step, max_steps)
        self.order, self.step = taylor_order(self.tol), step
        self.steps = np.zeros(0, dtype=np.int64)
        self._coef = {}

    @property
    def lanes(self) -> int | None:
        """The lane count fixed by per-lane params (None: any)."""
        return len(self.params) if self.per_lane else None

    def _lanes(self, hi) -> int:
        if self.per_lane and hi.shape[0] != len(self.params):
            raise ValueError(f"y0 holds {hi.shape[0]} lanes, params {len(self.params)}")
        return hi.shape[0]

    def _blocks(self, L: int):
        """Index arrays of the lanes of each block of W (the last padded with its first lane) and W."""
        W = block_width(L)
        blocks = [np.arange(start, min(start + W, L)) for start in range(0, L, W)]
        return [np.r_[idx, np.full(W - idx.size, idx[0])] for idx in blocks], W

    def _setup(self, yh, yl, idx, tangent: bool):
        """For the lanes ``idx`` (a block): the program, the series arrays [series, order, lane], the lanes'
        coefficients [term, lane] and stored states [variable, lane] (delta + pi reduced into [0, 2 pi))."""
        prog, W = program(tangent), idx.size
        Xh, Xl = np.zeros((prog.n_series, self.order + 1, W)), np.zeros((prog.n_series, self.order + 1, W))
        Xh[prog.one, 0] = 1.0
        if tangent not in self._coef:
            self._coef[tangent] = np.array([_coefficients(tangent, p) for p in self.params])
        coef = self._coef[tangent][idx if self.per_lane else np.zeros(W, dtype=int)]
        ch, cl = np.ascontiguousarray(coef[:, :, 0].T), np.ascontiguousarray(coef[:, :, 1].T)
        yh, yl = np.ascontiguousarray(yh[idx].T), np.ascontiguousarray(yl[idx].T)
        for lane in range(W):
            yh[3, lane], yl[3, lane] = dd.reduce_angle(*dd.sub_triple(yh[3, lane], yl[3, lane], dd.PI, -1))
        return prog, Xh, Xl, ch, cl, yh, yl

    def jet(self, y0, v0=None) -> tuple[np.ndarray, np.ndarray]:
        """(hi, lo), each (lanes, 4 or 8, order + 1): DDFlow.jet of every lane."""
        yh, yl = self._states(y0, v0)
        blocks, W = self._blocks(yh.shape[0])
        hi, lo = [], []
        for idx in blocks:
            prog, Xh, Xl, ch, cl, bh, bl = self._setup(yh, yl, idx, v0 is not None)
            ddlanes.jet(Xh, Xl, prog.ops, prog.lin_src, ch, cl, self.order, prog.n_vars, bh, bl, (0.0,) * W)
            hi.append(Xh[: prog.n_vars].transpose(2, 0, 1))
            lo.append(Xl[: prog.n_vars].transpose(2, 0, 1))
        L = yh.shape[0]
        return np.concatenate(hi)[:L].copy(), np.concatenate(lo)[:L].copy()

    def _states(self, y0, v0):
        yh, yl = as_pairs(y0)
        self._lanes(yh)
        if v0 is None:
            return yh, yl
        vh, vl = as_pairs(v0, name="v0")
        if vh.shape != yh.shape:
            raise ValueError(f"v0 holds {vh.shape[0]} lanes, y0 {yh.shape[0]}")
        if not np.all(np.any(vh != 0, axis=1)):
            raise ValueError("every lane's tangent vector v0 must be non-zero")
        return np.c_[yh, vh], np.c_[yl, vl]

    def _run(self, yh, yl, t_grid, tangent: bool):
        """Every block in turn; LaneError at the first lane that fails (the later blocks not started)."""
        L = yh.shape[0]
        grid = lane_grid(t_grid, L)
        blocks, W = self._blocks(L)
        n_vars = program(tangent).n_vars
        out_h, out_l = np.empty((L, grid.shape[1], n_vars)), np.empty((L, grid.shape[1], n_vars))
        out_e = np.empty((L, grid.shape[1]), dtype=np.int64)
        status, self.steps = np.full(L, ddlanes.RUNNING, dtype=np.int64), np.zeros(L, dtype=np.int64)
        for b, idx in enumerate(blocks):
            real = slice(0, min(W, L - b * W))
            lanes = idx[real]
            bh, bl, be, bs, bn, bt = self._run_block(yh, yl, grid, idx, real, tangent)
            status[lanes], self.steps[lanes] = bs[real], bn[real]
            if np.any(bs[real] > ddlanes.RUNNING):
                first = int(np.flatnonzero(bs[real] > ddlanes.RUNNING)[0])
                raise LaneError(int(lanes[first]), float(bt[first]), _WHY[int(bs[first])], status, self.steps.copy())
            out_h[lanes], out_l[lanes], out_e[lanes] = bh[real], bl[real], be[real]
        shift_angle(out_h.reshape(-1, n_vars), out_l.reshape(-1, n_vars), 1)
        return out_h, out_l, out_e

    def _run_block(self, yh, yl, grid, idx, real, tangent: bool):
        """One block's outputs [lane, time, variable], scales, statuses, steps and times."""
        prog, Xh, Xl, ch, cl, bh, bl = self._setup(yh, yl, idx, tangent)
        W, n = idx.size, grid.shape[1]
        out_h, out_l = np.empty((W, n, prog.n_vars)), np.empty((W, n, prog.n_vars))
        out_e = np.zeros((W, n), dtype=np.int64)
        status = np.full(W, ddlanes.OK, dtype=np.int64)
        status[real] = ddlanes.RUNNING
        steps, t = np.zeros(W, dtype=np.int64), np.zeros(W)
        times = np.ascontiguousarray(grid[idx])
        watched(lambda: ddlanes.propagate(Xh, Xl, prog.ops, prog.lin_src, ch, cl, self.order, bh, bl, times, out_h,
                                          out_l, out_e, self.max_steps, self.step == "common", status, steps, t,
                                          (0.0,) * W),
                t[real], times[real, -1], f"double-double, {_lanes_text(times[real].shape[0])}")
        return out_h, out_l, out_e, status, steps, t

    def propagate_grid(self, y0, t_grid) -> tuple[np.ndarray, np.ndarray]:
        """(hi, lo), each (lanes, n, 4): every lane's states at its grid times (t_grid (n,) for all lanes or
        (lanes, n)), as DDFlow.propagate_grid."""
        yh, yl = self._states(y0, None)
        return self._run(yh, yl, t_grid, tangent=False)[:2]

    def propagate_grids(self, y0, grids) -> list[tuple[np.ndarray, np.ndarray]]:
        """One orbit from y0 (4,) sampled on each of ``grids`` (time units from y0), each grid a lane started
        from y0, so each grid's samples are bit for bit DDFlow.propagate_grid's on it, at about the price of one
        orbit up to a block of MAX_WIDTH lanes (benchmarks/ddbatch.yaml). The grids are padded to one length by
        repeating their last time (the padding's samples dropped). Returns each grid's (hi, lo), each (n, 4)."""
        rows = [check_grid(g) for g in grids]
        n = max(r.size for r in rows)
        padded = np.array([np.r_[r, np.full(n - r.size, r[-1])] for r in rows])
        hi, lo = self.propagate_grid(np.tile(np.asarray(y0, dtype=float)[:4], (len(rows), 1)), padded)
        return [(hi[i, : r.size], lo[i, : r.size]) for i, r in enumerate(rows)]

    def propagate(self, y0, T) -> tuple[np.ndarray, np.ndarray]:
        """(hi, lo), each (lanes, 4): every lane's state a time T after its y0 (T a number or one per lane)."""
        yh, _ = as_pairs(y0)
        T = np.broadcast_to(np.asarray(T, dtype=float), (yh.shape[0],))
        grid = np.array([[positive("T", x)] for x in T])
        hi, lo = self.propagate_grid(y0, grid)
        return hi[:, 0], lo[:, 0]

    def propagate_tangent_grid(self, y0, v0, t_grid):
        """Every lane's orbit and tangent vector from (y0, v0) (each (lanes, 4)), as
        DDFlow.propagate_tangent_grid: (hi, lo) (lanes, n, 4), log_norm (lanes, n), direction (lanes, n, 4)."""
        yh, yl = self._states(y0, v0)
        out_h, out_l, out_e = self._run(yh, yl, t_grid, tangent=True)
        v = out_h[:, :, 4:] + out_l[:, :, 4:]
        norm = np.linalg.norm(v, axis=2)
        return out_h[:, :, :4], out_l[:, :, :4], out_e * math.log(2.0) + np.log(norm), v / norm[:, :, None]


def _lanes_text(n: int) -> str:
    """'1 lane', 'n lanes'."""
    return f"{n} lane" + ("" if n == 1 else "s")
