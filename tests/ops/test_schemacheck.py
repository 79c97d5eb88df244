"""The config's schema check with short messages (sleighsim.ops.schemacheck): an unknown key is refused in one
line naming its path, not with Snakemake's dump of the sub-schema; many errors are listed five at a time."""

import copy

import pytest
from test_config import SCHEMA_PATH, SMOKE

from sleighsim.ops.schemacheck import SHOWN, check_schema, schema_problems
from sleighsim.scenes.checks import ConfigError


def test_the_shipped_smoke_config_fits():
    assert schema_problems(SMOKE, SCHEMA_PATH) == []
    check_schema(SMOKE, SCHEMA_PATH)


def test_an_unknown_key_is_named_by_its_path_in_one_short_line():
    cfg = copy.deepcopy(SMOKE)
    cfg["scenes"]["fig3"]["foo"] = 1
    with pytest.raises(ConfigError) as err:
        check_schema(cfg, SCHEMA_PATH)
    text = str(err.value)
    assert "scenes.fig3: Additional properties are not allowed ('foo' was unexpected)" in text
    assert len(text) < 400 and "\n" not in text


def test_many_errors_are_listed_five_at_a_time_in_key_order():
    cfg = copy.deepcopy(SMOKE)
    names = sorted(cfg["scenes"])[: SHOWN + 2]
    for name in names:
        cfg["scenes"][name]["zz_unknown"] = 1
    found = schema_problems(cfg, SCHEMA_PATH)
    assert [f.split(":")[0] for f in found] == [f"scenes.{n}" for n in names]
    with pytest.raises(ConfigError, match=r"\(and 2 more\)$"):
        check_schema(cfg, SCHEMA_PATH)
