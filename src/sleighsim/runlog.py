"""Logging for workflow jobs: progress and errors go to the rule's log file."""

from __future__ import annotations

import contextlib
import logging


@contextlib.contextmanager
def logging_to(path):
    """Send the ``sleighsim`` logger to ``path``; log any exception with its traceback, then re-raise."""
    logger = logging.getLogger("sleighsim")
    handler = logging.FileHandler(path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    try:
        yield logger
    except BaseException:
        logger.exception("job failed")
        raise
    finally:
        logger.removeHandler(handler)
        handler.close()
