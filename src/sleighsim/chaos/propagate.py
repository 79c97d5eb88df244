"""Propagation legs of the chaos engines, with their failure checks.

Conventions: engines take a compiled heyoka integrator (parameters already set; double, long
double or real128, the precision of ``ta.state``) and an optional ``callback`` (e.g.
``heyoka.callback.angle_reducer``) passed to every propagate call. The flows are assumed
autonomous, so ``ta.time`` is reset to 0 before every leg, except in ``megno``, whose quadratures
use the time explicitly. An integration that does not end with ``taylor_outcome.time_limit`` or
ends with a non-finite state raises RuntimeError naming the time (in the flow's time unit).
"""

from __future__ import annotations

import numpy as np


def _propagate(ta, dt, callback, t_label):
    """Propagate for dt (callback only if given); RuntimeError naming the time on failure."""
    import heyoka as hy

    dt = ta.state.dtype.type(dt)  # the integrator's precision (double or long double)
    res = ta.propagate_for(dt) if callback is None else ta.propagate_for(dt, callback=callback)
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"integration stopped at t = {t_label:.6g} (+{float(ta.time):.6g}): heyoka outcome {res[0]}")
    if not np.all(np.isfinite(ta.state)):
        raise RuntimeError(f"non-finite state at t = {t_label:.6g} (+{float(ta.time):.6g})")


def _propagate_until(ta, t_end, callback):
    import heyoka as hy

    res = ta.propagate_until(t_end) if callback is None else ta.propagate_until(t_end, callback=callback)
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"integration stopped at t = {float(ta.time):.6g} (target {float(t_end):.6g}): "
                           f"heyoka outcome {res[0]}")
    if not np.all(np.isfinite(ta.state)):
        raise RuntimeError(f"non-finite state at t = {float(ta.time):.6g}")
