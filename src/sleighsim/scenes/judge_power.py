"""The judges' power and false rates on orbits of known class (``sleighsim.chaos.power``), as independent
chunk jobs gathered into one dataset: verdict counts (judge x orbit class x system x horizon x verdict),
every realization's verdict and reason, the rates per judge and class with their 95% bounds, the
judges that vote, and each chaotic system's long-run confirmation (lambda_1, how sticky).

Tasks: every (horizon factor, realization, system) of the block, and one long confirmation run per
chaotic system; chunk k takes tasks k, k + n_chunks, ... (the confirmations last)."""

from __future__ import annotations

import logging
import time

import numpy as np
import xarray as xr

from sleighsim.chaos import power
from sleighsim.chaos.known_orbits import CHAOTIC_ORBITS, SYSTEMS
from sleighsim.io import cf
from sleighsim.io.netcdf import read_dataset
from sleighsim.scenes.checks import ConfigError
from sleighsim.scenes.kind import SceneKind
from sleighsim.scenes.memory import Span

log = logging.getLogger("sleighsim")
STREAM = 0  # the realizations' random stream (tests/chaos/test_judge_power.py draws from others)
CONFIRM_FIELDS = ("lambda_1", "stderr", "bound", "confirmed", "sticky_fraction", "T")


def tasks(cfg: dict) -> list[tuple]:
    """("judge", system, factor, index) for every realization, longest horizon first, the systems
    cycling fastest (with n_chunks coprime to the number of systems, every chunk holds a mix of
    systems), then ("confirm", system) per chaotic system."""
    out = [("judge", s, float(h), k) for h in sorted(cfg["horizons"], reverse=True) for k in range(cfg["samples"])
           for s in cfg["systems"]]
    return out + [("confirm", s) for s in cfg["systems"] if SYSTEMS[s].cls == CHAOTIC_ORBITS]


def _runs(cfg: dict, mine: list) -> list[dict]:
    """Every judge on the realizations of the judge tasks ``mine``, one row per judge."""
    rows = []
    for _, system, factor, k in mine:
        orbit = power.realizations(system, 1, STREAM, first=k)[0]
        hz = power.Horizon.from_config(cfg, factor)
        for judge in cfg.get("judges", power.JUDGES):
            if not power.applies(judge, orbit.known):
                continue
            start = time.perf_counter()
            verdict, reason = power.JUDGES[judge](orbit, hz, orbit.index)
            rows.append({"system": system, "horizon": factor, "index": k, "judge": judge, "verdict": verdict,
                         "reason": reason, "wall_s": time.perf_counter() - start})
        log.info("judge_power: %s @ %g #%d done", system, factor, k)
    return rows


RUN_ATTRS = {"system": cf.attrs("system of the realization", "text"),
             "horizon": cf.attrs("horizon factor on the scaled sleigh horizons"),
             "index": cf.attrs("realization index (its seed)"), "judge": cf.attrs("judge", "text"),
             "verdict": cf.attrs("verdict", "text"), "reason": cf.attrs("the judge's reason", "text"),
             "wall_s": cf.attrs("wall time of the judge's runs", "s")}
CONFIRM_ATTRS = {"lambda_1": cf.attrs("largest Lyapunov exponent of the long confirmation run", "rate"),
                 "stderr": cf.attrs("its standard error over 10 consecutive blocks", "rate"),
                 "bound": cf.attrs("rate polynomial growth can fake over the run", "rate"),
                 "confirmed": cf.attrs("chaos confirmed (lambda_1 - sigma stderr above the bound; 1 yes)"),
                 "sticky_fraction": cf.attrs("share of windows of 20 / lambda_1 with FTLE below lambda_1 / 4"),
                 "T": cf.attrs("length of the confirmation run", "time")}


def chunk(cfg: dict, index: int, scene: str = "") -> xr.Dataset:
    """Tasks index, index + n_chunks, ... of :func:`tasks`: the run table (dim run) and the
    confirmations (dim chaotic_system)."""
    mine = tasks(cfg)[index::cfg["n_chunks"]]
    rows = _runs(cfg, [t for t in mine if t[0] == "judge"])
    conf = {t[1]: power.confirm(t[1], cfg["confirm_periods"], cfg["sleigh"]["sigma"]) for t in mine
            if t[0] == "confirm"}
    ds = xr.Dataset({f"run_{k}": ("run", np.array([r[k] for r in rows], dtype=object if k in
                                                   ("system", "judge", "verdict", "reason") else None), a)
                     for k, a in RUN_ATTRS.items()})
    for k, a in CONFIRM_ATTRS.items():
        ds[f"confirm_{k}"] = ("chaotic_system", np.array([float(c[k]) for c in conf.values()], float), a)
    ds = ds.assign_coords(chaotic_system=("chaotic_system", np.array(list(conf), dtype=object),
                                          cf.attrs("chaotic system confirmed", "text")))
    ds.attrs.update(chunk=index, n_chunks=cfg["n_chunks"], scene=scene)
    return ds


def _table(parts: list[xr.Dataset], prefix: str, dim: str) -> dict:
    """The variables ``prefix``* of the chunks along ``dim``, joined as lists."""
    names = [v for v in parts[0].data_vars if v.startswith(prefix)]
    return {v: sum((p[v].values.tolist() for p in parts if p.sizes.get(dim, 0)), []) for v in names}


def gather(paths, cfg: dict, scene: str = "") -> xr.Dataset:
    """Every chunk's runs and confirmations, the verdict counts (``power.counts``), the rates per judge
    and class (``power.rates``) and the vote (``power.voting``)."""
    parts = [read_dataset(p) for p in paths]
    runs, conf = _table(parts, "run_", "run"), _table(parts, "confirm_", "chaotic_system")
    judges = list(cfg.get("judges", power.JUDGES))
    ds = power.counts(zip(runs["run_judge"], runs["run_system"], runs["run_horizon"], runs["run_verdict"]), judges,
                      cfg["systems"], [float(h) for h in cfg["horizons"]])
    ds["system_class"] = ("system", [SYSTEMS[s].cls for s in cfg["systems"]], cf.attrs("orbit class", "text"))
    ds["period"] = ("system", [SYSTEMS[s].period for s in cfg["systems"]],
                    cf.attrs("characteristic period P of the system (its component's leading line)", "time"))
    for k, a in RUN_ATTRS.items():
        ds[f"run_{k}"] = ("run", np.array(runs[f"run_{k}"], dtype=object if k in ("system", "judge", "verdict",
                                                                                   "reason") else None), a)
    order = [n for p in parts for n in (p.chaotic_system.values.tolist() if p.sizes.get("chaotic_system") else [])]
    ds = ds.assign_coords(chaotic_system=("chaotic_system", np.array(order, dtype=object),
                                          cf.attrs("chaotic system confirmed", "text")))
    for k, a in CONFIRM_ATTRS.items():
        ds[f"confirm_{k}"] = ("chaotic_system", np.array(conf[f"confirm_{k}"], float), a)
    _rates_into(ds)
    ds.attrs.update(scene=scene, horizon_rule=HORIZON_RULE, vote_rule=power.voting.__doc__.strip(),
                    spike_period=float(cfg["spike_period"]), samples=int(cfg["samples"]),
                    cost_total_s=float(np.sum(runs["run_wall_s"])))
    return ds


HORIZON_RULE = ("the sleigh's chaos_verdict settings (sleigh block) times s = P / spike_period for every time "
                "(tau, windows, spacing, t_align, dt, horizons), the horizons (T_megno, T_two, T_round, the last "
                "Loschmidt T, frequency T) also times the horizon factor")


def _rates_into(ds: xr.Dataset) -> None:
    """N, correct, wrong, undecided and the 95% upper bound on the wrong rate per (judge, orbit_class);
    ``votes`` per judge."""
    rows = {(r["judge"], r["class"]): r for r in power.rates(ds)}
    shape = (ds.sizes["judge"], ds.sizes["orbit_class"])
    for key, long_name in (("N", "realizations judged"), ("correct", "correct verdicts"),
                           ("wrong", "wrong verdicts"), ("undecided", "undecided verdicts"),
                           ("wrong_upper95", "one-sided 95% Clopper-Pearson upper bound on the wrong rate")):
        v = np.array([[rows[(j, c)][key] for c in ds.orbit_class.values] for j in ds.judge.values]).reshape(shape)
        ds[f"rate_{key}"] = (("judge", "orbit_class"), v, cf.attrs(long_name))
    vote = power.voting(ds)
    ds["votes"] = ("judge", np.array([int(j in vote) for j in ds.judge.values]),
                   cf.attrs("the judge votes (wrong at most 1 in 100 on every class; 1 yes)"))


def _samples(cfg: dict) -> float:
    """Realizations judged: systems x horizons x samples."""
    return len(cfg["systems"]) * len(cfg["horizons"]) * cfg["samples"]


def work(cfg: dict) -> float:
    """Time units integrated, in the sleigh's time unit before the scaling by P / spike_period (which a
    system's step size undoes, roughly): per realization and horizon factor h, h x (T_megno + T_two x 2
    + replicas x (T_round x max_rounds + replica_spacing) + 2 x the last Loschmidt T + frequency T x 2,
    double and long double), plus confirm_periods x spike_period per chaotic system."""
    c = cfg["sleigh"]
    per = (c["T_megno"] + 2 * c["T_two"] + c["replicas"] * (c["T_round"] * c["max_rounds"] + c["replica_spacing"])
           + 2 * c["loschmidt_T"][1] + 2 * c["frequency"]["T"])
    n_chaotic = sum(SYSTEMS[s].cls == CHAOTIC_ORBITS for s in cfg["systems"])
    mean_h = sum(cfg["horizons"]) / len(cfg["horizons"])
    return _samples(cfg) * mean_h * per + n_chaotic * cfg["confirm_periods"] * cfg["spike_period"]


def chunk_work(cfg: dict) -> list[float]:
    """Work of each chunk job: the total shared equally (the round-robin mixes systems and horizons)."""
    return [work(cfg) / cfg["n_chunks"]] * cfg["n_chunks"]


def _checks(w: str, cfg: dict) -> None:
    unknown = [s for s in cfg["systems"] if s not in SYSTEMS]
    if unknown:
        raise ConfigError(f"{w}.systems: unknown {unknown}; known: {list(SYSTEMS)}")
    bad = [j for j in cfg.get("judges", ()) if j not in power.JUDGES]
    if bad:
        raise ConfigError(f"{w}.judges: unknown {bad}; known: {list(power.JUDGES)}")
    n_judged = len([t for t in tasks(cfg) if t[0] == "judge"])
    if not 1 <= cfg["n_chunks"] <= n_judged:
        raise ConfigError(f"{w}.n_chunks = {cfg['n_chunks']} must lie in [1, {n_judged}] (systems x horizons x "
                          "samples: every chunk judges at least one realization)")


#: Keys (leaves) the work model reads.
WORK_KEYS = ("T_megno", "T_two", "replicas", "T_round", "max_rounds", "replica_spacing", "loschmidt_T", "T", "systems",
             "horizons", "samples", "confirm_periods", "spike_period", "n_chunks")

JUDGE_POWER = SceneKind(
    name="judge_power",
    title=("the chaos judges' power and false rates on orbits of known class (sticky chaos, slow-fast tori, "
           "textbook orbits) and the judges that vote"),
    chunk=chunk, gather=gather, integrates=False,
    records=lambda c: [Span(("sleigh.frequency.T x max(horizons)", c["sleigh"]["frequency"]["T"] * max(c["horizons"])),
                            ("sleigh.frequency.dt", c["sleigh"]["frequency"]["dt"]), 4)],
    work=work, chunk_work=chunk_work, modelled=lambda leaf: leaf in WORK_KEYS, checks=_checks)
