"""Power spectra with scipy.signal.welch, and explicit rules for bands and peaks.

Frequency f is in cycles per unit time (angular frequency 2 pi f). Rules:
- band: above ``f_split`` (away from the near-zero cluster), the band edges are
  the lowest and highest frequencies whose PSD is at least ``rel_threshold``
  times the largest PSD above ``f_split``.
- distinct peaks near zero: local maxima below ``f_split`` whose prominence in
  log10(PSD) is at least ``prominence_decades`` and whose PSD is at least
  ``floor_rel`` times the largest PSD (so fluctuations of the round-off floor,
  some 20 decades down, are not counted).
"""

from __future__ import annotations

import numpy as np


def psd(x, dt: float, *, segment: float, window: str = "hann", detrend: str = "constant"):
    """Welch PSD of x sampled every dt; segments of ``segment`` time units, 50% overlap.

    Returns (f [cycles/time], S [units^2 * time])."""
    from scipy import signal  # here: at the top it costs every job start-up (scenes.catalog)

    nperseg = min(len(x), int(round(segment / dt)))
    return signal.welch(np.asarray(x, float), fs=1.0 / dt, window=window, nperseg=nperseg,
                        detrend=detrend, scaling="density")


def band_edges(f, S, *, f_split: float, rel_threshold: float) -> tuple[float, float, float]:
    """(low edge, high edge, peak frequency) of the band above f_split (see module rule)."""
    f, S = np.asarray(f), np.asarray(S)
    sel = f > f_split
    if not np.any(sel):
        raise ValueError(f"no frequencies above f_split = {f_split}")
    fs, Ss = f[sel], S[sel]
    above = fs[Ss >= rel_threshold * Ss.max()]
    return float(above.min()), float(above.max()), float(fs[np.argmax(Ss)])


def peaks_near_zero(f, S, *, f_split: float, prominence_decades: float, floor_rel: float) -> np.ndarray:
    """Frequencies of the distinct peaks below f_split (see module rule)."""
    from scipy import signal  # here: at the top it costs every job start-up (scenes.catalog)

    f, S = np.asarray(f), np.asarray(S)
    sel = (f > 0) & (f < f_split)
    logS = np.log10(np.maximum(S[sel], 1e-300))
    idx, _ = signal.find_peaks(logS, prominence=prominence_decades, height=np.log10(floor_rel * S.max()))
    return f[sel][idx]
