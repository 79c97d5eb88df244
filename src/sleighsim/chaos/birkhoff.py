"""Weighted Birkhoff averages (Das, Saiki, Sander and Yorke, "Quantitative quasiperiodicity", Nonlinearity 30
(2017), arXiv:1508.00062; Das and Yorke, "Super convergence of ergodic averages for quasiperiodic orbits",
Nonlinearity (2018), arXiv:1506.06810) as a chaos indicator without tangent dynamics, and its judge.

The time average of a smooth observable g along an orbit, weighted by the bump w(s) = exp(-1 / (s (1 - s)))
on the window's relative time s in (0, 1), converges faster than any power of the window length W on a
quasi-periodic orbit (a torus with Diophantine frequencies: the weight's Fourier transform decays like
exp(-c sqrt(|nu| W)) at every frequency nu of g along the orbit), and only like W^-1/2 on a chaotic orbit
(the central limit theorem). The digits dig = -log10(|WB_1 - WB_2| / scale) of two consecutive windows
therefore grow without bound on a torus and by about 0.5 per decade of W on chaos.

Sampling: the orbit is sampled every dt and the weighted sum runs over the samples, s_k = (k + 1) / (n + 1)
for the n samples of a window. That sum is exactly the weighted Birkhoff average of the time-dt map, which
on a torus is a rotation by dt times the flow's frequencies: it converges super-polynomially to the same
space average as the continuous one unless some k . f dt is an integer (a resonance of the sampling with
the torus); the sampled and continuous averages over one window differ by the aliased part of g, the
Fourier components of g(t) near multiples of 1/dt (exponentially small in 1/(f dt) for an analytic g).
Only differences between windows sampled the same way enter the digits.

Observables: the digits of a record are its worst observable's. A time derivative of a bounded function (a
momentum p = dq/dt) has a weighted average that converges super-polynomially on every orbit, chaotic or not
(the weight is flat to all orders at the window's ends: integrate by parts), so such an observable alone
would fake a torus (Henon-Heiles E = 1/6 over 1.6e4: x and y 0.8 and 1.4 digits, px and py 4.5 and 4.8).

Engine: ``window_averages``, ``digits`` (on sampled observables), ``sampled_observables`` (an integrator's
orbit sampled every dt). Judge: ``judge_birkhoff``; it says regular or undecided, never chaotic.
``birkhoff_indicator`` runs both on one orbit. Times in the flow's own time unit; digits are decimal.
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.common import _state, check_splits
from sleighsim.chaos.verdicts import REGULAR, UNDECIDED, _g, _is_finite
from sleighsim.engine.orbits import grid_samples
from sleighsim.model.params import positive

MIN_SAMPLES = 16  # samples a window needs at least
#: Digits a regular verdict needs at the longest window. Set from the audit (docs/birkhoff.md, 50 seeded records per
#: case at 86, 344 and 1376 periods, and 188 more sticky starts): 450 chaotic records (Henon-Heiles E = 1/6, Lorenz,
#: Nose-Hoover) reached at most 2.9 digits, 714 sticky Henon-Heiles E = 1/8 records (starting near an island) 5.4;
#: tori at 86 periods 1.4 to 12. The arithmetic must follow the orbit to 10^-(DIG_MIN + 1): G x rounding <= 1e-7,
#: or the verdict is undecided.
DIG_MIN = 6.0
#: Growth of the digits a regular verdict needs, in digits per decade of window length, between the shortest and
#: the longest window (a chaotic orbit's averages converge like W^-1/2: 0.5 digits per decade).
RATE_MIN = 2.0
#: Digits the sums can resolve: observables are sampled in double (relative rounding 1.1e-16) and summed in
#: long double, so differences below about 1e-15 of the observable's scale are rounding, not convergence.
DIGITS_MAX = 15.0


def bump(n: int) -> np.ndarray:
    """The weights w(s_k) = exp(-1 / (s_k (1 - s_k))), s_k = (k + 1) / (n + 1), k = 0 .. n - 1, in long
    double, normalised to sum 1."""
    if int(n) != n or n < 1:
        raise ValueError(f"n must be a positive integer, got {n!r}")
    s = np.arange(1, n + 1, dtype=np.longdouble) / np.longdouble(n + 1)
    w = np.exp(-1 / (s * (1 - s)))
    return w / w.sum()


def window_averages(X, n_windows: int) -> np.ndarray:
    """Weighted Birkhoff averages (``bump`` weights) of each column of X (samples x observables) over
    n_windows consecutive equal windows (a remainder of fewer than n_windows samples at the end is
    dropped). Returns (n_windows, observables), summed in long double."""
    X = np.asarray(X, float)
    if int(n_windows) != n_windows or n_windows < 1:
        raise ValueError(f"n_windows must be a positive integer, got {n_windows!r}")
    m = X.shape[0] // int(n_windows)
    if m < MIN_SAMPLES:
        raise ValueError(f"{X.shape[0]} samples give windows of {m} samples; at least {MIN_SAMPLES} needed")
    w = bump(m)
    blocks = X[: m * n_windows].reshape(n_windows, m, -1).astype(np.longdouble)
    return np.einsum("k,jko->jo", w, blocks)


def digits(X, dt: float, splits=(2, 4, 8)) -> dict:
    """Digits of agreement of the weighted Birkhoff averages of consecutive windows, for each column of X
    (samples every dt x observables) and windows of W = T / K, K in ``splits`` (T = n dt, the record).

    Per observable o and split K: the K window averages (``window_averages``), their K - 1 differences of
    consecutive windows over the observable's scale (its standard deviation over the whole record), and
    dig[K, o] = -log10(rms of those), at most DIGITS_MAX. Returns W (time, longest first), splits (in that
    order), digits (splits x observables), dig (the worst observable's digits per split), dig_err (the
    standard deviation of the observables' digits per split: their spread) and T."""
    X = np.asarray(X, float)
    if X.ndim == 1:
        X = X[:, None]
    if X.ndim != 2 or not np.all(np.isfinite(X)):
        raise ValueError(f"X must be a finite (samples x observables) array, got shape {X.shape}")
    dt = positive("dt", dt)
    splits = check_splits(splits, least=2)
    scale = X.std(axis=0)
    if not np.all(scale > 0):
        raise ValueError(f"observables {np.flatnonzero(~(scale > 0)).tolist()} are constant over the record")
    X = X - X.mean(axis=0)
    rows = []
    for K in splits:
        d = np.diff(window_averages(X, K), axis=0) / scale
        rms = np.sqrt(np.mean(d.astype(float) ** 2, axis=0))
        rows.append(np.minimum(-np.log10(np.maximum(rms, 1e-300)), DIGITS_MAX))
    dig = np.array(rows)
    n = X.shape[0]
    return {"W": np.array([(n // K) * dt for K in splits]), "splits": np.array(splits), "digits": dig,
            "dig": dig.min(axis=1), "dig_err": dig.std(axis=1), "T": n * dt}


def observables(Y, angles=()) -> np.ndarray:
    """Smooth observables of sampled states Y (samples x components): every component that is not an
    angle, then cos and sin of each angle component (an angle reduced to [0, 2 pi) jumps by 2 pi, which
    would spoil the averages' convergence). In double."""
    Y = np.asarray(Y).astype(float)
    angles = sorted({int(i) for i in angles})
    if any(not 0 <= i < Y.shape[1] for i in angles):
        raise ValueError(f"angles must index the state's {Y.shape[1]} components, got {angles}")
    keep = [i for i in range(Y.shape[1]) if i not in angles]
    return np.column_stack([Y[:, keep], np.cos(Y[:, angles]), np.sin(Y[:, angles])])


def sampled_observables(ta, y0, *, T: float, dt: float, angles=(), callback=None) -> np.ndarray:
    """``observables`` of the orbit of ``ta`` (parameters set) from y0 (its stored state), sampled every dt
    at t = 0, dt, ..., T - dt (one propagate_grid run in the integrator's precision: double, long double or
    real128). RuntimeError naming the time when the integration stops early or leaves the finite numbers."""
    y0 = _state("y0", y0, len(ta.state))
    T, dt = positive("T", T), positive("dt", dt)
    ta.state[:] = np.asarray(y0).astype(ta.state.dtype)
    return observables(grid_samples(ta, round(T / dt), dt, callback)[0].astype(float), angles)


def _arithmetic_digits(gain_rounding) -> float:
    """Digits the arithmetic can certify: -log10(G x rounding) - 1 (NaN when G x rounding is unknown)."""
    if not _is_finite(gain_rounding):
        return math.nan
    if float(gain_rounding) <= 0:
        raise ValueError(f"gain_rounding must be positive, got {gain_rounding!r}")
    return -math.log10(float(gain_rounding)) - 1.0


def judge_birkhoff(run: dict, *, gain_rounding: float, dig_min: float = DIG_MIN, rate_min: float = RATE_MIN):
    """Verdict from weighted Birkhoff averages (``digits``: W, the window lengths longest first, and dig, the
    worst observable's digits per window) of one orbit computed in an arithmetic that follows it to
    G x rounding = ``gain_rounding`` (the faithfulness gauge's product; NaN: unknown).

    regular: the arithmetic can certify dig_min digits (dig_min + 1 <= -log10(G x rounding): an orbit followed
    to 10^-(dig + 1) shifts each average by less than a tenth of the difference that dig digits leave), the
    digits at the longest window reach dig_min, and they grew faster than a chaotic orbit's averages allow:
    by at least rate_min digits per decade of window length from the shortest window to the longest, or were
    already within one digit of the resolvable ceiling (min(DIGITS_MAX, -log10(G x rounding))) at the
    shortest window, where growth can no longer show. Otherwise undecided, naming the numbers. Never chaotic:
    a torus whose windows hold only a few of its slowest periods has averages as unconverged as chaos."""
    W, dig = np.asarray(run["W"], float), np.asarray(run["dig"], float)
    if W.size < 2 or W.shape != dig.shape or not np.all(np.diff(W) < 0):
        raise ValueError(f"run needs at least two window lengths, longest first, one digit each; got W {W}, dig {dig}")
    have = _arithmetic_digits(gain_rounding)
    numbers = (f"dig {', '.join(_g(d) for d in dig)} at W {', '.join(_g(w) for w in W)}; "
               f"G x rounding {_g(gain_rounding)}")
    if not math.isfinite(have):
        return UNDECIDED, f"G x rounding not known: the digits cannot be certified; {numbers}"
    if dig_min > have:
        return UNDECIDED, (f"the arithmetic follows the orbit only to G x rounding {_g(gain_rounding)}: it certifies "
                           f"{_g(have)} digits, fewer than dig_min {_g(dig_min)}; {numbers}")
    if not np.all(np.isfinite(dig)):
        return UNDECIDED, f"not finite: dig; {numbers}"
    rate = (dig[0] - dig[-1]) / math.log10(W[0] / W[-1])
    ceiling = min(DIGITS_MAX, have + 1.0)
    numbers += f"; growth {_g(rate)} digits per decade of W"
    if dig[0] < dig_min:
        return UNDECIDED, f"dig {_g(dig[0])} at the longest window is below dig_min {_g(dig_min)}; {numbers}"
    if rate >= rate_min:
        return REGULAR, (f"the weighted Birkhoff averages converge faster than any chaotic orbit's: dig {_g(dig[0])} "
                         f">= {_g(dig_min)}, growing by {_g(rate)} >= {_g(rate_min)} digits per decade; {numbers}")
    if dig[-1] >= ceiling - 1.0:
        return REGULAR, (f"the weighted Birkhoff averages agree to the resolvable ceiling {_g(ceiling)} from the "
                         f"shortest window on (dig {_g(dig[-1])}): dig {_g(dig[0])} >= {_g(dig_min)}; {numbers}")
    return UNDECIDED, (f"the digits grow by {_g(rate)} < {_g(rate_min)} digits per decade (a chaotic orbit's: 0.5) "
                       f"below the ceiling {_g(ceiling)}; {numbers}")


def birkhoff_indicator(ta, y0, *, T: float, dt: float, gain_rounding: float, angles=(), callback=None,
                       splits=(2, 4, 8)) -> dict:
    """The weighted-Birkhoff indicator of the orbit of ``ta`` from y0 over T (``sampled_observables``,
    ``digits``, ``judge_birkhoff``). Value: the digits at the longest window (the worst observable's);
    error: their spread over the observables; verdict: (verdict, reason); also the digits per window (dig,
    longest first), the window lengths W and the per-observable digits."""
    run = digits(sampled_observables(ta, y0, T=T, dt=dt, angles=angles, callback=callback), dt, splits)
    return {"value": float(run["dig"][0]), "error": float(run["dig_err"][0]),
            "verdict": judge_birkhoff(run, gain_rounding=gain_rounding), **run}
