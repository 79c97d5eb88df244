"""The judges' power and false rates on orbits of known class (``known_orbits``), and the voting rule.

Every judge the verdict uses runs through one registry, :data:`JUDGES` = {name: callable(orbit,
horizon, seed) -> (verdict, reason)}, so one more judge is one more entry (and, if it needs a
reversible flow or the like, one entry in :data:`APPLIES`). Each judge is called as
tests/chaos/test_judge_audit.py and tests/chaos/test_chaos_frequency.py call it, in double (the
frequency judge, like the workflow, adds a long-double run while double has not converged).

Horizons (:class:`Horizon`): the sleigh's chaos_verdict settings (config/config.yaml: tau 10,
T_megno 5e4, T_two 5e4, T_round 2.5e4 x 4 rounds, Loschmidt T up to 2e4, frequency T 2e5, dt 0.5, ...)
in its time unit, each time multiplied by s = P / spike_period, the system's characteristic period
P (``known_orbits.System.period``) over the sleigh's spike period (about 2320 at the paper config),
so that an orbit is judged over as many of its periods as the sleigh over spike periods; the
horizons (T_megno, T_two, T_round, the last Loschmidt T, frequency T) are further multiplied by the
horizon ``factor``. Rates and bounds scale as 1 / s.

Counts: a dataset ``counts(judge, orbit_class, system, horizon, verdict)`` (:func:`counts`);
:func:`rates` gives N, P(correct), P(wrong), P(undecided) and the 95% upper bound on the wrong rate
(one-sided Clopper-Pearson) per judge and class, or per judge and system; :func:`voting` the judges
whose wrong rate on every class is at most 1 in 100.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from sleighsim.chaos import benettin, birkhoff, frequency, loschmidt, megno, section_megno, tangent, two_trajectory
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, SYSTEMS, TORI, System, draw, rng_for
from sleighsim.chaos.verdicts import CHAOTIC, REGULAR, UNDECIDED, VERDICTS, polynomial_rate_bound
from sleighsim.engine import integrators

CLASSES = (CHAOTIC_ORBITS, TORI)
RIGHT = {CHAOTIC_ORBITS: CHAOTIC, TORI: REGULAR}  # the correct verdict on each class
WRONG = {CHAOTIC_ORBITS: REGULAR, TORI: CHAOTIC}
MAX_WRONG_RATE = 0.01  # a judge votes only if it is wrong at most 1 time in 100 on every class
ROUNDING_RATIO = float(np.finfo(float).eps / np.finfo(np.longdouble).eps)  # double over long double


@dataclass(frozen=True)
class Horizon:
    """The chaos_verdict settings in the sleigh's time unit (times; the horizons already multiplied
    by ``factor``); :meth:`scale` converts them to a system's time unit."""

    factor: float
    spike_period: float
    tau: float
    T_megno: float
    megno_samples: int
    ftle_windows: tuple
    T_two: float
    d0_rel: float
    replicas: int
    replica_spacing: float
    t_align: float
    T_round: float
    max_rounds: int
    target_rel: float
    loschmidt_T: tuple
    loschmidt_n: int
    frequency_T: float
    frequency_dt: float
    splits: tuple
    min_cycles: float
    sigma: float
    decisive_T: float
    decisive_splits: tuple

    @classmethod
    def from_config(cls, cfg: dict, factor: float) -> Horizon:
        """From a judge_power block: its ``sleigh`` settings (chaos_verdict's keys) and a horizon factor."""
        c = cfg["sleigh"]
        fc = c["frequency"]
        return cls(factor=float(factor), spike_period=float(cfg["spike_period"]), tau=c["tau"],
                   T_megno=c["T_megno"] * factor, megno_samples=c["megno_samples"],
                   ftle_windows=tuple(c["ftle_windows"]), T_two=c["T_two"] * factor, d0_rel=c["d0_rel"],
                   replicas=c["replicas"], replica_spacing=c["replica_spacing"], t_align=c["t_align"],
                   T_round=c["T_round"] * factor, max_rounds=c["max_rounds"], target_rel=c["target_rel"],
                   loschmidt_T=(c["loschmidt_T"][0], c["loschmidt_T"][1] * factor), loschmidt_n=c["loschmidt_n"],
                   frequency_T=fc["T"] * factor, frequency_dt=fc["dt"], splits=tuple(fc["splits"]),
                   min_cycles=fc["min_cycles"], sigma=c["sigma"], decisive_T=c["decisive"]["T"] * factor,
                   decisive_splits=tuple(c["decisive"]["splits"]))

    def scale(self, system: System) -> float:
        """s = the system's characteristic period / the sleigh's spike period."""
        return system.period / self.spike_period

    def steps(self, system: System, key: str) -> tuple[float, int]:
        """(tau, the horizon ``key`` as a whole number of intervals tau) in the system's time unit."""
        tau = self.tau * self.scale(system)
        return tau, max(1, round(getattr(self, key) / self.tau))


@dataclass(frozen=True)
class Orbit:
    """One realization: ``system`` (a name of known_orbits.SYSTEMS), its start ``y0`` and ``index``."""

    system: str
    y0: tuple
    index: int

    @property
    def known(self) -> System:
        """Its system."""
        return SYSTEMS[self.system]


def realizations(system: str, n: int, stream: int, first: int = 0) -> list[Orbit]:
    """Realizations first .. first + n - 1 of ``system`` in ``stream``, each from its own generator."""
    s = SYSTEMS[system]
    ta = None if s.draw is not None else _flow(system, "double")
    return [Orbit(system, tuple(float(v) for v in draw(s, rng_for(system, stream, i), ta)), i)
            for i in range(first, first + n)]


# ----------------------------------------------------------------------------- integrators (one per process)

@functools.cache
def _flow(system: str, precision: str):
    hy = integrators.guarded_heyoka()  # the audit's only heyoka use; imported when a judge first runs

    fp = np.longdouble if precision == "long double" else float
    sys = SYSTEMS[system].build(hy)
    return hy.taylor_adaptive(sys, np.full(len(sys), 0.1, dtype=fp), fp_type=fp, compact_mode=True)


@functools.cache
def _megno_ta(system: str):
    import heyoka as hy

    return integrators.megno_integrator(SYSTEMS[system].build(hy))


@functools.cache
def _replica_ta(system: str, lanes: int):
    import heyoka as hy

    ta, n, _ = integrators.tangent_integrator_batch(SYSTEMS[system].build(hy), lanes)
    return ta, n


# ----------------------------------------------------------------------------- the judges

@functools.lru_cache(maxsize=2)
def _megno_run(orbit: Orbit, hz: Horizon, seed: int) -> dict:
    """One megno run (shared by the FTLE and MEGNO judges) over T_megno, renormalised every tau."""
    tau, n = hz.steps(orbit.known, "T_megno")
    tm, dim = _megno_ta(orbit.system)
    return megno.megno(tm, dim, np.array(orbit.y0), T=n * tau, n_samples=min(hz.megno_samples, n), tau=tau, seed=seed)


def judge_ftle(orbit: Orbit, hz: Horizon, seed: int) -> tuple[str, str]:
    """``tangent.judge_ftle`` on the megno run's one-vector series, windows ftle_windows x s (those
    with at least 2 windows after skipping t_align x s)."""
    m = _megno_run(orbit, hz, seed)
    tau = m["tau"]
    skip = tau * math.ceil(hz.t_align / hz.tau)
    usable = m["log_growth"].size * tau - skip
    windows = [tau * round(w / hz.tau) for w in hz.ftle_windows if usable / (tau * round(w / hz.tau)) >= 2]
    if not windows:
        return UNDECIDED, f"no FTLE window fits twice in {usable:.3g}"
    f = tangent.finite_time_exponents(m["log_growth"], tau, windows, t_skip=skip)
    return tangent.judge_ftle(f["rate"], f["rate_err"], f["T"], f["tau"], f["spread_slope"], f["spread_slope_err"],
                              sigma=hz.sigma)


def judge_megno(orbit: Orbit, hz: Horizon, seed: int) -> tuple[str, str]:
    """``megno.judge_megno_run`` on the megno run over T_megno x s."""
    m = _megno_run(orbit, hz, seed)
    return megno.judge_megno_run(m, m["tau"] * m["log_growth"].size, hz.sigma)


def _along_orbit(orbit: Orbit, lanes: int, spacing: float) -> np.ndarray:
    """``lanes`` states along the orbit from its start, ``spacing`` apart."""
    ta = _flow(orbit.system, "double")
    ta.time = 0.0
    ta.state[:] = orbit.y0
    return np.array(ta.propagate_grid(spacing * np.arange(lanes, dtype=float))[-1])


def judge_benettin(orbit: Orbit, hz: Horizon, seed: int) -> tuple[str, str]:
    """``tangent.judge_benettin`` on ``benettin.replica_exponents``: replicas lanes along the orbit,
    replica_spacing x s apart, rounds of T_round x s up to max_rounds, target_rel, t_align x s,
    regular_floor the polynomial bound at the capped horizon (as test_judge_audit's CONFIG_LIKE)."""
    s = hz.scale(orbit.known)
    tau, n_round = hz.steps(orbit.known, "T_round")
    ta, n = _replica_ta(orbit.system, hz.replicas)
    floor = polynomial_rate_bound(hz.max_rounds * n_round * tau, tau)
    res = benettin.replica_exponents(ta, n, 1, _along_orbit(orbit, hz.replicas, hz.replica_spacing * s), tau,
                                     T_round=n_round * tau, max_rounds=hz.max_rounds, target_rel=hz.target_rel,
                                     regular_floor=floor, t_align=tau * math.ceil(hz.t_align / hz.tau),
                                     sigma=hz.sigma, seed=seed)
    return tangent.judge_benettin(res, tau, hz.sigma)


def judge_two_trajectory(orbit: Orbit, hz: Horizon, seed: int) -> tuple[str, str]:
    """``two_trajectory.judge_two_trajectory`` on one run over T_two x s, d0 = d0_rel x max|y0|."""
    tau, n = hz.steps(orbit.known, "T_two")
    y0 = np.array(orbit.y0)
    r = two_trajectory.two_trajectory(_flow(orbit.system, "double"), y0, d0=hz.d0_rel * np.max(np.abs(y0)), tau=tau,
                                      T=n * tau, seed=seed)
    return two_trajectory.judge_two_trajectory(r["rate"], r["stderr"], r["T"], r["tau"], r["running_slope"],
                                               r["running_slope_err"], sigma=hz.sigma)


def judge_loschmidt(orbit: Orbit, hz: Horizon, seed: int) -> tuple[str, str]:
    """``loschmidt.judge_loschmidt_run`` on loschmidt_n return times log-spaced in loschmidt_T x s
    (reversible systems only; no seed: the run is deterministic)."""
    s = hz.scale(orbit.known)
    grid = np.geomspace(hz.loschmidt_T[0] * s, hz.loschmidt_T[1] * s, hz.loschmidt_n)
    L = loschmidt.loschmidt(_flow(orbit.system, "double"), np.array(orbit.y0), grid, orbit.known.involution)
    return loschmidt.judge_loschmidt_run(L, sigma=hz.sigma)


def _frequency_run(orbit: Orbit, hz: Horizon, precision: str) -> dict:
    s = hz.scale(orbit.known)
    fp = np.longdouble if precision == "long double" else float
    return frequency.frequency_drift(_flow(orbit.system, precision), np.array(orbit.y0, dtype=fp),
                                     T=hz.frequency_T * s, dt=hz.frequency_dt * s, component=orbit.known.component,
                                     splits=hz.splits, min_cycles=hz.min_cycles)


def judge_frequency(orbit: Orbit, hz: Horizon, seed: int) -> tuple[str, str]:
    """``frequency.judge_frequency`` on the drift of the system's component over frequency.T x s, sampled
    every dt x s: the double run, then (as the workflow) a long-double run while double has not converged
    and had at least two usable splits (no seed: deterministic)."""
    d = _frequency_run(orbit, hz, "double")
    runs = [frequency.judged_run("double", d)]
    verdict = frequency.judge_frequency(runs, sigma=hz.sigma)
    if verdict[0] == REGULAR or d["splits"].size < 2:
        return verdict
    ld = _frequency_run(orbit, hz, "long double")
    lr, lr_err = frequency.frequency_log_ratio(d, ld)
    runs.append(frequency.judged_run("long double", ld, log_ratio=lr, log_ratio_err=lr_err,
                                     rounding_ratio=ROUNDING_RATIO))
    return frequency.judge_frequency(runs, sigma=hz.sigma)


#: Samples per characteristic period of the decisive judges' orbit (the section's maxima and the Birkhoff
#: sums; the sleigh's decisive stage samples 0.5 in a spike period of ~2320, far finer than needed there).
DECISIVE_SAMPLES_PER_PERIOD = 50


@functools.lru_cache(maxsize=2)
def _decisive_run(orbit: Orbit, hz: Horizon, seed: int) -> dict:
    """The decisive stage's orbit: one tangent vector's log-norm and the state every P / 50 over decisive T x s
    (``section_megno.log_norm_series``, in double: the audit's orbits are followed by double)."""
    s = orbit.known
    tm, dim = _megno_ta(orbit.system)
    return section_megno.log_norm_series(tm, dim, np.array(orbit.y0), T=hz.decisive_T * hz.scale(s),
                                         dt=s.period / DECISIVE_SAMPLES_PER_PERIOD, seed=seed)


def judge_section_megno(orbit: Orbit, hz: Horizon, seed: int) -> tuple[str, str]:
    """``section_megno.judge_section_megno`` on the return map to the maxima of the system's component (the
    sleigh's: Omega's spikes) over decisive T x s."""
    r = _decisive_run(orbit, hz, seed)
    crossings = section_megno.section_times(r["t"], r["X"][:, orbit.known.component])
    if crossings.size < section_megno.MIN_RETURNS + 1:
        return UNDECIDED, f"{crossings.size} crossings of the section"
    return section_megno.judge_section_megno(section_megno.section_megno(r["t"], r["log_norm"], crossings), hz.sigma)


def judge_birkhoff(orbit: Orbit, hz: Horizon, seed: int) -> tuple[str, str]:
    """``birkhoff.judge_birkhoff`` on the weighted Birkhoff averages of the orbit's components over decisive
    T x s (windows T / K, K in decisive splits), followed in double: G x rounding taken as double's
    rounding (the audit's orbits need no gauge; the digits are capped at what double's sums resolve)."""
    r = _decisive_run(orbit, hz, seed)
    run = birkhoff.digits(birkhoff.observables(r["X"][:-1]), float(r["t"][1]), hz.decisive_splits)
    return birkhoff.judge_birkhoff(run, gain_rounding=2.0**-53)


#: name -> callable(orbit, horizon, seed) -> (verdict, reason)
JUDGES = {"ftle": judge_ftle, "megno": judge_megno, "benettin": judge_benettin,
          "two_trajectory": judge_two_trajectory, "loschmidt": judge_loschmidt, "frequency": judge_frequency,
          "section_megno": judge_section_megno, "birkhoff": judge_birkhoff}
#: name -> which systems the judge applies to (absent: all)
APPLIES = {"loschmidt": lambda system: system.involution is not None}


def applies(judge: str, system: System) -> bool:
    """Whether ``judge`` runs on ``system`` (the Loschmidt test: reversible systems only)."""
    return APPLIES.get(judge, lambda _: True)(system)


def judge_all(orbit: Orbit, hz: Horizon, judges=None) -> dict[str, tuple[str, str]]:
    """{judge: (verdict, reason)} of every applicable judge of ``judges`` (default: all) on one
    realization; the seed of the engines that take one is the realization's index."""
    return {name: JUDGES[name](orbit, hz, orbit.index) for name in (judges or JUDGES)
            if applies(name, orbit.known)}


# ----------------------------------------------------------------------------- counts, rates and the vote

def counts(rows, judges, systems, factors) -> xr.Dataset:
    """``counts(judge, orbit_class, system, horizon, verdict)`` (int) from rows (judge, system, factor,
    verdict); a system's counts sit under its own class only."""
    n = np.zeros((len(judges), len(CLASSES), len(systems), len(factors), len(VERDICTS)), int)
    for judge, system, factor, verdict in rows:
        n[list(judges).index(judge), CLASSES.index(SYSTEMS[system].cls), list(systems).index(system),
          list(factors).index(factor), VERDICTS.index(verdict)] += 1
    return xr.Dataset(
        {"counts": (("judge", "orbit_class", "system", "horizon", "verdict"), n,
                    {"long_name": "number of realizations given each verdict", "units": "1"})},
        coords={"judge": ("judge", list(judges), {"long_name": "judge (chaos.power.JUDGES)"}),
                "orbit_class": ("orbit_class", list(CLASSES), {"long_name": "known class of the orbits"}),
                "system": ("system", list(systems), {"long_name": "system (chaos.known_orbits.SYSTEMS)"}),
                "horizon": ("horizon", np.asarray(factors, float),
                            {"long_name": "horizon factor on the scaled sleigh horizons", "units": "1"}),
                "verdict": ("verdict", list(VERDICTS), {"long_name": "verdict"})})


def upper_bound(wrong: int, N: int, level: float = 0.95) -> float:
    """One-sided Clopper-Pearson upper confidence bound on a rate seen ``wrong`` times in N (1 at N = 0;
    3 / N roughly when none is seen, the rule of three)."""
    from scipy.stats import beta

    return 1.0 if N == 0 or wrong >= N else float(beta.ppf(level, wrong + 1, N - wrong))


def _row(judge: str, cls: str, c: np.ndarray) -> dict:
    """Rates from the verdict counts c (in VERDICTS order) of one judge on one class."""
    by = dict(zip(VERDICTS, (int(v) for v in c)))
    N = sum(by.values())
    right, wrong = by[RIGHT[cls]], by[WRONG[cls]]
    p = (lambda k: k / N) if N else (lambda k: math.nan)
    return {"judge": judge, "class": cls, "N": N, "correct": right, "wrong": wrong, "undecided": by[UNDECIDED],
            "p_correct": p(right), "p_wrong": p(wrong), "p_undecided": p(by[UNDECIDED]),
            "wrong_upper95": upper_bound(wrong, N)}


def rates(ds: xr.Dataset, by: str = "orbit_class") -> list[dict]:
    """Per judge and class (``by="orbit_class"``) or per judge and system (``by="system"``, the row's
    ``class`` its system's): N, correct, wrong, undecided, their shares and the wrong rate's 95% bound,
    summed over horizons (and systems)."""
    c = ds.counts.sum("horizon")
    out = []
    for judge in ds.judge.values:
        for key in ds[by].values:
            if by == "orbit_class":
                row = _row(str(judge), str(key), c.sel(judge=judge, orbit_class=key).sum("system").values)
            else:
                cls = SYSTEMS[str(key)].cls
                row = {**_row(str(judge), cls, c.sel(judge=judge, system=key, orbit_class=cls).values),
                       "system": str(key)}
            out.append(row)
    return out


def voting(ds: xr.Dataset, max_rate: float = MAX_WRONG_RATE) -> set[str]:
    """The judges that vote: measured on both classes, wrong at most ``max_rate`` of the time on each
    (a judge whose wrong-verdict rate on any class exceeds 1 in 100 does not vote)."""
    rows = rates(ds)
    out = set()
    for judge in ds.judge.values:
        mine = [r for r in rows if r["judge"] == judge]
        if all(r["N"] > 0 and r["wrong"] <= max_rate * r["N"] for r in mine) and len(mine) == len(CLASSES):
            out.add(str(judge))
    return out



# ----------------------------------------------------------------------------- the committed record

def record(ds: xr.Dataset) -> dict:
    """The audit's measured record: per horizon factor, judge and class the counts N, correct, wrong and
    undecided (``rates`` at that horizon), with where they came from (the dataset's commit, date and
    cost)."""
    keep = ("N", "correct", "wrong", "undecided")
    counts = {}
    for h in ds.horizon.values:
        rows = rates(ds.sel(horizon=[h]))
        counts[float(h)] = {str(j).replace("-", "_"): {r["class"]: {k: int(r[k]) for k in keep} for r in rows
                                                       if r["judge"] == j}
                            for j in ds.judge.values}  # "two-trajectory": the name the first audits used
    return {"counts": counts, "source": {"git_commit": str(ds.attrs.get("git_commit", "?")),
                                         "created_utc": str(ds.attrs.get("created_utc", "?")),
                                         "cost_total_s": float(ds.attrs.get("cost_total_s", math.nan))}}


def merged_records(records: list[dict]) -> dict:
    """Records of audits of different judges as one: the counts side by side (a judge in two records is
    refused), the sources listed."""
    out = {"counts": {}, "sources": []}
    for rec in records:
        for h, judges in rec["counts"].items():
            mine = out["counts"].setdefault(float(h), {})
            if set(mine) & set(judges):
                raise ValueError(f"judges {sorted(set(mine) & set(judges))} are in two records")
            mine.update(judges)
        out["sources"].append(rec["source"])
    return out


def record_rates(rec: dict, horizon: float | None = None) -> list[dict]:
    """Per judge and class of a record: N, correct, wrong, undecided, their shares and the 95% upper bound on
    the wrong rate, as ``rates`` gives them; at the audited horizon factor ``horizon``, or summed over the
    record's horizons (None)."""
    total = {}
    for h, judges in rec["counts"].items():
        if horizon is not None and float(h) != horizon:
            continue
        for judge, by_class in judges.items():
            for cls, c in by_class.items():
                t = total.setdefault((judge, cls), dict.fromkeys(("N", "correct", "wrong", "undecided"), 0))
                for k in t:
                    t[k] += int(c[k])
    out = []
    for (judge, cls), c in sorted(total.items()):
        p = (lambda k, n=c["N"]: k / n) if c["N"] else (lambda k: math.nan)
        out.append({"judge": judge, "class": cls, **c, "p_correct": p(c["correct"]), "p_wrong": p(c["wrong"]),
                    "p_undecided": p(c["undecided"]), "wrong_upper95": upper_bound(c["wrong"], c["N"])})
    return out


def record_voting(rec: dict, horizon: float, max_rate: float = MAX_WRONG_RATE) -> set[str]:
    """The judges that vote at a run's horizon factor ``horizon`` (its horizon over the audit's at factor 1):
    by the counts at the largest audited factor not above it (none: no judge votes), measured on both
    classes and wrong at most ``max_rate`` of the time on each (the rule of ``voting``)."""
    below = [float(h) for h in rec["counts"] if float(h) <= horizon]
    if not below:
        return set()
    rows = record_rates(rec, max(below))
    return {j for j in {r["judge"] for r in rows}
            if sum(r["judge"] == j for r in rows) == len(CLASSES)
            and all(r["N"] > 0 and r["wrong"] <= max_rate * r["N"] for r in rows if r["judge"] == j)}


# ----------------------------------------------------------------------------- the chaotic orbits' class

STICKY_EFOLDS, STICKY_SHARE = 20.0, 0.25  # a window of 20 / lambda_1 is sticky when its FTLE < lambda_1 / 4


def confirm(system: str, periods: float, sigma: float = 3.0, n_blocks: int = 10) -> dict:
    """Confirm a chaotic orbit's class by one long run from its base state (far beyond the audit's
    horizons): a megno run over ``periods`` characteristic periods P, renormalised every P;
    ``tangent.growth_confirmed`` on its log growth (lambda_1, stderr from n_blocks consecutive blocks,
    confirmed when lambda_1 - sigma stderr exceeds the polynomial bound). How sticky: the share of
    consecutive windows of STICKY_EFOLDS / lambda_1 whose FTLE lies below STICKY_SHARE lambda_1 (time spent
    near islands, where the orbit is nearly regular). Returns lambda_1, stderr, bound, confirmed,
    sticky_fraction, T."""
    s = SYSTEMS[system]
    tau = s.period
    n_steps = max(1, round(periods))
    tm, dim = _megno_ta(system)
    m = megno.megno(tm, dim, np.array(s.base), T=n_steps * tau, n_samples=min(100, n_steps), tau=tau, seed=0)
    lam, err, bound, ok = tangent.growth_confirmed(m["log_growth"], tau, n_steps * tau, sigma, n_blocks)
    w = math.ceil(STICKY_EFOLDS / (lam * tau)) if lam > 0 else 0
    g = m["log_growth"]
    ftle = g[:g.size // w * w].reshape(-1, w).sum(axis=1) / (w * tau) if 0 < w <= g.size // 2 else np.array([])
    sticky = float(np.mean(ftle < STICKY_SHARE * lam)) if ftle.size else math.nan
    return {"lambda_1": lam, "stderr": err, "bound": bound, "confirmed": ok, "sticky_fraction": sticky,
            "T": n_steps * tau}
