"""The chaos verdict at one steady state from the exponent spectrum and the 0-1 test (C27)."""

from __future__ import annotations

import logging

import xarray as xr

from .. import lyapunov
from ..io import read_dataset

log = logging.getLogger("sleighsim")


def verdict(cfg: dict, inputs: dict, scene: str = "") -> xr.Dataset:
    """Chaos verdict from the exponents and the 0-1 test on the P_2pi iterates (C19-C21, C27).

    chaotic: lambda_1 > sigma stderr, lambda_1(T) not decaying (slope of log lambda_1(T) over the
    last decade above -slope_limit) and K > K_threshold; quasi-periodic: lambda_1 within sigma
    stderr of 0 or decaying like 1/T, and K < K_threshold from a record spanning at least
    min_lyapunov_times Lyapunov times at the largest rate the exponent allows (|lambda_1| + sigma
    stderr); otherwise undecided.

    A short record of a slowly chaotic flow is a smooth, oversampled signal, for which the
    0-1 test returns K near 0 whatever the dynamics: such a K is not counted as evidence of
    regularity."""
    spectrum_nc, poincare_nc = inputs["exponents"], inputs["poincare"]
    spec, pc = read_dataset(spectrum_nc), read_dataset(poincare_nc)
    n = cfg["max_samples"]
    z = lyapunov.zero_one_test(pc[cfg["observable"]].values[:n], n_c=cfg["n_c"])
    t = pc.p2pi_time.values[:n]
    lam, err = float(spec.exponent.values[0]), float(spec.stderr.values[0])
    record = float(t[-1] - t[0])
    lyap_times = (abs(lam) + cfg["sigma"] * err) * record
    informative = lyap_times >= cfg["min_lyapunov_times"]
    slope = spec.attrs["lambda_1_decay_slope_last_decade"]
    positive = lam > cfg["sigma"] * err and slope > -cfg["slope_limit"]
    zero = abs(lam) <= cfg["sigma"] * err or slope <= -cfg["slope_limit"]
    chaotic_01 = z["K"] > cfg["K_threshold"]
    if positive and chaotic_01:
        v = "chaotic"
    elif zero and not chaotic_01 and informative:
        v = "quasi-periodic"
    else:
        v = "undecided"
    ds = xr.Dataset()
    ds.attrs.update({f"zero_one_{k}": val for k, val in z.items()})
    ds.attrs.update(
        verdict=v, lambda_1=lam, lambda_1_stderr=err, lambda_1_decay_slope=slope, T=spec.attrs["T"],
        zero_one_record_time=record, zero_one_record_lyapunov_times=lyap_times,
        zero_one_informative=int(informative or chaotic_01),
        exponents_agree_with_indicator=int(positive == chaotic_01),
        observable=f"{cfg['observable']} at the P_2pi crossings", rule=" ".join(verdict.__doc__.split("\n\n")[1].split()),
        sources=f"{spectrum_nc}, {poincare_nc}",
    )
    log.info("verdict %s: lambda_1 %.3g +- %.2g, K %.3f from a record of %.3g Lyapunov times", v, lam, err, z["K"],
             lyap_times)
    return ds

