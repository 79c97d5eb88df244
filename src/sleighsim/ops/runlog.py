"""Logging for workflow jobs: progress and errors go to the rule's log file."""

from __future__ import annotations

import contextlib
import logging
import signal


def _terminate(signum, frame):
    raise SystemExit(128 + signum)


@contextlib.contextmanager
def logging_to(path):
    """Send the ``sleighsim`` logger to ``path``; log any exception with its traceback, then re-raise.

    SIGTERM (what Snakemake sends an interrupted job) becomes SystemExit, so cleanup
    code runs and no temporary file is left behind."""
    logger = logging.getLogger("sleighsim")
    handler = logging.FileHandler(path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        yield logger
    except BaseException as err:
        if isinstance(err, SystemExit):
            logger.error("job terminated (exit %s)", err.code)
        else:
            logger.exception("job failed")
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)
        logger.removeHandler(handler)
        handler.close()
