"""``python -m sleighsim.claims``: re-judge the claims ledger from a results tree without Snakemake,
reading the precision ladders and realizations its config files (``--config``, default
config/config.yaml) declare (see :func:`sleighsim.outputs.claims.main`; ``--help`` lists the options)."""

from .outputs.claims import main

if __name__ == "__main__":
    raise SystemExit(main())
