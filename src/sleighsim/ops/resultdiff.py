"""Compare two result trees dataset by dataset: ``python -m sleighsim.resultdiff OLD NEW``.

For every netCDF file under ``data/`` (its subfolders included: precision variants, ladders,
realizations) and ``claims.nc`` present in either tree: the data variables and coordinates must be
equal bit for bit (NaN equal to NaN), the attributes equal apart from those that record when, where
and how fast a run happened (times, the commit, package versions); attributes or variables present
in only one tree are listed. Exit status 0 when every dataset is identical in that sense, 1
otherwise. A check for a restructure: results must not move. With ``--module-paths``, text naming
a module or function of this package (``sleighsim.engine.transient.phases``) compares by its last
name only (``phases``), so a restructure that moves modules can be checked for everything else.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import numpy as np

from sleighsim.io.netcdf import read_dataset
from sleighsim.ops.helptext import summary

#: Names of attributes and variables that measure the run, not its result.
# history and source (CF) carry the time of writing and the commit; lock_ the lock file installed from
VOLATILE = re.compile(r"wall|compile_time|created_utc|git_commit|^version_|^lock_|python_version|seconds_per_step"
                      r"|^history$|^source$|^cost_|_estimate_s$|^overhead_|speedup|fastest_at|^lambda_1_wall|^lyap_scipy_wall")


#: A dotted name inside this package, its module path and its last name: written out
#: (sleighsim.engine.transient.phases) or in a docstring's double backquotes (``chaos.orbits.loschmidt``).
MODULE_PATH = re.compile(r"sleighsim(?:\.\w+)*\.(\w+)|``(?:\w+\.)+(\w+)``")


def _without_module_paths(a: np.ndarray) -> np.ndarray:
    """Text with every dotted sleighsim name cut to its last name (``--module-paths``)."""
    cut = np.vectorize(lambda s: MODULE_PATH.sub(lambda m: f"..{m.group(1) or m.group(2)}", str(s)), otypes=[object])
    return cut(a) if a.size else a


def _equal(a, b, module_paths: bool = False) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype.kind != b.dtype.kind:
        return False
    if a.dtype.kind in "fc":
        return bool(np.array_equal(a, b, equal_nan=True))
    if module_paths and a.dtype.kind in "USO":
        a, b = _without_module_paths(a), _without_module_paths(b)
    if a.dtype.kind == "O":  # mixed text and numbers (a ledger column): NaN equal to NaN here too
        return all(x == y or (_is_nan(x) and _is_nan(y)) for x, y in zip(a.ravel(), b.ravel()))
    return bool(np.array_equal(a, b))


def _is_nan(x) -> bool:
    return isinstance(x, float) and x != x


def compare_datasets(old, new, module_paths: bool = False) -> list[str]:
    """Differences between two datasets, one line each (empty when identical); ``module_paths``:
    text naming sleighsim modules compares by the last name only."""
    out = []
    for kind, a, b in (("variable", old.variables, new.variables),):
        for name in sorted(set(a) | set(b)):
            if VOLATILE.search(name):
                continue
            if name not in a or name not in b:
                out.append(f"{kind} {name} only in {'new' if name in b else 'old'}")
            elif not _equal(a[name].values, b[name].values, module_paths):
                out.append(f"{kind} {name} differs")
    for name in sorted(set(old.attrs) | set(new.attrs)):
        if VOLATILE.search(name):
            continue
        if name not in old.attrs or name not in new.attrs:
            out.append(f"attribute {name} only in {'new' if name in new.attrs else 'old'}")
        elif not _equal(old.attrs[name], new.attrs[name], module_paths):
            out.append(f"attribute {name} differs: {old.attrs[name]!r} -> {new.attrs[name]!r}")
    return out


def compare_trees(old: Path, new: Path, module_paths: bool = False) -> dict[str, list[str]]:
    """{relative path: differences} for every dataset under data/ (subfolders included) and
    claims.nc in either tree; ``module_paths`` as in :func:`compare_datasets`."""
    names = set()
    for root in (old, new):
        names |= {p.relative_to(root) for p in (root / "data").rglob("*.nc")}
        names |= {p.relative_to(root) for p in root.glob("claims.nc")}
    out = {}
    for rel in sorted(names):
        a, b = old / rel, new / rel
        if not a.exists() or not b.exists():
            out[str(rel)] = [f"only in {'new' if b.exists() else 'old'} tree"]
            continue
        # unverified: an old tree may predate checksums (``sleighsim verify`` checks a tree's integrity)
        out[str(rel)] = compare_datasets(read_dataset(a, verified=False), read_dataset(b, verified=False),
                                         module_paths)
    return out


def main(argv=None, prog: str | None = None) -> int:
    """Compare the datasets of two results trees and print each one's differences (``argv``: OLD NEW,
    default sys.argv[1:]). Exit status 0 when all are identical, 1 when any differs."""
    parser = argparse.ArgumentParser(prog=prog, description=summary(__doc__))
    parser.add_argument("old", type=Path, help="results directory before the change")
    parser.add_argument("new", type=Path, help="results directory after the change")
    parser.add_argument("--module-paths", action="store_true",
                        help="compare text naming sleighsim modules by the last name only (a restructure)")
    args = parser.parse_args(argv)
    diffs = compare_trees(args.old, args.new, args.module_paths)
    for rel, lines in diffs.items():
        print(f"{rel}: {'identical' if not lines else str(len(lines)) + ' difference(s)'}")
        for line in lines:
            print(f"    {line}")
    n = sum(bool(v) for v in diffs.values())
    print(f"{len(diffs)} datasets compared, {n} differ")
    return 1 if n else 0


if __name__ == "__main__":
    sys.exit(main())
