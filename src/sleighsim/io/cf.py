"""CF conventions (CF-1.11) on every dataset sleighsim writes (applied by :func:`sleighsim.io.netcdf.write_dataset`).

The model is nondimensional (global attribute ``nondimensionalisation``): a quantity's ``units`` is
"1" (UDUNITS' dimensionless unit), angles are "rad", wall-clock times "s", and the quantity's model
unit (time, length, speed, angular velocity, rate, frequency) is stated in its ``long_name``
(:func:`attrs`). Text variables carry a ``long_name`` and no ``units`` (CF: units belong to
quantities). :data:`sleighsim.io.vocabulary.VOCABULARY` names the variables several scenes or outputs
write without attributes of their own, a scene kind's own vocabulary (``SceneKind.vocabulary``) those
only it writes; :func:`complete` fills in what a variable lacks and
:func:`missing` lists what no one named, which the tests require to be empty on every dataset of the smoke run.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

from sleighsim.io import layout
from sleighsim.io.vocabulary import PATTERNS, VOCABULARY
from sleighsim.precision import Precision

CONVENTIONS = "CF-1.11"
REFERENCES = ("Fedonyuk, V. and Tallapragada, P., Chaotic dynamics of the Chaplygin sleigh with a passive internal "
              "rotor (the LaTeX source, which states no journal or DOI, is "
              "paper/fedonyuk-tallapragada-sleigh-rotor.tex of the sleighsim repository; CITATION.cff)")
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


def flags(dims, words, meanings, long_name: str) -> tuple:
    """``words`` (texts, shaped as ``dims``) as a CF flag variable (dims, codes, attrs): each word's index in
    ``meanings`` (int8) with flag_values and flag_meanings (spaces as _); ValueError for a word not among them."""
    words = np.asarray(words, dtype=object)
    codes = np.array([list(meanings).index(w) for w in words.ravel()], dtype=np.int8).reshape(words.shape)
    return (dims, codes, {**attrs(long_name), "flag_values": np.arange(len(meanings), dtype=np.int8),
                          "flag_meanings": " ".join(str(m).replace(" ", "_") for m in meanings)})


def attrs(long_name: str, kind: str = "1") -> dict:
    """{"long_name", "units"} of a quantity of ``kind`` (:data:`KINDS`): the long_name ends with the
    model unit; a text variable ("text") gets no units."""
    units, unit_text = KINDS[kind]
    out = {"long_name": f"{long_name}, {unit_text}" if unit_text else long_name}
    if units is not None:
        out["units"] = units
    return out


def _entry(name: str, own: dict) -> tuple[str, str] | None:
    """The (long_name, kind) of ``name``: the writer's ``own`` vocabulary's, else the shared one's, or None."""
    if name in own:
        return own[name]
    if name in VOCABULARY:
        return VOCABULARY[name]
    return next((entry for pattern, entry in PATTERNS.items() if re.fullmatch(pattern, name)), None)


def is_text(var: xr.Variable) -> bool:
    """Whether a variable holds text (sleighsim's object arrays hold text)."""
    return var.dtype.kind in "OSU"


def completed(name: str, var: xr.Variable, own: dict | None = None) -> dict:
    """The attributes of variable ``name``: its own, a legacy unit string (:data:`LEGACY_UNITS`) made
    "1" with its model unit in the long_name, and what it lacks of long_name and units from the
    vocabulary (its model unit appended to its own long_name where the vocabulary supplies the units).
    ``own``: the writer's own vocabulary (a scene kind's), before the shared one. What neither has stays
    missing (:func:`missing`)."""
    out = dict(var.attrs)
    legacy = LEGACY_UNITS.get(out.get("units"))
    if legacy is not None:
        del out["units"]
        if "long_name" in out:
            out.update(attrs(out["long_name"], legacy))
    entry = _entry(name, own or {})
    if entry is None:
        return out
    if "units" not in out and not is_text(var):
        out.update(attrs(out.get("long_name", entry[0]), entry[1]))
    out.setdefault("long_name", attrs(*entry)["long_name"])
    return out


def complete(ds: xr.Dataset, own: dict | None = None) -> xr.Dataset:
    """A copy of ``ds`` whose variables' attributes are :func:`completed` with the writer's ``own``
    vocabulary (the data are shared)."""
    ds = ds.copy()
    for name, var in ds.variables.items():
        var.attrs = completed(name, var, own)
    return ds


def missing(ds: xr.Dataset) -> list[str]:
    """What CF attributes the variables of ``ds`` lack: a long_name on every variable, units on every
    variable that does not hold text; one line each (empty when complete)."""
    out = []
    for name, var in ds.variables.items():
        needed = ("long_name",) if is_text(var) else ("long_name", "units")
        out += [f"{name} has no {key}" for key in needed if key not in var.attrs]
    return out


def dataset_name(path, precision: str = Precision.DOUBLE) -> tuple[str, str]:
    """(name, variant) of a file of a results tree: the scene of ``data/<scene>.nc`` ("" variant),
    ``data/precision/<tag>/<scene>.nc``, ``data/ladder/<scene>.nc``, ``data/realization/<k>/<scene>.nc``,
    ``chunks/<scene>/<k>.nc`` or ``chunks/precision/<tag>/<scene>/<k>.nc``; any other file by its
    parent folder and stem when the folder is one of the results tree's (``layout.FOLDERS``:
    "stability/verdicts"), else by its stem ("claims"). ``precision``: the arithmetic the dataset was
    computed in (the writer's knowledge; never read back from the path); ValueError when a file under
    precision/ is said to be in double (:mod:`sleighsim.io.layout` reads the path)."""
    at = layout.place(path)
    match at.what:
        case "scene":
            return at.scene, ""
        case "finer":
            return at.scene, _in_precision(path, precision)
        case "ladder":
            return at.scene, "its precision ladder: the key observables in every arithmetic and where they converge"
        case "realization":
            return at.scene, f"realization {at.k}: the start states perturbed"
        case "chunk":
            return at.scene, f"chunk {at.k}"
        case "finer chunk":
            return at.scene, f"chunk {at.k} {_in_precision(path, precision)}"
    parts = Path(path).with_suffix("").parts
    return ("/".join(parts[-2:]), "") if len(parts) > 1 and parts[-2] in layout.FOLDERS else (at.scene, "")


def _in_precision(path, precision) -> str:
    p = Precision.parse(precision)
    if p is Precision.DOUBLE:
        raise ValueError(f"{path}: a dataset under precision/ needs the precision it was computed in")
    return f"in {p}"


#: What a dataset is when its writer does not say.
UNTOLD = "sleighsim dataset"


def title(path, precision=Precision.DOUBLE, what: str = UNTOLD) -> str:
    """The CF title of the dataset written to ``path`` and computed in ``precision``: ``what`` it is (its
    writer's words: a scene kind's or block's ``title``), its name and variant (:func:`dataset_name`)."""
    name, variant = dataset_name(path, precision)
    return f"Chaplygin sleigh with a passive internal rotor: {what} [{name}{', ' + variant if variant else ''}]"


def global_attrs(path, provenance: dict, history: str = "", precision=Precision.DOUBLE, what: str = UNTOLD) -> dict:
    """The CF global attributes of a dataset written to ``path`` (computed in ``precision``, ``what`` it is:
    see :func:`title`) with ``provenance``
    (:func:`sleighsim.io.netcdf.provenance_attrs`): Conventions, title, source, references, the model's
    units (time_unit, nondimensionalisation) and ``history`` with this write's line appended (CF:
    one line per program that wrote the data, an ISO 8601 time first)."""
    version = provenance["version_sleighsim"]
    line = (f"{provenance['created_utc']} sleighsim {version} (git commit {provenance['git_commit']}): "
            f"sleighsim.io.netcdf.write_dataset wrote {Path(path).name}")
    return {
        "Conventions": CONVENTIONS,
        "title": title(path, precision, what),
        "history": f"{history}\n{line}" if history else line,
        "source": (f"sleighsim {version} (git commit {provenance['git_commit']}); integrator library heyoka "
                   f"{provenance['version_heyoka']} (SciPy where the attribute backend says so); Python "
                   f"{provenance['python_version']}"),
        "references": REFERENCES,
        "time_unit": TIME_UNIT,
        "nondimensionalisation": NONDIMENSIONALISATION,
    }
