"""CF conventions on every dataset (sleighsim.io.cf, applied by sleighsim.io.netcdf.write_dataset): the CF
attributes of a small dataset, a title for every scene, and the IOOS compliance checker's CF-1.11
check on every dataset of the smoke run, with long_name and units on every variable."""

from __future__ import annotations

import logging
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from compliance_checker.cf.cf_1_11 import CF1_11Check
from compliance_checker.runner import CheckSuite
from conftest import SMOKE_RESULTS

from sleighsim.io import cf, netcdf, vocabulary
from sleighsim.scenes import basins, catalog, causes, grid

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = [ROOT / "config" / name for name in ("config.yaml", "smoke.yaml", "cluster.yaml")]
CHECKER = "cf:1.11"
HIGH, MEDIUM = 3, 2

#: The checker's findings exempted, by section, each for a stated reason; any other high or medium
#: finding fails the test.
#: - 5.1: a dimension named "time" must have standard_name "time", and a variable with that standard
#:   name must have units "<unit> since <reference date>" (4.4, also high). The model's time is
#:   nondimensional (global attribute time_unit): no physical unit, no calendar, no reference date, so
#:   standard_name "time" would trade this finding for a false 4.4 one; renaming the dimension would
#:   move every dataset's results (the figures, the judges and resultdiff read ``ds.time``).
#: - 2.3: CF recommends ("should") that no two names differ only in case. The paper names the sleigh's
#:   angular velocity Omega and the rotor's omega; the datasets keep its notation (u, Omega, omega and
#:   the names made from them), so the collisions Omega / omega, and no other, are exempt.
EXEMPT = {
    "§5.1 Independent Latitude, Longitude, Vertical, and Time Axes":
        re.compile(r"Coordinate variable 'time' should have standard_name='time', found: 'None'"),
    "§2.3 Naming Conventions": re.compile(r"Variables are not case sensitive\. Duplicate variables named: (\w+)"),
}
#: The checker's check that raises on a string-valued coordinate variable (np.diff of text, a bug of
#: the checker); :func:`numeric_coordinates_monotonic` checks the numeric ones instead (CF 5: strictly
#: monotonic).
CRASHES_ON_TEXT = "check_coordinate_variables_strict_monotonicity"


def check(path) -> tuple[list, dict]:
    """The checker's CF-1.11 results of the file at ``path`` and its errors {check: exception}."""
    suite = CheckSuite()
    suite.checkers = {CHECKER: CF1_11Check}  # the one checker (loading them all warns of deprecated ones)
    nc = suite.load_dataset(str(path))
    try:
        results, errors = suite.run_all(nc, [CHECKER])[CHECKER]
    finally:
        nc.close()
    return results, errors


def _exempt(section: str, message: str, names) -> bool:
    """Whether a finding is one of :data:`EXEMPT` (2.3: only a name that differs from another of the
    dataset by Omega / omega)."""
    m = EXEMPT[section].fullmatch(message) if section in EXEMPT else None
    if m is None:
        return False
    if section.startswith("§2.3"):
        same = {n for n in names if n.lower() == m.group(1).lower()}
        return len(same) > 1 and len({n.replace("Omega", "omega") for n in same}) == 1
    return True


def failures(path) -> list[str]:
    """The high and medium findings of the checker on ``path`` that are not exempt, and its errors
    other than the known crash on text coordinates."""
    results, errors = check(path)
    names = list(netcdf.read_dataset(path).variables)
    out = [f"{r.name}: {msg}" for r in results if r.weight >= MEDIUM and r.value[0] < r.value[1]
           for msg in r.msgs if not _exempt(r.name, msg, names)]
    out += [f"{name} raised {exc!r}" for name, (exc, _) in errors.items()
            if not (name == CRASHES_ON_TEXT and isinstance(exc, TypeError))]
    return out


def numeric_coordinates_monotonic(ds: xr.Dataset) -> list[str]:
    """The numeric coordinate variables of ``ds`` that are not strictly monotonic (CF 5)."""
    out = []
    for name in ds.dims:
        if name in ds.variables and ds[name].dims == (name,) and ds[name].dtype.kind in "fiu":
            d = np.diff(ds[name].values)
            if not (np.all(d > 0) or np.all(d < 0)):
                out.append(name)
    return out


def _tiny() -> xr.Dataset:
    return xr.Dataset(
        {"lambda_1": ("eps", [0.1, 0.2]),  # named by the vocabulary
         "T": ("eps", [1e3, 2e3], {"long_name": "horizon", "units": "time"}),  # a legacy unit string
         "verdict": ("eps", np.array(["chaotic", "regular"], dtype=object)),  # text
         "gain": ("eps", [1.0, 2.0], cf.attrs("my gain per unit time", "rate"))},  # its own attributes
        coords={"eps": [0.01, 0.1]}, attrs={"history": "2026-01-01T00:00:00+00:00 an earlier program", "tol": 1e-15})


def test_write_dataset_adds_the_cf_attributes(tmp_path):
    """Conventions, a title from what the writer says the dataset is, history appended (ISO time, version,
    commit), source, references, the model's units; long_name and units from the vocabulary, legacy units made "1" with
    the model unit in the long_name, a variable's own attributes kept, none on text; provenance kept."""
    path = netcdf.write_dataset(_tiny(), tmp_path / "results" / "data" / "fig3.nc", what="one run")
    ds = netcdf.read_dataset(path)
    a = ds.attrs
    assert a["Conventions"] == "CF-1.11" and a["title"].endswith(": one run [fig3]")
    earlier, line = a["history"].split("\n")
    assert earlier.startswith("2026-01-01T00:00:00")
    assert re.match(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\+00:00 sleighsim ", line)
    assert a["version_sleighsim"] in line and a["git_commit"] in line and a["created_utc"] in line
    assert a["version_sleighsim"] in a["source"] and f"heyoka {a['version_heyoka']}" in a["source"]
    assert "Fedonyuk" in a["references"] and "Chaplygin sleigh with a passive internal rotor" in a["references"]
    assert "time unit" in a["time_unit"] and "time_unit" in a["nondimensionalisation"]
    for key in ("git_commit", "version_heyoka", "python_version", "created_utc", "tol"):
        assert key in a, key
    assert ds.lambda_1.attrs == cf.attrs(*vocabulary.VOCABULARY["lambda_1"]) and ds.lambda_1.attrs["units"] == "1"
    assert ds.T.attrs == {"long_name": "horizon, in model time units", "units": "1"}
    assert ds.gain.attrs == cf.attrs("my gain per unit time", "rate")
    assert ds.verdict.attrs == {"long_name": "verdict"} and ds.eps.attrs["units"] == "1"
    assert "_FillValue" not in ds.eps.encoding and cf.missing(ds) == []
    assert "units" not in _tiny().lambda_1.attrs  # writing leaves the dataset in memory as it was
    assert failures(path) == []


def test_a_variable_nobody_named_is_reported_not_defaulted(tmp_path, caplog):
    ds = _tiny().assign(zz_unnamed=("eps", [0.0, 1.0]), zz_text=("eps", np.array(["a", "b"], dtype=object)))
    with caplog.at_level(logging.WARNING, logger="sleighsim"):
        out = netcdf.read_dataset(netcdf.write_dataset(ds, tmp_path / "v.nc"))
    assert out.zz_unnamed.attrs == {} and out.zz_text.attrs == {}
    assert cf.missing(out) == ["zz_unnamed has no long_name", "zz_unnamed has no units", "zz_text has no long_name"]
    assert "zz_unnamed has no long_name" in caplog.text
    assert out.attrs["title"].endswith("sleighsim dataset [v]")  # a writer that does not say what it wrote


def test_every_scene_of_every_config_has_a_title():
    """Each dataset of the paper config (on request too), in each of its variants, gets its block's title
    or its kind's (every kind declares one); the ledger and the stability table say their own."""
    from sleighsim.claims import ledger
    from sleighsim.ops import stability

    config = yaml.safe_load(CONFIGS[0].read_text())
    assert all(k.title for k in catalog.KINDS.values())
    for scene in catalog.datasets(config, on_request=True):
        what = catalog.writing(catalog.scene_config(config, scene))["what"]
        assert what == config["scenes"][scene].get("title", catalog.KINDS[config["scenes"][scene]["kind"]].title)
        for rel in (f"data/{scene}.nc", f"data/precision/long_double/{scene}.nc", f"data/ladder/{scene}.nc",
                    f"data/realization/2/{scene}.nc", f"chunks/{scene}/3.nc", f"chunks/precision/quad/{scene}/0.nc"):
            title = cf.title(Path("/any/results") / rel, "quad" if "precision/" in rel else "double", what)
            assert what in title and f"[{scene}" in title, rel
    assert cf.dataset_name("/r/results/data/precision/long_double/fig3.nc", "long double") == ("fig3", "in long double")
    with pytest.raises(ValueError, match="needs the precision"):
        cf.dataset_name("/r/results/data/precision/long_double/fig3.nc")
    assert cf.dataset_name("/r/results/stability/verdicts.nc") == ("stability/verdicts", "")
    assert cf.title("/r/results/claims.nc", what=ledger.TITLE).endswith(f"{ledger.TITLE} [claims]")
    assert stability.TITLE in cf.title("/r/results/stability/verdicts.nc", what=stability.TITLE)


def test_a_name_means_one_thing_in_every_dataset():
    """A kind's own vocabulary names what no other kind and no shared entry names: one meaning per name."""
    owners = {}
    for k in catalog.KINDS.values():
        for name in k.vocabulary:
            assert name not in vocabulary.VOCABULARY, (k.name, name)
            owners.setdefault(name, []).append(k.name)
    assert {n: o for n, o in owners.items() if len(o) > 1} == {}


def test_the_vocabulary_names_what_the_scenes_declare():
    """The variables the chunked scenes and the K2 sweep declare have vocabulary entries; every entry's
    kind is known and its units are UDUNITS strings (cf_units); no legacy unit string is a unit."""
    import cf_units

    declared = [*grid.ROW_VARIABLES, *basins.RUN_VARIABLES, *(f"reference_{v}" for v in basins.RUN_VARIABLES),
                *causes.K2_OBSERVABLES]
    known = vocabulary.VOCABULARY | basins.VOCABULARY
    assert [n for n in declared if n not in known] == []
    for own in [vocabulary.VOCABULARY, *(k.vocabulary for k in catalog.KINDS.values())]:
        assert {kind for _, kind in own.values()} <= set(cf.KINDS)
    for units, _ in cf.KINDS.values():
        if units is not None:
            cf_units.Unit(units)
    assert not set(cf.LEGACY_UNITS) & {u for u, _ in cf.KINDS.values()}


def _smoke_datasets(smoke_run) -> list[Path]:
    results = smoke_run / SMOKE_RESULTS
    return sorted(results.glob("data/**/*.nc")) + sorted(results.glob("chunks/**/*.nc")) + [results / "claims.nc"]


@pytest.mark.workflow
def test_every_smoke_dataset_passes_the_cf_checker(smoke_run):
    """No high or medium finding of the checker beyond :data:`EXEMPT`, on every dataset the smoke run
    writes (data, chunks, ledger)."""
    paths = _smoke_datasets(smoke_run)
    assert len(paths) > 40
    found = {str(p.relative_to(smoke_run)): failures(p) for p in paths}
    assert {k: v for k, v in found.items() if v} == {}


@pytest.mark.workflow
def test_every_smoke_variable_has_a_long_name_and_units(smoke_run):
    """Every data and coordinate variable of every smoke dataset: a long_name, units unless it holds
    text (CF: units belong to quantities), no legacy unit string; numeric coordinates strictly
    monotonic; the CF global attributes present."""
    for path in _smoke_datasets(smoke_run):
        ds = netcdf.read_dataset(path)
        assert cf.missing(ds) == [], path
        assert not [n for n, v in ds.variables.items() if v.attrs.get("units") in cf.LEGACY_UNITS], path
        assert numeric_coordinates_monotonic(ds) == [], path
        for key in ("Conventions", "title", "history", "source", "references", "time_unit"):
            assert ds.attrs[key], (path, key)


def test_texts_become_a_cf_flag_variable_of_their_meanings():
    from sleighsim.io import cf as cf_

    dims, codes, attrs = cf_.flags(("r", "s"), [["regular", "not judged"], ["fragile", "chaotic"]],
                                   ("chaotic", "regular", "fragile", "not judged"), "a verdict")
    assert dims == ("r", "s") and codes.dtype == np.int8 and codes.tolist() == [[1, 3], [2, 0]]
    assert attrs["flag_values"].tolist() == [0, 1, 2, 3]
    assert attrs["flag_meanings"] == "chaotic regular fragile not_judged"
    assert attrs["long_name"] == "a verdict"
    with pytest.raises(ValueError):
        cf_.flags("s", ["maybe"], ("chaotic", "regular"), "a verdict")
