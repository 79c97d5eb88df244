"""Scene names and the paths the workflow writes, checked before any job runs.

A scene name becomes a file name (results/data/<name>.nc), a wildcard value and a rule name, so it
matches :data:`SCENE_NAME` (a letter, then letters, digits or ``_``; at most 64 characters) and is
none of :data:`RESERVED` (the workflow's rule names and the directories it writes under results/).
Every path a rule writes lies under the results directory, judged on resolved paths, and the results
directory is not the file-system root (:func:`check_under`).
"""

from __future__ import annotations

import os
import re

from sleighsim.io import layout
from sleighsim.scenes.checks import ConfigError

#: The documented pattern of a scene name (the schema's ``scenes.propertyNames``).
SCENE_NAME = r"^[A-Za-z][A-Za-z0-9_]{0,63}$"
#: Names a scene may not take: the workflow's rules and the folders of the results tree (io.layout).
RESERVED = frozenset({
    # rules (workflow/Snakefile, workflow/rules/*.smk)
    "all", "atlas", "chunk", "chunk_first", "chunk_in_precision", "claims", "figure", "gather", "gather_in_precision",
    "ladder", "report", "scene", "scene_first", "scene_in_precision", "scene_realization", "schematic",
    "stability", *layout.RESERVED})


def _shown(name: str) -> str:
    """``name`` quoted, cut to 40 characters (a long name is not printed whole)."""
    return repr(name) if len(name) <= 40 else f"{name[:40]!r}... ({len(name)} characters)"


def check_scene_name(name) -> None:
    """Raise :class:`ConfigError` naming ``scenes.<name>`` unless ``name`` is an admissible scene name."""
    if not isinstance(name, str) or not re.fullmatch(SCENE_NAME, name):
        shown = _shown(name) if isinstance(name, str) else repr(name)
        raise ConfigError(f"scenes.{shown}: a scene name must match {SCENE_NAME} (a letter, then letters, "
                          "digits or _; at most 64 characters)")
    if name in RESERVED:
        raise ConfigError(f"scenes.{name}: {name!r} is reserved (a rule or a directory of the workflow: "
                          f"{', '.join(sorted(RESERVED))}); rename the scene")


def check_scene_names(config: dict) -> None:
    """Every key of ``config["scenes"]`` an admissible scene name (:func:`check_scene_name`)."""
    for name in config.get("scenes") or {}:
        check_scene_name(name)


def under(results, path) -> bool:
    """Whether ``path`` (relative to the working directory, or absolute) lies inside the directory
    ``results``, judged on the resolved paths (symbolic links followed, ``..`` resolved after them):
    a link under results/ pointing elsewhere leads outside."""
    root = os.path.realpath(results)
    target = os.path.realpath(path)
    return target != root and os.path.commonpath([root, target]) == root


def check_results(results) -> None:
    """Raise :class:`ConfigError` naming ``results`` when it resolves to the file-system root (``/.``,
    ``/tmp/..``): a run would plan, lock and sweep there."""
    if os.path.realpath(results) == os.path.realpath(os.sep):
        raise ConfigError(f"results = {_shown(str(results))}: resolves to the file-system root; give a directory "
                          "of its own (e.g. results)")


def _static(path) -> str:
    """A pattern's fixed part (cut at its first ``{``), made a file name when it ends a directory."""
    static = str(path).split("{", 1)[0]
    return static + "x" if static.endswith("/") or not static else static


def check_under(results, named_paths) -> None:
    """Raise :class:`ConfigError` when ``results`` is the root (:func:`check_results`), or naming
    the key of the first of ``named_paths`` ((key, path) pairs; a pattern's wildcards are cut off at
    its first ``{``) that does not lie under ``results`` (:func:`under`)."""
    check_results(results)
    for key, path in named_paths:
        if not under(results, _static(path)):
            raise ConfigError(f"{key}: writes {_shown(str(path))}, outside the results directory {results!r}"
                              + (" (through a symbolic link)" if _lexically_under(results, _static(path)) else ""))


def _lexically_under(results, path) -> bool:
    root = os.path.normpath(os.path.abspath(results))
    target = os.path.normpath(os.path.abspath(path))
    return target != root and os.path.commonpath([root, target]) == root


def written_dirs(results, named_paths) -> list[str]:
    """The directories directly under ``results`` that ``named_paths`` ((key, pattern) pairs under
    it) write into (data, chunks, figures, ...), sorted: the ones the stale-temp sweep looks in."""
    out = set()
    for _, path in named_paths:
        parts = os.path.relpath(os.path.abspath(_static(path)), os.path.abspath(results)).split(os.sep)
        if len(parts) > 1 and parts[0] not in (os.curdir, os.pardir):
            out.add(parts[0])
    return sorted(out)


def rule_paths(rules):
    """(``rule <name>``, pattern) of every output, log and benchmark file of Snakemake ``rules``."""
    for rule in rules:
        files = [*rule.output, *rule.log, *([rule.benchmark] if rule.benchmark else [])]
        yield from ((f"rule {rule.name}", str(f)) for f in files)
