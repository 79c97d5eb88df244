"""The chaos verdict at one steady state from the exponent spectrum and the 0-1 test."""

from __future__ import annotations

import logging
import math

import xarray as xr

from .. import lyapunov
from ..io import read_dataset

log = logging.getLogger("sleighsim")


def decide(lam: float, err: float, slope: float, K: float, n_samples: int, record: float, *, sigma: float,
           slope_limit: float, K_threshold: float, lambda_floor: float, min_lyapunov_times: float,
           min_samples: int) -> tuple[str, str]:
    """(verdict, reason): "chaotic" when lambda_1 > sigma stderr, lambda_1(T) does not decay (log-log
    slope over the last decade above -slope_limit) and the 0-1 test gives K > K_threshold;
    "quasi-periodic" when lambda_1 is within sigma stderr of 0 or decays, and K < K_threshold from an
    informative record: at least min_samples iterates spanning min_lyapunov_times / lambda_floor time
    units (so that chaos at any rate above lambda_floor would have decorrelated it); "undecided"
    otherwise, including when any input is NaN."""
    if not all(math.isfinite(v) for v in (lam, err, slope, K, record)):
        return "undecided", "an input is undetermined (NaN)"
    informative = n_samples >= min_samples and record * lambda_floor >= min_lyapunov_times
    positive = lam > sigma * err and slope > -slope_limit
    zero = abs(lam) <= sigma * err or slope <= -slope_limit
    chaotic_01 = K > K_threshold
    facts = (f"lambda_1 = {lam:.3g} +- {err:.2g} (slope of lambda_1(T) {slope:.2f}); 0-1 test K = {K:.3f} from "
             f"{n_samples} iterates over {record:.3g} time units ({record * lambda_floor:.3g} Lyapunov times at the "
             f"floor rate {lambda_floor:g})")
    if positive and chaotic_01:
        return "chaotic", "both say chaotic: " + facts
    if zero and not chaotic_01 and informative:
        return "quasi-periodic", "both say regular: " + facts
    if zero and not chaotic_01:
        return "undecided", "regular-looking, but the 0-1 record is too short to exclude slow chaos: " + facts
    return "undecided", "the exponent and the 0-1 test disagree: " + facts


def verdict(cfg: dict, inputs: dict, scene: str = "") -> xr.Dataset:
    """The verdict of :func:`decide` from a lyapunov_spectrum dataset and the P_2pi iterates of a
    poincare dataset of the same steady state (C27)."""
    spectrum_nc, poincare_nc = inputs["exponents"], inputs["poincare"]
    spec, pc = read_dataset(spectrum_nc), read_dataset(poincare_nc)
    n = cfg["max_samples"]
    samples = pc[cfg["observable"]].values[:n]
    z = lyapunov.zero_one_test(samples, n_c=cfg["n_c"])
    t = pc.p2pi_time.values[:n]
    lam, err = float(spec.exponent.values[0]), float(spec.stderr.values[0])
    record = float(t[-1] - t[0]) if t.size > 1 else math.nan
    slope = spec.attrs["lambda_1_decay_slope_last_decade"]
    keys = ("sigma", "slope_limit", "K_threshold", "lambda_floor", "min_lyapunov_times", "min_samples")
    v, reason = decide(lam, err, slope, float(z["K"]), int(samples.size), record, **{k: cfg[k] for k in keys})
    ds = xr.Dataset()
    ds.attrs.update({f"zero_one_{k}": val for k, val in z.items()})
    ds.attrs.update(
        verdict=v, reason=reason, lambda_1=lam, lambda_1_stderr=err, lambda_1_decay_slope=slope, T=spec.attrs["T"],
        zero_one_record_time=record, observable=f"{cfg['observable']} at the P_2pi crossings",
        rule=" ".join(decide.__doc__.split()), sources=f"{spectrum_nc}, {poincare_nc}",
        **{k: cfg[k] for k in keys},
    )
    log.info("verdict %s: %s", v, reason)
    return ds
