"""Progress of a long compiled kernel, read from the array of times it updates in place and logged by a
watcher thread.

The kernels are compiled without the GIL (``ddarith.jit``: ``nogil``), so the watcher runs while they do.
Times in the flow's time unit, wall time in seconds; one line every ``every`` seconds, none for a kernel
that ends sooner.
"""

from __future__ import annotations

import logging
import threading
import time

import numpy as np

log = logging.getLogger("sleighsim")

#: Seconds of wall time between two progress lines.
EVERY = 60.0


def watched(run, reached: np.ndarray, ends: np.ndarray, what: str, every: float | None = None):
    """``run()``'s result, with a line every ``every`` s while it runs: the share of the time done by the lane
    furthest behind (``reached``: a view of the times the kernel writes, one per lane; ``ends``: each lane's
    end time), the wall time so far and the time left at the rate so far; ``every`` defaults to EVERY."""
    every = EVERY if every is None else every
    stop = threading.Event()
    start = time.perf_counter()

    def report():
        while not stop.wait(every):
            k = int(np.argmin(reached / ends))
            done, spent = float(reached[k] / ends[k]), time.perf_counter() - start
            left = f"about {spent * (1 - done) / done:.0f} s left" if done > 0 else "no step yet"
            log.info("%s: %.0f%% (the lane furthest behind at t = %.6g of %.6g) after %.0f s; %s", what,
                     100 * done, reached[k], ends[k], spent, left)

    watcher = threading.Thread(target=report, name="progress", daemon=True)
    watcher.start()
    try:
        return run()
    finally:
        stop.set()
        watcher.join()
