"""LFT algebra against direct evaluation: random matrices and systems, repeated parameters, inverse, feedback."""

import numpy as np
import pytest

from lib import ports
from lib.lft import LFT, Parameter

RNG = np.random.default_rng(42)
P = Parameter.percent("m", 800.0, 20.0)
Q = Parameter("q", 0.0, -1.0, 1.0)
W = np.logspace(-1, 2, 7)


def stable_ss(n, ny, nu, rng=RNG):
    a = rng.normal(size=(n, n))
    a -= (np.max(np.linalg.eigvals(a).real) + 1.0) * np.eye(n)
    return a, rng.normal(size=(n, nu)), rng.normal(size=(ny, n)), rng.normal(size=(ny, nu))


def resp(mats, w=W):
    return ports.frequency_response(*mats, w)


def test_parameter_normalisation_and_errors():
    assert np.isclose(P.from_delta(1.0), 960.0) and np.isclose(P.to_delta(640.0), -1.0)
    with pytest.raises(ValueError, match="outside"):
        P.to_delta(1000.0)
    with pytest.raises(ValueError, match="low < high"):
        Parameter("x", 1.0, 2.0, 1.0)


@pytest.mark.parametrize("value", [640.0, 700.0, 800.0, 960.0])
def test_rational_functions_of_a_parameter(value):
    m = LFT.param(P)
    inv = m.inv()
    assert inv.occurrences() == {"m": 1}
    np.testing.assert_allclose(inv.evaluate({"m": value})[3], [[1.0 / value]], rtol=1e-13)
    # (m^2 + 3 m) / (m + 1): repeated parameter
    expr = (m @ m + 3.0 * m) @ (m + 1.0).inv()
    assert expr.occurrences() == {"m": 4}
    np.testing.assert_allclose(expr.evaluate({"m": value})[3], [[(value**2 + 3 * value) / (value + 1)]], rtol=1e-12)
    grouped = expr.grouped()
    assert grouped.delta_structure() == [("m", 4)]


def test_matrix_algebra_with_two_parameters():
    a0, a1, b0 = RNG.normal(size=(3, 3)), RNG.normal(size=(3, 3)), RNG.normal(size=(3, 3)) + 4 * np.eye(3)
    m, q = LFT.param(P), LFT.param(Q)
    amat = LFT.constant(a0) + a1 * q          # A(q) = a0 + q a1
    bmat = LFT.constant(b0) + np.eye(3) * (m * (1.0 / 800.0))  # B(m) = b0 + m/800 I
    expr = amat @ bmat.inv() - LFT.hstack(amat, bmat) @ LFT.vstack(np.eye(3), np.eye(3))
    for mv, qv in [(640.0, -1.0), (800.0, 0.3), (960.0, 1.0)]:
        am, bm = a0 + qv * a1, b0 + mv / 800.0 * np.eye(3)
        direct = am @ np.linalg.inv(bm) - (am + bm)
        np.testing.assert_allclose(expr.evaluate({"m": mv, "q": qv})[3], direct, rtol=1e-10, atol=1e-12)


def test_systems_series_sum_feedback_lower_and_star():
    s1, s2 = stable_ss(4, 2, 2), stable_ss(3, 2, 2)
    q = LFT.param(Q)
    g1 = LFT.from_ss(*s1) @ (np.eye(2) * (1.0 + 0.5 * q))  # input gain (1 + q/2)
    g2 = LFT.from_ss(*s2)
    for qv in (-1.0, 0.0, 0.7):
        k = 1.0 + 0.5 * qv
        g1v = (s1[0], s1[1] * k, s1[2], s1[3] * k)
        r1, r2 = resp(g1v), resp(s2)
        np.testing.assert_allclose(resp((g2 @ g1).evaluate({"q": qv})), np.einsum("ijw,jkw->ikw", r2, r1), rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(resp((g1 + g2).evaluate({"q": qv})), r1 + r2, rtol=1e-9, atol=1e-12)
        fb = g1.feedback(0.1 * np.eye(2)).evaluate({"q": qv})
        direct = np.stack([np.linalg.solve(np.eye(2) + r1[:, :, i] @ (0.1 * np.eye(2)), r1[:, :, i]) for i in range(W.size)], axis=2)
        np.testing.assert_allclose(resp(fb), direct, rtol=1e-9, atol=1e-12)
        # lower LFT with a static gain on the second channel pair
        kgain = np.array([[0.3]])
        low = g1.lower(kgain, 1, 1).evaluate({"q": qv})
        direct = np.stack([r1[:1, :1, i] + r1[:1, 1:, i] @ kgain @ np.linalg.solve(np.eye(1) - r1[1:, 1:, i] @ kgain, r1[1:, :1, i])
                           for i in range(W.size)], axis=2)
        np.testing.assert_allclose(resp(low), direct, rtol=1e-9, atol=1e-12)
        # star product with inner size 1 equals the lower LFT of g1 with g2[0,0] when g2 is 1x1 inside
        st = g1.star(LFT.constant([[0.3]]), 1, 1).evaluate({"q": qv})
        np.testing.assert_allclose(resp(st), direct, rtol=1e-9, atol=1e-12)


def test_random_static_lft_matches_formula():
    nd, ny, nu = 3, 2, 2
    m = RNG.normal(size=(nd + ny, nd + nu)) * 0.3
    lf = LFT([], np.zeros((0, nd + nu)), np.zeros((nd + ny, 0)), m, ["q"] * nd, {"q": Q})
    for qv in (-1.0, -0.2, 0.9):
        delta = qv * np.eye(nd)
        m11, m12, m21, m22 = m[:nd, :nd], m[:nd, nd:], m[nd:, :nd], m[nd:, nd:]
        direct = m22 + m21 @ delta @ np.linalg.solve(np.eye(nd) - m11 @ delta, m12)
        np.testing.assert_allclose(lf.evaluate({"q": qv}, normalized=True)[3], direct, rtol=1e-12)


def test_singular_inverse_and_ill_posed_feedback_raise():
    with pytest.raises(ValueError, match="singular inverse"):
        LFT.param(Q).inv()  # q has centre 0: 1/q has no LFT realisation around delta = 0
    with pytest.raises(ValueError, match="ill-posed"):
        LFT.constant([[1.0]]).feedback(-1.0 * np.ones((1, 1)))  # 1 / (1 - 1)
    with pytest.raises(ValueError, match="unknown parameter"):
        LFT.param(P).evaluate({"z": 1.0})
    with pytest.raises(ValueError, match="outside"):
        LFT.param(P).evaluate({"m": 2000.0})


def test_right_multiplication_by_a_matrix_is_the_matrix_product():
    a = np.array([[1.0, 2.0], [0.0, 1.0]])
    sym = LFT.param(P) * np.array([[1.0, 0.5], [0.5, 1.0]])
    value = sym.evaluate({"m": 700.0})[3]
    np.testing.assert_allclose((a * sym).evaluate({"m": 700.0})[3], a @ value, rtol=1e-13)  # not value @ a
    np.testing.assert_allclose((np.ones((3, 2)) * sym).evaluate({"m": 700.0})[3], np.ones((3, 2)) @ value, rtol=1e-13)
    np.testing.assert_allclose((2.0 * sym).evaluate({"m": 700.0})[3], 2.0 * value, rtol=1e-13)


def test_scalar_sum_is_symmetric_and_square_only():
    sym = LFT.param(P) * np.array([[1.0, 0.5], [0.5, 1.0]])
    value = sym.evaluate({"m": 900.0})[3]
    for expr, expected in ((3.0 - sym, 3.0 * np.eye(2) - value), (LFT.constant(3.0) + sym, 3.0 * np.eye(2) + value),
                           (sym + 3.0, value + 3.0 * np.eye(2))):
        np.testing.assert_allclose(expr.evaluate({"m": 900.0})[3], expected, rtol=1e-13)
    with pytest.raises(ValueError, match="square"):
        LFT.constant(np.ones((2, 3))) + 1.0


def test_normalised_evaluation_defaults_to_the_nominal_not_the_centre():
    h = Parameter("h", 0.03, 0.015, 0.03)  # nominal at the upper bound, as the tunable section side
    g = LFT.param(h) + LFT.param(Q)
    assert g.evaluate({})[3][0, 0] == pytest.approx(0.03)
    assert g.evaluate({}, normalized=True)[3][0, 0] == pytest.approx(0.03)


def test_bad_matrices_and_ill_posed_substitution_name_the_cause():
    with pytest.raises(ValueError, match="B must be"):
        LFT.from_ss(np.eye(3), np.ones((2, 3)), np.ones((3, 2)), np.zeros((2, 2)))  # B and C transposed: same sizes
    with pytest.raises(ValueError, match="square"):
        LFT.from_ss(np.ones((2, 3)), np.ones((2, 1)), np.ones((1, 2)), 0.0)
    with pytest.raises(ValueError, match="finite"):
        LFT.constant([[np.nan]])
    bad = LFT(np.zeros((0, 0)), np.zeros((0, 2)), np.zeros((2, 0)), [[2.0, 1.0], [1.0, 0.0]], ["q"], {"q": Q})
    with pytest.raises(ValueError, match="ill-posed at"):
        bad.substitute({"q": 0.5}, normalized=True)  # 1 - 2 * 0.5 = 0
