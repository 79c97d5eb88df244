"""The strict YAML loader of config files: plain data only, read the way a reviewer reads it.

- a text longer than :data:`MAX_BYTES` or nested deeper than :data:`MAX_DEPTH` is refused from its
  raw text, before it is parsed (PyYAML builds nested nodes recursively: 5,000 levels raise
  RecursionError);
- a mapping that repeats a key is refused (PyYAML keeps the last value silently);
- a document whose aliases would add more than :data:`MAX_NODES` nodes when expanded is refused
  before it is built (a "billion laughs" bomb, of lists or of mappings), and so is an alias that
  refers to itself; a long document without aliases is not a bomb;
- ``__use_yte__`` (Snakemake's YTE templating, which runs code from the config) is refused unless the
  environment sets :data:`YTE_OPT_IN` to 1.

Each error (:class:`sleighsim.scenes.checks.ConfigError`) names the file and the key or line, and
never prints the document.
"""

from __future__ import annotations

import os
from pathlib import Path

import yaml

from sleighsim.scenes.checks import ConfigError

#: Nodes a document's aliases may add when expanded, each counted at every use (config/config.yaml: a few hundred).
MAX_NODES = 50_000
#: Bytes of a config file (config/config.yaml: about 30 kB).
MAX_BYTES = 1_000_000
#: Nesting of collections (config/config.yaml: 6).
MAX_DEPTH = 64
#: The environment variable that lets a config use Snakemake's YTE templating (it executes code).
YTE_OPT_IN = "SLEIGHSIM_ALLOW_YTE"


class _Loader(yaml.SafeLoader):
    """SafeLoader refusing repeated mapping keys."""

    def construct_mapping(self, node, deep=False):
        seen = {}
        for key_node, _ in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                continue
            key = self.construct_object(key_node, deep=True)
            if not isinstance(key, (str, int, float, bool, type(None))):
                continue  # SafeLoader refuses an unhashable key itself
            if key in seen:
                raise ConfigError(f"{self.name}: key {key!r} appears twice (lines {seen[key] + 1} and "
                                  f"{key_node.start_mark.line + 1}); keep one")
            seen[key] = key_node.start_mark.line
        return super().construct_mapping(node, deep=deep)


def expanded_size(node, limit: int = MAX_NODES, where: str = "<yaml>") -> int:
    """Nodes of ``node`` with every alias expanded (shared nodes counted at each use); refuses a
    document whose aliases add more than ``limit`` nodes to its own, and a node that contains
    itself, without expanding anything (each distinct node is visited once)."""
    sizes, open_ = {}, set()

    def size(n):
        if id(n) in sizes:
            return sizes[id(n)]
        if id(n) in open_:
            raise ConfigError(f"{where}: line {n.start_mark.line + 1}: an alias refers to itself")
        open_.add(id(n))
        if isinstance(n, yaml.SequenceNode):
            total = 1 + sum(size(c) for c in n.value)
        elif isinstance(n, yaml.MappingNode):
            total = 1 + sum(size(k) + size(v) for k, v in n.value)
        else:
            total = 1
        open_.discard(id(n))
        sizes[id(n)] = total
        return total

    total = size(node)
    if total - len(sizes) > limit:
        raise ConfigError(f"{where}: its aliases expand to more than {limit} nodes (an alias bomb?); "
                          "write the values out")
    return total


def check_raw(text: str, where: str = "<yaml>") -> None:
    """Refuse, from the raw text and before any parsing, a text longer than :data:`MAX_BYTES` or
    collections nested deeper than :data:`MAX_DEPTH` (counted on PyYAML's token stream, which is
    read without recursion)."""
    if len(text.encode()) > MAX_BYTES:
        raise ConfigError(f"{where}: {len(text.encode())} bytes, more than a config file may have ({MAX_BYTES})")
    opening = (yaml.BlockMappingStartToken, yaml.BlockSequenceStartToken, yaml.FlowMappingStartToken,
               yaml.FlowSequenceStartToken)
    closing = (yaml.BlockEndToken, yaml.FlowMappingEndToken, yaml.FlowSequenceEndToken)
    depth = 0
    try:
        for token in yaml.scan(text, Loader=yaml.SafeLoader):
            depth += isinstance(token, opening) - isinstance(token, closing)
            if depth > MAX_DEPTH:
                line = token.start_mark.line + 1
                raise ConfigError(f"{where}: line {line}: nested more than {MAX_DEPTH} levels deep")
    except yaml.YAMLError:
        return  # the parser names the fault


def loads(text: str, where: str = "<yaml>", limit: int = MAX_NODES):
    """The data of one YAML document ``text`` (``where`` names it in errors), strictly."""
    check_raw(text, where)
    loader = _Loader(text)
    loader.name = where
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        expanded_size(node, limit, where)
        data = loader.construct_document(node)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        line = f" line {mark.line + 1}" if mark else ""
        raise ConfigError(f"{where}:{line} not valid YAML ({getattr(err, 'problem', None) or type(err).__name__})") \
            from None
    finally:
        loader.dispose()
    _refuse_yte(data, where)
    return data


def _refuse_yte(data, where: str) -> None:
    """``__use_yte__`` only with the opt-in: a YTE template runs Python code while Snakemake loads it."""
    if isinstance(data, dict) and data.get("__use_yte__") and os.environ.get(YTE_OPT_IN) != "1":
        raise ConfigError(f"{where}: __use_yte__ = true makes Snakemake run code from this config; sleighsim "
                          f"reads configs as plain data (set {YTE_OPT_IN}=1 to allow it)")


def load(path):
    """The data of the YAML file at ``path``, strictly (:func:`loads`)."""
    path = Path(path)
    try:
        if path.stat().st_size > MAX_BYTES:
            raise ConfigError(f"{path}: {path.stat().st_size} bytes, more than a config file may have ({MAX_BYTES})")
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as err:
        raise ConfigError(f"{path}: cannot be read ({err})") from None
    return loads(text, str(path))


def check_files(paths) -> None:
    """Read each config file at ``paths`` strictly (Snakemake's own loader keeps a repeated key's
    last value, recurses without bound and its config merge expands aliases unbounded); raises
    :class:`ConfigError` naming the file."""
    for path in paths:
        load(path)
