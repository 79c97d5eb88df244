"""The measured price of the Lyapunov grid's row verdicts (``scenes.grid_verdict``) for the cost estimate.

A row's verdict runs the judge-power audit's cycles whatever its eps, in the arithmetic its gauge names, so its
price is its Taylor steps per spike cycle times the measured cost of one such step
(``claims.faithful.row_verdict_cost``: the judged rows' median wall time over their steps per cycle). Steps per
cycle grow steeply as eps falls (the cycle lengthens and stiffens), which a work model in time units does not see;
they follow a power law in eps fitted by log-log least squares over the rows the run gauged. Seconds of wall time
on one core; eps dimensionless.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from sleighsim.analysis.fits import loglog
from sleighsim.claims.faithful import row_verdict_cost
from sleighsim.io.netcdf import read_dataset
from sleighsim.scenes import grid

#: The summary's section (``ops.summary``): {scene: :func:`from_grid`'s answer}.
SECTION = "row_verdicts"


def from_grid(ds) -> dict | None:
    """A grid dataset's verdict prices: cost_per_cycle_step_s, the steps-per-cycle law (exponent k, log_coef c:
    steps = exp(c) eps^k, the exponent's standard error, the rows fitted) and per row its eps, steps per cycle,
    verdict wall time and verdict; None when the grid judged no row or gauged fewer than two."""
    cost = row_verdict_cost(ds)
    if "row_gain_steps_per_cycle" not in ds or not math.isfinite(cost):
        return None
    eps, steps = ds.eps.values, ds.row_gain_steps_per_cycle.values
    ok = np.isfinite(steps) & (steps > 0)
    k, c, se = loglog(eps[ok], steps[ok])
    if not math.isfinite(k):
        return None
    rows = [{"eps": float(e), "steps_per_cycle": float(s), "verdict_wall_s": float(w), "verdict": str(v)}
            for e, s, w, v in zip(eps, steps, ds.row_verdict_wall_s.values, ds.row_verdict.values)]
    return {"cost_per_cycle_step_s": float(cost), "rows": rows,
            "steps_per_cycle_law": {"exponent": float(k), "log_coef": float(c), "exponent_stderr": float(se),
                                    "rows_fitted": int(ok.sum())}}


def measured(results_dir, config: dict | None) -> dict:
    """{scene: :func:`from_grid`} for the Lyapunov grid scenes of ``config`` whose dataset lies in
    ``results_dir``/data and that judged a row."""
    out = {}
    for name, block in ((config or {}).get("scenes") or {}).items():
        path = Path(results_dir) / "data" / f"{name}.nc"
        if block.get("kind") == grid.LYAPUNOV_GRID.name and path.is_file():
            section = from_grid(read_dataset(path))
            if section:
                out[name] = section
    return out


def verdict_price(section: dict, eps: float, mcfg: dict, tcfg: dict) -> float:
    """Seconds of the verdict of a row at ``eps`` of the target block ``tcfg``: the cost per step times the law's
    steps per cycle, times the target's realizations x T over the measured block's ``mcfg`` (the cycles run)."""
    law, (m, t) = section["steps_per_cycle_law"], (mcfg["verdict"], tcfg["verdict"])
    runs = (t["realizations"] * t["T"]) / (m["realizations"] * m["T"])
    return section["cost_per_cycle_step_s"] * math.exp(law["log_coef"]) * eps ** law["exponent"] * runs


def _judged(cfg: dict) -> np.ndarray:
    """Mask of the rows a grid block judges here: from verdict.eps_min on, not left elsewhere."""
    return (grid.axes(cfg)[0] >= cfg["verdict"]["eps_min"]) & ~grid.elsewhere(cfg)


def chunk_seconds(section: dict, mcfg: dict, tcfg: dict, measured_chunks: dict, base: float) -> list[float]:
    """Seconds of each chunk job of the target grid ``tcfg``: ``base`` (start-up), its rows' work outside the
    verdict (``grid.grid_rows(verdict=False)``, time units) at the measured rate, and the verdict of each row it
    judges (:func:`verdict_price`). The rate: the measured chunks' seconds above start-up less their rows' verdict
    times, over their work outside the verdict (``measured_chunks``: {chunk index: seconds})."""
    m_rows, n_m = grid.grid_rows(mcfg, verdict=False), mcfg["n_chunks"]
    walls = {round(r["eps"], 12): r["verdict_wall_s"] for r in section["rows"]}
    spent, work = 0.0, 0.0
    for k, cpu in measured_chunks.items():
        rows = m_rows[k::n_m]
        verdicts = float(np.nansum([walls.get(round(e, 12), 0.0) for e, _ in rows]))
        spent += max(cpu - base - verdicts, 0.0)
        work += sum(w for _, w in rows)
    rate = spent / work if work > 0 else 0.0
    t_rows, judged = grid.grid_rows(tcfg, verdict=False), _judged(tcfg)
    cost = [rate * w + (verdict_price(section, e, mcfg, tcfg) if judged[i] else 0.0)
            for i, (e, w) in enumerate(t_rows)]
    n_t = tcfg["n_chunks"]
    return [float(base + sum(cost[k::n_t])) for k in range(n_t)]  # plain floats: the record is YAML
