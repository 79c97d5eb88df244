"""``python -m sleighsim.claims``: re-judge the claims ledger from a results tree without Snakemake,
reading the precision ladders and realizations its config files (``--config``, default
config/config.yaml) declare (see :func:`sleighsim.claims.ledger.main`; ``--help`` lists the options)."""

from sleighsim.claims.ledger import main

if __name__ == "__main__":
    raise SystemExit(main())
