"""The results tree's layout, in one place: where each product of a run lies under the results
directory, and what a path there names. Everything that builds or reads a path of the tree (the
workflow, the catalog, the ledger, the report, the cost estimate, the CF titles) asks here.

::

    data/<scene>.nc                           a scene's dataset (double, the paper's arithmetic)
    data/precision/<tag>/<scene>.nc           the scene in a finer arithmetic (its Precision.tag)
    data/ladder/<scene>.nc                    the scene's precision ladder
    data/realization/<k>/<scene>.nc           realization k >= 1 (its start states perturbed)
    chunks/[precision/<tag>/]<scene>/<k>.nc   chunk k of a chunked scene (or of its finer variant)
    figures/, report/, logs/, benchmarks/, stability/, unreadable/, claims.{csv,nc}

A dataset's *name* is its path under ``data/`` without the suffix (``precision/long_double/<scene>``);
the patterns :data:`FINER`, :data:`LADDER_OF` and :data:`REALIZED` spell the names with Snakemake's
wildcards (``tag``, ``scene``, ``k``), so the workflow's rules and the functions below share one spelling.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from sleighsim.precision import Precision

DATA, CHUNKS = "data", "chunks"
PRECISION, LADDER, REALIZATION = "precision", "ladder", "realization"
#: The folders a run writes directly under the results directory (no scene may take these names).
FOLDERS = (DATA, CHUNKS, "figures", "report", "logs", "benchmarks", "stability", "unreadable")
#: Every folder name the tree uses at some level.
RESERVED = frozenset((*FOLDERS, PRECISION, LADDER, REALIZATION))
#: Name patterns: a scene in a finer arithmetic, its ladder, its realization k.
FINER = PRECISION + "/{tag}/{scene}"
LADDER_OF = LADDER + "/{scene}"
REALIZED = REALIZATION + "/{k}/{scene}"


def variant(scene: str, precision) -> str:
    """The name of ``scene`` computed in ``precision``: the scene itself in double, else
    precision/<tag>/<scene>."""
    p = Precision.parse(precision)
    return scene if p is Precision.DOUBLE else FINER.format(tag=p.tag, scene=scene)


def ladder(scene: str) -> str:
    """The name of the precision ladder of ``scene``."""
    return LADDER_OF.format(scene=scene)


def realization(scene: str, k: int) -> str:
    """The name of realization ``k`` of ``scene`` (0: the scene itself)."""
    return scene if k == 0 else REALIZED.format(k=k, scene=scene)


def chunk_folder(scene: str, precision=Precision.DOUBLE) -> str:
    """The folder under chunks/ holding the chunk files of ``scene`` in ``precision``."""
    return variant(scene, precision)


def is_finer(name: str) -> bool:
    """Whether the dataset ``name`` is a scene in a finer arithmetic than double."""
    return name.startswith(f"{PRECISION}/")


def is_ladder(name: str) -> bool:
    """Whether the dataset ``name`` is a precision ladder."""
    return name.startswith(f"{LADDER}/")


def is_realization(name: str) -> bool:
    """Whether the dataset ``name`` is a realization k >= 1."""
    return name.startswith(f"{REALIZATION}/")


def scene_of(name: str) -> str:
    """The scene a dataset ``name`` belongs to (its last part)."""
    return name.rsplit("/", 1)[-1]


@dataclass(frozen=True)
class Place:
    """What a path of the tree holds: ``what`` ("scene", "finer", "ladder", "realization", "chunk",
    "finer chunk", or "" for anything else), the ``scene``, the precision ``tag`` of a finer product and
    the index ``k`` as written (a realization's or a chunk's; "" where none)."""

    what: str
    scene: str
    tag: str = ""
    k: str = ""


def place(path) -> Place:
    """What ``path`` holds, read from its parts after its last ``data`` or ``chunks`` folder; a path
    outside those is ``Place("", <stem>)``."""
    parts = Path(path).with_suffix("").parts
    anchors = [i for i, p in enumerate(parts[:-1]) if p in (DATA, CHUNKS)]
    match list(parts[anchors[-1]:]) if anchors else []:
        case ["data", scene]:
            return Place("scene", scene)
        case ["data", "precision", tag, scene]:
            return Place("finer", scene, tag)
        case ["data", "ladder", scene]:
            return Place("ladder", scene)
        case ["data", "realization", k, scene]:
            return Place("realization", scene, k=k)
        case ["chunks", "precision", tag, scene, k]:
            return Place("finer chunk", scene, tag, k)
        case ["chunks", scene, k]:
            return Place("chunk", scene, k=k)
    return Place("", parts[-1] if parts else "")
