"""Section crossings of a sampled orbit (sleighsim.engine.ddsection): delta's turns counted right even when the
sampling step is near half a turn, and each crossing solved on its jet to where a direct double-double run
puts delta on the section."""

import math

import numpy as np

from sleighsim.engine import ddsection
from sleighsim.engine.ddbatch import DDBatch
from sleighsim.engine.ddtaylor import DDFlow
from sleighsim.model.params import Params

P = Params.paper(eps=0.1, K2=1.1)
#: A state of the sleigh's steady regime (delta turns about once per 2 time units).
STATE = np.array([0.0269154900340110, 0.0237695612672332, 3.299243512952921, 2.5060573896810956])


def test_turns_are_counted_right_at_a_step_near_half_a_turn():
    """Sampled every 1 (delta moves about 3.2, close to pi, per step: a plain unwrap miscounts), the unwrapped
    delta is the finely sampled one at the same times."""
    flow = DDFlow(P)
    coarse, fine = np.arange(0.0, 60.5, 1.0), np.arange(0.0, 60.05, 0.1)
    hi_c, _ = flow.propagate_grid(STATE, coarse)
    hi_f, _ = flow.propagate_grid(STATE, fine)
    d = ddsection.unwrapped_delta(hi_c, coarse)
    assert np.allclose(d, np.unwrap(hi_f[:, 3])[::10], atol=1e-9)
    assert not np.allclose(np.unwrap(hi_c[:, 3]), d, atol=1.0)  # the plain unwrap does miscount here


def test_crossings_put_delta_on_the_section():
    flow, batch = DDFlow(P), DDBatch(P)
    grid = np.arange(0.0, 40.25, 0.5)
    hi, lo = flow.propagate_grid(STATE, grid)
    t, X = ddsection.crossings(batch, hi, lo, grid)
    assert t.size >= 15 and np.all(np.diff(t) > 1.0)
    at_h, at_l = flow.propagate_grid(STATE, t)
    delta = np.mod(at_h[:, 3] + at_l[:, 3] + math.pi, 2 * math.pi) - math.pi
    assert np.max(np.abs(delta)) < 1e-12
    assert np.allclose(X, (at_h + at_l)[:, :3], atol=1e-12)
    near, _ = ddsection.crossings(batch, hi, lo, grid, near=[20.0], half_width=3.0)
    assert 2 <= near.size <= 4 and np.all(np.abs(near - 20.0) <= 3.6)


def test_quarter_crossings_put_delta_on_its_quarter_and_name_the_class():
    """Each crossing of delta = k pi/2 lands on its quarter to 1e-12 in a direct double-double run, with the
    class k mod 4 of that quarter, and delta's residual there is at double's rounding."""
    flow, batch = DDFlow(P), DDBatch(P)
    grid = np.arange(0.0, 40.05, 0.1)
    hi, lo = flow.propagate_grid(STATE, grid)
    t, X, k, residual = ddsection.quarter_crossings(batch, hi, lo, grid)
    assert t.size >= 4 * 15 and set(k) == {0, 1, 2, 3} and np.max(residual) < 1e-15
    at_h, at_l = flow.propagate_grid(STATE, t)
    off = np.mod(at_h[:, 3] + at_l[:, 3] - k * (math.pi / 2) + math.pi, 2 * math.pi) - math.pi
    assert np.max(np.abs(off)) < 1e-12 and np.allclose(X, (at_h + at_l)[:, :3], atol=1e-12)


def test_the_residual_does_not_lose_digits_as_delta_unwraps():
    """Far along the orbit (delta unwrapped to thousands of radians) a crossing's residual is still taken from the
    sample's own delta: the solved crossing puts delta on the section to 1e-12."""
    flow, batch = DDFlow(P), DDBatch(P)
    grid = np.arange(0.0, 3000.05, 0.1)
    hi, lo = flow.propagate_grid(STATE, grid)
    t, _, k, _ = ddsection.quarter_crossings(batch, hi, lo, grid)
    at_h, at_l = flow.propagate_grid(STATE, t[-5:])
    off = np.mod(at_h[:, 3] + at_l[:, 3] - k[-5:] * (math.pi / 2) + math.pi, 2 * math.pi) - math.pi
    assert abs(ddsection.unwrapped_delta(hi, grid)[-1]) > 1000 and np.max(np.abs(off)) < 1e-12
