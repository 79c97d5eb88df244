"""The weighted Birkhoff average judge (sleighsim.chaos.birkhoff): its engine on signals with known answers, its
judge on every branch, and its power and false rates on known orbits.

Audit (``audit``; the table in docs/birkhoff.md comes from ``python tests/chaos/test_birkhoff.py``, the test
below runs a smaller one). Classes, seeded (one RNG stream per system), each record sampled every dt over
T = m P (P the orbit's characteristic period, m the horizon in periods; the sleigh's T = 2e5 is m = 86 spike
periods), judged with splits (2, 4, 8) and G x rounding = 1e-13 (the judge's digits logic is audited here; on a
chaotic orbit the faithfulness gauge would itself stop a regular verdict):

* tori: Henon-Heiles E = 1/12 from x = 0 with (y, px) drawn uniformly in [-0.3, 0.3] x [-0.25, 0.25] and kept
  only when a MEGNO run over 1e4 says regular (P = 2 pi); quartic and linear uncoupled oscillators from starts
  drawn as in test_judge_audit (P = 2 pi); the slow-fast torus H = p1^2/2 + w1^2 (1 - cos q1) + p2^2/2 + q2^2/2,
  w1 = 1e-3, the pendulum rotating just above its separatrix (energy 2 w1^2 (1 + kappa), kappa log-uniform in
  [1e-6, 1e-3]; P = its period 2 K(1/(1 + kappa)) / (w1 sqrt(1 + kappa)), 1.1e4 to 1.7e4, about 2000 periods of
  the oscillator; p1 spikes to 2 w1 once a period), every orbit a torus.
* chaos: Henon-Heiles E = 1/6 orbit C perturbed by 1e-6 (P = 2 pi); Lorenz perturbed by 1e-6 (P = 0.75, its
  mean lobe period); the Nose-Hoover oscillator x' = y, y' = -x + y z, z' = 1 - y^2 (reversible under
  (x, y, z, t) -> (x, -y, -z, -t), not Hamiltonian; lambda_1 about 0.014, Sprott 2010) from (0, 5, 0) perturbed
  by 1e-6 (P = 2 pi); STICKY Henon-Heiles E = 1/8 orbits: states where a chaotic orbit (orbit C perturbed)
  enters a stretch of at least STICKY_MIN time units with local exponent below STICKY_RATE (windows of
  STICKY_CHUNK), each confirmed chaotic by its exponent over STICKY_CONFIRM from that state (> 0.01; the E = 1/8
  sea has lambda_1 about 0.04); the record starts there, so it begins near an island.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from sleighsim.chaos import birkhoff
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED

G_ROUNDING = 1e-13  # the G x rounding the audits pass (double, a torus's moderate shear over the record)
SPLITS = (2, 4, 8)
W1 = 1e-3  # the slow-fast torus's pendulum frequency
STICKY_CHUNK, STICKY_RATE, STICKY_MIN, STICKY_CONFIRM = 100.0, 0.005, 1000.0, 1.0e5


# ----------------------------------------------------------------------------- systems

def _pendulum_oscillator(hy):
    q1, q2, p1, p2 = hy.make_vars("q1", "q2", "p1", "p2")
    return [(q1, p1), (q2, p2), (p1, -(W1**2) * hy.sin(q1)), (p2, -q2)]


def _nose_hoover(hy):
    x, y, z = hy.make_vars("x", "y", "z")
    return [(x, y), (y, -x + y * z), (z, 1.0 - y * y)]


def _pendulum_start(rng):
    """A slow-fast torus: (start, slow period)."""
    from scipy.special import ellipk

    kappa = 10 ** rng.uniform(-6, -3)
    q1 = rng.uniform(0, 2 * math.pi)
    p1 = math.sqrt(2 * (2 * W1**2 * (1 + kappa) - W1**2 * (1 - math.cos(q1))))
    a, phase = rng.uniform(0.5, 1.5), rng.uniform(0, 2 * math.pi)
    return np.array([q1, a * math.cos(phase), p1, a * math.sin(phase)]), 2 * ellipk(1 / (1 + kappa)) / (
        W1 * math.sqrt(1 + kappa))


def _hh_torus_start(rng):
    from chaos_textbook import _hh_V, _hh_y0

    while True:
        y, px = rng.uniform(-0.3, 0.3), rng.uniform(-0.25, 0.25)
        if 2 * (1 / 12 - _hh_V(0.0, y)) - px * px > 1e-4:
            return np.array(_hh_y0(0.0, y, px, 1 / 12)), 2 * math.pi


def _perturbed(base, energy=None):
    def draw(rng):
        from chaos_textbook import _hh_y0

        b = np.asarray(base, float)
        y = b + 1e-6 * np.max(np.abs(b)) * rng.normal(size=b.size)
        return (np.array(_hh_y0(y[0], y[1], y[2], energy)) if energy else y), None
    return draw


def _oscillator_start(rng):
    return np.array([rng.uniform(0.5, 1.5), rng.uniform(0.25, 0.75), rng.uniform(-0.5, 0.5),
                     rng.uniform(-0.5, 0.5)]), 2 * math.pi


def _cases():
    """name -> (class, system builder, draw(rng) -> (start, period or None: the case's P), P, dt, angle indices)."""
    from chaos_textbook import HH_CHAOS, LORENZ0, _hh_sys, _lorenz_sys, _oscillators

    quartic, linear = (functools.partial(_oscillators, quartic=q) for q in (True, False))
    return {
        "henon-heiles E=1/12": ("tori", _hh_sys, _hh_torus_start, 2 * math.pi, 0.25, ()),
        "quartic oscillators": ("tori", quartic, _oscillator_start, 2 * math.pi, 0.25, ()),
        "linear oscillators": ("tori", linear, _oscillator_start, 2 * math.pi, 0.25, ()),
        "slow-fast torus": ("tori", _pendulum_oscillator, _pendulum_start, None, 1.0, (0,)),
        "henon-heiles E=1/6": ("chaos", _hh_sys, _perturbed(HH_CHAOS, 1 / 6), 2 * math.pi, 0.25, ()),
        "lorenz": ("chaos", _lorenz_sys, _perturbed(LORENZ0), 0.75, 0.02, ()),
        "nose-hoover": ("chaos", _nose_hoover, _perturbed([0.0, 5.0, 0.0]), 2 * math.pi, 0.25, ()),
        "sticky henon-heiles E=1/8": ("chaos", _hh_sys, None, 2 * math.pi, 0.25, ()),
    }


@functools.cache
def _flow(name):
    import heyoka as hy

    sys_ = _cases()[name][1](hy)
    return hy.taylor_adaptive(sys_, [0.1] * len(sys_), compact_mode=True)


@functools.cache
def _tangent_flow(name):
    import heyoka as hy

    from sleighsim.engine import integrators

    ta, n, _ = integrators.tangent_integrator(_cases()[name][1](hy), 1)
    return ta, n


def tangent_record(name, y0, T, dt, T_more=0.0, chunk=STICKY_CHUNK):
    """The orbit from y0 sampled every dt over T (observables) and the local exponents of one tangent
    vector in windows of ``chunk`` over T + T_more (one integration): (X, rates, states at the window
    starts)."""
    ta, n = _tangent_flow(name)
    per = round(chunk / dt)
    ta.state[:n], v = y0, np.ones(n) / math.sqrt(n)
    samples, rates, states = [], [], []
    for i in range(round((T + T_more) / chunk)):
        ta.time, ta.state[n:] = 0.0, v
        states.append(ta.state[:n].copy())
        res = ta.propagate_grid(np.arange(per + 1) * dt)
        if i * chunk < T:
            samples.append(res[-1][:per, :n])
        v = np.array(ta.state[n:])
        rates.append(math.log(np.linalg.norm(v)) / chunk)
        v /= np.linalg.norm(v)
    return birkhoff.observables(np.concatenate(samples)), np.array(rates), np.array(states)


def sticky_starts(n_wanted, seed, T_find=1.0e5):
    """States where a chaotic Henon-Heiles E = 1/8 orbit (orbit C perturbed by 1e-6, one per finder run
    over T_find) enters a stretch of STICKY_MIN over which its exponent is below STICKY_RATE (non-overlapping
    stretches), and the number of finder runs."""
    from chaos_textbook import _hh_y0

    rng, out, runs = np.random.default_rng([2027, seed]), [], 0
    need = round(STICKY_MIN / STICKY_CHUNK)
    while len(out) < n_wanted and runs < 4 * n_wanted:
        y = np.array([0.0, -0.016, 0.4997]) * (1 + 1e-6 * rng.normal(size=3))
        _, rates, states = tangent_record("sticky henon-heiles E=1/8", _hh_y0(y[0], y[1], y[2], 1 / 8),
                                          STICKY_CHUNK, 0.25, T_find)
        runs += 1
        mean = np.convolve(rates, np.ones(need) / need, mode="valid")  # over [i, i + STICKY_MIN)
        i = 0
        while i < mean.size:
            if mean[i] < STICKY_RATE:
                out.append(states[i])
                i += need
            else:
                i += 1
    return out[:n_wanted], runs


def _megno_regular(name, y0, T=1.0e4):
    """Whether a MEGNO run over T says regular (sigma 3): the test setup's confirmation of a drawn torus."""
    import heyoka as hy

    from sleighsim.chaos import megno

    tm, n = _megno_ta(name, hy)
    return megno.judge_megno_run(megno.megno(tm, n, y0, T=T, n_samples=100, tau=1.0), T, 3.0)[0] == REGULAR


@functools.cache
def _megno_ta(name, hy):
    from sleighsim.engine import integrators

    return integrators.megno_integrator(_cases()[name][1](hy))


def _prefix_digits(X, dt, P, horizons):
    """``birkhoff.digits`` of the record's first m P, for each m in horizons."""
    return {m: birkhoff.digits(X[: round(m * P / dt)], dt, SPLITS) for m in horizons}


def case_records(name, n, horizons, seed=0):
    """n realizations of case ``name``: dicts with the start, the period P, the digits per horizon (m periods)
    and, for the sticky case, the exponent over STICKY_CONFIRM and the share of each horizon's record spent in
    windows of local exponent below STICKY_RATE. Tori that MEGNO does not confirm are skipped and counted
    (returned second)."""
    cls, _, draw, P, dt, angles = _cases()[name]
    rng = np.random.default_rng([2026, list(_cases()).index(name), seed])
    starts = sticky_starts(n, seed)[0] if draw is None else None
    out, rejected = [], 0
    while len(out) < n:
        if starts is not None:
            y0, period = starts[len(out)], P
            T = max(horizons) * P
            X, rates, _ = tangent_record(name, y0, T, dt, STICKY_CONFIRM - T)
            low = rates < STICKY_RATE
            extra = {"lambda": float(rates.mean()),
                     "sticky": {m: float(np.mean(low[: round(m * P / STICKY_CHUNK)])) for m in horizons}}
        else:
            y0, period = draw(rng)
            period = period or P
            if name == "henon-heiles E=1/12" and not _megno_regular(name, y0):
                rejected += 1
                continue
            X = birkhoff.sampled_observables(_flow(name), y0, T=max(horizons) * period, dt=dt, angles=angles)
            extra = {}
        out.append({"case": name, "class": cls, "y0": np.asarray(y0, float), "P": period,
                    "digits": _prefix_digits(X, dt, period, horizons), **extra})
    return out, rejected


HORIZONS = {"slow-fast torus": (22.0, 86.0, 172.0)}  # periods; every other case: DEFAULT_HORIZONS
DEFAULT_HORIZONS = (86.0, 344.0, 1376.0)


def audit(n, cases=None, seed=0) -> list:
    """``case_records`` of n realizations of each case (all by default), each judged at each of its horizons
    (HORIZONS) with G x rounding = G_ROUNDING: dicts with case, class, m, verdict, reason, dig and, for the
    sticky case, lambda and the sticky share; then the MEGNO rejections per case (key "rejected")."""
    rows, rejected = [], {}
    for name in cases or _cases():
        horizons = HORIZONS.get(name, DEFAULT_HORIZONS)
        recs, rejected[name] = case_records(name, n, horizons, seed)
        for r in recs:
            for m in horizons:
                v, reason = birkhoff.judge_birkhoff(r["digits"][m], gain_rounding=G_ROUNDING)
                rows.append({"case": name, "class": r["class"], "m": m, "verdict": v, "reason": reason,
                             "dig": r["digits"][m]["dig"], "sticky": r.get("sticky", {}).get(m, math.nan),
                             "lambda": r.get("lambda", math.nan)})
    return rows, rejected


def table(rows) -> list[str]:
    """Lines: per case and horizon, N and the counts of each verdict, the digits' range at the longest window."""
    out = [f"{'case':28s} {'m':>6s} {'N':>4s} {'regular':>8s} {'chaotic':>8s} {'undecided':>9s}  dig(T/2) min-med-max"]
    for key in dict.fromkeys((r["case"], r["m"]) for r in rows):
        sel = [r for r in rows if (r["case"], r["m"]) == key]
        d = np.array([r["dig"][0] for r in sel])
        counts = [sum(r["verdict"] == v for r in sel) for v in (REGULAR, CHAOTIC, UNDECIDED)]
        out.append(f"{key[0]:28s} {key[1]:6g} {len(sel):4d} {counts[0]:8d} {counts[1]:8d} {counts[2]:9d}  "
                   f"{d.min():.2f} {np.median(d):.2f} {d.max():.2f}")
    return out


if __name__ == "__main__":  # the audit behind docs/birkhoff.md: python tests/chaos/test_birkhoff.py N [case ...]
    import pickle
    import sys

    sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parents[1]))
    rows, rejected = audit(int(sys.argv[1]), sys.argv[2:] or None)
    print("\n".join(table(rows)), "\nMEGNO rejections:", rejected)
    with open("birkhoff_audit.pkl", "wb") as f:
        pickle.dump(rows, f)
