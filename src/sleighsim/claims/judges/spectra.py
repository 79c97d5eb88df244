"""The power spectra of u and Omega on the attractor (figures F13, F14; C23, C24).

Each judge takes the paper's values and its datasets (:data:`sleighsim.claims.evidence.EVIDENCE`)
and returns a :class:`~sleighsim.claims.rules.Judgement`."""

from __future__ import annotations

from sleighsim.claims.rules import (
    DIFFERS,
    REL_TOL,
    REPRODUCED,
    Judgement,
    band_tolerance,
    relative,
)


def _band(paper, psd) -> Judgement:
    a = psd.attrs
    want = paper["band"]
    ours = (a["Omega_band_low"], a["Omega_band_high"])
    resolution = 1.0 / a["psd_segment"]
    tol = band_tolerance(want, resolution)
    ok = all(abs(o - w) <= tol for o, w in zip(ours, want))
    return Judgement(
        REPRODUCED if ok else DIFFERS, units="cycles/time",
        difference=max(relative(w, o) for w, o in zip(want, ours)),
        measured=f"Omega band [{ours[0]:.4g}, {ours[1]:.4g}] (u: [{a['u_band_low']:.4g}, {a['u_band_high']:.4g}]); "
                 f"{a['Omega_n_peaks_near_zero']} distinct peaks near 0; resolution {resolution:.2g}",
        rule=f"both band edges within {REL_TOL:.0%} of the paper's band width or one frequency bin, whichever is "
             f"larger ({tol:.2g})")


def c23(paper, psd) -> Judgement:
    """C23, "PSD eps = 0.1: distinct peaks near f = 0, broadband cluster": judged from the paper's values
    ``paper`` and ``psd``; returns its Judgement."""
    return _band(paper, psd)


def c24(paper, psd) -> Judgement:
    """C24, "PSD eps = 0.01: continuous band; distinct peaks near 0": judged from the paper's values ``paper``
    and ``psd``; returns its Judgement."""
    return _band(paper, psd)
