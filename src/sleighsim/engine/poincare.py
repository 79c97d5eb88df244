"""Poincare sections delta = n pi/2 by heyoka event detection, and their analysis.

One non-terminal event, sin(2 delta) = 0, fires at every delta = k pi/2; the map
P_pi/2 keeps all crossings and P_2pi those with k = 0 mod 4. The state at each
crossing comes from heyoka's dense output at the event time (not from
interpolating samples). delta is reduced to [0, 2 pi) after every step (an exact
symmetry, sleighsim.engine.integrators.bounded), so the crossing residual |delta - k pi/2|
stays at rounding level; the integrator's clock restarts at 0 every chunk (the flow
is autonomous) and the offset is kept apart: an event time near t = 3e4 has a
rounding error of 4e-12, which would put delta 1e-11 off the section.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np

from sleighsim.engine import ddsection, integrators
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.engine.integrate import IntegrationError, check_tol
from sleighsim.model.params import Params
from sleighsim.precision import Precision

log = logging.getLogger("sleighsim")
TWO_PI = 2.0 * math.pi


def crossings(params: Params, y0, t0: float, t_end: float, *, tol: float = 2.0**-52,
              precision: Precision = Precision.DOUBLE, scene: str = "", progress: int = 20) -> dict:
    """All crossings of delta = k pi/2 for t in (t0, t_end], starting from y0 at t0, integrated in
    ``precision`` at ``tol``; the crossings are returned in double.

    Returns arrays: time, u, Omega, omega, k (the multiple of pi/2 of the reduced delta, so
    k mod 4 is the section class), residual |delta - k pi/2| (rad); plus steps, wall_time_s,
    compile_time_s, backend and method. Double-double (which heyoka does not have) is :func:`dd_crossings`.
    """
    import heyoka as hy

    if not (math.isfinite(t0) and math.isfinite(t_end) and t_end > t0):
        raise ValueError(f"t_end = {t_end} is outside the admissible range (t0 = {t0}, inf): crossings need t_end > t0")
    if Precision.parse(precision) is Precision.DOUBLE_DOUBLE:
        return dd_crossings(params, y0, t0, t_end, tol=tol, scene=scene)
    check_tol(tol, precision)
    ta, compile_s = integrators.events(tol, precision)
    fp = ta.state.dtype.type
    callback = integrators.bounded(ta)
    rec = ta.nt_events[0].callback
    rec.hits.clear()
    rec.offset = float(t0)
    y0 = np.array(y0, dtype=float)
    y0[3] %= TWO_PI
    integrators.load(ta, y0)
    integrators.set_pars(ta, params)
    start, steps, next_report = time.perf_counter(), 0, t0
    report_every = (t_end - t0) / max(1, progress)
    while rec.offset < t_end:
        rate = abs(ta.state[1] - ta.state[2]) + 1e-3
        span = min(t_end - rec.offset, 20.0 * math.pi / float(rate))
        ta.time = fp(0)
        y_before = integrators.read(ta, 4).astype(float)
        res = ta.propagate_until(fp(span), callback=callback)
        steps += res[3]
        if res[0] != hy.taylor_outcome.time_limit or not np.all(np.isfinite(ta.state)):
            raise IntegrationError(f"scene {scene or '?'}: integration failed at t = {rec.offset:.6g}, "
                                   f"state = {y_before.tolist()}: heyoka outcome {res[0].name}")
        rec.offset = t_end if span == t_end - rec.offset else rec.offset + span
        if rec.offset >= next_report:
            log.info("%s: t = %.6g / %.6g, %d crossings", scene, rec.offset, t_end, len(rec.hits))
            next_report += report_every
    hits = np.array([[float(v) for v in h] for h in rec.hits], dtype=float).reshape(-1, 6)
    hits = hits[hits[:, 0] > 0]  # a crossing exactly at a chunk start was recorded by the chunk before
    hits[:, 1:5] = integrators.samples(ta, hits[:, 1:5])
    k = np.round(hits[:, 4] / (math.pi / 2))
    return {
        "time": hits[:, 5] + hits[:, 0], "u": hits[:, 1], "Omega": hits[:, 2], "omega": hits[:, 3],
        "k": k.astype(np.int64) % 4, "residual": np.abs(hits[:, 4] - k * (math.pi / 2)),
        "steps": steps, "wall_time_s": time.perf_counter() - start, "compile_time_s": compile_s,
        "backend": "heyoka", "method": "taylor_adaptive + nt_event sin(2 delta)",
    }


#: The longest sampling step (time units) of a double-double orbit whose section crossings are solved on the
#: jets: a crossing at most DD_SAMPLE_DT / 2 from its sample (:func:`dd_sample_dt` shortens it for a fast rotor).
DD_SAMPLE_DT = 0.1


def dd_sample_dt(y0) -> float:
    """The sampling step of :func:`dd_crossings` from the start ``y0``: DD_SAMPLE_DT, shortened so that delta
    turns at most an eighth of a turn per step at the start's rate |Omega - omega| (each crossing of delta = k
    pi/2 then has its own step; :func:`dd_crossings` checks the whole orbit)."""
    rate = abs(float(y0[1]) - float(y0[2]))
    return min(DD_SAMPLE_DT, 0.25 * math.pi / rate) if rate > 0 else DD_SAMPLE_DT


def dd_crossings(params: Params, y0, t0: float, t_end: float, *, tol: float, scene: str = "",
                 samples=None) -> dict:
    """:func:`crossings` in double-double (sleighsim.engine.ddtaylor at ``tol``): the orbit sampled every
    DD_SAMPLE_DT, each crossing solved on the double-double Taylor jet of its nearest sample
    (:func:`sleighsim.engine.ddsection.quarter_crossings`); returned in double, with the same keys. With
    ``samples`` (absolute times from t0 on), also the orbit at those times (key "samples": (n, 4) states in
    double, hi + lo) from the same integration: a second lane of one DDBatch (``DDBatch.propagate_grids``), bit
    for bit a run of its own, at about the price of one orbit."""
    start = time.perf_counter()
    dt = dd_sample_dt(y0)
    grid = np.arange(0.0, t_end - t0 + 0.5 * dt, dt)
    log.info("%s: double-double orbit over %.6g time units, sampled every %.3g%s", scene, t_end - t0, dt,
             "" if samples is None else f" and at {len(samples)} further times (a second lane)")
    batch = DDBatch(params, tol)
    orbits = batch.propagate_grids(y0, [grid] + ([] if samples is None else [np.asarray(samples, float) - t0]))
    (hi, lo), steps = orbits[0], int(batch.steps[0])
    turn = float(np.max(np.abs(np.diff(ddsection.unwrapped_delta(hi, grid))), initial=0.0))
    if turn >= 0.5 * math.pi:
        raise RuntimeError(f"{scene}: delta turned {turn:.3g} rad between samples {dt:.3g} apart (more than a "
                           "quarter turn: crossings would be missed); the orbit's rotor speeds up beyond its start's")
    t, x, k, residual = ddsection.quarter_crossings(batch, hi, lo, grid)
    keep = (t > 1e-9) & (t <= t_end - t0)  # a crossing at the start is not one (as heyoka's events)
    out = {"time": t0 + t[keep], "u": x[keep, 0], "Omega": x[keep, 1], "omega": x[keep, 2], "k": k[keep],
           "residual": residual[keep], "steps": steps, "wall_time_s": time.perf_counter() - start,
           "compile_time_s": 0.0, "backend": "sleighsim.engine.ddtaylor",
           "method": f"double-double Taylor sampled every {dt:.3g}, crossings solved on the jets"}
    if samples is not None:
        out["samples"] = orbits[1][0] + orbits[1][1]
    return out


def rotation_number(points) -> dict:
    """Mean angular advance per iterate (in turns, unsigned) of points on a closed curve.

    The points (n, d) are standardised and projected onto their two leading
    principal axes; angles are taken about the centroid, advances wrapped to
    (-pi, pi]; the sign is dropped because the orientation of the projection
    plane is arbitrary. Returned for the whole run and for each half, with the standard
    deviation of the advances: a well-defined, stable value indicates an
    invariant circle (quasi-periodic motion), a drifting or noisy one does not.
    """
    X = np.asarray(points, float)
    Z = (X - X.mean(0)) / (X.std(0) + 1e-300)
    _, _, vt = np.linalg.svd(Z, full_matrices=False)
    P = Z @ vt[:2].T
    ang = np.arctan2(P[:, 1], P[:, 0])
    adv = np.angle(np.exp(1j * np.diff(ang)))
    half = len(adv) // 2
    return {
        "rotation_number": float(abs(adv.mean()) / TWO_PI),
        "rotation_number_first_half": float(abs(adv[:half].mean()) / TWO_PI),
        "rotation_number_second_half": float(abs(adv[half:].mean()) / TWO_PI),
        "advance_std_turns": float(adv.std() / TWO_PI),
    }


def curve_thickness(points, bins: int = 180) -> float:
    """How far points are from a single closed curve: the median absolute deviation of the
    radius within angular bins (principal plane, about the centroid), over the median radius."""
    X = np.asarray(points, float)
    Z = (X - X.mean(0)) / (X.std(0) + 1e-300)
    _, _, vt = np.linalg.svd(Z, full_matrices=False)
    P = Z @ vt[:2].T
    r, ang = np.hypot(P[:, 0], P[:, 1]), np.arctan2(P[:, 1], P[:, 0])
    idx = np.minimum(((ang + math.pi) / TWO_PI * bins).astype(int), bins - 1)
    dev = np.empty_like(r)
    for b in np.unique(idx):
        sel = idx == b
        dev[sel] = np.abs(r[sel] - np.median(r[sel]))
    return float(np.median(dev) / np.median(r))


def recurrence(points, q_max: int = 50) -> float:
    """How close the iterates come to repeating: the smallest, over q = 1..q_max, of the median
    distance |x_{n+q} - x_n| in units of the set's size (RMS distance to its centroid). About 0 for
    a periodic orbit of period <= q_max; of order 1/q_max or more for iterates filling a curve."""
    X = np.asarray(points, float)
    size = float(np.sqrt(np.mean(np.sum((X - X.mean(0)) ** 2, axis=1))))
    q_max = min(q_max, len(X) - 1)
    if q_max < 1 or size == 0:
        return float("nan")
    return float(min(np.median(np.linalg.norm(X[q:] - X[:-q], axis=1)) for q in range(1, q_max + 1)) / size)


def flatness(points) -> float:
    """Smallest over largest singular value of the centred point cloud: 0 for a planar set."""
    X = np.asarray(points, float)
    s = np.linalg.svd(X - X.mean(0), compute_uv=False)
    return float(s[-1] / s[0])


def knn_components(points, k: int = 10, min_fraction: float = 0.01) -> tuple[int, np.ndarray]:
    """Connected components of the symmetric k-nearest-neighbour graph of the
    standardised points (scale-free: thin curves sampled with any density stay
    connected, separate curves stay apart). Returns (number of components holding
    at least ``min_fraction`` of the points, label per point)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    X = np.asarray(points, float)
    Z = (X - X.mean(0)) / (X.std(0) + 1e-300)
    n = len(Z)
    k = min(k, n - 1)
    idx = cKDTree(Z).query(Z, k=k + 1)[1][:, 1:]
    graph = coo_matrix((np.ones(n * k), (np.repeat(np.arange(n), k), idx.ravel())), shape=(n, n))
    _, labels = connected_components(graph, directed=False)
    return int(np.sum(np.bincount(labels) >= min_fraction * n)), labels


def count_loops(points, classes, k: int = 10) -> dict:
    """Loops of P_pi/2: the iterates of each section class (delta = k pi/2 mod 2 pi)
    are split into k-NN graph components (:func:`knn_components`); the loop count
    is the sum over classes. Also returns the components of all points together
    in the (u, Omega, omega) projection, where loops of different classes may cross."""
    classes = np.asarray(classes)
    per_class = {int(c): knn_components(np.asarray(points)[classes == c], k)[0] for c in np.unique(classes)}
    n_projected, labels = knn_components(points, k)
    return {"n_loops": sum(per_class.values()), "loops_per_class": per_class,
            "n_components_projected": n_projected, "labels": labels}


def min_pairwise_difference(x) -> float:
    """Smallest |x_i - x_j| over i != j (sort, then adjacent differences)."""
    s = np.sort(np.asarray(x, float))
    return float(np.min(np.diff(s))) if s.size > 1 else float("nan")


def scaled_set_distance(ref_points, ref_classes, other_points, other_classes, c: float) -> dict:
    """Distance from ``other_points / c`` (velocities) to the nearest reference iterate of the
    same class, in units of the reference attractor's size (RMS distance to its centroid).

    The time-scaling law maps the attractor at energy c^2 E onto c times the one at E, so
    with the right c the distance is at the sampling level; with c = 1 it is not."""
    from scipy.spatial import cKDTree

    ref = np.asarray(ref_points, float)
    size = float(np.sqrt(np.mean(np.sum((ref - ref.mean(0)) ** 2, axis=1))))
    out = {}
    for tag, factor in (("scaled", c), ("unscaled", 1.0)):
        d = np.concatenate([
            cKDTree(ref[np.asarray(ref_classes) == k]).query(
                np.asarray(other_points)[np.asarray(other_classes) == k] / factor)[0]
            for k in np.unique(ref_classes)
        ]) / size
        out[f"{tag}_median"] = float(np.median(d))
        out[f"{tag}_p95"] = float(np.quantile(d, 0.95))
    nn = cKDTree(ref).query(ref, k=2)[0][:, 1] / size
    out["ref_nearest_neighbour_median"] = float(np.median(nn))
    out["attractor_size"] = size
    return out
