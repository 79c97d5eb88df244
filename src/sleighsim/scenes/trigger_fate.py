"""Where the paper's orbit lands after each escape (the trigger law's fate, issue 52 item 3): every level's
post-escape state followed on in an arithmetic the faithfulness gauge accepts for the torus it reaches.

Each level's state ``offset`` after its first spike, taken from that run's own samples in that run's
arithmetic (what its error chose), starts one lane of a double-double batch (sleighsim.engine.ddbatch) over T,
sampled every dt. Its spikes (transient rule) are refined on the section delta = 0 (sleighsim.engine.ddsection,
sleighsim.analysis.fate.refined_peaks); the train of refined intervals gives the torus' interval, scatter and
class (sleighsim.analysis.fate.train). The gauge: from the sample ``lead`` before the first refined spike, the
orbit with its 4 x 4 tangent map over two cycles (sleighsim.chaos.lane_gain), ln G of its cycle, the plain
run's Taylor steps per cycle, and faithfulness.follows with the arithmetic's rounding. A level double-double
does not follow is followed again, the same way, in triple-double (sleighsim.engine.tdtaylor), and recorded
from there with that run's CPU seconds (its measured price).

Conventions: times in the flow's time unit from each level's post-escape state; CPU seconds of this process.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np

from sleighsim.analysis import fate
from sleighsim.chaos import faithfulness
from sleighsim.chaos.lane_gain import lane_gains
from sleighsim.engine import ddsection, tdarith
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.engine.ddtaylor import as_pair
from sleighsim.engine.tdtaylor import TDBatch, as_triples
from sleighsim.engine.transient import spike_times
from sleighsim.precision import Precision
from sleighsim.scenes.trigger_price import log10_needed

log = logging.getLogger("sleighsim")
DD, TD = Precision.DOUBLE_DOUBLE.value, "triple-double"

#: Written into the trigger_law dataset (attribute fate_rule).
FATE_RULE = (
    "Each run's sample fate_offset after its refined first spike, in the run's own arithmetic, starts one lane of "
    "a double-double batch (tolerance fate_tol) over fate_T sampled every fate_dt; its spikes (the transient rule) "
    "refined (peak_rule) give the landed torus' train (class_rule). The gauge: from the sample fate_lead before "
    "the train's first spike past its approach, the orbit with its 4 x 4 tangent map over two refined intervals "
    "and MARGIN (5) QR steps (QR every fate_tau; sleighsim.chaos.lane_gain), ln G the largest over its complete "
    "cycles placed at the plain run's refined spikes (faithfulness.cycle_gains), steps per cycle the plain run's "
    "Taylor steps per time unit times the refined interval, and the arithmetic follows the torus when G x steps x "
    "rounding < faithfulness.FAITHFUL_MAX (double-double's rounding 2^-106). Where double-double does not follow, "
    "its gauge found no complete cycle in a train that has one, or the landing check (check_rule) finds another "
    "torus, the run is followed again the same way in triple-double (tolerance fate_td_tol, rounding "
    "tdarith.ROUNDING) and recorded from there, with its share of that run's CPU seconds."
)
ROUNDING = {DD: Precision.DOUBLE_DOUBLE.rounding, TD: tdarith.ROUNDING}
#: The gain run goes this many QR steps past two intervals (its cycles are placed at its own spikes, found to
#: within a block, and a cycle's gain needs the steps of two whole cycles from its first spike).
MARGIN = 5


def _pairs(out) -> tuple[np.ndarray, np.ndarray]:
    """A batch's samples as (hi, lo) pairs: DDBatch's as they are, TDBatch's triples' two leading components."""
    return out if isinstance(out, tuple) else (out[..., 0], out[..., 1])


def _train(jets: DDBatch, hi, lo, grid, cfg: dict) -> dict:
    """One lane's refined spikes (times, errors) and train (sleighsim.analysis.fate.train)."""
    coarse = spike_times(grid, hi[:, 1], factor=cfg["spike_factor"])
    t_sec, x_sec = ddsection.crossings(jets, hi, lo, grid, coarse, 2 * cfg["half_width"])
    times, errors = fate.refined_peaks(t_sec, x_sec, coarse, cfg["half_width"])
    return {"times": times, "errors": errors, **fate.train(times, errors, min_intervals=cfg["min_intervals"],
                                                           factor=cfg["periodic_factor"])}


def follow(batch, jets: DDBatch, starts, cfg: dict) -> tuple[list[dict], object]:
    """Every lane from ``starts`` (the batch's form) over T: (per lane its train, steps per time unit and the
    gain run's start (row of the sample ``lead`` before the train's first periodic spike, past its approach) and
    horizon (two intervals past that spike and MARGIN QR steps more; 0 without an interval); the samples in the
    batch's form)."""
    grid = np.arange(0.0, cfg["T"] + 0.5 * cfg["dt"], cfg["dt"])
    out = batch.propagate_grid(starts, grid)
    hi, lo = _pairs(out)
    rows = []
    for k in range(hi.shape[0]):
        tr = _train(jets, hi[k], lo[k], grid, cfg)
        first = tr["times"][tr["approach"]] if tr["times"].size else 0.0
        row = int(max(0.0, first - cfg["lead"]) // cfg["dt"])
        span = first - grid[row] + 2 * tr["interval"] + MARGIN * cfg["tau"] if tr["cycles"] else 0.0
        rows.append({**tr, "steps_per_tu": batch.steps[k] / cfg["T"], "gain_row": row, "gain_span": span})
    return rows, out


def gauge(batch, out, rows, cfg: dict, arithmetic: str) -> None:
    """Adds to each row ln G (:func:`sleighsim.chaos.lane_gain.lane_gains` from its gain start), steps per cycle,
    log10 G x steps x rounding and whether ``arithmetic`` follows the torus (faithfulness.follows)."""
    todo = [k for k, r in enumerate(rows) if r["gain_span"] > 0]
    gains = {}
    if todo:
        picks = [rows[k]["gain_row"] for k in todo]
        starts = (out[0][todo, picks], out[1][todo, picks]) if isinstance(out, tuple) else out[todo, picks]
        spikes = [t[t >= 0] for t in (rows[k]["times"] - rows[k]["gain_row"] * cfg["dt"] for k in todo)]
        found = lane_gains(batch, starts, [rows[k]["gain_span"] for k in todo], spikes, tau=cfg["tau"])
        gains = dict(zip(todo, found))
    for k, r in enumerate(rows):
        ln = gains[k]["ln_gain_max"] if k in gains else math.nan
        steps = r["steps_per_tu"] * r["interval"] if r["cycles"] else math.nan
        r.update(arithmetic=arithmetic, ln_gain=ln, steps_per_cycle=steps,
                 log10_gain_rounding=faithfulness.log10_gain_rounding(ln, ROUNDING[arithmetic], steps),
                 follows=faithfulness.follows(ln, ROUNDING[arithmetic], steps_per_cycle=steps))


def followed(batch, jets: DDBatch, starts, cfg: dict, arithmetic: str) -> list[dict]:
    """:func:`follow` then :func:`gauge` in one arithmetic, each row with its share of their CPU seconds."""
    start = time.process_time()
    rows, out = follow(batch, jets, starts, cfg)
    gauge(batch, out, rows, cfg, arithmetic)
    cpu = time.process_time() - start
    for r in rows:
        r["cpu_s"] = cpu / len(rows)
    log.info("fate in %s: %d levels, %.1f CPU-s", arithmetic, len(rows), cpu)
    return rows


#: A triple-double landing is checked against a twin started this far away (relative, in every component):
#: above all triple-double injects over a run (about 1e5 steps of rounding 2^-150: 1e-40), far below what
#: double-double injects.
TWIN_REL = 1e-38

#: Written into the trigger_law dataset (attribute check_rule).
CHECK_RULE = (
    "Is a landing the escape's, or the follow-on arithmetic's? The gauge judges the torus, not the passage from "
    "the escape to it, which amplifies more. So each recorded landing is compared with a twin that differs from "
    "it by at least the recorded arithmetic's own error: a double-double landing with triple-double (fate_td_tol) "
    "from the same post-escape state, a triple-double landing with triple-double from that state perturbed by "
    "TWIN_REL (1e-38) in every component. The twins run to a little past the latest second refined spike of the "
    "runs checked together (plus fate_lead and two half_widths); the landing is confirmed (1) when the first two "
    "refined spikes of both (one where the run has one) lie within fate_periodic_factor times the larger of their "
    "refinement errors, 0 when they do not (or the twin has fewer spikes), -1 when the run has no refined spike."
)


def check(jets: DDBatch, rows: list[dict], twin, starts, cfg: dict) -> None:
    """Applies :data:`CHECK_RULE` (the rule as the datasets record it, just above) to ``rows`` with their twins
    (the batch ``twin`` from ``starts``), adding confirmed, check_difference (time units) and check_cpu_s (the
    twins' CPU seconds, shared) to each."""
    start = time.process_time()
    ends = [r["times"][min(1, r["times"].size - 1)] for r in rows if r["times"].size]
    for r in rows:
        r.update(confirmed=-1, check_difference=math.nan)
    found = follow(twin, jets, starts, {**cfg, "T": max(ends) + cfg["lead"] + 2 * cfg["half_width"]})[0] \
        if ends else [None] * len(rows)
    for r, t in zip(rows, found):
        n = min(2, r["times"].size)
        if n and t["times"].size < n:
            r["confirmed"] = 0
        elif n:
            diff = float(np.max(np.abs(r["times"][:n] - t["times"][:n])))
            limit = cfg["periodic_factor"] * float(np.max(np.r_[r["errors"][:n], t["errors"][:n]]))
            r.update(confirmed=int(diff <= limit), check_difference=diff)
    cpu = time.process_time() - start
    log.info("landing check of %d runs in %s: %.1f CPU-s", len(rows), TD, cpu)
    for r in rows:
        r["check_cpu_s"] = cpu / len(rows)


def finer_needed(r: dict) -> bool:
    """Whether a double-double row is followed again in triple-double: double-double does not follow its torus,
    its gauge found no complete cycle in a train that has one, or triple-double lands elsewhere."""
    return (r["follows"] == faithfulness.DOES_NOT_FOLLOW or r["confirmed"] == 0
            or (r["follows"] == faithfulness.UNKNOWN and r["cycles"] > 0))


def landed(params, after, cfg: dict) -> list[dict | None]:
    """Per level its fate row (None where ``after``, its post-escape state in its run's arithmetic, is None: no
    escape): followed in double-double and checked in triple-double (:func:`check`); where :func:`finer_needed`,
    followed again in triple-double and checked against a perturbed triple-double twin (the row then holds the
    double-double one as ``instead_of``)."""
    ok = [k for k, a in enumerate(after) if a is not None]
    if not ok:
        return [None] * len(after)
    jets = DDBatch(params, cfg["tol"])
    pairs = [as_pair(after[k]) for k in ok]
    starts = (np.array([h for h, _ in pairs]), np.array([lo for _, lo in pairs]))
    rows = dict(zip(ok, followed(DDBatch(params, cfg["tol"]), jets, starts, cfg, DD)))
    triples = {k: as_triples(np.array([after[k]])) for k in ok}
    check(jets, [rows[k] for k in ok], TDBatch(params, cfg["td_tol"]), np.concatenate(list(triples.values())), cfg)
    redo = [k for k in ok if finer_needed(rows[k])]
    if redo:
        again = np.concatenate([triples[k] for k in redo])
        found = followed(TDBatch(params, cfg["td_tol"]), jets, again, cfg, TD)
        twins = again.copy()
        twins[:, :, 2] += TWIN_REL * again[:, :, 0]
        check(jets, found, TDBatch(params, cfg["td_tol"]), twins, cfg)
        for k, r in zip(redo, found):
            rows[k] = {**r, "instead_of": rows[k]}
    return [rows.get(k) for k in range(len(after))]


def follows_text(r: dict | None) -> str:
    """What the gauge says of row r's arithmetic(s) on the torus, with log10 G x steps x rounding and, for a
    level followed again in triple-double, double-double's answer and the price paid."""
    if r is None:
        return "no escape within t_end"
    said = {faithfulness.FOLLOWS: "followed by", faithfulness.DOES_NOT_FOLLOW: "not followed by",
            faithfulness.UNKNOWN: "unknown (no complete cycle measured) for"}[r["follows"]]
    text = f"{said} {r['arithmetic']}"
    if math.isfinite(r["log10_gain_rounding"]):
        text += f" (G x steps x rounding 10^{r['log10_gain_rounding']:.1f})"
    if r["follows"] == faithfulness.DOES_NOT_FOLLOW:
        needed = log10_needed(r["log10_gain_rounding"], ROUNDING[r["arithmetic"]], faithfulness.FAITHFUL_MAX)
        text += f": needs rounding below 10^{needed:.1f}" + (f"; {r['price']}" if "price" in r else "")
    if "instead_of" in r:
        elsewhere = "" if r["instead_of"]["confirmed"] != 0 else ", but triple-double lands elsewhere"
        text = f"{follows_text(r['instead_of'])}{elsewhere}; {text}, at {r['cpu_s']:.3g} CPU-s"
    return text
