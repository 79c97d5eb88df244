"""Detecting the end of transients from sampled data.

Definitions (stated in every dataset that uses them, :data:`RULE`):
- spike (:func:`spike_train`): a local maximum of |Omega| above ``factor`` times the typical steady
  oscillation amplitude, taken as the median of the per-block maxima of |Omega| over the second half
  of the record (blocks of ``block`` time units), from which |Omega| falls below that threshold within
  one block on each side inside the record (a peak cut by the record's start or end, or the start's
  own decay on a fresh orbit, is not a spike); spikes closer than ``min_separation`` are merged;
  spikes before ``t_min`` (the sleigh-like first phase, where Omega starts large) are ignored. Then
  the period's check: with at least :data:`MIN_SPIKES` spikes, a gap of at least :data:`GAP` median
  intervals is searched for the spike the fixed threshold missed (a low one: the highest isolated
  peak within :data:`WINDOW` median intervals of one median interval after the previous spike, kept
  when it stands :data:`RESCUE` times above the gap's envelope, the median block maximum there), and
  an interval near twice the median left after that (:data:`DOUBLED`) is flagged. A record in which the
  fixed threshold finds fewer than :data:`MIN_SPIKES` spikes is searched once more at :data:`RESCUE` times
  the median block maximum (spikes that stand only about ``factor`` above the oscillation, as at small
  eps), each the highest of its block and both neighbouring blocks inside the record (so a spike's flank
  cut by the record's end does not count); those spikes are kept only when they form a periodic train (at
  least MIN_SPIKES, every interval within :data:`PERIODIC` of their median), else the fixed threshold's
  stand.
- settling time of omega: blocks of ``window`` time units; the reference is the
  mean of omega over the second half of the record; the settling time is the
  start of the first block after which every block mean lies within
  ``rtol`` * |reference| of it.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from sleighsim.engine.integrate import final_state, integrate, sample_grid

log = logging.getLogger("sleighsim")


def _blocks(t, x, length):
    t, x = np.asarray(t, float), np.asarray(x, float)
    dt = t[1] - t[0]
    n = max(1, int(round(length / dt)))
    m = len(x) // n
    if m < 2:
        raise ValueError(f"record of {t[-1] - t[0]:g} time units is too short for blocks of {length:g}")
    return t[: m * n].reshape(m, n), x[: m * n].reshape(m, n)


#: The period's check: the fewest spikes that give a median interval P; a gap of at least GAP P is searched;
#: a missed spike lies within WINDOW P of one P after the previous one and stands RESCUE times above the gap's
#: envelope; an interval within DOUBLED (multiples of P) left after the search is flagged.
MIN_SPIKES, GAP, WINDOW, RESCUE, DOUBLED = 4, 1.5, 0.1, 1.4, (1.75, 2.25)
#: The lower threshold's train is kept when every interval is within PERIODIC of their median.
PERIODIC = 0.05

RULE = ("spike: a local maximum of |Omega| (block maxima, 50 time units) above spike_factor x median block maximum "
        "of the second half, |Omega| falling below that within one block on each side inside the record, after "
        f"t_min; with at least {MIN_SPIKES} spikes, a gap of at least {GAP:g} median intervals P searched for a "
        f"missed spike (the highest isolated peak within {WINDOW:g} P of P after the previous one, at least "
        f"{RESCUE:g} x the gap's median block maximum), intervals within {DOUBLED[0]:g}-{DOUBLED[1]:g} P left "
        f"flagged; with fewer than {MIN_SPIKES} spikes, the spikes above {RESCUE:g} x the median block maximum "
        "instead (each above both neighbouring blocks' maxima) when they form a periodic train (every "
        f"interval within {PERIODIC:g} of their median); settling: block means of omega (window) within rtol of "
        "the second-half mean from the settling time on")


@dataclass(frozen=True)
class SpikeTrain:
    """The spikes of one record (:func:`spike_train`): their ``times`` and |Omega| ``heights``, which were
    ``rescued`` by the period's check (bool per spike), the fixed ``threshold`` (|Omega|), the median
    interval (NaN with fewer than MIN_SPIKES spikes) and ``doubled``: the indices i of the intervals
    times[i + 1] - times[i] still near twice the median (a spike may be missing there)."""

    times: np.ndarray
    heights: np.ndarray
    rescued: np.ndarray
    threshold: float
    median_interval: float
    doubled: np.ndarray


def _record(t, x) -> tuple[np.ndarray, np.ndarray]:
    """``t`` and ``x`` as float arrays, or ValueError naming what is malformed: not one-dimensional,
    lengths that differ, an empty record, a non-finite time or value, times that do not advance."""
    t, x = np.asarray(t, float), np.asarray(x, float)
    if t.ndim != 1 or x.ndim != 1:
        raise ValueError(f"spikes need one-dimensional records (t has shape {t.shape}, Omega {x.shape})")
    if t.size != x.size:
        raise ValueError(f"t has {t.size} samples and Omega {x.size}: one Omega per time")
    if t.size == 0:
        raise ValueError("an empty record has no spikes to find")
    bad = int(np.sum(~np.isfinite(x)))
    if bad:
        raise ValueError(f"Omega is not finite at {bad} of its {x.size} samples" + (" (all)" if bad == x.size else ""))
    if not np.all(np.isfinite(t)) or t[-1] <= t[0]:
        raise ValueError("the times must be finite and advance")
    return t, x


def _isolated(a, j: int, n: int, level: float) -> bool:
    """Whether |Omega| (``a``) falls below ``level`` within ``n`` samples on each side of sample ``j``,
    inside the record."""
    before, after = a[max(0, j - n): j], a[j + 1: j + 1 + n]
    return bool(before.size and after.size and before.min() < level and after.min() < level)


def _merged(times, heights, min_separation: float) -> list[int]:
    """Indices of the spikes kept when those closer than ``min_separation`` merge (the higher kept)."""
    keep: list[int] = []
    for k in range(len(times)):
        if keep and times[k] - times[keep[-1]] < min_separation:
            if heights[k] > heights[keep[-1]]:
                keep[-1] = k
        else:
            keep.append(k)
    return keep


def _missed(t, a, last: float, nxt: float, period: float, n: int, level: float):
    """The sample of the spike missed in the gap (``last``, ``nxt``), or None: the highest isolated
    peak within WINDOW period of one period after ``last`` (not at the window's edge), when it stands
    RESCUE times above the gap's envelope (median of the maxima of the gap's blocks of ``n`` samples)."""
    gap = a[(t > last + period * WINDOW) & (t < nxt - period * WINDOW)]
    m = gap.size // n
    if m < 3:
        return None
    envelope = np.median(gap[: m * n].reshape(m, n).max(axis=1))
    inside = np.flatnonzero(np.abs(t - (last + period)) <= WINDOW * period)
    if inside.size < 3:
        return None
    j = int(inside[np.argmax(a[inside])])
    if j in (inside[0], inside[-1]) or a[j] < RESCUE * envelope or not _isolated(a, j, n, level):
        return None
    return j


def _period_check(t, a, times, heights, n: int, level: float):
    """The period's check (module docstring): (times, heights, rescued) with the missed spikes of the
    long gaps added."""
    rescued = np.zeros(times.size, bool)
    if times.size < MIN_SPIKES:
        return times, heights, rescued
    period = float(np.median(np.diff(times)))
    out_t, out_h, out_r = [times[0]], [heights[0]], [False]
    for k in range(1, times.size):
        while times[k] - out_t[-1] >= GAP * period:
            j = _missed(t, a, out_t[-1], times[k], period, n, level)
            if j is None:
                break
            out_t.append(t[j]), out_h.append(a[j]), out_r.append(True)
        out_t.append(times[k]), out_h.append(heights[k]), out_r.append(False)
    return np.array(out_t), np.array(out_h), np.array(out_r)


def _above(t, a, xb, peaks, level: float, t_min: float, min_separation: float) -> np.ndarray:
    """Sample indices of the isolated block maxima above ``level`` after ``t_min``, merged within
    ``min_separation`` (the higher kept)."""
    n = xb.shape[1]
    j = np.flatnonzero(peaks > level) * n + np.argmax(xb[peaks > level], axis=1)
    j = np.array([i for i in j if t[i] >= t_min and _isolated(a, i, n, level)], dtype=int)
    return j[_merged(t[j], a[j], min_separation)]


def _block_peaks(blocks, peaks) -> np.ndarray:
    """Which of the ``blocks`` (indices) hold a maximum above both neighbouring blocks' (``peaks``), both
    inside the record."""
    inside = (blocks > 0) & (blocks < peaks.size - 1)
    b = np.where(inside, blocks, 1)
    return inside & (peaks[b] > peaks[b - 1]) & (peaks[b] > peaks[np.minimum(b + 1, peaks.size - 1)])


def _periodic_train(times) -> bool:
    """Whether spike ``times`` form a periodic train: at least MIN_SPIKES spikes, every interval within
    PERIODIC of their median."""
    if times.size < MIN_SPIKES:
        return False
    d = np.diff(times)
    return bool(np.max(np.abs(d - np.median(d))) <= PERIODIC * np.median(d))


def spike_train(t, Omega, *, factor=1.8, block=50.0, min_separation=300.0, t_min=0.0) -> SpikeTrain:
    """The spikes of Omega sampled at times ``t`` (see the module docstring; time units), with the period's
    check. ValueError for a malformed record (lengths that differ, empty, not finite) or one shorter
    than two blocks."""
    t, x = _record(t, Omega)
    a = np.abs(x)
    tb, xb = _blocks(t, a, block)
    n = xb.shape[1]
    peaks = xb.max(axis=1)
    typical = float(np.median(peaks[len(peaks) // 2:]))
    level = factor * typical
    j = _above(t, a, xb, peaks, level, t_min, min_separation)
    if j.size < MIN_SPIKES and RESCUE < factor:
        low = _above(t, a, xb, peaks, RESCUE * typical, t_min, min_separation)
        low = low[_block_peaks(low // n, peaks)]
        if _periodic_train(t[low]):
            j = low
    times, heights, rescued = _period_check(t, a, t[j], a[j], n, level)
    d = np.diff(times)
    period = float(np.median(d)) if times.size >= MIN_SPIKES else float("nan")
    doubled = np.flatnonzero((d >= DOUBLED[0] * period) & (d <= DOUBLED[1] * period))
    return SpikeTrain(times, heights, rescued, level, period, doubled)


def spike_times(t, Omega, *, factor=1.8, block=50.0, min_separation=300.0, t_min=0.0) -> np.ndarray:
    """Times of the Omega spikes (:func:`spike_train`); an interval still near twice the median after the
    period's check is logged as a warning."""
    train = spike_train(t, Omega, factor=factor, block=block, min_separation=min_separation, t_min=t_min)
    for i in train.doubled:
        log.warning("spike interval %.6g from t = %.6g is %.2f median intervals: a spike may be missed there",
                    train.times[i + 1] - train.times[i], train.times[i],
                    (train.times[i + 1] - train.times[i]) / train.median_interval)
    return train.times


def interval_stats(spikes) -> tuple[float, float]:
    """Mean and standard deviation (ddof 1) of the intervals between successive spike times (time
    units); NaN when there are too few spikes (the mean needs two, the deviation three)."""
    d = np.diff(np.asarray(spikes, float))
    return (float(d.mean()) if d.size else float("nan")), (float(d.std(ddof=1)) if d.size > 1 else float("nan"))


def settling_time(t, omega, *, window=2500.0, rtol=0.02) -> float:
    """Settling time of the block means of omega (see module docstring); NaN if never settled."""
    tb, xb = _blocks(t, omega, window)
    means = xb.mean(axis=1)
    ref = means[len(means) // 2:].mean()
    bad = np.flatnonzero(np.abs(means - ref) > rtol * abs(ref))
    if bad.size == 0:
        return float(tb[0, 0])
    if bad[-1] == len(means) - 1:
        return float("nan")
    return float(tb[bad[-1] + 1, 0])


def block_fluctuation(t, omega, *, window=2500.0) -> float:
    """How much omega's block means (``window`` time units) scatter about their least-squares line
    over the record's second half: the residuals' standard deviation (n - 2 degrees of freedom) over
    the absolute mean of those block means (dimensionless); NaN with fewer than three blocks there.
    A drift leaves small residuals; the settling rule cannot hold block means that scatter by rtol or
    more within rtol of one value."""
    tb, xb = _blocks(t, omega, window)
    means, mid = xb.mean(axis=1), tb[:, 0]
    half = len(means) // 2
    means, mid = means[half:], mid[half:]
    if means.size < 3 or not np.mean(means):
        return float("nan")
    residuals = means - np.polyval(np.polyfit(mid, means, 1), mid)
    return float(np.sqrt(np.sum(residuals**2) / (means.size - 2)) / abs(np.mean(means)))


def steady_state_report(t, Omega, omega, *, spike_factor=1.8, window=2500.0, rtol=0.02, t_min=0.0) -> dict:
    """Settling time, spikes and spike intervals over each half of the record."""
    spikes = spike_times(t, Omega, factor=spike_factor, t_min=t_min)
    settle = settling_time(t, omega, window=window, rtol=rtol)
    mid = 0.5 * (t[0] + t[-1])
    out = {"settling_time": settle, "n_spikes": int(spikes.size),
           "first_spike": float(spikes[0]) if spikes.size else float("nan")}
    for half, sel in (("first", spikes < mid), ("second", spikes >= mid)):
        out[f"spike_interval_mean_{half}_half"], out[f"spike_interval_std_{half}_half"] = interval_stats(spikes[sel])
    return out


def settle(params, y0, t_settle: float, *, dt: float, window: float, rtol: float, spike_factor: float,
           t_min: float, tol: float, label: str = "", progress: int = 20, fluctuation: bool = False):
    """Integrate the pre-run [0, t_settle] from y0, sampled every dt, and judge it with the rules
    above: the transient is over when omega's block means (``window``) have settled within ``rtol``
    at least two windows before t_settle. Returns (end state, attributes): ``transient_over``, the
    settling time, spikes and spike intervals of each half, the rule and the pre-run's energy drift;
    with ``fluctuation``, also ``transient_block_fluctuation`` (:func:`block_fluctuation`)."""
    pre = integrate(params, y0, sample_grid(0.0, t_settle, dt), tol=tol, scene=f"{label}.pre", progress=progress)
    report = steady_state_report(pre.time.values, pre.Omega.values, pre.omega.values, spike_factor=spike_factor,
                                 window=window, rtol=rtol, t_min=t_min)
    settled = report["settling_time"]
    over = bool(np.isfinite(settled) and settled <= t_settle - 2 * window)
    attrs = {f"transient_{k}": v for k, v in report.items()}
    attrs.update(transient_over=int(over), transient_window=window, transient_rtol=rtol,
                 transient_spike_factor=spike_factor, transient_rule=RULE,
                 pre_run_energy_max_rel_drift=pre.attrs["energy_max_rel_drift"], pre_run_steps=pre.attrs["steps"])
    if fluctuation:
        attrs["transient_block_fluctuation"] = block_fluctuation(pre.time.values, pre.omega.values, window=window)
    log.info("%s: transient %s (settling time %.6g, pre-run to %.6g)", label, "over" if over else "NOT over",
             settled, t_settle)
    return final_state(pre), attrs


PHASES_RULE = ("sleigh-like phase ends when the running mean of u (window mean_window) first reaches sleigh_frac "
               "(0.99) of its maximum before the first spike; the second transient ends at the first Omega spike "
               "after four times that time (spike rule above); steady spike interval: mean and standard deviation "
               "of the intervals between later spikes")


def interval_groups(intervals, rel_tol: float) -> np.ndarray:
    """Label runs by steady spike interval: a run joins the first group whose first member's
    interval is within rel_tol (so runs listed first head the groups); NaN intervals get -1."""
    labels, heads = np.full(len(intervals), -1), []
    for i, x in enumerate(intervals):
        if not np.isfinite(x):
            continue
        for g, h in enumerate(heads):
            if abs(x - h) <= rel_tol * h:
                labels[i] = g
                break
        else:
            heads.append(x)
            labels[i] = len(heads) - 1
    return labels


def running_mean(x, n: int) -> np.ndarray:
    """Centred running mean over n samples (valid part, length len(x) - n + 1)."""
    c = np.cumsum(np.insert(np.asarray(x, float), 0, 0.0))
    return (c[n:] - c[:-n]) / n


def phases(t, u, Omega, omega, *, mean_window=25.0, sleigh_frac=0.99, spike_factor=1.8, window=2500.0,
           rtol=0.02) -> dict:
    """The transient phases of one record (see PHASES_RULE); times in the record's units, NaN when absent."""
    t = np.asarray(t, float)
    dt = t[1] - t[0]
    n = max(1, int(round(mean_window / dt)))
    um = running_mean(u, n)
    tm = t[(n - 1) // 2: (n - 1) // 2 + um.size]
    first_guess = spike_times(t, Omega, factor=spike_factor, t_min=t[0] + 10 * mean_window)
    stop = np.searchsorted(tm, first_guess[0]) if first_guess.size else um.size
    early = um[: max(1, stop)]
    t_sleigh = float(tm[int(np.argmax(early >= sleigh_frac * early.max()))])
    spikes = spike_times(t, Omega, factor=spike_factor, t_min=4.0 * t_sleigh)
    interval_mean, interval_std = interval_stats(spikes)
    try:
        settle = settling_time(t, omega, window=window, rtol=rtol)
    except ValueError:
        settle = float("nan")
    return {"sleigh_phase_end": t_sleigh, "first_spike": float(spikes[0]) if spikes.size else float("nan"),
            "n_spikes": int(spikes.size), "spike_interval_mean": interval_mean, "spike_interval_std": interval_std,
            "omega_settling_time": settle, "spikes": spikes}
