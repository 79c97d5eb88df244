"""Which runs are judged against the paper, and the identity of a run's configuration.

A config names itself with its top-level ``label`` (config/config.yaml: ``paper``; the overlays
config/smoke.yaml: ``smoke``, config/cluster.yaml: ``cluster``). Only a run whose label is one of
:data:`PAPER_FIDELITY` is judged against the paper's numbers; every row of any other run's ledger reads
"not a reproduction", its own data's verdict kept beside it (``run_verdict``). The configuration's
identity is its label and the SHA-256 of its canonical JSON (:func:`config_sha256`), recorded in the
ledger and shown on the report's first line.
"""

from __future__ import annotations

import hashlib
import json

#: The config key that names a run's configuration.
LABEL = "label"
#: The labels of the configs at (or beyond) the paper's fidelity: the paper's, and the cluster overlay's.
PAPER_FIDELITY = ("paper", "cluster")
#: Written into the ledger (attribute fidelity_rule).
FIDELITY_RULE = (
    f"A run is judged against the paper only when its config's label is one of {', '.join(PAPER_FIDELITY)}; "
    "every row of another run's ledger (the smoke run's) reads \"not a reproduction\", with the verdict the "
    "rules give on that run's own datasets in the column run_verdict."
)


def label(config: dict) -> str:
    """The config's label; ValueError naming the key when it has none (a run of unknown fidelity is never
    judged against the paper by default)."""
    value = config.get(LABEL)
    if not isinstance(value, str) or not value:
        raise ValueError(f"the config names no {LABEL!r} (config/config.yaml sets {LABEL}: paper; an overlay "
                         "may set its own): which run this is decides whether it is judged against the paper")
    return value


def at_paper_fidelity(name: str) -> bool:
    """Whether a run labelled ``name`` is judged against the paper (one of PAPER_FIDELITY)."""
    return name in PAPER_FIDELITY


def reproduction(config: dict) -> bool:
    """Whether the run of ``config`` is judged against the paper (:func:`at_paper_fidelity` of its label)."""
    return at_paper_fidelity(label(config))


def config_sha256(config: dict) -> str:
    """SHA-256 (hex) of ``config`` as canonical JSON: keys sorted, no spaces, numbers as JSON writes them
    (a value JSON cannot hold as its str)."""
    text = json.dumps(config, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def identity(config: dict) -> dict[str, str]:
    """The configuration's identity, as the ledger's attributes record it: ``config_label`` and
    ``config_sha256``."""
    return {"config_label": label(config), "config_sha256": config_sha256(config)}


def describe(ident: dict) -> str:
    """A line naming the configuration (``identity``): its label and the first 12 hex digits of its hash."""
    return f"config {ident['config_label']} (sha256 {ident['config_sha256'][:12]})"
