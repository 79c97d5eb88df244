"""config/README.md from the config schema's descriptions: every key of every kind.

``python -m sleighsim.ops.configdoc [--schema workflow/schemas/config.schema.yaml] [--out config/README.md]``;
``--check`` exits 1 when the file differs from what the schema gives (a test runs it).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import yaml

from sleighsim.ops.helptext import summary

HEADER = """# Configuration

Generated from `workflow/schemas/config.schema.yaml` by `python -m sleighsim.ops.configdoc`;
edit the schema's descriptions, not this file. `config/config.yaml` is the paper at full
fidelity; `config/smoke.yaml` (the same scenes tiny, for CI) and `config/cluster.yaml` (a SLURM
cluster) are overlays that hold only what differs from it: Snakemake merges a `--configfile` onto
`config/config.yaml` (mappings key by key, lists and scalars replaced whole).

Every value is checked before any job starts: the schema (types, bounds, unknown keys) and
`sleighsim.ops.configcheck` (finite numbers, tolerances in (0, 1), cross-field constraints,
inputs, memory). Times are in the model's time unit, angles in rad.
"""


def _resolve(schema: dict, node: dict) -> dict:
    """The node with its $ref followed (keys beside the $ref win), recursively."""
    while "$ref" in node:
        target = schema
        for part in node["$ref"].lstrip("#/").split("/"):
            target = target[part]
        node = {**target, **{k: v for k, v in node.items() if k != "$ref"}}
    return node


def _type(schema: dict, node: dict) -> str:
    node = _resolve(schema, node)
    if "enum" in node:
        return "one of " + ", ".join(f"`{v}`" for v in node["enum"])
    kinds = node.get("type", "")
    kinds = " or ".join(kinds) if isinstance(kinds, list) else kinds
    if kinds == "array" and "items" in node:
        n = (f"{node['minItems']}" if node.get("minItems") == node.get("maxItems") and "minItems" in node else "")
        inner = _type(schema, node["items"])
        return f"list of {n + ' ' if n else ''}{inner}".strip()
    bounds = []
    for key, op in (("exclusiveMinimum", ">"), ("minimum", ">="), ("exclusiveMaximum", "<"), ("maximum", "<=")):
        if key in node:
            bounds.append(f"{op} {node[key]}")
    return (kinds or "object") + (" " + ", ".join(bounds) if bounds else "")


def _rows(schema: dict, node: dict, prefix: str = "") -> list[str]:
    node = _resolve(schema, node)
    required = set(node.get("required", []))
    out = []
    for key, sub in node.get("properties", {}).items():
        full = _resolve(schema, sub)
        name = f"{prefix}{key}"
        default = f" (default `{full['default']}`)" if "default" in full else ""
        desc = " ".join(str(full.get("description", "")).split()).replace("|", "\\|")
        req = "yes" if key in required else "no"
        out.append(f"| `{name}` | {_type(schema, sub)} | {req} | {desc}{default} |")
        if full.get("type") == "object" and "properties" in full and key not in ("params",):
            out += _rows(schema, full, name + ".")
        if full.get("type") == "array" and _resolve(schema, full.get("items", {})).get("properties"):
            out += _rows(schema, full["items"], name + "[].")
    return out


def render(schema: dict) -> str:
    """The Markdown documentation of every key."""
    table = ["| key | type | required | meaning |", "|---|---|---|---|"]
    lines = [HEADER, "## Top level", "", *table, *_rows(schema, {k: v for k, v in schema.items() if k != "$defs"}), ""]
    defs = schema["$defs"]
    lines += ["## Shared blocks", ""]
    for name in ("params", "transient"):
        lines += [f"### `{name}`", "", " ".join(defs[name]["description"].split()), "", *table,
                  *_rows(schema, defs[name]), ""]
    lines += ["## Scene kinds", "",
              ("Each block under `scenes` names its `kind`; the keys below are those of each kind "
               "(besides `kind` and `on_request`)."), ""]
    for kind in defs["scene"]["properties"]["kind"]["enum"]:
        d = defs[kind]
        rows = [r for r in _rows(schema, d) if not r.startswith(("| `kind` ", "| `on_request` "))]
        lines += [f"### `{kind}`", "", " ".join(d["description"].split()), "", *table, *rows, ""]
    return "\n".join(lines)


def main(argv=None, prog: str | None = None) -> int:
    """Write config/README.md from the schema (``--check``: compare only); exit status 0, or 1 when
    ``--check`` finds the file out of date. ``argv``: the arguments (default sys.argv[1:])."""
    parser = argparse.ArgumentParser(prog=prog, description=summary(__doc__))
    parser.add_argument("--schema", type=Path, default=Path("workflow/schemas/config.schema.yaml"))
    parser.add_argument("--out", type=Path, default=Path("config/README.md"))
    parser.add_argument("--check", action="store_true", help="exit 1 when --out differs from the schema's text")
    args = parser.parse_args(argv)
    text = render(yaml.safe_load(args.schema.read_text()))
    if args.check:
        same = args.out.exists() and args.out.read_text() == text
        verdict = "up to date" if same else "differs from the schema; run python -m sleighsim.ops.configdoc"
        print(f"{args.out}: {verdict}")
        return 0 if same else 1
    args.out.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
