"""The gauge's gain on lanes of the batched engines (sleighsim.chaos.lane_gain): the QR-restarted runs carry the
tangent map whole (the product of their R factors has the singular values of the map propagated in one go), in
double-double and triple-double, with each orbit's own horizon."""

import numpy as np
import pytest

from sleighsim.chaos import lane_gain
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.engine.tdtaylor import TDBatch, as_triples
from sleighsim.model.params import Params

P = Params.paper(eps=0.1, K2=1.1)
STATES = np.array([[0.0269154900340110, 0.0237695612672332, 3.299243512952921, 2.5060573896810956],
                   [0.00629153102944064, -0.0047627596021641615, 3.3860754061535774, 1.4306947470407945]])


def _map_singular_values(batch, y, T):
    """Singular values of the tangent map over T from y, its four columns propagated in one run."""
    ys = (np.repeat(y[None], 4, axis=0), np.zeros((4, 4))) if isinstance(batch, DDBatch) else np.repeat(y[None], 4, 0)
    out = batch.propagate_tangent_grid(ys, np.eye(4), [T])
    ln, d = out[-2][:, -1], out[-1][:, -1]
    return np.linalg.svd((d * np.exp(ln)[:, None]).T, compute_uv=False)


@pytest.mark.parametrize("make", [lambda: DDBatch(P), lambda: TDBatch(P, 1e-40)])
def test_qr_restarts_carry_the_whole_tangent_map(make):
    batch = make()
    starts = (STATES, np.zeros_like(STATES)) if isinstance(batch, DDBatch) else as_triples(STATES)
    runs = lane_gain.tangent_runs(batch, starts, [40.0, 20.0], tau=10.0)
    assert [r["R"].shape[0] for r in runs] == [4, 2] and runs[1]["t"].tolist() == [10.0, 20.0]
    for run, y, T in zip(runs, STATES, (40.0, 20.0)):
        product = np.eye(4)
        for r in run["R"]:
            product = r @ product
        want = _map_singular_values(make(), y, T)
        assert np.allclose(np.linalg.svd(product, compute_uv=False), want, rtol=1e-8)


@pytest.mark.parametrize("spikes, cycles", [([20.0, 60.0], 1), ([20.0, 70.0], 0), ([20.0], 0)])
def test_a_cycle_counts_only_when_the_run_holds_its_map_from_every_start(spikes, cycles):
    """Spikes at 20 and 60 over a run of 100 (QR every 10): the cycle's map from each start in it runs to 100 at
    the latest; one spike later, it would run past the end; one spike alone makes no cycle."""
    out = lane_gain.lane_gains(DDBatch(P), (STATES[:1], np.zeros((1, 4))), [100.0], [spikes], tau=10.0)
    assert out[0]["ln_gain"].size == cycles and np.isfinite(out[0]["ln_gain_max"]) == bool(cycles)
