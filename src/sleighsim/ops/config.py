"""The project's config files: where the repository and its base config lie, and the merged config
of a run (the base config with a run's ``--configfile`` overlays merged onto it)."""

from __future__ import annotations

from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
BASE_CONFIG = REPO / "config" / "config.yaml"


def _plain(value):
    """Plain dicts and lists (Snakemake's loaders may return ordered or custom mappings)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def merged_config(configfiles=(), base=BASE_CONFIG) -> dict:
    """The config a run reads: ``base`` (a path) with each of ``configfiles`` (paths, in order) merged
    onto it, the way Snakemake merges ``--configfile`` onto the Snakefile's ``configfile:``
    (snakemake.utils.update_config), each file read with the strict loader
    (:func:`sleighsim.ops.strictyaml.load`: no repeated key, no alias bomb, no YTE). Returns plain
    dicts and lists."""
    # Imported here for start-up time: snakemake.utils takes 0.1 s to import (python -X importtime),
    # which the modules reading only REPO or BASE_CONFIG need not pay.
    from snakemake.utils import update_config

    from sleighsim.ops.strictyaml import load

    config = _plain(load(base))
    for f in configfiles:
        update_config(config, _plain(load(f)))
    return _plain(config)
