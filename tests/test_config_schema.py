"""Invalid configs generated from the schema: every bounded number, every typed value and
every closed object of the smoke config, broken one at a time, must be refused, naming
the offending key. The bulk runs through jsonschema's validator for the schema's draft
(what snakemake.utils.validate uses, compiled once here); one test checks that Snakemake's
own validate refuses the same way. (The end-to-end tests in test_workflow.py check that
a refused config stops Snakemake before any job.)"""

import copy
from pathlib import Path

import jsonschema
import pytest
import yaml
from snakemake.utils import validate

ROOT = Path(__file__).resolve().parents[1]
SCHEMA_PATH = ROOT / "workflow" / "schemas" / "config.schema.yaml"
SCHEMA = yaml.safe_load(SCHEMA_PATH.read_text())
SMOKE = yaml.safe_load((ROOT / "config" / "smoke.yaml").read_text())
VALIDATOR = jsonschema.validators.validator_for(SCHEMA)(SCHEMA)


def _resolve(node):
    while "$ref" in node:
        node = SCHEMA["$defs"][node["$ref"].split("/")[-1]]
    return node


def _breakages(value, node, path):
    """(path, bad value, why) for one config value against its schema node."""
    node = _resolve(node)
    types = node.get("type")
    types = [types] if isinstance(types, str) else (types or [])
    if isinstance(value, dict) and node.get("properties"):
        if node.get("additionalProperties") is False:
            yield path + ("not_a_key",), 1.0, "unknown key"
        for k, v in value.items():
            if k in node["properties"]:
                yield from _breakages(v, node["properties"][k], path + (k,))
        return
    if isinstance(value, list) and "items" in node and isinstance(node["items"], dict):
        if value:
            yield from _breakages(value[0], node["items"], path + (0,))
        return
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if "number" in types or "integer" in types:
            yield path, "text", "wrong type"
        for key, bad in (("minimum", lambda b: b - 1), ("exclusiveMinimum", lambda b: b),
                         ("maximum", lambda b: b + 1), ("exclusiveMaximum", lambda b: b)):
            if key in node:
                yield path, bad(node[key]), key


CASES = list(_breakages(SMOKE, SCHEMA, ()))


def _set(cfg, path, value):
    node = cfg
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value


def _key(path):
    return next(str(p) for p in reversed(path) if not isinstance(p, int))


def test_the_schema_yields_many_cases_and_the_smoke_config_is_valid():
    assert len(CASES) > 100
    assert {why for *_, why in CASES} >= {"unknown key", "wrong type", "minimum", "exclusiveMinimum"}
    validate(copy.deepcopy(SMOKE), str(SCHEMA_PATH))
    VALIDATOR.validate(copy.deepcopy(SMOKE))


def test_snakemake_validate_refuses_a_generated_case_like_the_bulk_validator():
    path, bad, _ = next(c for c in CASES if c[2] == "exclusiveMinimum")
    cfg = copy.deepcopy(SMOKE)
    _set(cfg, path, bad)
    with pytest.raises(Exception) as err:
        validate(cfg, str(SCHEMA_PATH))
    assert _key(path) in str(err.value)
    assert not VALIDATOR.is_valid(cfg)


@pytest.mark.parametrize("path, bad, why", CASES, ids=[".".join(map(str, c[0])) + f":{c[2]}" for c in CASES])
def test_each_generated_invalid_value_is_refused_naming_the_key(path, bad, why):
    cfg = copy.deepcopy(SMOKE)
    _set(cfg, path, bad)
    errors = list(VALIDATOR.iter_errors(cfg))
    assert errors, f"{path} = {bad!r} ({why}) was accepted"
    where = " ".join(str(e.message) + " " + " ".join(map(str, e.absolute_path)) for e in errors)
    assert _key(path) in where, where[-500:]


@pytest.mark.parametrize("name", ["config.yaml", "smoke.yaml", "cluster.yaml"])
def test_shipped_configs_are_valid_and_pass_the_cross_field_checks(name):
    """Each as Snakemake sees it: --configfile is merged onto config/config.yaml."""
    from snakemake.common.configfile import load_configfile
    from snakemake.utils import update_config

    from sleighsim import configcheck

    cfg = load_configfile(str(ROOT / "config" / "config.yaml"))
    update_config(cfg, load_configfile(str(ROOT / "config" / name)))
    errors = [e.message for e in VALIDATOR.iter_errors(cfg)]
    assert not errors, errors
    configcheck.check(cfg)
