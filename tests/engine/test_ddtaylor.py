"""The double-double engine: pair arithmetic against exact fractions and mpmath, the derived Taylor recurrences
against the model's right-hand side and Jacobian, the integrator against heyoka's real128 flow, its energy drift,
its tangent vector against a finite difference of two orbits, its refusals."""

from fractions import Fraction

import mpmath
import numpy as np
import pytest

from sleighsim.engine import ddarith as dd
from sleighsim.engine import ddtaylor
from sleighsim.engine.ddtaylor import DDFlow
from sleighsim.model import equations
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE

P = Params.paper(eps=0.1, K2=1.1)
U = dd.ROUNDING


def exact(hi, lo=0.0) -> Fraction:
    """The value of a pair as a fraction."""
    return Fraction(float(hi)) + Fraction(float(lo))


def random_pairs(rng, n):
    """n pairs with magnitudes over 1e-3 .. 1e3, signs mixed, lo a full 53-bit tail."""
    hi = rng.choice([-1, 1], n) * 10.0 ** rng.uniform(-3, 3, n)
    return [dd.pair(Fraction(h) + Fraction(h) * Fraction(float(t)) * Fraction(2) ** -53)
            for h, t in zip(hi, rng.uniform(-1, 1, n))]


def rel(value: Fraction, pair) -> float:
    """|pair - value| / |value|."""
    return float(abs(exact(*pair) - value) / abs(value))


# ---------------------------------------------------------------- pair arithmetic


def test_error_free_transformations_are_exact(rng):
    for a, b in rng.normal(size=(200, 2)) * 10.0 ** rng.integers(-20, 20, size=(200, 2)):
        s, e = dd.two_sum(a, b)
        assert Fraction(s) + Fraction(e) == Fraction(a) + Fraction(b) and s == a + b
        p, e = dd.two_prod(a, b)
        assert Fraction(p) + Fraction(e) == Fraction(a) * Fraction(b) and p == a * b


@pytest.mark.parametrize("op, exact_op, bound", [
    ("add", lambda x, y: x + y, 4), ("sub", lambda x, y: x - y, 4), ("mul", lambda x, y: x * y, 8),
    ("div", lambda x, y: x / y, 8)])
def test_pair_operations_round_within_a_few_units(rng, op, exact_op, bound):
    """Relative error of each operation on 300 random pairs against the exact rational result, in units of
    2^-106 (a double-only result, error ~2^-53, would fail by 15 orders of magnitude). Sums of nearly opposite
    numbers are left out of add/sub (there the bound is relative to the operands, not the result)."""
    a, b = random_pairs(rng, 300), random_pairs(rng, 300)
    worst = 0.0
    for x, y in zip(a, b):
        want = exact_op(exact(*x), exact(*y))
        if want == 0 or abs(want) < abs(exact(*x)) / 4:
            continue
        worst = max(worst, rel(want, getattr(dd, op)(*x, *y)))
    assert worst < bound * U, worst / U


def test_pair_by_double_operations_round_within_a_few_units(rng):
    worst = 0.0
    for x, y in zip(random_pairs(rng, 200), rng.uniform(1, 40, 200)):
        worst = max(worst, rel(exact(*x) * Fraction(y), dd.mul_d(*x, y)), rel(exact(*x) / Fraction(y), dd.div_d(*x, y)))
    assert worst < 4 * U, worst / U


def test_constants_are_pi_to_well_below_a_pair():
    with mpmath.workprec(300):
        for c, value in ((dd.HALF_PI, mpmath.pi / 2), (dd.PI, mpmath.pi), (dd.TWO_PI, 2 * mpmath.pi)):
            err = mpmath.mpf(c[0]) + mpmath.mpf(c[1]) + mpmath.mpf(c[2]) - value
            assert abs(err) < 1e-47 * value and abs(c[1]) <= 2.0**-53 * abs(c[0]) * 1.0000001


def test_sincos_agrees_with_mpmath_in_every_quadrant(rng):
    worst = 0.0
    with mpmath.workprec(200):
        for x in [*rng.uniform(-7.0, 7.0, 150), 0.0, np.pi / 2, np.pi, -np.pi, 2 * np.pi]:
            xh, xl = dd.pair(Fraction(float(x)) * (1 + Fraction(1, 3 * 2**60)))
            sh, sl, ch, cl = dd.sincos(xh, xl)
            arg = mpmath.mpf(xh) + mpmath.mpf(xl)
            worst = max(worst, float(abs(mpmath.mpf(sh) + sl - mpmath.sin(arg))),
                        float(abs(mpmath.mpf(ch) + cl - mpmath.cos(arg))))
    assert worst < 4 * U, worst / U


@pytest.mark.parametrize("x", [7.0, -1.0, 2 * np.pi, -2 * np.pi, 100.0, -1e-30, 0.0])
def test_reduce_angle_lands_in_one_turn_by_whole_turns(x):
    rh, rl = dd.reduce_angle(x, 0.0)
    with mpmath.workprec(300):
        r = mpmath.mpf(rh) + mpmath.mpf(rl)
        turns = (mpmath.mpf(x) - r) / (2 * mpmath.pi)
        assert 0 <= r < 2 * mpmath.pi
        assert abs(turns - mpmath.nint(turns)) < 1e-30


# ---------------------------------------------------------------- the derived recurrences


@pytest.fixture(scope="module")
def flow():
    return DDFlow(P)


def test_program_is_derived_from_the_polynomial_form():
    """Every K[j] of the polynomial form and d delta/dt's coefficients reach the program; the tangent
    program differentiates every operation (one tangent operation or more per primal one)."""
    plain, tangent = ddtaylor.program(False), ddtaylor.program(True)
    form = equations.mech.derive().polynomial
    assert set(form.K) <= set(plain.lin_coef)
    assert plain.n_vars == 4 and tangent.n_vars == 8
    assert len(tangent.ops) > len(plain.ops) and tangent.n_series > plain.n_series
    assert {int(c) for c in plain.ops[:, 0]} == {ddtaylor.MUL, ddtaylor.LIN, ddtaylor.DIV, ddtaylor.SINCOS,
                                                 ddtaylor.DERIV}
    assert {ddtaylor.MUL2, ddtaylor.DIVT} <= {int(c) for c in tangent.ops[:, 0]}


def test_jet_first_orders_are_the_vector_field_and_its_derivative(flow, rng):
    """x_1 = f(x) and x_2 = J(x) f(x) / 2 (the model's lambdified rhs and Jacobian, in double), and for the
    tangent v_1 = J(x) v, at random states."""
    for _ in range(5):
        y = np.r_[rng.normal(size=3), rng.uniform(-np.pi, np.pi)]
        v = rng.normal(size=4)
        hi, lo = flow.jet(y, v)
        f, J = equations.rhs(y, P), equations.jacobian(y, P)
        scale = np.abs(f).max() + 1
        np.testing.assert_allclose(hi[:4, 1], f, rtol=0, atol=1e-14 * scale)
        np.testing.assert_allclose(hi[:4, 2], J @ f / 2, rtol=0, atol=1e-13 * scale**2)
        np.testing.assert_allclose(hi[4:, 1], J @ v, rtol=0, atol=1e-13 * scale * np.abs(v).max())
        assert hi.shape == (8, flow.order + 1)


def test_order_and_step_follow_heyokas_rule():
    assert ddtaylor.taylor_order(1e-32) == 38 and ddtaylor.taylor_order(2.0**-52) == 20
    assert DDFlow(P, tol=1e-20).order == 25


# ---------------------------------------------------------------- refusals


@pytest.mark.parametrize("tol", [1e-40, 1e-3, 0.0, -1e-30, float("nan"), "x"])
def test_tolerance_out_of_range_is_refused(tol):
    with pytest.raises(ValueError, match="tol"):
        DDFlow(P, tol=tol)


@pytest.mark.parametrize("y0", [[0.0, 0.1, np.nan, 0.0], [0.0, np.inf, 1.0, 0.0], [0.0, 0.1, 1.0],
                                ([0.0] * 4, [0.0] * 3)])
def test_bad_states_are_refused(flow, y0):
    with pytest.raises(ValueError, match="state"):
        flow.propagate(y0, 1.0)


@pytest.mark.parametrize("grid", [[], [1.0, 0.5], [-1.0, 1.0], [0.0, np.nan]])
def test_bad_grids_are_refused(flow, grid):
    with pytest.raises(ValueError, match="t_grid"):
        flow.propagate_grid(REFERENCE_STATE, grid)


def test_a_zero_tangent_vector_and_too_many_steps_are_refused():
    with pytest.raises(ValueError, match="non-zero"):
        DDFlow(P).propagate_tangent_grid(REFERENCE_STATE, np.zeros(4), [1.0])
    with pytest.raises(RuntimeError, match="max_steps"):
        DDFlow(P, max_steps=3).propagate(REFERENCE_STATE, 100.0)


def test_an_overflowing_step_is_refused_naming_the_time():
    with pytest.raises(RuntimeError, match=r"failed at t = 0: a non-finite step or state"):
        DDFlow(P).propagate([1e300, 1e300, 1e300, 0.0], 1.0)


def test_states_in_any_precision_become_the_same_pair():
    hy = pytest.importorskip("heyoka")
    third = Fraction(1, 3)
    for y in (np.full(4, 1 / 3), np.full(4, np.longdouble(1) / 3), np.full(4, hy.real128(1) / 3, dtype=hy.real128)):
        hi, lo = ddtaylor.as_pair(y)
        assert float(abs(exact(hi[0], lo[0]) - third)) <= float(abs(exact(np.asarray(y).astype(float)[0]) - third))
        assert hi[0] == 1 / 3
    hi, lo = ddtaylor.as_pair(np.full(4, hy.real128(1) / 3, dtype=hy.real128))
    assert float(abs(exact(hi[0], lo[0]) - third)) < 2.0**-105 / 3


def test_propagate_is_the_last_grid_state(flow):
    hi, lo = flow.propagate_grid(REFERENCE_STATE, [0.0, 3.0, 7.5])
    fh, fl = flow.propagate(REFERENCE_STATE, 7.5)
    assert np.array_equal(hi[-1], fh) and np.array_equal(lo[-1], fl)
    # t = 0 is y0, up to delta's round trip through the stored angle delta + pi (a pair: 3e-33 here)
    assert np.array_equal(hi[0, :3], REFERENCE_STATE[:3]) and abs(hi[0, 3] + lo[0, 3]) < 1e-32


# ---------------------------------------------------------------- against real128, energy, tangent


def quad_grid(y0, grid, tol=2.0**-112):
    """heyoka's real128 flow (integrators.flow, quad) from y0 sampled on grid (grid[0] = 0): rows as pairs."""
    hy = pytest.importorskip("heyoka")
    from sleighsim.engine import integrators
    from sleighsim.precision import Precision

    ta, _ = integrators.flow(False, tol, Precision.QUAD)
    integrators.set_pars(ta, P)
    ta.time = hy.real128(0)
    hi, lo = ddtaylor.as_pair(y0)
    integrators.load(ta, hi.astype(hy.real128) + lo.astype(hy.real128))
    out = ta.propagate_grid(np.asarray(grid).astype(hy.real128), callback=integrators.bounded(ta))
    assert out[0] == hy.taylor_outcome.time_limit
    pairs = [ddtaylor.as_pair(r) for r in integrators.samples(ta, out[-1])]
    return np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])


def test_agrees_with_real128_over_100_time_units(flow):
    """From the reference state: dd (tol 1e-32) and real128 (tol 2^-112) stay within 1e-28 of each other
    (measured 2.3e-30 at t = 100; double's rounding alone would be 1e-16)."""
    grid = np.linspace(0.0, 100.0, 11)
    sep = ddtaylor.separation(flow.propagate_grid(REFERENCE_STATE, grid), quad_grid(REFERENCE_STATE, grid))
    assert sep.max() < 1e-28, sep


def test_steps_are_heyokas_at_the_same_tolerance(flow):
    """Same order (38) and step rule as heyoka's real128 flow at tol 1e-32: the same number of steps over 100
    time units from the reference state, within one (a different safety factor or norm would move it by
    several per cent)."""
    hy = pytest.importorskip("heyoka")
    from sleighsim.engine import integrators
    from sleighsim.precision import Precision

    ta, _ = integrators.flow(False, 1e-32, Precision.QUAD)
    integrators.set_pars(ta, P)
    ta.time = hy.real128(0)
    integrators.load(ta, np.array(REFERENCE_STATE).astype(hy.real128))
    res = ta.propagate_until(hy.real128(100), callback=integrators.bounded(ta))
    flow.propagate(REFERENCE_STATE, 100.0)
    assert ta.order == flow.order and abs(flow.steps - res[3]) <= 1, (flow.steps, res[3])


def test_energy_is_conserved_to_the_pairs_rounding(flow):
    """Over 1000 time units from the reference state (about 2500 steps), the energy (at 200 bits from the
    pairs) drifts by less than 1e-29 relative."""
    hi, lo = flow.propagate_grid(REFERENCE_STATE, np.linspace(0.0, 1000.0, 41))
    drift = ddtaylor.energy_drift(P, hi, lo)
    assert 0 < drift < 1e-29, drift


def test_tangent_vector_is_the_derivative_of_the_flow(flow, rng):
    """v(t) against the central difference (y(x + e v) - y(x - e v)) / 2 e of two dd orbits, e = 2^-30 (the
    perturbed states exact as pairs): its truncation is of order e^2 (third derivative) ~ 1e-18, its rounding
    1e-32 / 1e-9 = 1e-23; the tangent's log-norm is that difference's norm."""
    y0, v0 = np.array(REFERENCE_STATE), rng.normal(size=4)
    grid, e = np.array([0.0, 10.0, 60.0]), 2.0**-30
    hi, lo, log_norm, direction = flow.propagate_tangent_grid(y0, v0, grid)
    plus = flow.propagate_grid(dd.two_sum(y0, e * v0), grid)
    minus = flow.propagate_grid(dd.two_sum(y0, -e * v0), grid)
    fd = np.array([[float((exact(plus[0][i, j], plus[1][i, j]) - exact(minus[0][i, j], minus[1][i, j])) / 2)
                    for j in range(4)] for i in range(len(grid))]) / e
    v = np.exp(log_norm)[:, None] * direction
    assert np.abs(v - fd).max() / np.abs(fd).max() < 1e-15  # measured 3.1e-17
    assert log_norm[0] == pytest.approx(np.log(np.linalg.norm(v0)), abs=1e-15)


def test_separation_subtracts_pairs_and_wraps_the_angle():
    a = (np.array([[1.0, 0.5, 2.0, 3.0]]), np.array([[1e-20, 0.0, 0.0, 0.0]]))
    b = (np.array([[1.0, 0.5, 2.0, 3.0 - 2 * np.pi]]), np.zeros((1, 4)))
    assert ddtaylor.separation(a, b)[0] == pytest.approx(1e-20 / 2.0, rel=1e-12)


# ---------------------------------------------------------------- one spike cycle of the main steady state

CYCLE = 2322.0  # one spike cycle of the main state (time units; mean interval measured in benchmarks/doubledouble.yaml)


@pytest.fixture(scope="module")
def settled():
    """The main steady state: (0, 0.1, 1, 0) at the label 0.1127 (eps 0.1, b 1, K2 1.1) after 2e4 time units
    in double (heyoka at its epsilon), a double state."""
    hy = pytest.importorskip("heyoka")
    from sleighsim.engine import integrators
    from sleighsim.model.symmetries import REFERENCE_LABEL, state_at_label

    ta, _ = integrators.flow(False, 2.0**-52)
    integrators.set_pars(ta, P)
    ta.time = 0.0
    integrators.load(ta, state_at_label(REFERENCE_STATE, P, REFERENCE_LABEL))
    assert ta.propagate_until(2e4, callback=integrators.bounded(ta))[0] == hy.taylor_outcome.time_limit
    return integrators.read(ta, 4).astype(float)


@pytest.fixture(scope="module")
def cycle_runs(settled):
    """The settled state over one cycle sampled every 10 time units, in double-double (tol 1e-32) and real128
    (2^-112, about 16 s of CPU), and their separation."""
    grid = np.arange(0.0, CYCLE + 1.0, 10.0)
    dd_run, quad_run = DDFlow(P).propagate_grid(settled, grid), quad_grid(settled, grid)
    return grid, dd_run, quad_run, ddtaylor.separation(quad_run, dd_run)


@pytest.fixture(scope="module")
def gauge(settled):
    """chaos.faithfulness.spike_cycle_gains on the settled orbit: double, 4 tangent vectors, 12000 time units,
    tau 5 (about 12 s of CPU)."""
    from sleighsim.chaos import faithfulness
    from sleighsim.engine import integrators

    ta, _ = integrators.sleigh_tangent(4, 2.0**-52, True)
    integrators.set_pars(ta, P)
    return faithfulness.spike_cycle_gains(ta, settled, T=12000.0, tau=5.0)


def test_one_cycle_agrees_with_real128_to_1e_28_until_the_approach_to_the_spike(cycle_runs):
    """Until 700 time units before the cycle's spike the two orbits agree to 1e-28 (measured: at most 4e-30);
    the approach to the spike then amplifies their difference (measured 6e-19 at the cycle's end)."""
    from sleighsim.engine import transient

    grid, _, quad_run, sep = cycle_runs
    spikes = transient.spike_times(grid, quad_run[0][:, 1], factor=1.8, block=50.0)
    assert len(spikes) == 1, spikes
    quiet = grid < spikes[0] - 700.0
    assert quiet.sum() > 100 and sep[quiet].max() < 1e-28, sep[quiet].max()
    assert sep[-1] > 1e3 * sep[quiet].max()  # the amplification this engine exists for is there


def test_one_cycle_separation_stays_within_the_gauge(cycle_runs, gauge):
    """After one cycle, double-double and real128 differ by less than G_max x 2^-106 (the gauge's bound on the
    amplified rounding of a cycle; measured ln G_max 36.3: 7e-17; separation measured 6e-19)."""
    sep = cycle_runs[3]
    assert np.isfinite(gauge["ln_gain_max"])
    assert sep[-1] < np.exp(gauge["ln_gain_max"]) * dd.ROUNDING, (sep[-1], gauge["ln_gain_max"])


def test_faithfulness_gauge_puts_double_double_far_below_the_bound(gauge):
    """G_max x 2^-106 far below FAITHFUL_MAX = 1e-3 (measured 1e-16.2), while double's is of order 1 (1e-0.2)."""
    from sleighsim.chaos import faithfulness
    from sleighsim.precision import Precision

    ln_g = gauge["ln_gain_max"]
    assert (ln_g + np.log(dd.ROUNDING)) / np.log(10) < -12
    n = gauge["steps_per_cycle"]  # the rounding injected per cycle is counted per Taylor step
    assert faithfulness.follows(ln_g, dd.ROUNDING, steps_per_cycle=n) == faithfulness.FOLLOWS
    assert faithfulness.follows(ln_g, Precision.DOUBLE.rounding, steps_per_cycle=n) == faithfulness.DOES_NOT_FOLLOW


def test_energy_drift_over_a_cycle_is_at_the_1e_30_level(cycle_runs):
    """Energy (200 bits from the pairs) over one cycle from the settled state: measured 6e-31."""
    _, (hi, lo), _, _ = cycle_runs
    drift = ddtaylor.energy_drift(P, hi, lo)
    assert 0 < drift < 3e-30, drift
