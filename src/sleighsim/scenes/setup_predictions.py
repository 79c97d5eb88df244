"""What each candidate setup of the paper predicts for its numbers, read from the datasets the ledger's
cause tests read (no integration): the paper's unstated choices are the *elements* of a setup, each
with its candidates:

- ``K2``: K^2 at eps = 0.1, on a grid inside the k2_sweep (linear interpolation between swept
  values, NaN outside the swept range or next to an undetermined one: no extrapolation);
- ``integrator``: heyoka at the run's tolerance, or the integration_error solver (RK45) at each rtol;
- ``psd``: the frequency convention (cycles/time or rad/time) and the sampling interval that may
  alias the band (none, or each dt of the block's grid: f -> |f - round(f dt) / dt|);
- ``energy``: the energy normalisations of the audit (``d5_normalisation_*``);
- ``lyapunov``: the paper's protocol integrated by heyoka (the protocol scene, mean over its states) or by
  the RK45 of integration_error at each of its ``lyapunov_rtol``, or our converged spectrum.

Separability: :data:`SEPARABILITY` (an assumption, written into the paper_setup dataset)."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

#: How the joint predictions are composed from the one-at-a-time sweeps (attribute ``separability``).
SEPARABILITY = (
    "the data sweep one element at a time from the run's baseline (K2 of integration_error, heyoka). A number "
    "swept against K2 and the integrator is predicted as k2(K2) + rk(rtol) - k2(K2_base) (additive shifts, "
    "first order); one swept against only one element takes the others at the baseline. The psd convention is "
    "an exact map applied to the predicted band. Values in model units (time, 1/time, cycles/time before the "
    "psd map)."
)

HEYOKA = "heyoka (tol {tol:.1e})"
CONVERGED = "converged spectrum (the spectrum scene)"


def interp_inside(x, y, at) -> np.ndarray:
    """y(x) linearly interpolated at ``at`` (``numpy.interp``): NaN outside [min x, max x] and where a
    neighbour is NaN."""
    at = np.atleast_1d(np.asarray(at, float))
    return np.interp(at, np.asarray(x, float), np.asarray(y, float), left=np.nan, right=np.nan)


def k2_grid(k2: xr.Dataset, step: float, baseline: float) -> np.ndarray:
    """The K2 candidates: every swept K2, a grid of ``step`` inside the sweep, and the run's baseline
    K2 when it lies inside the sweep."""
    lo, hi = float(k2.K2.min()), float(k2.K2.max())
    grid = np.r_[k2.K2.values, np.arange(lo, hi, step), [baseline] if lo <= baseline <= hi else []]
    return np.unique(np.round(grid, 10))


def integrators(err: xr.Dataset, tol: float) -> list[str]:
    """The integrator candidates: heyoka at ``tol`` (the baseline), then the solver at each rtol."""
    return [HEYOKA.format(tol=tol)] + [f"{err.attrs['method']} rtol {r:.0e}" for r in err.rtol.values]


def spike_observable(k2, err, var: str, grid) -> xr.DataArray:
    """A number swept against K2 and the integrator (first_spike, spike_interval, omega_rel_error) at
    every (K2, integrator): k2(K2), plus rk(rtol) - k2(K2_base) for the solver."""
    base = interp_inside(k2.K2, k2[var], err.attrs["param_K2"])[0]
    along_k2 = interp_inside(k2.K2, k2[var], grid)
    shift = np.r_[0.0, err[var].values - base]
    return xr.DataArray(along_k2[:, None] + shift[None, :], dims=("K2", "integrator"))


def spike_stderr(k2, err, var: str, grid) -> xr.DataArray:
    """The standard error of :func:`spike_observable` from the sweeps' own (quadrature sum of the
    terms); 0 for a number whose sweeps carry none."""
    name = f"{var}_stderr"
    if name not in k2 or name not in err:
        return xr.DataArray(np.zeros((len(grid), err.rtol.size + 1)), dims=("K2", "integrator"))
    se_k2 = interp_inside(k2.K2, k2[name], grid)
    se_base = interp_inside(k2.K2, k2[name], err.attrs["param_K2"])[0]
    extra = np.r_[0.0, err[name].values ** 2 + se_base ** 2]
    return xr.DataArray(np.sqrt(se_k2[:, None] ** 2 + extra[None, :]), dims=("K2", "integrator"))


def k2_observable(k2, var: str, grid) -> xr.DataArray:
    """A number swept against K2 only, along the K2 grid."""
    return xr.DataArray(interp_inside(k2.K2, k2[var], grid), dims=("K2",))


def psd_conventions(dts) -> list[tuple[str, float, float]]:
    """(label, factor, dt) of each psd candidate: cycles/time (factor 1) and rad/time (2 pi), each
    unsampled (dt NaN) and sampled at every dt of ``dts``."""
    out = []
    for unit, factor in (("cycles/time", 1.0), ("rad/time", 2 * math.pi)):
        out.append((unit, factor, math.nan))
        out += [(f"{unit}, sampled every {dt:.3g}", factor, float(dt)) for dt in dts]
    return out


def psd_map(f, factor: float, dt: float) -> np.ndarray:
    """Frequencies ``f`` (cycles/time) as a spectrum sampled every ``dt`` shows them (folded about
    the Nyquist frequency; dt NaN: not sampled) in the unit of ``factor`` (1: cycles, 2 pi: rad)."""
    f = np.asarray(f, float)
    if math.isfinite(dt):
        fs = 1.0 / dt
        f = np.abs(f - fs * np.round(f / fs))
    return factor * f


def band_edges(low, high, conventions) -> tuple[np.ndarray, np.ndarray]:
    """The (low, high) band edges under every psd convention: arrays (..., psd) from band edges in
    cycles/time (any shape; the mapped edges sorted)."""
    lo, hi = np.asarray(low, float)[..., None], np.asarray(high, float)[..., None]
    mapped = [(psd_map(lo, fa, dt), psd_map(hi, fa, dt)) for _, fa, dt in conventions]
    a = np.concatenate([m[0] for m in mapped], axis=-1)
    b = np.concatenate([m[1] for m in mapped], axis=-1)
    return np.minimum(a, b), np.maximum(a, b)


def lyapunov_candidates(err, protocol, spectrum) -> tuple[list[str], np.ndarray, np.ndarray]:
    """(labels, exponents (candidate, 4), standard deviations (candidate, 4)) of the Lyapunov
    candidates, each spectrum descending: the converged spectrum (its standard errors), the
    protocol in heyoka (mean over its states; their standard deviation: one state's scatter), and the
    protocol in the solver at each ``lyapunov_rtol`` (no uncertainty carried: 0)."""
    conv = spectrum.exponent.values  # written sorted descending, beside its stderr
    states = -np.sort(-protocol.exponent.values, axis=1)
    rk = -np.sort(-err.protocol_exponent.values, axis=1)
    labels = [CONVERGED, f"protocol, heyoka (mean of {states.shape[0]} states)"] + [
        f"protocol, {err.attrs['method']} rtol {r:.0e}" for r in err.lyapunov_rtol.values]
    values = np.vstack([conv, states.mean(axis=0), rk])
    sd = np.vstack([spectrum.stderr.values, states.std(axis=0, ddof=1) if states.shape[0] > 1 else
                    np.zeros(4), np.zeros_like(rk)])
    return labels, values, sd
