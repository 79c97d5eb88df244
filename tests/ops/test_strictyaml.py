"""The strict YAML loader of config files (sleighsim.ops.strictyaml), with Hypothesis documents."""

import time

import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from test_config import ROOT

from sleighsim.ops.config import merged_config
from sleighsim.ops.strictyaml import YTE_OPT_IN, load, loads
from sleighsim.scenes.checks import ConfigError

#: The 369-byte "billion laughs" of the issue: nine levels of nine aliases (9**9 strings expanded).
BOMB = "a: &a [" + ",".join(['"lol"'] * 9) + "]\n" + "".join(
    f"{c}: &{c} [" + ",".join([f"*{p}"] * 9) + "]\n" for p, c in zip("abcdefgh", "bcdefghi"))


def test_a_repeated_key_is_refused_naming_it_and_its_lines(tmp_path):
    cfg = tmp_path / "twice.yaml"
    cfg.write_text("scenes:\n  fig3:\n    dt: 0.1\n    t_end: 300\n    dt: 0.2\n")
    with pytest.raises(ConfigError, match=r"twice.yaml: key 'dt' appears twice \(lines 3 and 5\)"):
        load(cfg)
    with pytest.raises(ConfigError, match="twice.yaml"):
        merged_config([cfg])


def test_an_alias_bomb_is_refused_quickly_with_a_short_message():
    assert len(BOMB) < 400
    start = time.perf_counter()
    with pytest.raises(ConfigError, match="aliases expand to more than") as err:
        loads(BOMB, "bomb.yaml")
    assert time.perf_counter() - start < 1.0 and len(str(err.value)) < 200 and "lol" not in str(err.value)


def test_a_self_referring_alias_and_invalid_yaml_are_refused_naming_the_line():
    with pytest.raises(ConfigError, match="x.yaml: line 2: an alias refers to itself"):
        loads("a: 1\nb: &b [1, *b]\n", "x.yaml")
    with pytest.raises(ConfigError, match=r"x.yaml: line \d+ not valid YAML"):
        loads("a: [1\n", "x.yaml")


def test_yte_configs_are_refused_unless_opted_in(monkeypatch):
    monkeypatch.delenv(YTE_OPT_IN, raising=False)
    with pytest.raises(ConfigError, match=rf"__use_yte__ = true makes Snakemake run code.*{YTE_OPT_IN}=1"):
        loads("__use_yte__: true\nresults: out\n", "t.yaml")
    monkeypatch.setenv(YTE_OPT_IN, "1")
    assert loads("__use_yte__: true\nresults: out\n")["results"] == "out"


def test_merge_keys_and_the_project_configs_load_as_plain_yaml_does():
    assert loads("x: &a {p: 1, q: 2}\ny: {<<: *a, p: 3}\n") == {"x": {"p": 1, "q": 2}, "y": {"p": 3, "q": 2}}
    for name in ("config.yaml", "smoke.yaml", "cluster.yaml"):
        path = ROOT / "config" / name
        assert load(path) == yaml.safe_load(path.read_text()), name


KEYS = st.text(alphabet="abcdefgh_", min_size=1, max_size=6)
SCALARS = st.none() | st.booleans() | st.integers(-10**6, 10**6) | st.floats(allow_nan=False) | st.text(max_size=8)
DOCS = st.recursive(SCALARS, lambda kids: st.lists(kids, max_size=4) | st.dictionaries(KEYS, kids, max_size=4),
                    max_leaves=20)


@settings(max_examples=40, deadline=None, database=None)
@given(DOCS)
def test_every_plain_document_loads_as_pyyaml_loads_it(doc):
    text = yaml.safe_dump({"root": doc})
    assert loads(text) == yaml.safe_load(text)


@settings(max_examples=30, deadline=None, database=None)
@given(st.dictionaries(KEYS, SCALARS, min_size=1, max_size=5), st.data())
def test_every_document_repeating_a_key_is_refused(mapping, data):
    key = data.draw(st.sampled_from(sorted(mapping)))
    text = yaml.safe_dump(mapping) + yaml.safe_dump({key: "again"})
    with pytest.raises(ConfigError, match=f"key {key!r} appears twice"):
        loads(text)


@settings(max_examples=20, deadline=None, database=None)
@given(st.integers(2, 12), st.integers(4, 12))
def test_every_deep_alias_chain_beyond_the_bound_is_refused(width, depth):
    lines = ["l0: &l0 [" + ",".join(["x"] * width) + "]"]
    lines += [f"l{i}: &l{i} [" + ",".join([f"*l{i - 1}"] * width) + "]" for i in range(1, depth)]
    text = "\n".join(lines) + "\n"
    expanded = sum(width ** i for i in range(1, depth + 1)) * 2  # at least the node count, at most about twice it
    if expanded > 4 * 50_000:
        with pytest.raises(ConfigError, match="aliases expand"):
            loads(text)
    elif expanded < 20_000:
        assert loads(text)["l0"] == ["x"] * width


# Issue 55: limits checked on the raw text, bombs of mappings, long plain documents.
MAPPING_BOMB = "l0: &l0 {" + ", ".join(f"k{j}: lol" for j in range(9)) + "}\n" + "".join(
    f"l{i}: &l{i} {{" + ", ".join(f"k{j}: *l{i - 1}" for j in range(9)) + "}\n" for i in range(1, 9))


def test_a_mapping_alias_bomb_is_refused_quickly():
    assert len(MAPPING_BOMB) < 1000
    start = time.perf_counter()
    with pytest.raises(ConfigError, match="aliases expand to more than"):
        loads(MAPPING_BOMB, "bomb.yaml")
    assert time.perf_counter() - start < 1.0


@pytest.mark.parametrize("text", ["a: " + "[" * 5000 + "]" * 5000 + "\n",
                                  "".join(" " * i + f"k{i}:\n" for i in range(900)) + " " * 900 + "x: 1\n",
                                  "- " * 5000 + "x\n"],
                         ids=["flow", "block mappings 900 deep (5000 exceed the size limit)", "block sequences"])
def test_a_document_nested_5000_deep_is_refused_naming_the_line(text):
    with pytest.raises(ConfigError, match=r"deep.yaml: line \d+: nested more than 64 levels deep"):
        loads(text, "deep.yaml")


def test_a_long_document_without_aliases_is_not_an_alias_bomb():
    assert loads("x: [" + ", ".join(["1"] * 60_000) + "]\n")["x"] == [1] * 60_000


def test_a_text_over_the_size_limit_is_refused_before_parsing(tmp_path):
    big = tmp_path / "big.yaml"
    big.write_text("# " + "x" * 1_000_000 + "\n")
    with pytest.raises(ConfigError, match=r"big.yaml: 1000003 bytes, more than a config file may have"):
        load(big)
