"""``sleighsim verify RESULTS_DIR``: check every dataset of a results tree against the checksum of its
values, attributes and dimensions and its identity recorded when it was written
(:mod:`sleighsim.io.checksum`); print each file that fails, and why, then a count. Symlinked
directories are followed; a directory that cannot be listed, a file that is not a regular file (a
FIFO named *.nc) or cannot be read fails, and so does a tree holding no dataset. Exit status 0 when
all pass, 1 when any fails or there is none, 2 for a usage error."""

from __future__ import annotations

import argparse
from pathlib import Path

from sleighsim.io.checksum import verify_tree
from sleighsim.ops.helptext import summary


def main(argv=None, prog: str = "sleighsim verify") -> int:
    """Verify the netCDF files under RESULTS_DIR (``argv``, default sys.argv[1:]); the exit status."""
    ap = argparse.ArgumentParser(prog=prog, description=summary(__doc__))
    ap.add_argument("results", metavar="RESULTS_DIR", help="the results directory (every *.nc under it is checked)")
    args = ap.parse_args(argv)
    if not Path(args.results).is_dir():
        ap.error(f"RESULTS_DIR {args.results}: no such directory")
    checked = verify_tree(args.results)
    failed = [why for why in checked.values() if why]
    for why in failed:
        print(f"FAILED {why}")
    print(f"{len(checked)} datasets checked under {args.results}, {len(failed)} failed")
    if not checked:
        print(f"FAILED {args.results}: holds no dataset (*.nc); nothing was verified")
        return 1
    return 1 if failed else 0
