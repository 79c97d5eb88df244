"""The config's schema check (workflow/schemas/config.schema.yaml) with one short line per refused key.

Snakemake's ``validate`` prints the whole sub-schema an error sits in (some sixty lines for an unknown key of
a scene); this check runs first and names the key path and jsonschema's message instead. Snakemake's
``validate`` still runs after it, for the schema's defaults.
"""

from __future__ import annotations

from pathlib import Path

import jsonschema

from sleighsim.io.yamlfile import read_yaml
from sleighsim.scenes.checks import ConfigError

#: At most this many refused keys are listed; each message is cut to WIDTH characters.
SHOWN, WIDTH = 5, 300


def schema_problems(config: dict, schema_path) -> list[str]:
    """Each schema error of ``config`` as "key.path: message", in key order (empty when it fits)."""
    schema = read_yaml(schema_path)
    validator = jsonschema.validators.validator_for(schema)(schema)
    errors = sorted(validator.iter_errors(config), key=lambda e: [str(k) for k in e.absolute_path])
    return [f"{'.'.join(map(str, e.absolute_path)) or '(the top level)'}: {_cut(e.message)}" for e in errors]


def check_schema(config: dict, schema_path) -> None:
    """ConfigError listing the first SHOWN of ``schema_problems``; nothing when the config fits."""
    found = schema_problems(config, schema_path)
    if found:
        more = f" (and {len(found) - SHOWN} more)" if len(found) > SHOWN else ""
        raise ConfigError(f"the config does not fit its schema ({Path(schema_path).name}): " + "; ".join(found[:SHOWN])
                          + more)


def _cut(text: str) -> str:
    """``text`` cut to WIDTH characters."""
    return text if len(text) <= WIDTH else text[: WIDTH - 3] + "..."
