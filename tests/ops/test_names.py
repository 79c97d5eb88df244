"""Scene names and the paths the workflow writes (sleighsim.ops.names), with Hypothesis names."""

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_config import ROOT, SMOKE, refused

from sleighsim.ops.names import RESERVED, SCENE_NAME, check_scene_name, check_under, under
from sleighsim.scenes.checks import ConfigError

# The cases of issue 40: each refused at plan time, naming the key.
BAD_NAMES = ["../../../../tmp/x", "all", "report", "fig(3", "x|fig7", "ladder/fig3", "", "a" * 300, "data",
             "unreadable", "9fig", "fig 3", "fig-3", "fig3.nc"]


def _renamed(name, old="fig3"):
    scenes = {(name if k == old else k): v for k, v in SMOKE["scenes"].items()}
    return {**SMOKE, "scenes": scenes}


@pytest.mark.parametrize("name", BAD_NAMES, ids=lambda n: n[:20] or "empty")
def test_a_bad_or_reserved_scene_name_is_refused_naming_the_key(name):
    with pytest.raises(ConfigError, match=r"^scenes\.") as err:
        check_scene_name(name)
    assert len(str(err.value)) < 400  # a 300-character name is cut, not printed whole
    assert refused(_renamed(name))  # the schema's propertyNames refuses it too


def test_existing_scene_names_pass():
    for name in SMOKE["scenes"]:
        check_scene_name(name)
    assert not refused(_renamed("fig9_eps001_b"))


def test_reserved_names_cover_every_rule_and_results_directory():
    files = [ROOT / "workflow" / "Snakefile", *(ROOT / "workflow" / "rules").glob("*.smk")]
    text = "\n".join(p.read_text() for p in files)
    rules = set(re.findall(r"^rule (\w+):", text, flags=re.M)) | set(re.findall(r"^use rule \w+ as (\w+)", text, re.M))
    dirs = set(re.findall(r'\{R\}/(\w+)/', text))
    assert rules and dirs and (rules | dirs | {"unreadable"}) <= RESERVED


@pytest.mark.parametrize("path, inside", [("results/data/fig3.nc", True), ("results/../tmp/x.nc", False),
                                          ("results/data/../../../../tmp/x.nc", False), ("results", False),
                                          ("results2/x", False), ("/tmp/x.nc", False), ("./results/a/b", True)])
def test_under_judges_normalised_paths(path, inside):
    assert under("results", path) is inside


def test_check_under_names_the_key_of_a_path_outside():
    check_under("results", [("rule scene", "results/data/{scene}.nc")])
    with pytest.raises(ConfigError, match=r"^rule evil: writes '\.\./x/\{scene\}\.nc', outside the results"):
        check_under("results", [("rule scene", "results/data/{scene}.nc"), ("rule evil", "../x/{scene}.nc")])
    with pytest.raises(ConfigError, match="rule bare"):
        check_under("results", [("rule bare", "{scene}.nc")])


@settings(max_examples=60, deadline=None, database=None)
@given(st.text(max_size=80))
def test_every_name_is_accepted_exactly_when_it_is_a_safe_file_name(name):
    try:
        check_scene_name(name)
        ok = True
    except ConfigError as err:
        ok = False
        assert str(err).startswith("scenes.") and len(str(err)) < 400
    assert ok == bool(re.fullmatch(SCENE_NAME, name) and name not in RESERVED)
    if ok:
        assert under("results", f"results/data/{name}.nc") and under("results", f"results/logs/scene/{name}.log")


@settings(max_examples=30, deadline=None, database=None)
@given(st.from_regex(SCENE_NAME, fullmatch=True).filter(lambda n: n not in RESERVED))
def test_every_name_of_the_pattern_passes_the_schema_and_the_checks(name):
    assert not refused(_renamed(name, old="fig2")), name


def test_a_link_under_results_leading_outside_is_refused_naming_the_key(tmp_path, monkeypatch):
    """Issue 55: judged on resolved paths (before: lexically, so results/data -> /elsewhere passed)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "data").symlink_to(tmp_path / "elsewhere")
    assert not under("results", "results/data/fig3.nc") and under("results", "results/figures/fig3.png")
    with pytest.raises(ConfigError, match=r"^rule scene: writes 'results/data/\{scene\}\.nc', outside the results "
                                          r"directory 'results' \(through a symbolic link\)"):
        check_under("results", [("rule scene", "results/data/{scene}.nc")])
    (tmp_path / "big").mkdir()  # the results directory itself a link: what lies under it stays under it
    (tmp_path / "linked").symlink_to(tmp_path / "big")
    check_under("linked", [("rule scene", "linked/data/{scene}.nc")])


@pytest.mark.parametrize("results", ["/", "/.", "/tmp/..", "//", "/tmp/../tmp/.."])
def test_a_results_directory_resolving_to_the_root_is_refused(results):
    with pytest.raises(ConfigError, match=r"^results = .*: resolves to the file-system root"):
        check_under(results, [("rule scene", "/data/{scene}.nc")])
