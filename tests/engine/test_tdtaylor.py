"""The triple-double engine: its arithmetic against exact fractions and mpmath (also on lane vectors), its jets
against the double-double engine's, its orbits against heyoka's 256-bit real and between lanes, its tangent
vector against a finite difference, its refusals."""

from fractions import Fraction

import mpmath
import numba
import numpy as np
import pytest

from sleighsim.engine import ddsimd, tdtaylor
from sleighsim.engine import tdarith as td
from sleighsim.engine.ddbatch import DDBatch, LaneError
from sleighsim.engine.tdtaylor import TDBatch
from sleighsim.model.params import Params
from sleighsim.model.symmetries import REFERENCE_STATE

P = Params.paper(eps=0.1, K2=1.1)
#: A settled state of the main steady state (benchmarks/doubledouble.yaml: 2e4 time units from the reference).
SETTLED = (0.026915490034010996, 0.0237695612672332, 3.299243512952921, 2.5060573896810956)


def value(t) -> Fraction:
    return sum((Fraction(float(c)) for c in t), Fraction(0))


def random_triples(rng, n):
    """n numbers of 1e-3 .. 1e3 in magnitude with full 159-bit expansions, as (Fraction, triple)."""
    out = []
    for h, a, b in zip(rng.choice([-1, 1], n) * 10.0 ** rng.uniform(-3, 3, n), rng.integers(1, 2**62, n),
                       rng.integers(1, 2**62, n)):
        x = Fraction(float(h)) * (1 + Fraction(int(a), 2**70) + Fraction(int(b), 2**130))
        out.append((x, td.expansion(x)))
    return out


@pytest.mark.parametrize("op, exact_op", [("add", lambda x, y: x + y), ("mul", lambda x, y: x * y),
                                          ("div", lambda x, y: x / y)])
def test_triple_operations_round_below_the_claimed_unit(rng, op, exact_op):
    """Relative error on 300 random pairs of triples against the exact result (measured at most 2^-157.7; a
    double-double result would be 2^-106): below ROUNDING = 2^-150. Near-cancelling sums left out."""
    worst = 0.0
    for (x, X), (y, Y) in zip(random_triples(rng, 300), random_triples(rng, 300)):
        want = exact_op(x, y)
        if abs(want) < abs(x) / 4:
            continue
        worst = max(worst, float(abs(value(getattr(td, op)(*X, *Y)) - want) / abs(want)))
    assert worst < td.ROUNDING, np.log2(worst)


def test_sincos_and_angle_reduction_agree_with_mpmath(rng):
    worst = 0.0
    with mpmath.workprec(320):
        for x in [*rng.uniform(-7.0, 7.0, 100), 0.0, np.pi / 2, np.pi, 2 * np.pi]:
            X = td.expansion(Fraction(float(x)) * (1 + Fraction(1, 3 * 2**60)))
            r, arg = td.sincos(*X), sum(mpmath.mpf(c) for c in X)
            worst = max(worst, abs(sum(map(mpmath.mpf, r[:3])) - mpmath.sin(arg)),
                        abs(sum(map(mpmath.mpf, r[3:])) - mpmath.cos(arg)))
        assert worst < td.ROUNDING
        for x in (7.0, -1.0, 100.0, -2 * np.pi):
            r = sum(map(mpmath.mpf, td.reduce_angle(x, 0.0, 0.0)))
            turns = (x - r) / (2 * mpmath.pi)
            assert 0 <= r < 2 * mpmath.pi and abs(turns - mpmath.nint(turns)) < 1e-44


@numba.njit(fastmath=False, error_model="numpy")
def _vector_mul_div(a, b, like):
    out = np.empty((6, a.shape[1]))
    A = ddsimd.load(a[0], like), ddsimd.load(a[1], like), ddsimd.load(a[2], like)
    B = ddsimd.load(b[0], like), ddsimd.load(b[1], like), ddsimd.load(b[2], like)
    for r, v in enumerate((*td.mul(*A, *B), *td.div(*A, *B))):
        ddsimd.store(out[r], v)
    return out


def test_triples_in_lane_vectors_are_the_scalar_triples(rng):
    pairs = random_triples(rng, 16)
    a = np.array([t for _, t in pairs[:8]]).T.copy()
    b = np.array([t for _, t in pairs[8:]]).T.copy()
    out = _vector_mul_div(a, b, (0.0,) * 8)
    for lane in range(8):
        assert tuple(out[:3, lane]) == td.mul(*a[:, lane], *b[:, lane])
        assert tuple(out[3:, lane]) == td.div(*a[:, lane], *b[:, lane])


def test_states_are_split_exactly_or_to_the_nearest_triple():
    with mpmath.workprec(400):
        third = mpmath.mpf(1) / 3
    y = tdtaylor.as_triples([[1 / 3, 0.5, third, np.longdouble(1) / 3]])
    assert tuple(y[0, 0]) == (1 / 3, 0.0, 0.0) and tuple(y[0, 1]) == (0.5, 0.0, 0.0)
    assert abs(value(y[0, 2]) - Fraction(1, 3)) < Fraction(1, 2**158)
    assert value(y[0, 3]) == Fraction(*(np.longdouble(1) / 3).as_integer_ratio())


# ---------------------------------------------------------------- the engine


def test_jets_agree_with_the_double_double_engine(rng):
    """The same program in triples: Taylor coefficients (with a tangent vector) within double-double's rounding
    of the pair engine's, relative to each series' largest coefficient."""
    y, v = np.array([SETTLED, REFERENCE_STATE]), rng.normal(size=(2, 4))
    t = TDBatch(P, tol=1e-30).jet(y, v)
    hi, lo = DDBatch(P, tol=1e-30).jet(y, v)
    scale = np.abs(hi).max(axis=2, keepdims=True)
    assert np.abs((t[..., 0] - hi) + (t[..., 1] - lo) + t[..., 2]).max() / scale.max() < 1e-30


def _real256(rows, T):
    hy = pytest.importorskip("heyoka")
    from sleighsim.engine import integrators
    from sleighsim.model import equations

    fp = lambda x: hy.real(x, 256)  # noqa: E731
    ta = hy.taylor_adaptive(equations.heyoka_system(False, integrators.DELTA_SHIFT), [fp(0.1)] * 4,
                            tol=fp(2.0**-250), pars=[fp(0.0)] * equations.n_heyoka_pars(), fp_type=hy.real,
                            compact_mode=True, prec=256)
    integrators.register(ta, integrators.SLEIGH_ANGLES)
    with mpmath.workprec(320):
        ta.pars[:] = [fp(mpmath.nstr(mpmath.mpf(v.p) / v.q, 90)) for v in _exact_pars()]
    out = []
    for y in rows:
        ta.time = fp(0.0)
        integrators.load(ta, [fp(float(x)) for x in y])
        assert ta.propagate_until(fp(T), callback=integrators.bounded(ta))[0] == hy.taylor_outcome.time_limit
        out.append([Fraction(str(x)) for x in integrators.read(ta, 4)])
    return out


def _exact_pars():
    import sympy as sp

    from sleighsim.model import mechanics as mech

    exact = {s: sp.Rational(Fraction(v)) for s, v in zip(mech.PHYSICAL, P.values)}
    return [exact[s] for s in mech.PHYSICAL] + [sp.Rational(sp.expand(c.subs(exact)))
                                                for c in mech.derive().polynomial.coefficients]


def test_orbits_agree_with_heyokas_256_bit_real_to_1e_44():
    """Three lanes (a block of four with a padding lane) over 50 time units from the settled state and two
    neighbours: within 1e-44 of heyoka's real at 256 bits (tol 2^-250) (measured 4e-47 .. 2e-46; double-double's
    own rounding would leave 1e-30)."""
    rows = np.array([SETTLED, np.multiply(SETTLED, [1, 1, 1.0001, 1]), np.multiply(SETTLED, [1, 1.01, 1, 1])])
    ref = _real256(rows, 50.0)
    out = TDBatch(P).propagate(rows, 50.0)
    for lane in range(3):  # delta in [-pi, pi) in both, far from the wrap here
        d = max(abs(value(out[lane, i]) - ref[lane][i]) for i in range(4))
        assert float(d / max(abs(ref[lane][i]) for i in range(3))) < 1e-44, float(d)


def test_a_lane_does_not_depend_on_its_neighbours_or_the_block_width(rng):
    """The settled state alone (one lane), and as lane 5 of 16 among other states: the same triples bit for bit."""
    alone = TDBatch(P, tol=1e-40).propagate_grid([SETTLED], [3.0, 10.0])
    y = np.array(SETTLED) + 0.01 * rng.normal(size=(16, 4))
    y[5] = SETTLED
    batch = TDBatch(P, tol=1e-40)
    assert np.array_equal(batch.propagate_grid(y, [3.0, 10.0])[5], alone[0])


def test_tangent_vector_is_the_derivative_of_the_flow(rng):
    """v(t) against the central difference of two triple-double orbits 2^-40 apart (truncation ~e^2 ~ 1e-24,
    rounding 1e-45 / 1e-12): agreement to 1e-20 relative."""
    y0, v0 = np.array(REFERENCE_STATE), rng.normal(size=4)
    e = 2.0**-40
    batch = TDBatch(P, tol=1e-40)
    states, log_norm, direction = batch.propagate_tangent_grid([y0], [v0], [0.0, 10.0])
    pm = np.array([[td.renorm(y, sign * e * v, 0.0) for y, v in zip(y0, v0)] for sign in (1, -1)])  # exact
    plus, minus = batch.propagate_grid(pm, [10.0])[:, 0]
    fd = np.array([float((value(plus[i]) - value(minus[i])) / 2) for i in range(4)]) / e
    v = np.exp(log_norm[0, 1]) * direction[0, 1]
    assert np.abs(v - fd).max() / np.abs(fd).max() < 1e-20
    assert log_norm[0, 0] == pytest.approx(np.log(np.linalg.norm(v0)), abs=1e-15)


@pytest.mark.parametrize("kwargs, match", [({"tol": 1e-50}, "tol"), ({"tol": 1e-3}, "tol"), ({"step": "x"}, "step"),
                                           ({"params": []}, "params")])
def test_bad_settings_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        TDBatch(**{"params": P, **kwargs})


@pytest.mark.parametrize("y0", [np.zeros((0, 4)), np.zeros((2, 3)), [[0.0, np.inf, 1.0, 0.0]], np.zeros(4)])
def test_bad_states_are_refused_naming_y0(y0):
    with pytest.raises(ValueError, match="y0"):
        TDBatch(P).propagate(y0, 1.0)


def test_a_failing_lane_stops_the_batch_naming_lane_and_time():
    y = np.tile(REFERENCE_STATE, (3, 1))
    y[1] = [1e300, 1e300, 1e300, 0.0]
    with pytest.raises(LaneError, match="lane 1 at t = 0: a non-finite step or state"):
        TDBatch(P).propagate(y, 1.0)
