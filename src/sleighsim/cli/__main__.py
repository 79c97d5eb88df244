"""``python -m sleighsim.cli SUBCOMMAND ...``: the sleighsim command without its installed script."""

from sleighsim.cli import main

raise SystemExit(main())
