"""The batched double-double engine: lane vectors against the scalar arithmetic, every lane against the scalar
engine DDFlow (bit for bit with per-lane steps, parameters per lane, padding and several blocks, the tangent
variant, jets), the common step against per-lane steps, the generated code's vector FMAs, and the refusals."""

from pathlib import Path

import numba
import numpy as np
import pytest

from sleighsim.engine import ddarith as dd
from sleighsim.engine import ddbatch, ddlanes, ddsimd
from sleighsim.engine.ddbatch import DDBatch, LaneError
from sleighsim.engine.ddtaylor import DDFlow, separation
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE

P = Params.paper(eps=0.1, K2=1.1)


def starts(rng, n):
    """n states near the reference state (velocities perturbed, angles spread over a turn)."""
    y = np.tile(np.array(REFERENCE_STATE), (n, 1))
    y[:, :3] += 0.2 * rng.normal(size=(n, 3))
    y[:, 3] = rng.uniform(-np.pi, np.pi, n)
    return y


@numba.njit(fastmath=False, error_model="numpy")
def _vector_ops(a, b, c, like):
    """ddarith's pair operations on lane vectors (rows of a, b, c), stored back into rows."""
    out, f = np.empty((8, a.shape[1])), np.empty(a.shape[1])
    ah, al, bh, bl = ddsimd.load(a[0], like), ddsimd.load(a[1], like), ddsimd.load(b[0], like), ddsimd.load(b[1], like)
    for r, (h, lo) in enumerate((dd.add(ah, al, bh, bl), dd.mul(ah, al, bh, bl), dd.div(ah, al, bh, bl),
                                 dd.div_d(ah, al, 3.0))):
        ddsimd.store(out[2 * r], h)
        ddsimd.store(out[2 * r + 1], lo)
    ddsimd.store(f, dd.fma(ah, bh, ddsimd.load(c, like)))
    return out, f


@numba.njit(fastmath=False, error_model="numpy")
def _scalar_ops(a, b, c):
    out, f = np.empty((8, a.shape[1])), np.empty(a.shape[1])
    for i in range(a.shape[1]):
        out[0, i], out[1, i] = dd.add(a[0, i], a[1, i], b[0, i], b[1, i])
        out[2, i], out[3, i] = dd.mul(a[0, i], a[1, i], b[0, i], b[1, i])
        out[4, i], out[5, i] = dd.div(a[0, i], a[1, i], b[0, i], b[1, i])
        out[6, i], out[7, i] = dd.div_d(a[0, i], a[1, i], 3.0)
        f[i] = dd.fma(a[0, i], b[0, i], c[i])
    return out, f


@pytest.mark.parametrize("width", [1, 4, 8, 16])
def test_lane_vectors_compute_the_scalar_pair_operations_bit_for_bit(rng, width):
    """add, mul, div, div_d and fma on vectors of ``width`` lanes give, lane by lane, exactly the scalar results."""
    a = np.array([dd.two_sum(x, y) for x, y in zip(rng.normal(size=width), 1e-17 * rng.normal(size=width))]).T.copy()
    b = np.array([dd.two_sum(x, y) for x, y in zip(rng.normal(size=width), 1e-17 * rng.normal(size=width))]).T.copy()
    c = rng.normal(size=width)
    (vec, vf), (sca, sf) = _vector_ops(a, b, c, (0.0,) * width), _scalar_ops(a, b, c)
    assert np.array_equal(vec, sca) and np.array_equal(vf, sf)


# ---------------------------------------------------------------- every lane is the scalar engine


@pytest.mark.parametrize("lanes", [1, 3, 16, 20])
def test_every_lane_is_ddflow_bit_for_bit(rng, lanes):
    """Different states (3: one block of 4 with a padding lane; 20: a block of 16 and one of 4 padded), each lane's
    grid its own: states and step counts identical to DDFlow's from the same state."""
    y = starts(rng, lanes)
    grids = np.sort(rng.uniform(0.0, 20.0, size=(lanes, 4)), axis=1)
    batch, flow = DDBatch(P), DDFlow(P)
    hi, lo = batch.propagate_grid(y, grids)
    for lane in range(lanes):
        fh, fl = flow.propagate_grid(y[lane], grids[lane])
        assert np.array_equal(fh, hi[lane]) and np.array_equal(fl, lo[lane]), lane
        assert flow.steps == batch.steps[lane]


def test_the_widest_block_is_two_of_the_hosts_vector_registers():
    """16 lanes with AVX-512 (8 doubles a register), 8 with AVX2 (4), where 16 would spill; 9 lanes then run as
    one block of 16 or two of 8, each lane bit for bit DDFlow's either way (the tests below run at the host's)."""
    from llvmlite import binding

    from sleighsim.engine import ddbatch

    doubles = ddbatch.host_vector_doubles()
    assert doubles == (8 if binding.get_host_cpu_features().get("avx512f") else 4)
    assert ddbatch.MAX_WIDTH == 2 * doubles and ddbatch.block_width(9) == 2 * doubles
    assert ddbatch.block_width(3) == 4 and ddbatch.block_width(1) == 1


def test_one_orbit_on_grids_of_different_lengths_is_ddflow_on_each_bit_for_bit():
    """propagate_grids: one start, three grids (3, 7 and 1 times; the shorter padded), each lane DDFlow's."""
    grids = [np.array([0.5, 3.0, 9.0]), np.linspace(0.0, 12.0, 7), np.array([4.0])]
    batch = DDBatch(P)
    got = batch.propagate_grids(REFERENCE_STATE, grids)
    assert [h.shape for h, _ in got] == [(3, 4), (7, 4), (1, 4)]
    for (hi, lo), grid, steps in zip(got, grids, batch.steps):
        flow = DDFlow(P)
        fh, fl = flow.propagate_grid(REFERENCE_STATE, grid)
        assert np.array_equal(fh, hi) and np.array_equal(fl, lo) and flow.steps == steps
    assert len(set(batch.steps)) == 3  # the grids' ends (9, 12, 4) did reach the lanes


def test_lanes_with_their_own_parameters_are_ddflow_bit_for_bit():
    """A row of eps (0.05 .. 0.3) in the lanes, one start: each lane is DDFlow with its own parameters."""
    params = [Params.paper(eps=e, K2=1.1) for e in (0.05, 0.1, 0.2, 0.3)]
    y = np.tile(REFERENCE_STATE, (4, 1))
    batch = DDBatch(params)
    hi, lo = batch.propagate(y, 25.0)
    steps = []
    for lane, p in enumerate(params):
        flow = DDFlow(p)
        fh, fl = flow.propagate(y[lane], 25.0)
        assert np.array_equal(fh, hi[lane]) and np.array_equal(fl, lo[lane])
        steps.append(flow.steps)
    assert list(batch.steps) == steps and len(set(steps)) == 4  # the parameters did reach the lanes
    assert batch.lanes == 4


def test_tangent_lanes_are_ddflow_bit_for_bit(rng):
    y, v = starts(rng, 5), rng.normal(size=(5, 4))
    grid = np.array([0.0, 4.0, 15.0])
    out = DDBatch(P).propagate_tangent_grid(y, v, grid)
    flow = DDFlow(P)
    for lane in range(5):
        ref = flow.propagate_tangent_grid(y[lane], v[lane], grid)
        assert all(np.array_equal(r, o[lane]) for r, o in zip(ref, out))


def test_jets_are_ddflow_jets(rng):
    y, v = starts(rng, 6), rng.normal(size=(6, 4))
    hi, lo = DDBatch(P, tol=1e-20).jet(y, v)
    flow = DDFlow(P, tol=1e-20)
    for lane in range(6):
        fh, fl = flow.jet(y[lane], v[lane])
        assert np.array_equal(fh, hi[lane]) and np.array_equal(fl, lo[lane])


def test_states_in_long_double_become_the_same_pairs(rng):
    y = starts(rng, 2).astype(np.longdouble) / 3
    hi, lo = ddbatch.as_pairs(y)
    for lane in range(2):
        h, lo_ = ddbatch.as_pair(y[lane])
        assert np.array_equal(h, hi[lane]) and np.array_equal(lo_, lo[lane]) and np.any(lo_ != 0)


def test_a_common_step_takes_the_smallest_and_agrees_within_the_tolerance(rng):
    """step="common": every lane makes as many steps as the lane that needs most (the parameters differ), and its
    states differ from the per-lane steps' by rounding and truncation only (measured 1e-31 after 30 time units)."""
    params = [Params.paper(eps=e, K2=1.1) for e in (0.05, 0.15, 0.3)]
    y = np.tile(REFERENCE_STATE, (3, 1))
    own, common = DDBatch(params), DDBatch(params, step="common")
    a, b = own.propagate(y, 30.0), common.propagate(y, 30.0)
    assert len(set(common.steps)) == 1 and common.steps[0] >= own.steps.max() > own.steps.min()
    assert separation(a, b).max() < 1e-29


# ---------------------------------------------------------------- the generated code


def test_the_lane_kernels_compile_to_vector_fmas():
    """The jet at 8 lanes compiled afresh (numba's disk cache hides the assembly): fused multiply-adds and
    subtracts on packed doubles (vfmadd/vfmsub ...pd) in 512-bit registers on an AVX-512 machine, 256-bit else."""
    flags = Path("/proc/cpuinfo").read_text() if Path("/proc/cpuinfo").exists() else ""
    if " avx2 " not in flags:
        pytest.skip("not an x86-64 machine with AVX2")
    register = "zmm" if " avx512f " in flags else "ymm"
    jet = numba.njit(ddlanes.jet.py_func, fastmath=False, error_model="numpy")
    batch = DDBatch(P, tol=1e-20)
    prog, Xh, Xl, ch, cl, yh, yl = batch._setup(*batch._states(np.tile(REFERENCE_STATE, (8, 1)), None),
                                                np.arange(8), False)
    jet(Xh, Xl, prog.ops, prog.lin_src, ch, cl, batch.order, 4, yh, yl, (0.0,) * 8)
    asm = jet.inspect_asm(jet.signatures[0])
    assert "vfmsub213pd" in asm or "vfmsub231pd" in asm or "vfmsub132pd" in asm
    packed = [line for line in asm.splitlines() if "vfm" in line and "pd" in line.split()[0]]
    assert packed and all(register in line for line in packed), packed[:3]


# ---------------------------------------------------------------- refusals


@pytest.mark.parametrize("kwargs, match", [({"tol": 1e-40}, "tol"), ({"tol": "x"}, "tol"), ({"step": "both"}, "step"),
                                           ({"params": []}, "params"), ({"params": [P, "eps"]}, "params")])
def test_bad_settings_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        DDBatch(**{"params": P, **kwargs})


@pytest.mark.parametrize("y0", [np.zeros((0, 4)), np.zeros((ddbatch.MAX_LANES + 1, 4)), np.zeros((2, 3)),
                                [[0.0, 0.1, np.nan, 0.0]], np.zeros(4)])
def test_bad_lane_counts_and_states_are_refused_naming_y0(y0):
    with pytest.raises(ValueError, match="y0"):
        DDBatch(P).propagate(y0, 1.0)


def test_mismatched_lanes_are_refused():
    with pytest.raises(ValueError, match="y0 holds 3 lanes, params 2"):
        DDBatch([P, P]).propagate(np.zeros((3, 4)), 1.0)
    with pytest.raises(ValueError, match="t_grid has 2 rows for 3 lanes"):
        DDBatch(P).propagate_grid(np.zeros((3, 4)), np.ones((2, 2)))
    with pytest.raises(ValueError, match="non-zero"):
        DDBatch(P).propagate_tangent_grid(np.zeros((2, 4)), [[1.0, 0, 0, 0], [0.0] * 4], [1.0])


def test_a_failing_lane_stops_the_batch_naming_lane_and_time():
    """Lane 2 overflows at once: LaneError names it and t = 0, its status NOT_FINITE, the others RUNNING (no result
    returned); too many steps in a later block: its first lane named, the earlier block's lanes done."""
    y = np.tile(REFERENCE_STATE, (4, 1))
    y[2] = [1e300, 1e300, 1e300, 0.0]
    with pytest.raises(LaneError, match=r"lane 2 at t = 0: a non-finite step or state \(3 other") as err:
        DDBatch(P).propagate(y, 1.0)
    assert err.value.lane == 2 and err.value.time == 0.0
    assert list(err.value.status) == [ddlanes.RUNNING, ddlanes.RUNNING, ddlanes.NOT_FINITE, ddlanes.RUNNING]
    T = np.r_[np.full(16, 0.5), np.full(2, 50.0)]
    with pytest.raises(LaneError, match="lane 16 at t = .*: more than max_steps") as err:
        DDBatch(P, max_steps=20).propagate(np.tile(REFERENCE_STATE, (18, 1)), T)
    assert np.all(err.value.status[:16] == ddlanes.OK) and err.value.steps[16] == 20
