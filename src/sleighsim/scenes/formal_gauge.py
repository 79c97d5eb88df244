"""The faithfulness gauge of the formal system's rows (C26, ``scenes.formal``): which arithmetic follows a row's
settled orbit, and where none of the ladder does, the unit roundoff one would need and its measured price.

Times in the flow's time unit; ln G the natural log of the largest singular value of a spike cycle's tangent map;
prices in CPU seconds on one core (the price record's machine and commit).
"""

from __future__ import annotations

import math

import numpy as np

from sleighsim.chaos.faithfulness import FAITHFUL_MAX, FOLLOWS, log10_gain_rounding, settled_gains
from sleighsim.precision import Precision
from sleighsim.scenes import trigger_price
from sleighsim.scenes.grid import LADDER

#: The row's gauge variables: floats, then texts.
FLOATS = ("row_ln_gain_max", "row_gain_steps_per_cycle", "gauge_spike_interval", "gauge_needed_log10_rounding")
TEXTS = ("faithful_arithmetic", "faithful_price")

#: The (long_name, kind) of the gauge's own variables (sleighsim.io.cf); row_ln_gain_max, row_gain_steps_per_cycle
#: and faithful_arithmetic mean what they mean on F11's rows (the shared vocabulary's).
VOCABULARY = {
    "gauge_spike_interval": ("mean spike interval of the gauge's run", "time"),
    "gauge_needed_log10_rounding": ("log10 of the unit roundoff an arithmetic needs to follow the row's orbit, where "
                                    "none of the gauge's ladder does", "1"),
    "faithful_price": ("the cheapest measured arithmetic fine enough for the row's orbit and its price, where none of "
                       "the gauge's ladder follows it (scenes.trigger_price.PRICE_RULE)", "text"),
}

#: Written into the formal_exponents dataset (attribute gauge_rule).
GAUGE_RULE = (
    "per row from gauge.eps_min on: the faithfulness gauge along the row's settled orbit (chaos.faithfulness."
    "spike_cycle_gains over gauge.T, the tangent renormalised every gauge.tau, in double at tol): the largest ln G "
    "of a complete spike cycle, the Taylor steps per cycle, the mean spike interval and the cheapest of "
    f"{', '.join(p.value for p in LADDER)} that follows (G x steps x rounding below chaos.faithfulness.FAITHFUL_MAX); "
    "where none does, log10 of the unit roundoff one would need (scenes.trigger_price.log10_needed) and its price "
    "(scenes.trigger_price.PRICE_RULE, per cycle of the mean interval). Rows below eps_min: not gauged (empty texts, "
    "NaN); a row without two spikes within gauge.T: unknown."
)


def not_gauged(why: str = "") -> dict:
    """A row the gauge does not read: NaN numbers, ``why`` as its arithmetic (empty below eps_min)."""
    return {**dict.fromkeys(FLOATS, math.nan), "faithful_arithmetic": why, "faithful_price": ""}


def cheapest(gauge: dict) -> Precision | None:
    """The cheapest of LADDER that follows by ``gauge`` (``spike_cycle_gains``' answer); None when none does."""
    return next((p for p in LADDER if gauge["follows"][p] == FOLLOWS), None)


def row_gauge(params, y, g: dict, tol: float, compact_mode: bool, spike_factor: float, record: dict) -> dict:
    """:data:`GAUGE_RULE` for one row from its settled state ``y`` (model variables) at ``params``, with the gauge
    block ``g`` (T, tau), the tolerance and compact mode of the double run and the price ``record``."""
    gauge = settled_gains(params, y, tol=tol, compact_mode=compact_mode, T=g["T"], tau=g["tau"],
                          spike_factor=spike_factor)
    if not math.isfinite(gauge["ln_gain_max"]):
        return not_gauged(f"unknown (fewer than two spikes within gauge.T = {g['T']:g})")
    interval = float(np.mean(np.diff(gauge["spike_times"])))
    out = {"row_ln_gain_max": gauge["ln_gain_max"], "row_gain_steps_per_cycle": gauge["steps_per_cycle"],
           "gauge_spike_interval": interval, "gauge_needed_log10_rounding": math.nan, "faithful_price": ""}
    best = cheapest(gauge)
    if best is not None:
        return {**out, "faithful_arithmetic": best.value}
    finest = LADDER[-1]
    lgr = log10_gain_rounding(gauge["ln_gain_max"], finest.rounding, gauge["steps_per_cycle"])
    need = trigger_price.log10_needed(lgr, finest.rounding, FAITHFUL_MAX)
    return {**out, "gauge_needed_log10_rounding": need,
            "faithful_arithmetic": f"none of {', '.join(p.value for p in LADDER)} (G x steps x rounding 10^{lgr:.1f} "
                                   f"in {finest.value})",
            "faithful_price": trigger_price.price(record, 10.0**need, interval)}
