"""The ledger's ``cause`` column: each "differs" tested against its likely causes, from the datasets
named in :data:`sleighsim.claims.evidence.CAUSES`. A cause explains a number when, at some setting, it
moves our value to within the judge's tolerance of the paper's; the text says which setting, or
that none of the causes tested explains the difference and what they gave."""

from __future__ import annotations

import math

import numpy as np

from sleighsim.analysis.torus import ANOTHER
from sleighsim.claims.rules import REL_TOL, band_tolerance, finite, fmt

NONE = "not explained by the causes tested"


def _crossing(x, y, target):
    """x values where the piecewise-linear y(x) crosses target (log-interpolated in x)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    out = []
    for i in range(len(x) - 1):
        a, b = y[i] - target, y[i + 1] - target
        if finite(a, b) and a * b <= 0 and a != b:
            w = a / (a - b)
            out.append(float(np.exp((1 - w) * np.log(x[i]) + w * np.log(x[i + 1]))))
    return out


def _sweep(name, unit, x, y, target, rel_tol=REL_TOL, fmt_x="{:.3g}"):
    """(explained?, text) for one observable swept against one setting."""
    ok = np.isfinite(y)
    if not ok.any():
        return False, f"{name}: not determined at any {unit}"
    span = f"{name} from {np.nanmin(y):.4g} to {np.nanmax(y):.4g} over {unit} {fmt_x.format(np.min(x[ok]))} to " \
           f"{fmt_x.format(np.max(x[ok]))}"
    hits = _crossing(x, y, target)
    close = [fmt_x.format(v) for v, w in zip(x, y) if finite(w) and abs(w - target) <= rel_tol * abs(target)]
    if hits:
        return True, f"{span}; {target:g} at {unit} " + ", ".join(fmt_x.format(h) for h in hits)
    if close:
        return True, f"{span}; within {rel_tol:.0%} of {target:g} at {unit} " + ", ".join(close)
    return False, span


def _verdict(findings):
    """'explained by A, B: details' or 'not explained by the causes tested: details' (findings of one
    cause grouped)."""
    names = list(dict.fromkeys(name for name, _, _ in findings))
    explained = [n for n in names if any(ok for m, ok, _ in findings if m == n)]
    details = "; ".join(f"{n}: " + "; ".join(text for m, _, text in findings if m == n) for n in names)
    return (f"explained by {', '.join(explained)}: " if explained else f"{NONE}: ") + details


def _k2_joint(k2, targets: dict):
    """One K2 for several numbers: explained only when a single K2 of the sweep puts every
    number within REL_TOL of its paper value."""
    K2 = k2.K2.values
    fits = np.ones(K2.size, bool)
    texts = []
    for var, want in targets.items():
        y = k2[var].values
        fits &= np.isfinite(y) & (np.abs(y - want) <= REL_TOL * abs(want))
        texts.append(_sweep(var, "K2", K2, y, want)[1])
    joint = (f"one K2 fits them all: {', '.join(f'{v:g}' for v in K2[fits])}" if fits.any() else
             "no single K2 of the sweep fits them all")
    return ("the unstated K", bool(fits.any()), "; ".join(texts) + "; " + joint)


def _k2(k2, var, target):
    ok, text = _sweep(var, "K2", k2.K2.values, k2[var].values, target)
    return ("the unstated K", ok, text)


def _ode45(err, var, target):
    ok, text = _sweep(var, "rtol", err.rtol.values, err[var].values, target, fmt_x="{:.0e}")
    return (f"integration error ({err.attrs['method']})", ok, text)


def _slopes_text(law) -> str:
    """The local slopes per range of a trigger_law dataset, with the pooled scatter's degrees of freedom."""
    rows = [f"{label} {hi:.0e} to {lo:.0e}: {slope:.3g} +- {err:.2g}" for label, hi, lo, slope, err in zip(
        law.range_label.values, law.range_tol_max.values, law.range_tol_min.values, law.range_slope.values,
        law.range_slope_stderr.values)]
    return (f"local slopes per decade of injected error ({law.attrs['slopes_dof']} degrees of freedom): "
            + "; ".join(rows)) if rows else "no range of two levels"


def _trigger(law, want):
    """The injected error as a cause, within the measured range only: explained when the first spikes of the runs
    in the slopes reach the paper's time (a crossing between two of them, or one within REL_TOL); the text gives
    the measured range, the saturated runs left out, the local slopes per range and what the finest range still
    does, and extrapolates nothing beyond the finest level measured."""
    name = "the injected error (trigger law)"
    ok = law.in_slopes.values == 1
    if not ok.any():
        return name, False, "no run within reach of the slopes"
    order = np.argsort(-law.tol.values[ok])
    tol, first = law.tol.values[ok][order], law.first_spike.values[ok][order]
    hit, span = _sweep("first spike", "injected error", tol, first, want, fmt_x="{:.0e}")
    saturated = int(np.sum(law.saturated.values == 1))
    text = (f"{span} ({int(ok.sum())} runs, {saturated} saturated left out); {_slopes_text(law)}; measured down to "
            f"{tol.min():.0e}, nothing extrapolated beyond it")
    return name, hit, text


def c04(judgement, paper, k2, err, audit, law):
    """The likely causes of a differing C04 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``k2``, ``err``, ``audit``, ``law``; returns the ledger's cause text."""
    want = paper["first_spike"]
    printed = audit.attrs["printed_first_spike"]
    return _verdict([_k2(k2, "first_spike", want), _ode45(err, "first_spike", want),
                     ("the printed udot", finite(printed) and abs(printed - want) <= REL_TOL * want,
                      f"first spike {printed:.5g}" if finite(printed) else
                      f"no spike by t = {audit.attrs['printed_spikes_t_end']:g}"), _trigger(law, want)])


def c05(judgement, paper, k2, err, audit):
    """The likely causes of a differing C05 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``k2``, ``err``, ``audit``; returns the ledger's cause text."""
    want = paper["spike_interval"]
    printed = audit.attrs["printed_spike_interval"]
    return _verdict([_k2(k2, "spike_interval", want), _ode45(err, "spike_interval", want),
                     ("the printed udot", finite(printed) and abs(printed - want) <= REL_TOL * want,
                      f"interval {printed:.5g}" if finite(printed) else "no steady spike interval")])


def _groups(fig4) -> dict[int, np.ndarray]:
    """The spike intervals (level-0 units) of fig4's runs that reached a steady state, per interval group."""
    ok = fig4.reached.values == 1
    iv, g = fig4.spike_interval_level0_units.values[ok], fig4.group.values[ok]
    return {int(k): iv[g == k] for k in np.unique(g)}


def c06(judgement, paper, torus, fig4):
    """A family of tori as the cause of a differing C06 (extra interval groups on a level): explained when
    every perturbed orbit of the torus-stability scene is shown to be on a torus of the family other than
    the reference's (sleighsim.analysis.torus: a periodic or k-interval reversal train, another period) and
    every extra group's intervals lie within the span of periods that family was measured over (its
    perturbed orbits' and the reference's)."""
    ident = torus.torus_identity.values[1:]
    family = bool(ident.size) and bool(np.all(ident == ANOTHER))
    span = np.r_[torus.period.values[1:], torus.attrs["reference_period"]]
    lo, hi = float(np.nanmin(span)), float(np.nanmax(span))
    groups = _groups(fig4)
    main = max(groups, key=lambda k: groups[k].size)
    extra = np.concatenate([v for k, v in groups.items() if k != main] or [np.array([])])
    inside = bool(extra.size) and bool(np.all((extra >= lo) & (extra <= hi)))
    amps = torus.amplitude.values[1:]
    text = (f"{int(np.sum(ident == ANOTHER))} of {ident.size} orbits perturbed by {amps.min():.0e} to "
            f"{amps.max():.0e} are on other tori of the family, periods {lo:.5g} to {hi:.5g}; the main group's "
            f"intervals {groups[main].min():.5g} to {groups[main].max():.5g}, the extra groups' "
            + (", ".join(f"{v:.5g}" for v in extra) or "none")
            + (" within that span" if inside else " outside it"))
    return _verdict([("a family of tori, each orbit on its own", family and inside, text)])


def c09(judgement, paper, k2):
    """The likely causes of a differing C09 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``k2``; returns the ledger's cause text."""
    return _verdict([_k2_joint(k2, {"Omega2_amplitude": paper["Omega2_amplitude"],
                                    "phi1_over_pi": paper["phi1_over_pi"]})])


def c10(judgement, paper, k2):
    """The likely causes of a differing C10 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``k2``; returns the ledger's cause text."""
    return _verdict([_k2_joint(k2, {"T2": paper["T2"], "B": paper["B"], "omega2_growth": paper["growth"]})])


def c11(judgement, paper, k2, err):
    """The likely causes of a differing C11 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``k2``, ``err``; returns the ledger's cause text."""
    want = paper["omega_rel_error"]
    return _verdict([_k2(k2, "omega_rel_error", want), _ode45(err, "omega_rel_error", want)])


def c13(judgement, paper, k2):
    """The spike times near t = 10000 follow the first spike and the interval: does some K2 put one there?"""
    want = paper["spike_time"]
    times = [(K, f + n * d) for K, f, d in zip(k2.K2.values, k2.first_spike.values, k2.spike_interval.values)
             if finite(f, d) for n in range(0, 8)]
    near = sorted({f"{K:g}" for K, t in times if abs(t - want) <= 0.05 * want})
    text = (f"a spike within 5% of t = {want:g} at K2 " + ", ".join(near)) if near else \
        f"no K2 in [{k2.K2.values.min():g}, {k2.K2.values.max():g}] puts a spike within 5% of t = {want:g}"
    return _verdict([("the unstated K (spike times = first spike + n x interval)", bool(near), text)])


def c18(judgement, paper, err):
    """Numerical dissipation of a loose explicit solver can fake a contraction: the sum of the protocol's exponents."""
    sums = err.protocol_exponent.values.sum(axis=1)
    rtols = err.lyapunov_rtol.values
    fakes = [f"{r:.0e}" for r, s in zip(rtols, sums) if s < 0]
    text = "sum of the protocol's exponents " + ", ".join(f"{s:.2g} at rtol {r:.0e}" for r, s in zip(rtols, sums))
    return _verdict([(f"integration error ({err.attrs['method']}: numerical dissipation)", bool(fakes), text)])


def c19(judgement, paper, err):
    """The likely causes of a differing C19 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``err``; returns the ledger's cause text."""
    want = np.sort(np.asarray(paper["exponents"], float))[::-1]
    rows = []
    for r, lam in zip(err.lyapunov_rtol.values, err.protocol_exponent.values):
        close = all(abs(o - w) <= REL_TOL * abs(w) for o, w in zip(lam, want))
        rows.append((r, close, lam))
    hits = [f"{r:.0e}" for r, c, _ in rows if c]
    text = "; ".join(f"rtol {r:.0e}: {fmt(lam, 2)}" for r, _, lam in rows)
    return _verdict([(f"integration error ({err.attrs['method']} protocol)", bool(hits), text)])


def c20(judgement, paper, err):
    """The likely causes of a differing C20 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``err``; returns the ledger's cause text."""
    lam1 = err.protocol_exponent.values[:, 0]
    text = "lambda_1 of the protocol " + ", ".join(f"{v:.2g} at rtol {r:.0e}"
                                                  for r, v in zip(err.lyapunov_rtol.values, lam1))
    hit = any(abs(v - paper["smallest"]) <= REL_TOL * paper["smallest"] for v in lam1)
    return _verdict([(f"integration error ({err.attrs['method']} protocol)", hit, text)])


def c21(judgement, paper, err):
    """The likely causes of a differing C21 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``err``; returns the ledger's cause text."""
    return c20(judgement, {"smallest": paper["smallest_above"]}, err)


def c22(judgement, paper, ref):
    """The likely causes of a differing C22 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``ref``; returns the ledger's cause text."""
    a = ref.attrs
    N, width = a["n_p2pi"] - 1, a["return_time_max"] - a["return_time_min"]
    expected = N * N * paper["tie"] / width
    return _verdict([("the number of return times (near-ties by chance)", expected >= 1,
                      f"{N} values over a range of {width:.3g} give about {expected:.3g} pairs closer than "
                      f"{paper['tie']:g}")])


def _units_and_sampling(paper, psd):
    """Our Omega band in rad/time, and the sampling intervals that would alias it onto the paper's band."""
    a = psd.attrs
    want = np.asarray(paper["band"], float)
    ours = np.array([a["Omega_band_low"], a["Omega_band_high"]])
    tol = band_tolerance(want, 1.0 / a["psd_segment"])
    radians = 2 * math.pi * ours
    rad_ok = bool(np.all(np.abs(radians - want) <= tol))
    hits = []
    for dt in np.geomspace(0.01, 2.0, 2000):
        fs = 1.0 / dt
        alias = np.abs(ours - fs * np.round(ours / fs))
        if np.all(np.abs(np.sort(alias) - want) <= tol):
            hits.append(dt)
    return [("units (rad/time for cycles/time)", rad_ok, f"our band x 2 pi = [{radians[0]:.4g}, {radians[1]:.4g}]"),
            ("sampling (aliasing)", bool(hits),
             (f"sampling intervals {hits[0]:.3g} to {hits[-1]:.3g} alias our band onto the paper's" if hits else
              "no sampling interval in [0.01, 2] aliases our band onto the paper's"))]


def c23(judgement, paper, psd, k2):
    """The likely causes of a differing C23 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``psd``, ``k2``; returns the ledger's cause text."""
    want = paper["band"]
    k2_low, k2_high = _k2(k2, "band_low", want[0]), _k2(k2, "band_high", want[1])
    both = k2_low[1] and k2_high[1]
    return _verdict([*_units_and_sampling(paper, psd),
                     ("the unstated K", both, f"{k2_low[2]}; {k2_high[2]}")])


def c24(judgement, paper, psd):
    """The likely causes of a differing C24 (``judgement``: its judge's, ``paper``: the claim's values) tested
    on ``psd``; returns the ledger's cause text."""
    return _verdict(_units_and_sampling(paper, psd))


def d5(judgement, paper, audit):
    """The likely causes of a differing D5 (``judgement``: its judge's, ``paper``: the claim's values) tested on
    ``audit``; returns the ledger's cause text."""
    a = audit.attrs
    names = a["d5_normalisation_names"].split(" | ")
    values = np.asarray(a["d5_normalisation_values"], float)
    want = paper["label"]
    hits = [n for n, v in zip(names, values) if abs(v - want) <= REL_TOL * want]
    return _verdict([("an energy normalisation", bool(hits),
                      "; ".join(f"{n}: {v:.4g}" for n, v in zip(names, values)))])


#: Claim id -> cause test (called only for rows that differ).
CAUSE_TESTS = {"C04": c04, "C05": c05, "C06": c06, "C09": c09, "C10": c10, "C11": c11, "C13": c13, "C18": c18,
               "C19": c19, "C20": c20, "C21": c21, "C22": c22, "C23": c23, "C24": c24, "D5": d5}
