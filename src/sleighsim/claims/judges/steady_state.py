"""The steady state and its Poincare maps: velocities and path after the transient, the maps
P_2pi and P_pi/2, their return times and the attractor under the time-scaling law (figures F7-F9,
F12; C13-C17, C22).

Each judge takes the paper's values and its datasets (:data:`sleighsim.claims.evidence.EVIDENCE`)
and returns a :class:`~sleighsim.claims.rules.Judgement`."""

from __future__ import annotations

import math

import numpy as np

from sleighsim.analysis.path import shape
from sleighsim.claims.rules import (
    DIFFERS,
    REL_TOL,
    REPRODUCED,
    Judgement,
    all_of,
    finite,
    relative,
)


def _backward_stretch(t, u, window=5.0):
    """Centre and length of the longest stretch where the running maximum of u (over ``window``) is negative."""
    n = max(1, int(round(window / (t[1] - t[0]))))
    runmax = np.array([u[max(0, i - n): i + n + 1].max() for i in range(u.size)])
    neg = runmax < 0
    if not neg.any():
        return math.nan, 0.0
    edges = np.flatnonzero(np.diff(np.r_[0, neg.astype(int), 0]))
    starts, ends = edges[::2], edges[1::2] - 1
    k = int(np.argmax(t[ends] - t[starts]))
    return float(0.5 * (t[starts[k]] + t[ends[k]])), float(t[ends[k]] - t[starts[k]])


def c13(paper, fig7) -> Judgement:
    """C13, "near t = 9800 u stays negative (moving backward); near t = 10000 a spike turns the heading by about
    pi": judged from the paper's values ``paper`` and ``fig7``; returns its Judgement."""
    t, u, Om, th = fig7.time.values, fig7.u.values, fig7.Omega.values, fig7.theta.values
    i = int(np.argmax(np.abs(Om)))
    turn = float(np.interp(t[i] + 300, t, th) - np.interp(t[i] - 300, t, th)) / math.pi
    back, length = _backward_stretch(t, u)
    parts = [REPRODUCED if finite(back) and abs(back - paper["backward_time"]) < 0.05 * paper["backward_time"]
             else DIFFERS,
             REPRODUCED if abs(t[i] - paper["spike_time"]) < 0.05 * paper["spike_time"] else DIFFERS,
             REPRODUCED if abs(abs(turn) - paper["turn_over_pi"]) < REL_TOL else DIFFERS]
    return Judgement(
        all_of(parts), difference=relative(paper["spike_time"], t[i]),
        measured=(f"u stays negative for {length:.3g} time units around t = {back:.0f}" if finite(back) else
                  "u never stays negative in the window") + f"; the largest spike at t = {t[i]:.0f} turns the heading "
                                                            f"by {turn:.3f} pi",
        rule="a backward stretch (running maximum of u over 5 time units negative) within 5% of the paper's time, the "
             "largest spike within 5% of the paper's time and |turn| within 10% of pi")


#: C14's rule: bounded when the farthest distance from the start grows by less than this over the path's second half;
#: not periodic when at every lag the path's RMS distance from its shifted copy exceeds this fraction of its size.
BOUNDED_GROWTH, APERIODIC = 1.2, 0.01
#: The rule's text (the double judge's and the faithful judge's).
PATH_RULE = (f"bounded: the farthest distance from the start grows by less than {BOUNDED_GROWTH:g} over the second "
             f"half of the path; not periodic: at every lag the RMS distance between the path and its shifted copy "
             f"exceeds {APERIODIC:g} of its size")


def path_verdict(growth: float, recurrence: float) -> tuple[bool, bool]:
    """(bounded, not periodic) of a path of that growth and recurrence (``analysis.path.shape``) by PATH_RULE."""
    return growth < BOUNDED_GROWTH, recurrence > APERIODIC


def c14(paper, fig8) -> Judgement:
    """C14, "the path with the rotor is bounded and not periodic": judged from the paper's values ``paper`` and
    ``fig8``; returns its Judgement."""
    t = fig8.time.values
    p = shape(t, fig8.x.values, fig8.y.values)
    bounded, aperiodic = path_verdict(p["growth"], p["recurrence"])
    return Judgement(
        REPRODUCED if bounded and aperiodic else DIFFERS, units="length",
        measured=f"the farthest distance from the start grows by {p['growth']:.3f} from half the path to all of it "
                 f"(bounded about 1, diffusive 1.41, straight 2), reaching {p['reach']:.3g}; the path never repeats "
                 f"itself to better than {p['recurrence']:.3g} of its size at any lag of 50 to {t[-1] - t[0]:.3g} / 3",
        rule=PATH_RULE,
        reason="" if bounded else f"the path keeps leaving: its reach grows by {p['growth']:.2f} over the second half")


def c15(paper, ref) -> Judgement:
    """C15, "P_2pi is not periodic for thousands of iterations and fills a closed curve": judged from the
    paper's values ``paper`` and ``ref``; returns its Judgement."""
    a = ref.attrs
    # a periodic orbit of period q <= 50 returns to within the integration error (1e-12 relative):
    # 1e-6 of the set's size separates it from the close, but never exact, returns of a dense curve
    thin, many, aperiodic = a["p2pi_curve_thickness"] < 0.01, a["n_p2pi"] >= 1000, a["p2pi_recurrence"] > 1e-6
    verdict = REPRODUCED if thin and many and aperiodic else DIFFERS
    return Judgement(
        verdict,
        measured=f"{a['n_p2pi']} iterates; curve thickness {a['p2pi_curve_thickness']:.2g} of the radius; iterates "
                 f"never come back closer than {a['p2pi_recurrence']:.2g} of the set's size (q <= 50); rotation number "
                 f"{a['rotation_number']:.5g} (halves {a['rotation_number_first_half']:.5g}, "
                 f"{a['rotation_number_second_half']:.5g})",
        rule="at least 1000 iterates (thousands), curve thickness < 0.01 (a closed curve) and no return closer than "
             "1e-6 of the set's size within 50 iterates (not periodic: a periodic orbit returns to integration "
             "accuracy)",
        reason="" if verdict == REPRODUCED else ", ".join(
            w for w, bad in (("fewer than 1000 iterates", not many), ("the set is not a thin curve", not thin),
                             ("the iterates repeat", not aperiodic)) if bad))


def c16(paper, ref) -> Judgement:
    """C16, "P_pi/2 iterates form four distinct closed loops": judged from the paper's values ``paper`` and
    ``ref``; returns its Judgement."""
    a = ref.attrs
    return Judgement(REPRODUCED if a["n_loops"] == paper["loops"] else DIFFERS,
                     measured=f"{a['n_loops']} loops (per class {[int(n) for n in a['loops_per_class']]}; "
                              f"{a['n_components_projected']} components in the 3-D projection)",
                     rule="exact count of k-NN graph components per section class (loop rule in the dataset)")


def c17(paper, ref, high, small, scaling=None) -> Judgement:
    """C17, "attractor topology persists for E = 0.8313 and for eps = 0.01; larger eps with smaller E gives a
    flatter attractor": judged from the paper's values ``paper`` and ``ref``, ``high`` , ``small``, ``scaling``
    (None: its comparison left out of the text; the verdict never reads it); returns its Judgement."""
    persists = high.attrs["n_loops"] == 4 and small.attrs["n_loops"] == 4
    f_ref, f_high, f_small = (d.attrs["attractor_flatness"] for d in (ref, high, small))
    flatter_at_larger_eps = f_ref < f_small
    scaled = "" if scaling is None else (
        f"; the higher label divided by c = {scaling.attrs['scale_factor_c']:.4g} lies "
        f"{scaling.attrs['distance_scaled_median']:.2g} of the size from the reference set (unscaled "
        f"{scaling.attrs['distance_unscaled_median']:.2g})")
    return Judgement(
        REPRODUCED if persists and flatter_at_larger_eps else DIFFERS,
        measured=f"loops {high.attrs['n_loops']} (E label {high.attrs['energy_label']:.4g}), {small.attrs['n_loops']} "
                 f"(eps {small.attrs['param_eps']:g}); flatness (smallest / largest axis) {f_ref:.3g} at eps "
                 f"{ref.attrs['param_eps']:g}, {f_small:.3g} at eps {small.attrs['param_eps']:g}, {f_high:.3g} at "
                 f"E label {high.attrs['energy_label']:.4g}" + scaled,
        rule="the 4 loops persist at the higher label and at the smaller eps, and the attractor is flatter at the "
             "larger eps; the energy changes only the scale (exact time-scaling symmetry), so it cannot change the "
             "shape",
        reason="" if persists and flatter_at_larger_eps else
        ("the loops do not persist; " if not persists else "") +
        ("" if flatter_at_larger_eps else f"the attractor is not flatter at the larger eps ({f_ref:.3g} against "
                                          f"{f_small:.3g}); ")
        + f"at the same eps the shape does not depend on the energy ({f_ref:.3g} against {f_high:.3g})")


def c22(paper, ref) -> Judgement:
    """C22, "return times of P_2pi bounded; no two equal to 1e-7": judged from the paper's values ``paper`` and
    ``ref``; returns its Judgement."""
    a = ref.attrs
    tie = paper["tie"]
    n = a["return_time_n_adjacent_pairs_within_tie_tol"]
    N, width = a["n_p2pi"] - 1, a["return_time_max"] - a["return_time_min"]
    expected = N * N * tie / width if width > 0 else math.nan
    return Judgement(
        REPRODUCED if n == 0 else DIFFERS, units="time",
        measured=f"{N} return times in [{a['return_time_min']:.5g}, {a['return_time_max']:.5g}]; {n} adjacent pairs "
                 f"closer than {tie:g}; smallest difference {a['return_time_min_pairwise_difference']:.2g}",
        rule=f"no two return times closer than the paper's {tie:g}",
        reason=f"{N} values spread over {width:.3g} give about {expected:.3g} pairs closer than {tie:g} by chance"
        if n else "")
