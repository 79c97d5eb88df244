"""Entry point kept for ``python -m sleighsim.resultdiff OLD NEW``, the command the developers'
guide names; the comparison itself is :mod:`sleighsim.ops.resultdiff`."""

from sleighsim.ops.resultdiff import main

if __name__ == "__main__":
    raise SystemExit(main())
