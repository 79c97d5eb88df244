"""Audit of the false verdicts of every chaos-indicator judge on known orbits (chaos_textbook): how often
a judge calls a chaotic orbit "regular" and a torus "chaotic", over many independent realizations.

The frequency judge's false-"regular" audit is in test_chaos_frequency.py (it never says chaotic); this
module audits the others, each judge on its own engine's runs with its default settings (sigma 3):

* ``tangent.judge_ftle`` and ``megno.judge_megno_run`` on one ``megno.megno`` run per realization (the
  FTLE from its one-vector Benettin series, windows n / 500 x (1, 2, 4, 8, 16) intervals tau after
  skipping the first half, as chaos_textbook scales them at n = 1e4);
* ``tangent.judge_benettin`` on ``benettin.replica_exponents`` with 4 replicas (lanes) along the
  realization's orbit (CONFIG_LIKE: target_rel 0.1 as in config.yaml, regular_floor the polynomial bound
  at the capped horizon, as config.yaml's floor sits at its cap);
* ``two_trajectory.judge_two_trajectory`` on one ``two_trajectory`` run (d0 = 1e-8; in the workflow the
  d0-independence check can only turn its verdict undecided);
* ``loschmidt.judge_loschmidt_run`` on one ``loschmidt`` run (reversible systems only: not Lorenz).

Realizations (seeded, independent draws): chaotic orbits: Henon-Heiles E = 1/6 orbit C and Lorenz, each
start perturbed by 1e-6 of its largest component (Henon-Heiles: then put back on its energy level); the
perturbation decorrelates the records within about 100 time units (Lorenz: 15), far below every horizon.
Tori: Henon-Heiles E = 1/12 perturbed the same way, and the uncoupled quartic / linear oscillators from
starts drawn uniformly (q1 in [0.5, 1.5], q2 in [0.25, 0.75], p1, p2 in [-0.5, 0.5]): every orbit of
those is a torus, so each draw is a different known torus (a 1e-6 perturbation of one torus would repeat
one measurement). Where the engine takes a seed (the tangent vector's or the partner's direction, the
replicas' vectors) each realization has its own. Every judge sees three horizons (HORIZONS, in intervals
tau). "undecided" is no false verdict; its share is reported.

Bound: the target of the frequency audit, at most 1 false verdict in 100, asserted as at most
floor(N / 100) false of N. With none allowed (N < 100) or none seen, the 95% upper confidence bound on
the rate is 3 / N (rule of three): 1% at N = 300, 1.7% at N = 180, 6.7% at N = 45, so the smaller samples
bound the rate only that loosely.

AUDIT collects (judge, orbit class) -> N, false, undecided, correct (and the counts per system and
horizon); the table is printed at the end of the module (pytest -s) and each row is a
``record_property``. Measured here (heyoka, double, compact mode; about 55 s on one core):

    judge           orbits     N  false  undecided
    ftle            chaotic  300      0         57  (Lorenz T = 50: 44 of 50; HH T = 500: 9 of 50)
    ftle            tori     306      0        175  (linear oscillators undecided up to T = 1e3, spread
                                                     flat where the windows are shorter than a beat period)
    megno           chaotic  300      0          0
    megno           tori     306      0          2
    benettin        chaotic  300      0          1
    benettin        tori     306      0        285  (replica_exponents stops "converged" on a sheared torus:
                                                     the replicas along it share lambda_1 ~ ln T / T to < 10%,
                                                     so the "regular" status is never reached)
    two-trajectory  chaotic  300      0          6
    two-trajectory  tori     306      0        118  (linear oscillators 98 of 102: no shear, the running
                                                     rate's log-log slope is noise)
    loschmidt       chaotic  300      0          3
    loschmidt       tori      72      0         44  (linear oscillators: the return error stays below the
                                                     rounding floor x 1e3 up to T = 2e4)
"""

import functools
import math
from collections import Counter

import numpy as np
import pytest
from chaos_textbook import (
    HH_CHAOS,
    HH_REG,
    LORENZ0,
    _flip_momenta,
    _hh_sys,
    _hh_y0,
    _lorenz_sys,
    _oscillators,
)

from sleighsim.chaos import benettin, loschmidt, megno, tangent, two_trajectory
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED, VERDICTS, polynomial_rate_bound
from sleighsim.engine import integrators

SIGMA = 3.0
TARGET = 0.01  # at most 1 false verdict in 100 (the frequency judge's target)
CHAOS, TORI = "chaotic", "tori"
FALSE = {CHAOS: REGULAR, TORI: CHAOTIC}  # the false verdict on each orbit class

# system -> (class, builder, base state, energy to project on (None: none), tau, replica spacing)
SYSTEMS = {
    "henon-heiles E=1/6": (CHAOS, _hh_sys, HH_CHAOS, 1.0 / 6.0, 1.0, 100.0),
    "lorenz": (CHAOS, _lorenz_sys, LORENZ0, None, 0.1, 10.0),
    "henon-heiles E=1/12": (TORI, _hh_sys, HH_REG, 1.0 / 12.0, 1.0, 100.0),
    "quartic oscillators": (TORI, functools.partial(_oscillators, quartic=True), None, None, 1.0, 100.0),
    "linear oscillators": (TORI, functools.partial(_oscillators, quartic=False), None, None, 1.0, 100.0),
}
REVERSIBLE = ("henon-heiles E=1/6", "henon-heiles E=1/12", "quartic oscillators", "linear oscillators")

# horizons in intervals tau (MEGNO / FTLE / two trajectories: the run; Benettin: one round of at most 4);
# Loschmidt: the largest return time of the grid, in time units
HORIZONS = (500, 1000, 2000)
BENETTIN_ROUNDS = (250, 500, 1000)
LOSCHMIDT_CHAOS = (200.0, 300.0, 400.0)  # linspace(10, T, 30): the window floor-saturation is ~ 25 / lambda
LOSCHMIDT_TORI = (1.0e4, 2.0e4, 4.0e4)  # geomspace(100, T, 16): rounding on a torus needs T >~ 1e3 to show
# realizations per (system, horizon)
PER = {CHAOS: 50, TORI: 34}
PER_LOSCHMIDT = {CHAOS: 100, TORI: 8}

AUDIT: dict = {}


# ----------------------------------------------------------------------------- realizations

def _draw(system, rng):
    """One realization's start: the base state perturbed by 1e-6 of its largest component (on the
    energy level when it has one), or a random torus of the uncoupled oscillators."""
    _, _, base, energy, _, _ = SYSTEMS[system]
    if base is None:
        return np.array([rng.uniform(0.5, 1.5), rng.uniform(0.25, 0.75), rng.uniform(-0.5, 0.5),
                         rng.uniform(-0.5, 0.5)])
    base = np.asarray(base, float)
    y = base + 1e-6 * np.max(np.abs(base)) * rng.normal(size=base.size)
    return np.array(_hh_y0(y[0], y[1], y[2], energy)) if energy is not None else y


def _starts(system, n, stream):
    """n seeded starts of ``system`` (stream: one independent RNG stream per engine)."""
    rng = np.random.default_rng([2026, list(SYSTEMS).index(system), stream])
    return [_draw(system, rng) for _ in range(n)]


@functools.cache
def _flow(system):
    import heyoka as hy

    build = SYSTEMS[system][1]
    sys = build(hy)
    return hy.taylor_adaptive(sys, [0.1] * len(sys), compact_mode=True)


@functools.cache
def _megno_ta(system):
    import heyoka as hy

    return integrators.megno_integrator(SYSTEMS[system][1](hy))


@functools.cache
def _replica_ta(system, lanes=4):
    import heyoka as hy

    ta, n, _ = integrators.tangent_integrator_batch(SYSTEMS[system][1](hy), lanes)
    return ta, n


def _systems(cls, reversible=False):
    return [s for s, v in SYSTEMS.items() if v[0] == cls and (not reversible or s in REVERSIBLE)]


@functools.cache
def _tangent_verdicts(cls):
    """(system, horizon, FTLE verdict, MEGNO verdict) of one ``megno`` run per realization."""
    out = []
    for system in _systems(cls):
        tau = SYSTEMS[system][4]
        tm, n = _megno_ta(system)
        starts = iter(_starts(system, PER[cls] * len(HORIZONS), 0))
        for steps in HORIZONS:
            T = steps * tau
            windows = tau * steps / 500 * np.array([1, 2, 4, 8, 16])
            for seed in range(PER[cls]):
                m = megno.megno(tm, n, next(starts), T=T, n_samples=100, tau=tau, seed=seed)
                f = tangent.finite_time_exponents(m["log_growth"], tau, windows, t_skip=T / 2)
                ftle = tangent.judge_ftle(f["rate"], f["rate_err"], f["T"], f["tau"], f["spread_slope"],
                                          f["spread_slope_err"], sigma=SIGMA)
                out.append((system, T, ftle, megno.judge_megno_run(m, T, SIGMA)))
    return out


@functools.cache
def _two_trajectory_verdicts(cls):
    out = []
    for system in _systems(cls):
        tau = SYSTEMS[system][4]
        starts = iter(_starts(system, PER[cls] * len(HORIZONS), 1))
        for steps in HORIZONS:
            T = steps * tau
            for seed in range(PER[cls]):
                r = two_trajectory.two_trajectory(_flow(system), next(starts), d0=1e-8, tau=tau, T=T, seed=seed)
                out.append((system, T, two_trajectory.judge_two_trajectory(r["rate"], r["stderr"], r["T"], r["tau"],
                                                                   r["running_slope"], r["running_slope_err"],
                                                                   sigma=SIGMA)))
    return out


def _along_orbit(system, y0, lanes):
    """``lanes`` states along the orbit from y0, the replica spacing apart."""
    ta = _flow(system)
    ta.time = 0.0
    ta.state[:] = y0
    res = ta.propagate_grid(SYSTEMS[system][5] * np.arange(lanes, dtype=float))
    return np.array(res[-1])


@functools.cache
def _benettin_verdicts(cls, lanes=4, max_rounds=4):
    """judge_benettin on replica_exponents (lanes replicas along each realization's orbit, their own
    seed for the vectors), rounds of T_round until converged (stderr <= 0.1 lambda_1), regular (the
    polynomial bound, then below regular_floor) or capped after max_rounds."""
    out = []
    for system in _systems(cls):
        tau = SYSTEMS[system][4]
        ta, n = _replica_ta(system, lanes)
        starts = iter(_starts(system, PER[cls] * len(BENETTIN_ROUNDS), 2))
        for steps in BENETTIN_ROUNDS:
            T_round = steps * tau
            floor = polynomial_rate_bound(max_rounds * T_round, tau)
            for seed in range(PER[cls]):
                res = benettin.replica_exponents(ta, n, 1, _along_orbit(system, next(starts), lanes), tau,
                                                 T_round=T_round, max_rounds=max_rounds, target_rel=0.1,
                                                 regular_floor=floor, t_align=20 * tau, sigma=SIGMA, seed=seed)
                out.append((system, T_round, tangent.judge_benettin(res, tau, SIGMA)))
    return out


@functools.cache
def _loschmidt_verdicts(cls):
    out = []
    for system in _systems(cls, reversible=True):
        horizons = LOSCHMIDT_CHAOS if cls == CHAOS else LOSCHMIDT_TORI
        starts = iter(_starts(system, PER_LOSCHMIDT[cls] * len(horizons), 3))
        for T in horizons:
            grid = np.linspace(10.0, T, 30) if cls == CHAOS else np.geomspace(100.0, T, 16)
            for _ in range(PER_LOSCHMIDT[cls]):
                L = loschmidt.loschmidt(_flow(system), next(starts), grid, _flip_momenta)
                out.append((system, T, loschmidt.judge_loschmidt_run(L, sigma=SIGMA)))
    return out


def _verdicts(judge, cls):
    """(system, horizon, (verdict, reason)) of every realization of ``judge`` on orbit class ``cls``."""
    if judge in ("ftle", "megno"):
        i = 2 if judge == "ftle" else 3
        return [(r[0], r[1], r[i]) for r in _tangent_verdicts(cls)]
    return {"benettin": _benettin_verdicts, "two-trajectory": _two_trajectory_verdicts,
            "loschmidt": _loschmidt_verdicts}[judge](cls)


# ----------------------------------------------------------------------------- the audit

def _bound(N):
    """At most floor(TARGET N) false verdicts of N: the measured rate may not exceed 1 in 100."""
    return math.floor(TARGET * N)


CASES = [(j, c) for j in ("ftle", "megno", "benettin", "two-trajectory", "loschmidt") for c in (CHAOS, TORI)]


@pytest.mark.parametrize("judge, cls", CASES, ids=[f"{j}-{c}" for j, c in CASES])
def test_false_verdict_rate_on_known_orbits(hy, judge, cls, record_property):
    """false-"regular" on chaotic orbits / false-"chaotic" on tori: at most floor(N / 100) of N."""
    rows = _verdicts(judge, cls)
    want = CHAOTIC if cls == CHAOS else REGULAR
    counts = Counter(v for _, _, (v, _) in rows)
    assert set(counts) <= set(VERDICTS)
    by = Counter((s, T, v) for s, T, (v, _) in rows)
    row = {"N": len(rows), "false": counts[FALSE[cls]], "undecided": counts[UNDECIDED], "correct": counts[want],
           "bound": _bound(len(rows)),
           "by_system_horizon": {f"{s} @ {T:g}": {v: by[(s, T, v)] for v in VERDICTS if by[(s, T, v)]}
                                 for s, T in dict.fromkeys((s, T) for s, T, _ in rows)}}
    AUDIT[(judge, cls)] = row
    record_property(f"audit_{judge}_{cls}", {k: row[k] for k in ("N", "false", "undecided", "correct", "bound")})
    per, systems = (PER_LOSCHMIDT, _systems(cls, True)) if judge == "loschmidt" else (PER, _systems(cls))
    assert row["N"] == per[cls] * 3 * len(systems)  # every realization judged, none skipped
    false = [(s, T, r[:300]) for s, T, (v, r) in rows if v == FALSE[cls]]
    assert row["false"] <= row["bound"], (row["false"], row["N"], false[:5])


@pytest.fixture(scope="module", autouse=True)
def _print_table():
    yield
    if AUDIT:
        lines = [f"{'judge':16s}{'orbits':9s}{'N':>5s}{'false':>7s}{'bound':>7s}{'undecided':>11s}{'correct':>9s}"]
        for (j, c), r in AUDIT.items():
            lines.append(f"{j:16s}{c:9s}{r['N']:5d}{r['false']:7d}{r['bound']:7d}{r['undecided']:11d}{r['correct']:9d}")
        print("\njudge audit (false = regular on chaotic orbits, chaotic on tori):\n" + "\n".join(lines))
        for (j, c), r in AUDIT.items():
            if r["undecided"] or r["false"]:
                print(f"  {j} / {c}: {r['by_system_horizon']}")
