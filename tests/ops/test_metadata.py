"""The project's metadata agrees with itself: the conda environment pins pyproject.toml's lower
bounds, CITATION.cff cites this version and the paper under the title its LaTeX source gives."""

import re
import tomllib

import yaml

#: PyPI names whose conda-forge package is named otherwise.
CONDA_NAMES = {"heyoka": "heyoka.py", "netcdf4": "netcdf4", "matplotlib": "matplotlib-base",
               "snakemake": "snakemake-minimal"}


def _pyproject(root):
    return tomllib.loads((root / "pyproject.toml").read_text())["project"]


def test_the_conda_environment_pins_every_dependency_at_its_lower_bound(root):
    env = yaml.safe_load((root / "workflow" / "envs" / "sleighsim.yaml").read_text())
    pins = dict(d.split(" =") for d in env["dependencies"] if isinstance(d, str) and " =" in d)
    for dep in _pyproject(root)["dependencies"]:
        name, low = re.fullmatch(r"([A-Za-z0-9_.-]+)>=([0-9.]+)", dep).groups()
        conda = CONDA_NAMES.get(name.lower(), name.lower())
        assert pins.get(conda) == low, (dep, conda, pins.get(conda))
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
