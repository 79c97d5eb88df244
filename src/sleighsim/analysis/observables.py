"""A scene's key observables in each precision, and the precision they converge in.

A scene whose block lists ``precisions`` is computed once per precision from the same settled
point (the transient in double, then the steady-state part in that arithmetic at its machine
epsilon, :func:`sleighsim.scenes.common.steady_arithmetic`). Its observables (those its kind
declares, ``SceneKind.observables`` in :mod:`sleighsim.scenes.kind`, passed in by the caller) are read
from each precision's dataset with an
uncertainty stated by the dataset itself; :func:`ladder` compares them precision by precision.

Uncertainties (how each is estimated):
- ``rotation_number``: the difference between the run's two halves (block estimate; the
  halves are not assumed independent, and a drifting value shows up as a large difference);
- ``return_time_mean``: the difference between the mean return time of the two halves;
- band edges and peaks of a power spectrum: the Welch frequency bin, 1 / segment (the
  resolution of the estimate; the value cannot be known better);
- counts (loops, peaks, spikes): exact; two counts agree only when equal;
- any other observable: the uncertainty its dataset states beside it (``<name>_uncertainty``;
  the dataset's ``observables_rule`` says how it was estimated, e.g. a trajectory's spikes and
  reach, :func:`sleighsim.scenes.trajectories.observed`).
An observable a precision's dataset does not state (a run with too few spikes for an interval)
is NaN there, and NaN never agrees; one that no precision states is left out of the ladder.
Every uncertainty is floored at :data:`REL_FLOOR` of the value (the agreement of two faithful
runs from one point is limited by rounding in the observable's own computation).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

#: Uncertainties are at least this fraction of the value.
REL_FLOOR = 1e-9
#: Two values agree within this many combined uncertainties.
K_SIGMA = 2.0
#: The separation of two precisions' sampled orbits at which they no longer follow one orbit.
SEPARATED = 1e-3


def _halves(x) -> float:
    x = np.asarray(x, float)
    h = x.size // 2
    return abs(float(x[:h].mean()) - float(x[h:].mean())) if h else math.nan


def observable(ds: xr.Dataset, name: str) -> tuple[float, float]:
    """(value, uncertainty) of observable ``name`` in a scene's dataset (module docstring: how each
    uncertainty is estimated; 0 for a count)."""
    a = ds.attrs
    if name not in a:
        return math.nan, math.nan
    if f"{name}_uncertainty" in a:
        return a[name], a[f"{name}_uncertainty"]
    if name == "rotation_number":
        return a[name], abs(a["rotation_number_first_half"] - a["rotation_number_second_half"])
    if name == "return_time_mean":
        return float(np.mean(ds.return_time.values)), _halves(ds.return_time.values)
    if _is_count(name):
        return float(a[name]), 0.0
    if name.endswith(("_band_low", "_band_high", "_band_peak", "_lowest_peak")):
        return a[name], 1.0 / a["psd_segment"]
    raise KeyError(f"no rule for the uncertainty of observable {name!r}")


#: Written into every ladder dataset (attribute agreement_rule).
AGREES_RULE = (
    "Do two precisions' values (value, uncertainty) of one observable agree? Counts: equal. Other values: |a - "
    "b| <= K_SIGMA x sqrt(u_a^2 + u_b^2), each u floored at REL_FLOOR x |value|. A NaN on either side never "
    "agrees."
)


def agrees(a: tuple[float, float], b: tuple[float, float], *, count: bool) -> bool:
    """Applies :data:`AGREES_RULE`, the rule as the datasets record it (just above)."""
    if not all(math.isfinite(v) for v in (*a, *b)):
        return False
    if count:
        return a[0] == b[0]
    ua, ub = (max(u, REL_FLOOR * abs(v)) for v, u in (a, b))
    return abs(a[0] - b[0]) <= K_SIGMA * math.hypot(ua, ub)


#: Written into every ladder dataset (attribute converged_rule).
CONVERGED_RULE = (
    "The lowest precision whose values agree (``agrees``) with those of every finer precision, ``agree[i, j]`` "
    "telling whether precisions i and j agree; \"not converged\" when none does below the finest (a single "
    "precision is never called converged)."
)


def converged(agree: np.ndarray, precisions: list[str]) -> str:
    """Applies :data:`CONVERGED_RULE`, the rule as the datasets record it (just above)."""
    for i in range(len(precisions) - 1):
        if all(agree[i, j] for j in range(i + 1, len(precisions))):
            return str(precisions[i])
    return "not converged"


def _separation(runs: list[xr.Dataset]):
    """Per neighbouring pair, max |velocity difference| / max |velocity| of the finer run over the
    sampled attractor stretch (a Poincare scene's ``attractor_*``), and its first time above
    SEPARATED (NaN: never); None when the datasets hold no common samples."""
    if not all("attractor_u" in r for r in runs):
        return None
    vel = [np.stack([r[f"attractor_{v}"].values for v in ("u", "Omega", "omega")], axis=1) for r in runs]
    seps = [np.abs(a - b).max(axis=1) / np.abs(b).max() for a, b in zip(vel[:-1], vel[1:])]
    dt = float(runs[0].attrs.get("attractor_dt", math.nan))
    # sample 0: t = 0
    first = [float(dt * np.argmax(s > SEPARATED)) if np.any(s > SEPARATED) else math.nan for s in seps]
    return seps, first, dt


def gauge(params_cfg: dict, y, *, T: float, tau: float, spike_factor: float, tol: float, window: bool = False) -> dict:
    """The faithfulness gauge along the settled orbit from y (in double at tol over T in steps of tau): ln G
    per spike cycle (``faithfulness.spike_cycle_gains``; "unknown" without a complete cycle within T) or, with
    ``window``, over the whole window [0, T] (``faithfulness.window_gains``: an orbit without a spike cycle in
    its data's window) and, per arithmetic, G x rounding and whether it follows the orbit."""
    from sleighsim.chaos.faithfulness import settled_gains
    from sleighsim.model.params import Params

    return settled_gains(Params.from_config(params_cfg), y, tol=tol, compact_mode=True, T=T, tau=tau,
                         spike_factor=spike_factor, window=window)


#: What the gauge's gains span, by its ``window`` setting.
GAIN_SPANS = {False: "each complete spike cycle along the settled orbit",
              True: "the whole window [0, T_gain] from the settled point (no spike cycle needed)"}


def _with_gauge(ds: xr.Dataset, g: dict, precisions: list[str], T: float, window: bool = False) -> xr.Dataset:
    ds["ln_gain"] = ("cycle", g["ln_gain"] if len(g["ln_gain"]) else [math.nan],
                     {"long_name": f"ln G over {GAIN_SPANS[window]} (double)"})
    ds["log10_gain_rounding"] = ("precision", [g["log10_gain_rounding"][p] for p in precisions])
    ds["follows_orbit"] = ("precision", np.array([g["follows"][p] for p in precisions], dtype=object),
                           {"long_name": f"the arithmetic follows the exact orbit through {GAIN_SPANS[window]} "
                                         "(G x steps x rounding < 1e-3)"})
    ds.attrs.update(ln_gain_max=g["ln_gain_max"], T_gain=T, gain_span=GAIN_SPANS[window],
                    gain_steps=g["steps_per_cycle"])
    return ds


def ladder(kind: str, names: tuple[str, ...], runs: list[xr.Dataset], precisions: list[str], scene: str = "",
           gain: dict | None = None) -> xr.Dataset:
    """The observables ``names`` of a scene of ``kind`` in every precision's dataset (``runs``, coarse to fine), whether
    each pair of precisions agrees, and per observable and overall the converged precision; with
    ``gain`` ({T, tau, spike_factor, tol, params}) also the faithfulness gauge from the settled point.
    Raises when the runs did not start from one settled point."""
    starts = [np.asarray(r.attrs["settled_state"], float) for r in runs]
    if any(not np.array_equal(starts[0], s, equal_nan=True) for s in starts[1:]):  # NaN: a row computed elsewhere
        raise ValueError(f"{scene}: the precisions' runs start from different settled states {starts}")
    names = [n for n in names if any(n in r.attrs for r in runs)]
    vals = np.array([[observable(r, n) for n in names] for r in runs])  # (precision, observable, 2)
    agree = np.array([[[agrees(tuple(vals[i, k]), tuple(vals[j, k]), count=_is_count(n)) for j in range(len(runs))]
                       for i in range(len(runs))] for k, n in enumerate(names)])
    per_obs = [converged(agree[k], precisions) for k in range(len(names))]
    overall = converged(np.all(agree, axis=0), precisions)
    ds = xr.Dataset(
        {"value": (("precision", "observable"), vals[..., 0]),
         "uncertainty": (("precision", "observable"), vals[..., 1],
                         {"long_name": "stated uncertainty of the value "
                                       "(sleighsim.analysis.observables: how each is estimated)"}),
         "agrees": (("observable", "precision", "finer"), agree.astype(np.int8)),
         "converged_precision_of": ("observable", np.array(per_obs, dtype=object)),
         "run_wall_s": ("precision", [float(r.attrs.get("wall_time_s", math.nan)) for r in runs]),
         "run_energy_max_rel_drift": ("precision",
                                      [float(r.attrs.get("energy_max_rel_drift", math.nan)) for r in runs]),
         "tol": ("precision", [float(r.attrs["tol"]) for r in runs])},
        coords={"precision": precisions, "finer": precisions, "observable": names},
    )
    sep = _separation(runs)
    if sep is not None:
        seps, first, dt = sep
        pairs = [f"{a} / {b}" for a, b in zip(precisions[:-1], precisions[1:])]
        ds["separation"] = (("pair", "t_separation"), np.array(seps),
                            {"long_name": "max |velocity difference| / max |velocity| of the finer run"})
        ds["t_separated"] = ("pair", first, {"long_name": f"time after the settled point when the separation first "
                                                          f"exceeds {SEPARATED:g} (NaN: never)", "units": "time"})
        ds = ds.assign_coords(pair=pairs, t_separation=dt * np.arange(seps[0].size))
    ds.attrs.update({k: v for k, v in runs[0].attrs.items() if k.startswith(("param_", "y0_", "energy_label"))})
    ds.attrs.update(scene=scene, kind=kind, converged_precision=overall, settled_state=starts[0],
                    start_rule="transient in double from the scene's y0, then each precision from that settled point "
                               "at its machine epsilon", agreement_rule=AGREES_RULE,
                    converged_rule=CONVERGED_RULE, rel_floor=REL_FLOOR, k_sigma=K_SIGMA)
    if gain:
        window = bool(gain.get("window", False))
        g = gauge(gain["params"], starts[0], T=gain["T"], tau=gain["tau"], spike_factor=gain["spike_factor"],
                  tol=gain["tol"], window=window)
        ds = _with_gauge(ds, g, precisions, gain["T"], window)
    return ds


def _is_count(name: str) -> bool:
    return name.startswith("n_") or "_n_" in name
