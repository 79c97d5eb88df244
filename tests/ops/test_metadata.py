"""The project's metadata agrees with itself: the conda environment pins pyproject.toml's lower
bounds, CITATION.cff cites this version and the paper under the title its LaTeX source gives."""

import re
import tomllib

import yaml
from packaging.requirements import Requirement

#: PyPI names whose conda-forge package is named otherwise.
CONDA_NAMES = {"heyoka": "heyoka.py", "netcdf4": "netcdf4", "matplotlib": "matplotlib-base",
               "snakemake": "snakemake-minimal"}
#: The conda-forge packages of a dependency's extra.
CONDA_EXTRAS = {("snakemake", "reports"): {"pygments"}}


def _pyproject(root):
    return tomllib.loads((root / "pyproject.toml").read_text())["project"]


def test_the_conda_environment_pins_every_dependency_at_its_lower_bound(root):
    env = yaml.safe_load((root / "workflow" / "envs" / "sleighsim.yaml").read_text())
    pins = dict(d.split(" =") for d in env["dependencies"] if isinstance(d, str) and " =" in d)
    names = {d.split()[0] for d in env["dependencies"] if isinstance(d, str)}
    for dep in map(Requirement, _pyproject(root)["dependencies"]):
        (spec,) = dep.specifier
        conda = CONDA_NAMES.get(dep.name.lower(), dep.name.lower())
        assert spec.operator == ">=" and pins.get(conda) == spec.version, (dep, conda, pins.get(conda))
        for extra in dep.extras:  # conda-forge's snakemake-minimal has no extras: their packages are listed
            assert CONDA_EXTRAS[dep.name, extra] <= names, (dep, extra)
    assert pins["python"] == _pyproject(root)["requires-python"].removeprefix(">=")
    assert {"pip": ["../.."]} in env["dependencies"]  # the package from the workflow's own path, not editable


def test_the_citation_names_this_version_and_the_paper(root):
    cff = yaml.safe_load((root / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0" and cff["version"] == _pyproject(root)["version"]
    assert cff["license"] == _pyproject(root)["license"] and (root / "LICENSE").read_text().startswith("MIT License")
    tex = (root / "paper" / "fedonyuk-tallapragada-sleigh-rotor.tex").read_text()
    title = re.search(r"\\title\{(.*?)\\thanks", tex, re.S).group(1)
    (paper,) = cff["references"]
    assert paper["title"].lower() == " ".join(title.split()).lower()
    assert [a["family-names"] for a in paper["authors"]] == ["Fedonyuk", "Tallapragada"]
