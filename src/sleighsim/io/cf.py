"""CF conventions (CF-1.11) on every dataset sleighsim writes (applied by :func:`sleighsim.io.netcdf.write_dataset`).

The model is nondimensional (global attribute ``nondimensionalisation``): a quantity's ``units`` is
"1" (UDUNITS' dimensionless unit), angles are "rad", wall-clock times "s", and the quantity's model
unit (time, length, speed, angular velocity, rate, frequency) is stated in its ``long_name``
(:func:`attrs`). Text variables carry a ``long_name`` and no ``units`` (CF: units belong to
quantities). :data:`VOCABULARY` names every variable a scene or output writes without attributes of
its own; :func:`complete` fills in what a variable lacks and :func:`missing` lists what no one
named, which the tests require to be empty on every dataset of the smoke run.
"""

from __future__ import annotations

import re
from pathlib import Path

import xarray as xr

from sleighsim.ops.registry import TITLES

CONVENTIONS = "CF-1.11"
REFERENCES = ("Fedonyuk, V. and Tallapragada, P., Chaotic dynamics of the Chaplygin sleigh with a passive internal "
              "rotor (the LaTeX source, which states no journal or DOI, is paper/fedonyuk-tallapragada-sleigh-rotor.tex "
              "of the sleighsim repository; CITATION.cff)")
TIME_UNIT = ("the model's time unit: the equations (the paper's form with m = 1) fix no time scale, and the "
             "time-scaling symmetry (c u, c Omega, c omega, delta)(c t) maps a run at energy E to one at c^2 E, so "
             "times are nondimensional numbers (units '1') in this unit; rates, frequencies and velocities are per "
             "this unit")
NONDIMENSIONALISATION = ("every quantity is nondimensional (units '1', angles 'rad', wall-clock times 's'): masses "
                         "in units of the total mass m = m_c + m_r = 1, lengths in the model's length unit (the runner "
                         "distance b is the parameter param_b, a / b = eps), times in the model's time unit (global "
                         "attribute time_unit); energies E = 1/2 v^T M v in the resulting unit, and the paper's energy "
                         "label E_p = 0.1127 x (E / E of the reference state (0, 0.1, 1, 0)); each long_name states "
                         "its model unit (docs/model.md)")

#: kind -> (units, the model unit stated in the long_name)
KINDS: dict[str, tuple[str | None, str]] = {
    "1": ("1", ""),
    "time": ("1", "in model time units"),
    "rate": ("1", "per model time unit"),
    "length": ("1", "in model length units"),
    "speed": ("1", "in model length units per model time unit"),
    "acceleration": ("1", "in model length units per model time unit squared"),
    "angle": ("rad", ""),
    "angular_velocity": ("1", "in radians per model time unit"),
    "angular_acceleration": ("1", "in radians per model time unit squared"),
    "frequency": ("1", "in cycles per model time unit"),
    "angular_frequency": ("1", "in radians per model time unit"),
    "psd_speed": ("1", "in (model length units per model time unit)^2 per (cycle per model time unit)"),
    "psd_angular_velocity": ("1", "in (radians per model time unit)^2 per (cycle per model time unit)"),
    "s": ("s", ""),
    "text": (None, ""),
}

#: Unit strings of the earlier, private vocabulary still written (by sleighsim.engine.integrate for its
#: time coordinate, by sleighsim.analysis.observables for t_separated) -> their kind.
LEGACY_UNITS = {"time": "time"}

#: The kind of each state variable (u, Omega, omega, delta) and kinematic variable.
STATE_KINDS = {"u": "speed", "Omega": "angular_velocity", "omega": "angular_velocity", "delta": "angle",
               "theta": "angle", "x": "length", "y": "length"}


def attrs(long_name: str, kind: str = "1") -> dict:
    """{"long_name", "units"} of a quantity of ``kind`` (:data:`KINDS`): the long_name ends with the
    model unit; a text variable ("text") gets no units."""
    units, unit_text = KINDS[kind]
    out = {"long_name": f"{long_name}, {unit_text}" if unit_text else long_name}
    if units is not None:
        out["units"] = units
    return out


_STATE_LONG = {"u": "runner longitudinal speed u", "Omega": "sleigh angular velocity Omega",
               "omega": "rotor angular velocity omega", "delta": "relative angle delta = theta - beta"}
_STATE = "state (u, Omega, omega, delta) in model units (speed, angular velocities per model time unit, angle in rad)"

#: name -> (long_name, kind) of the variables written without attributes of their own (and the
#: units of those written with a long_name only). A name means one thing in every dataset.
VOCABULARY: dict[str, tuple[str, str]] = {
    # time, state and coordinates shared by many scenes
    "time": ("time", "time"),
    "t": ("time from t = 0 of the portrait trajectories", "time"),
    "eps": ("eps = m_r / m = a / b, the rotor's mass ratio", "1"),
    "b": ("runner distance b", "length"),
    "K2": ("K^2 = 1 + I_c / (m b^2), the sleigh's inertia parameter", "1"),
    "i": ("index i of the Lyapunov exponent lambda_i (1: largest)", "1"),
    "component": ("state component", "text"),
    "state": ("name of the start state", "text"),
    "precision": ("floating-point arithmetic of the run", "text"),
    "finer": ("the other arithmetic of the comparison", "text"),
    "pair": ("pair of neighbouring arithmetics, coarse / fine", "text"),
    "arithmetic": ("floating-point arithmetic", "text"),
    "observable": ("name of the key observable (sleighsim.ops.registry.OBSERVABLES)", "text"),
    "replica": ("index of the replica (an independent start point along the settled orbit)", "1"),
    "run": ("index of the run", "1"),
    "realization": ("index of the realization (0: the configured start states)", "1"),
    "label": ("paper energy label E_p of the level", "1"),
    "level": ("index of the energy level", "1"),
    "state_index": ("index of the start state on its level", "1"),
    "scale_c": ("time-scaling factor c = sqrt(E_p / E_p of level 0)", "1"),
    "y0": (f"start {_STATE}", "1"),
    "replica_y0": (f"start {_STATE} of each replica", "1"),
    "row_settled_state": (f"the row's settled {_STATE} (double pre-run; its steady part starts here)", "1"),
    "reference_state": (f"reference end {_STATE} (heyoka in long double)", "1"),
    "u_start": ("u at t = 0 of each portrait trajectory", "speed"),
    "Omega_start": ("Omega at t = 0 of each portrait trajectory", "angular_velocity"),
    "u_grid": ("u of the vector-field grid", "speed"),
    "Omega_grid": ("Omega of the vector-field grid", "angular_velocity"),
    "path_time": ("time along the path", "time"),
    "eps_study": ("eps of the convergence study", "1"),
    # integration and accuracy
    "tol": ("integrator tolerance (relative; heyoka's Taylor tolerance unless the method says otherwise)", "1"),
    "rtol": ("relative tolerance of SciPy's method", "1"),
    "lyapunov_rtol": ("relative tolerance of SciPy's method in the paper's Lyapunov protocol", "1"),
    "rounding": ("machine epsilon of the arithmetic", "1"),
    "steps": ("integrator steps", "1"),
    "steps_per_time": ("integrator steps", "rate"),
    "steps_estimate": ("integrator steps to the end of the transient, extrapolated", "1"),
    "energy_max_rel_drift": ("max |E(t) / E(0) - 1| of the run", "1"),
    "run_energy_max_rel_drift": ("max |E(t) / E(0) - 1| of the run", "1"),
    "energy_rel_change_printed": ("E(t) / E(0) - 1 of the printed equations", "1"),
    "energy_rel_change_derived": ("E(t) / E(0) - 1 of the derived equations", "1"),
    "energy_rel_drift": ("E / E(settled) - 1 at the window's end", "1"),
    "omega_rel_error": ("|series - exact| / max |exact| of omega at the series' t_end (C11)", "1"),
    "protocol_exponent": ("Lyapunov exponent lambda_i of the paper's protocol integrated with SciPy's method", "rate"),
    "wall_time_s": ("wall-clock time", "s"),
    "run_wall_s": ("wall-clock time of the run", "s"),
    "wall_estimate_s": ("wall-clock time to the end of the transient, extrapolated (one core)", "s"),
    "transient_over": ("1 when the transient rule shows the transient over, else 0", "1"),
    "steady": ("1 when every replica's omega block means are steady, else 0", "1"),
    "flagged": ("1 when the row is flagged (attribute flag_rule), else 0", "1"),
    "reached": ("1 when the run reached its steady state, else 0", "1"),
    "mirrored": ("share of mirror images (mean omega < 0): 1 or 0 for one run, a fraction for a group", "1"),
    "tangent_based": ("1 when the indicator uses tangent vectors, else 0", "1"),
    "agrees": ("1 when the observable agrees between the two arithmetics, else 0", "1"),
    "in_fit": ("1 when the run is in the fit, else 0", "1"),
    # spikes, transients and steady states
    "first_spike": ("time of the first Omega spike", "time"),
    "second_spike": ("time of the second Omega spike", "time"),
    "sleigh_phase_end": ("end of the sleigh-like phase", "time"),
    "n_spikes": ("number of Omega spikes", "1"),
    "spike_interval": ("mean interval between Omega spikes", "time"),
    "spike_interval_mean": ("mean interval between Omega spikes", "time"),
    "spike_interval_std": ("standard deviation of the intervals between Omega spikes", "time"),
    "spike_interval_sd": ("standard deviation of the intervals between Omega spikes", "time"),
    "spike_interval_stderr": ("standard error of the mean interval between Omega spikes", "time"),
    "spike_interval_level0_units": ("mean interval between Omega spikes times c (level-0 time units)", "time"),
    "interval": ("mean interval between the Omega spikes of the record", "time"),
    "interval_std": ("standard deviation of the intervals between the Omega spikes of the record", "time"),
    "interval_mean": ("mean interval between the Omega spikes after the settled point", "time"),
    "omega_settling_time": ("time by which omega has settled (transient rule)", "time"),
    "settling_time": ("settling time of the transient (transient rule)", "time"),
    "t_end": ("end of the run", "time"),
    "t_pre": ("length of the pre-run", "time"),
    "t_run": ("length of the run", "time"),
    "t_settled": ("time by which the transient rule shows the transient over", "time"),
    "t_separation": ("time after the settled point", "time"),
    "t_separated": ("time after the settled point when the separation first exceeds 0.001 (NaN: never)", "time"),
    "separation": ("max |velocity difference| / max |velocity| of the finer run", "1"),
    "omega_mean": ("mean of the aligned omega", "angular_velocity"),
    "omega_sign": ("sign of the mean omega of the record", "1"),
    "mean_u": ("time mean of u over the second half of the state's run", "speed"),
    "mean_omega": ("time mean of omega over the second half of the state's run", "angular_velocity"),
    "settled": ("1 when the transient rule shows the transient over within max_rounds pre-runs, else 0", "1"),
    "group": ("steady-state group", "1"),
    "group_id": ("steady spike interval group of the long-horizon check", "1"),
    "long_representative_run": ("the run whose start state the long-horizon check repeats", "1"),
    "long_spike_time": ("times of the Omega spikes of the long-horizon check", "time"),
    "omega_block_drift": ("largest relative drift of omega's block means over the replicas", "1"),
    "rotation_number": ("rotation number of the P_2pi iterates", "1"),
    "curve_thickness": ("thickness of the curve of the P_2pi iterates (sleighsim.engine.poincare.curve_thickness)", "1"),
    # Lyapunov exponents and chaos indicators
    "lambda_1": ("largest Lyapunov exponent lambda_1", "rate"),
    "stderr": ("standard error of the Lyapunov exponent", "rate"),
    "exponent": ("Lyapunov exponent lambda_i", "rate"),
    "T": ("horizon T of the Lyapunov estimate (per replica)", "time"),
    "tau": ("renormalisation interval tau of the Lyapunov estimate", "time"),
    "status": ("status of the lambda_1 estimate: converged, regular, capped or elsewhere", "text"),
    "status_code": ("status of the lambda_1 estimate: 0 converged, 1 regular, 2 capped, 3 elsewhere", "1"),
    "b_check_max_diff": ("largest difference of lambda_1 at the b_check values from b = 1 after one round", "rate"),
    "b_check_bound": ("allowed difference 2 |ln b| / T of lambda_1 at the b_check values", "rate"),
    "target": ("target eps of the extrapolation", "1"),
    "transient_estimate": ("transient length (first Omega spike), extrapolated", "time"),
    "verdict": ("verdict", "text"),
    "reason": ("reason for the verdict", "text"),
    "state_class": ("class of the steady state", "text"),
    "indicator": ("name of the chaos indicator", "text"),
    "indicator_value": ("value of the chaos indicator (a rate: an exponent, a growth rate or a slope)", "rate"),
    "indicator_verdict": ("verdict of the chaos indicator", "text"),
    "indicator_reason": ("reason for the chaos indicator's verdict", "text"),
    "sum_exponents": ("sum of the four Lyapunov exponents", "rate"),
    "sum_exponents_stderr": ("standard error of the sum of the four Lyapunov exponents", "rate"),
    "R_image": ("whether the reversal R's image of the state stays on it or leaves it (a repeller)", "text"),
    "R_image_distance": ("distance of the R image's time means from R of the state's means, over their scale", "1"),
    "d0": ("initial separation d0 of the two-trajectory indicator (Euclidean distance of the states, model units)",
           "1"),
    "two_trajectory_rate": ("growth rate of the two trajectories' separation", "rate"),
    "two_trajectory_stderr": ("standard error of the two trajectories' growth rate", "rate"),
    "megno_sample": ("index of the MEGNO sample", "1"),
    "megno_verdict_double": ("the MEGNO verdict of the double run", "text"),
    "T_loschmidt": ("horizon T of the Loschmidt return (forward T, R, forward T)", "time"),
    "split": ("number of windows the frequency record is split into", "1"),
    "frequency_precision": ("arithmetic of the frequency indicator's run", "text"),
    "realization_verdict": ("verdict of each realization", "text"),
    "realization_reason": ("reason for each realization's verdict", "text"),
    "realization_class": ("class of each realization's steady state", "text"),
    "ln_gain": ("ln G of each complete spike cycle along the settled orbit (double)", "1"),
    "log10_gain_rounding": ("log10(G_max x unit roundoff of the arithmetic)", "1"),
    "follows_orbit": ("does the arithmetic follow the exact orbit (G x rounding below 1e-3)", "text"),
    "converged_precision": ("the coarsest arithmetic from which on the observables agree", "text"),
    "converged_precision_of": ("the coarsest arithmetic from which on the observable agrees", "text"),
    "value": ("value of the observable (its unit: sleighsim.analysis.observables)", "1"),
    "uncertainty": ("stated uncertainty (in the unit of the value)", "1"),
    # the perturbation hierarchy and K2 sweep
    "Omega2_amplitude": ("amplitude A of Omega2, the order-2 term of Omega (C09)", "angular_velocity"),
    "phi1_over_pi": ("phase phi_1 of Omega2 against delta0, over pi (C09)", "1"),
    "T2": ("period T2 of omega2, the order-2 term of omega (C10)", "time"),
    "B": ("amplitude B of omega2, the order-2 term of omega (C10)", "angular_velocity"),
    "omega2_growth": ("growth rate of omega2, the order-2 term of omega (C10)", "angular_acceleration"),
    "band_low": ("lower edge of the Omega band of the PSD (C23)", "frequency"),
    "band_high": ("upper edge of the Omega band of the PSD (C23)", "frequency"),
    "equation": ("equation of the hierarchy", "text"),
    "term": ("term (monomial) of the equation", "text"),
    "derived": ("coefficient of the term, derived", "text"),
    "derived_with_kappa": ("coefficient of the term, derived, with K^2 - 1 = kappa eps", "text"),
    "printed": ("coefficient of the term, as printed", "text"),
    "order4_equation": ("equation of the order-4 forcing term", "text"),
    "order4_term": ("order-4 forcing term", "text"),
    "order4_kind": ("kind of the order-4 forcing term on the late window: decays, bounded or secular", "text"),
    "order4_mean_over_rms": ("mean over RMS of the order-4 forcing term on the late window", "1"),
    "order4_rms_growth": ("RMS of the order-4 forcing term, second half of the late window over the first", "1"),
    "order4_late_rms": ("RMS of the order-4 forcing term on the late window (model units of its equation)", "1"),
    # basins (sleighsim.scenes.basins)
    "sample": ("index of the sampled start state", "1"),
    "reference": ("name of the reference state", "text"),
    "group_of": ("steady-state group of the run", "text"),
    "count": ("runs in the group", "1"),
    "fraction": ("fraction of the runs in the group", "1"),
    "ci_low": ("lower end of the fraction's Wilson interval", "1"),
    "ci_high": ("upper end of the fraction's Wilson interval", "1"),
    "group_interval": ("mean steady spike interval of the group", "time"),
    # drift windows
    "window": ("index of the window", "1"),
    "t_start": ("start of the window", "time"),
    "t_mid": ("middle of the window", "time"),
    # hard cases
    "case": ("hard case", "text"),
    "outcome": ("outcome: reliable, degraded or refused", "text"),
    "error": ("error of the case (drift, disagreement or scaling error, as its detail says)", "1"),
    "drift": ("max |E(t) / E(0) - 1| of the run", "1"),
    "disagreement": ("max |heyoka - DOP853| of the end state over the velocity scale", "1"),
    "min_step": ("smallest integrator step", "time"),
    "max_step": ("largest integrator step", "time"),
    "wall_s": ("wall-clock time of the run", "s"),
    "detail": ("detail of the outcome", "text"),
    # speed benchmark
    "backend": ("integration backend", "text"),
    "method": ("integration method", "text"),
    "error_short": ("max |state difference| from the reference at t_short", "1"),
    "wall_short": ("median wall-clock time of the run to t_short", "s"),
    "drift_long": ("max |E(t) / E(0) - 1| of the run to t_long", "1"),
    "wall_long": ("wall-clock time of the run to t_long", "s"),
    "steps_long": ("integrator steps of the run to t_long (-1: not run)", "1"),
    "compile_s": ("compile time", "s"),
    "tol_observable": ("heyoka tolerance of the observables' runs", "1"),
    "lambda_1_wall": ("wall-clock time of the lambda_1 run", "s"),
    "error_target": ("error target", "1"),
    "peer": ("peer engine", "text"),
    "peer_run": ("index of the peer run", "1"),
    "peer_engine": ("peer engine of the run", "text"),
    "peer_rtol": ("relative tolerance of the peer run", "1"),
    "peer_error": ("max |state difference| of the peer run from the reference", "1"),
    "peer_wall": ("median wall-clock time of the peer run after warm-up", "s"),
    "peer_compile_s": ("compile time of the peer run", "s"),
    "peer_note": ("note on the peer run", "text"),
    "peer_ratio": ("fastest wall-clock time of the peer reaching the error target over heyoka's", "1"),
    "peer_engine_compile_s": ("compile time of the peer engine", "s"),
    "lyap_peer": ("index of the Lyapunov peer run", "1"),
    "lyap_peer_system": ("system of the Lyapunov peer run (the sleigh, or Lorenz in its own time unit)", "text"),
    "lyap_peer_engine": ("engine of the Lyapunov peer run", "text"),
    "lyap_peer_lambda_1": ("largest Lyapunov exponent lambda_1 of the peer run's system", "rate"),
    "lyap_peer_wall": ("wall-clock time of the Lyapunov peer run", "s"),
    "lyap_peer_compile_s": ("compile time of the Lyapunov peer run", "s"),
    "lyap_peer_note": ("note on the Lyapunov peer run", "text"),
    "lyap_scipy": ("index of the SciPy Lyapunov run", "1"),
    "lyap_scipy_method": ("SciPy method of the Lyapunov run", "text"),
    "lyap_scipy_rtol": ("relative tolerance of the SciPy Lyapunov run", "1"),
    "lyap_scipy_lambda_1": ("largest Lyapunov exponent lambda_1 with SciPy's method", "rate"),
    "lyap_scipy_wall": ("wall-clock time of the SciPy Lyapunov run", "s"),
    # the claims ledger (sleighsim.claims.ledger) and the verdict stability table
    "id": ("claim id (paper/CLAIMS.md)", "text"),
    "statement": ("the paper's statement", "text"),
    "paper_value": ("the paper's value", "text"),
    "measured": ("what the datasets measure", "text"),
    "units": ("unit of the measured value, in the ledger's words", "text"),
    "evidence": ("the datasets and figures the verdict rests on", "text"),
    "rule": ("the rule the verdict applies", "text"),
    "cause": ("the likely cause of a difference", "text"),
    "difference": ("relative difference of the measured value from the paper's", "1"),
    "double_value": ("the value in double where the verdict rests on a finer arithmetic", "text"),
    "realizations": ("how the realizations agree", "text"),
    "base": ("verdict of the unperturbed run", "text"),
    "perturbed": ("verdict with every start state perturbed", "text"),
    "changed": ("1 when a variant's verdict differs from the base run's, else 0", "1"),
}

# the perturbation series' terms, v = v0 + eps v1 + eps^2 v2 + ... (sleighsim.model.perturbation)
VOCABULARY.update({f"{v}{k}": (f"order-{k} term of {_STATE_LONG[v]}", STATE_KINDS[v])
                   for v in _STATE_LONG for k in range(5)})
# a basins reference state's run has the run's variables
VOCABULARY.update({f"reference_{v}": (f"{VOCABULARY[v][0]}, reference state", VOCABULARY[v][1])
                   for v in ("settled", "t_settled", "n_spikes", "interval", "interval_std", "omega_sign",
                             "energy_max_rel_drift", "wall_time_s")})

#: Names made from settings (regular expression -> (long_name, kind)).
PATTERNS: dict[str, tuple[str, str]] = {
    r"tol_[0-9.e+-]+": ("verdict of the run at that looser tolerance", "text"),
}


def _entry(name: str) -> tuple[str, str] | None:
    """The vocabulary's (long_name, kind) of ``name``, or None."""
    if name in VOCABULARY:
        return VOCABULARY[name]
    return next((entry for pattern, entry in PATTERNS.items() if re.fullmatch(pattern, name)), None)


def is_text(var: xr.Variable) -> bool:
    """Whether a variable holds text (sleighsim's object arrays hold text)."""
    return var.dtype.kind in "OSU"


def completed(name: str, var: xr.Variable) -> dict:
    """The attributes of variable ``name``: its own, a legacy unit string (:data:`LEGACY_UNITS`) made
    "1" with its model unit in the long_name, and what it lacks of long_name and units from the
    vocabulary (its model unit appended to its own long_name where the vocabulary supplies the units).
    What neither has stays missing (:func:`missing`)."""
    out = dict(var.attrs)
    legacy = LEGACY_UNITS.get(out.get("units"))
    if legacy is not None:
        del out["units"]
        if "long_name" in out:
            out.update(attrs(out["long_name"], legacy))
    entry = _entry(name)
    if entry is None:
        return out
    if "units" not in out and not is_text(var):
        out.update(attrs(out.get("long_name", entry[0]), entry[1]))
    out.setdefault("long_name", attrs(*entry)["long_name"])
    return out


def complete(ds: xr.Dataset) -> xr.Dataset:
    """A copy of ``ds`` whose variables' attributes are :func:`completed` (the data are shared)."""
    ds = ds.copy()
    for name, var in ds.variables.items():
        var.attrs = completed(name, var)
    return ds


def missing(ds: xr.Dataset) -> list[str]:
    """What CF attributes the variables of ``ds`` lack: a long_name on every variable, units on every
    variable that does not hold text; one line each (empty when complete)."""
    out = []
    for name, var in ds.variables.items():
        needed = ("long_name",) if is_text(var) else ("long_name", "units")
        out += [f"{name} has no {key}" for key in needed if key not in var.attrs]
    return out


def dataset_name(path, precision: str = "double") -> tuple[str, str]:
    """(name, variant) of a file of a results tree: the scene of ``data/<scene>.nc`` ("" variant),
    ``data/precision/<tag>/<scene>.nc``, ``data/ladder/<scene>.nc``, ``data/realization/<k>/<scene>.nc``,
    ``chunks/<scene>/<k>.nc`` or ``chunks/precision/<tag>/<scene>/<k>.nc``; any other file by its
    parent folder and stem ("stability/verdicts") when :data:`sleighsim.ops.registry.TITLES` knows that, else
    by its stem ("claims"). ``precision``: the config name of the arithmetic the dataset was computed
    in (the writer's knowledge; never read back from the path); ValueError when a file under
    precision/ is said to be in double."""
    parts = Path(path).with_suffix("").parts
    anchors = [i for i, p in enumerate(parts[:-1]) if p in ("data", "chunks")]
    rest = list(parts[anchors[-1]:]) if anchors else []
    match rest:
        case ["data", scene]:
            return scene, ""
        case ["data", "precision", _, scene]:
            return scene, _in_precision(path, precision)
        case ["data", "ladder", scene]:
            return scene, "its precision ladder: the key observables in every arithmetic and where they converge"
        case ["data", "realization", k, scene]:
            return scene, f"realization {k}: the start states perturbed"
        case ["chunks", scene, k]:
            return scene, f"chunk {k}"
        case ["chunks", "precision", _, scene, k]:
            return scene, f"chunk {k} {_in_precision(path, precision)}"
    nested = "/".join(parts[-2:])
    return (nested, "") if nested in TITLES else (parts[-1], "")


def _in_precision(path, precision: str) -> str:
    if precision == "double":
        raise ValueError(f"{path}: a dataset under precision/ needs the precision it was computed in")
    return f"in {precision}"


def title(path, precision: str = "double") -> str:
    """The CF title of the dataset written to ``path`` and computed in ``precision`` (its config
    name): what it is (:data:`sleighsim.ops.registry.TITLES`), its name and variant; a file the
    registry does not know is named by its file name."""
    name, variant = dataset_name(path, precision)
    what = TITLES.get(name, "sleighsim dataset")
    return f"Chaplygin sleigh with a passive internal rotor: {what} [{name}{', ' + variant if variant else ''}]"


def global_attrs(path, provenance: dict, history: str = "", precision: str = "double") -> dict:
    """The CF global attributes of a dataset written to ``path`` (computed in ``precision``, see
    :func:`title`) with ``provenance``
    (:func:`sleighsim.io.netcdf.provenance_attrs`): Conventions, title, source, references, the model's
    units (time_unit, nondimensionalisation) and ``history`` with this write's line appended (CF:
    one line per program that wrote the data, an ISO 8601 time first)."""
    version = provenance["version_sleighsim"]
    line = (f"{provenance['created_utc']} sleighsim {version} (git commit {provenance['git_commit']}): "
            f"sleighsim.io.netcdf.write_dataset wrote {Path(path).name}")
    return {
        "Conventions": CONVENTIONS,
        "title": title(path, precision),
        "history": f"{history}\n{line}" if history else line,
        "source": (f"sleighsim {version} (git commit {provenance['git_commit']}); integrator library heyoka "
                   f"{provenance['version_heyoka']} (SciPy where the attribute backend says so); Python "
                   f"{provenance['python_version']}"),
        "references": REFERENCES,
        "time_unit": TIME_UNIT,
        "nondimensionalisation": NONDIMENSIONALISATION,
    }
