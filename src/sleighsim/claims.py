"""``python -m sleighsim.claims``: re-judge the claims ledger from a results tree without Snakemake
(see :func:`sleighsim.outputs.claims.main`; ``--help`` lists the options)."""

from .outputs.claims import main

if __name__ == "__main__":
    raise SystemExit(main())
