"""The chaos verdict's tangent indicators: Benettin over independent replicas, the finite-time exponents,
MEGNO and its long-double precision check, and the faithfulness gauge that gates every indicator,
run on the sleigh for :mod:`sleighsim.scenes.verdict`."""

from __future__ import annotations

import logging
import math

from sleighsim.chaos import benettin
from sleighsim.chaos.faithfulness import settled_gains
from sleighsim.chaos.megno import (
    judge_megno_run,
    megno,
    megno_in_long_double,
    megno_rate,
)
from sleighsim.chaos.rule import (
    TANGENT_BASED,
    precision_gate,
)
from sleighsim.chaos.tangent import (
    finite_time_exponents,
    growth_confirmed,
    judge_benettin,
    judge_ftle,
)
from sleighsim.chaos.verdicts import CHAOTIC
from sleighsim.engine import integrators
from sleighsim.precision import Precision
from sleighsim.scenes.common import stored_state, tolerance

log = logging.getLogger("sleighsim")


N_BLOCKS = 10  # consecutive blocks of the long-double run for its standard error


def gain_run(params, y, cfg: dict) -> dict:
    """The faithfulness gauge along the settled orbit from y: ln G of each spike cycle (the largest
    singular value of the one-period tangent map, ``faithfulness.spike_cycle_gains``) over T_gain, in
    double at tol, and G x rounding per arithmetic."""
    return settled_gains(params, y, tol=cfg["tol"], compact_mode=cfg["compact_mode"], T=cfg["T_gain"],
                         tau=cfg["tau_gain"], spike_factor=cfg["transient"]["spike_factor"])


def replica_run(params, replicas, cfg: dict, scene: str) -> dict:
    """Benettin over the replicas (one SIMD lane each, 4 tangent vectors), ``benettin.replica_exponents``
    at tol with tau, T_round, max_rounds, target_rel, t_align, regular_floor and sigma from cfg."""
    ta, _ = integrators.sleigh_tangent_batch(cfg["replicas"], cfg["tol"], cfg["compact_mode"], k=4)
    integrators.set_pars(ta, params)
    return benettin.replica_exponents(ta, 4, 4, replicas, cfg["tau"], T_round=cfg["T_round"],
                                      max_rounds=cfg["max_rounds"],
                                      target_rel=cfg["target_rel"], t_align=cfg["t_align"],
                                      regular_floor=cfg["regular_floor"], sigma=cfg["sigma"], label=scene)


def tangent_indicators(params, replicas, res: dict, cfg: dict, scene: str, values: dict, errors: dict,
                        verdicts: dict, *, long_double: bool) -> tuple:
    """The tangent-based indicators into values, errors and verdicts: Benettin from the replica run
    res, the finite-time exponents of its first vector, MEGNO from the first replica; when one of
    them says chaotic in double, the long-double precision check, which gates them and whose MEGNO
    run is judged instead (only with ``long_double``: without, a chaotic tangent-based verdict is
    left undecided, the check not made). Returns the double MEGNO run, the check
    (``precision_check``; "not run" and no MEGNO run when not made), the double run's MEGNO verdict
    and the precision judged."""
    tau, sigma = cfg["tau"], cfg["sigma"]
    values["benettin"], errors["benettin"] = float(res["exponents"][0]), float(res["stderr"][0])
    verdicts["benettin"] = judge_benettin(res, tau, sigma)
    g = res["log_growth"][:, 0, 0]
    windows = [w for w in cfg["ftle_windows"] if g.size * tau / w >= 2]
    f = finite_time_exponents(g, tau, windows)
    values["ftle"], errors["ftle"] = f["rate"], f["rate_err"]
    verdicts["ftle"] = judge_ftle(f["rate"], f["rate_err"], f["T"], tau, f["spread_slope"], f["spread_slope_err"],
                                  sigma=sigma)
    m = megno_run(params, replicas[0], cfg)
    values["megno"], errors["megno"] = megno_rate(m)
    verdicts["megno"] = megno_double = judge_megno_run(m, cfg["T_megno"], sigma)
    megno_precision = Precision.DOUBLE
    ld = {"lambda_1": math.nan, "stderr": math.nan, "check": "not run", "megno": None,
          "reason": "long-double check not made: the decisive stage judges this state"}
    if not long_double:
        precision_gate(verdicts, ld)
    elif any(verdicts[k][0] == CHAOTIC for k in TANGENT_BASED if k in verdicts):
        ld = precision_check(params, replicas[0], cfg, scene)
        precision_gate(verdicts, ld)
        values["megno"], errors["megno"] = megno_rate(ld["megno"])
        megno_precision = Precision.LONG_DOUBLE
        verdicts["megno"] = megno_in_long_double(judge_megno_run(ld["megno"], cfg["T_long_double"], sigma), ld,
                                                 megno_double, cfg["T_long_double"], cfg["T_megno"])
    return m, ld, megno_double, megno_precision


def megno_run(params, y, cfg: dict, *, precision: Precision = Precision.DOUBLE) -> dict:
    """MEGNO from y (model variables), renormalised every tau, <Y> recorded at megno_samples times
    (``chaos.megno.megno``): over T_megno in double at tol, or over T_long_double in long double at its
    machine epsilon."""
    T = cfg["T_long_double"] if precision is Precision.LONG_DOUBLE else cfg["T_megno"]
    ta, _ = integrators.sleigh_megno(tolerance(cfg, precision), precision, cfg["compact_mode"])
    integrators.set_pars(ta, params)
    return megno(ta, 4, stored_state(y), T=T, n_samples=cfg["megno_samples"], tau=cfg["tau"],
                 callback=integrators.bounded(ta))


#: Written into the chaos_verdict dataset (attribute precision_rule).
PRECISION_CHECK_RULE = (
    "One replica (from y, model variables) in long double over T_long_double, with MEGNO: a tangent-based "
    "chaotic verdict stands only if its tangent vector, too, grows exponentially: lambda_1 (log growth after "
    "t_align / its time) - sigma stderr (N_BLOCKS consecutive blocks) > 2 ln(T / tau) / T. On the sleigh, "
    "rounding noise off the leading direction is amplified by many orders at every spike, which inflates "
    "double-precision exponents and MEGNO. The run's MEGNO replaces the double-precision one as the MEGNO "
    "indicator. The check runs only when a tangent-based indicator says chaotic in double (it costs about 4 "
    "min), so MEGNO's precision depends on the other tangent-based verdicts: the one place where a larger "
    "uncertainty elsewhere (a Benettin rate no longer resolved) can change which MEGNO run is judged. Returns "
    "lambda_1, stderr, check (\"confirmed\" | \"not confirmed\"), the reason and the run (``megno``)."
)


def precision_check(params, y, cfg: dict, scene: str) -> dict:
    """Applies :data:`PRECISION_CHECK_RULE`, the rule as the datasets record it (just above)."""
    tau, sigma, T = cfg["tau"], cfg["sigma"], cfg["T_long_double"]
    m = megno_run(params, y, cfg, precision=Precision.LONG_DOUBLE)
    g = m["log_growth"][math.ceil(cfg["t_align"] / tau):]  # the alignment of the vector left out
    lam, err, bound, ok = growth_confirmed(g, tau, T, sigma, N_BLOCKS)
    text = (f"long double (tol {Precision.LONG_DOUBLE.epsilon:.2g}): lambda_1 = {lam:.3g} +- {err:.2g} "
            f"over T = {T:.3g}, bound {bound:.2g}")
    log.info("%s: precision check: %s", scene, text)
    return {"lambda_1": lam, "stderr": err, "check": "confirmed" if ok else "not confirmed",
            "reason": ("confirmed in " if ok else "not confirmed in ") + text, "megno": m}
