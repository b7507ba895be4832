"""LFT algebra against direct evaluation: random matrices and systems, repeated parameters, inverse, feedback."""

import numpy as np
import pytest
from trusscodesign.model import statespace
from trusscodesign.model.lft import LFT, Parameter

RNG = np.random.default_rng(42)
P = Parameter.percent("m", 800.0, 20.0)
Q = Parameter("q", 0.0, -1.0, 1.0)
W = np.logspace(-1, 2, 7)


def stable_ss(n, ny, nu, rng=RNG):
    a = rng.normal(size=(n, n))
    a -= (np.max(np.linalg.eigvals(a).real) + 1.0) * np.eye(n)
    return a, rng.normal(size=(n, nu)), rng.normal(size=(ny, n)), rng.normal(size=(ny, nu))


def resp(mats, w=W):
    return statespace.frequency_response(*mats, w)


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


# ------------------------------------------------------------------ mutation-testing additions (review of 2026-12-03)
def _static(m, blocks, params):
    nd_in = m.shape[1]
    return LFT(np.zeros((0, 0)), np.zeros((0, nd_in)), np.zeros((m.shape[0], 0)), m, blocks, params)


def test_star_product_with_external_channels_on_both_sides_matches_the_loop_equations():
    """Redheffer star product of two uncertain matrices, each with external inputs and outputs besides the inner ones,
    against solving the interconnection equations directly at sampled parameter values (both partitions of ``other``:
    its inner outputs first, its external outputs after; its inner inputs first, its external inputs after)."""
    rng = np.random.default_rng(7)
    ny1, nu1, ny2, nu2, a1, b1 = 4, 3, 3, 4, 2, 1  # self: 2 inner outputs, 1 inner input; other: 1 inner output, 2 inner inputs
    p0, p1 = 0.3 * rng.normal(size=(ny1, nu1)), 0.3 * rng.normal(size=(ny1, nu1))
    q0, q1 = 0.3 * rng.normal(size=(ny2, nu2)), 0.3 * rng.normal(size=(ny2, nu2))
    q, m = LFT.param(Q), LFT.param(P)
    p_lft = LFT.constant(p0) + p1 * q
    q_lft = LFT.constant(q0) + q1 * (m * (1.0 / 800.0) - 1.0)
    st = p_lft.star(q_lft, a1, b1)
    assert st.shape == ((ny1 - a1) + (ny2 - b1), (nu1 - b1) + (nu2 - a1))
    for qv, mv in ((-1.0, 640.0), (0.4, 900.0), (1.0, 960.0)):
        pm, qm = p0 + qv * p1, q0 + q1 * (mv / 800.0 - 1.0)
        # unknowns y1 (ny1), y2 (ny2): y1 = P [u_ext; y2[:b1]], y2 = Q [y1[-a1:]; v_ext]
        s1 = np.zeros((nu1, ny2))
        s1[nu1 - b1:, :b1] = np.eye(b1)
        s2 = np.zeros((nu2, ny1))
        s2[:a1, ny1 - a1:] = np.eye(a1)
        e1 = np.zeros((nu1, nu1 - b1))
        e1[:nu1 - b1] = np.eye(nu1 - b1)
        e2 = np.zeros((nu2, nu2 - a1))
        e2[a1:] = np.eye(nu2 - a1)
        lhs = np.block([[np.eye(ny1), -pm @ s1], [-qm @ s2, np.eye(ny2)]])
        rhs = np.block([[pm @ e1, np.zeros((ny1, nu2 - a1))], [np.zeros((ny2, nu1 - b1)), qm @ e2]])
        y = np.linalg.solve(lhs, rhs)
        direct = np.vstack([y[:ny1 - a1], y[ny1 + b1:]])
        np.testing.assert_allclose(st.evaluate({"q": qv, "m": mv})[3], direct, rtol=1e-10, atol=1e-12)


def test_negation_of_an_uncertain_system_whose_delta_channels_read_states():
    """``-G`` for a dynamic LFT whose Delta channels are driven by its states (C has z rows): ``-G(q)`` at each q."""
    s1 = stable_ss(4, 2, 2, rng=np.random.default_rng(8))
    q = LFT.param(Q)
    g = (np.eye(2) * (1.0 + 0.5 * q)) @ LFT.from_ss(*s1)  # the parameter acts on the outputs of the states
    assert np.any(g.c[:g.n_delta])
    g2 = LFT.from_ss(*stable_ss(3, 2, 2, rng=np.random.default_rng(9)))
    for qv in (-1.0, 0.6):
        ref = resp(g.evaluate({"q": qv}))
        np.testing.assert_allclose(resp((-g).evaluate({"q": qv})), -ref, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(resp((g2 - g).evaluate({"q": qv})), resp(g2.evaluate()) - ref, rtol=1e-9, atol=1e-12)


def test_grouped_and_transpose_keep_the_value_with_interleaved_parameters():
    """Delta channels of two parameters interleaved (q, m, q, m, q): grouping them by parameter (a permutation of the
    rows and columns of M) and transposing keep the value at every sampled point."""
    rng = np.random.default_rng(10)
    m = 0.3 * rng.normal(size=(5 + 2, 5 + 3))
    lf = _static(m, ["q", "m", "q", "m", "q"], {"q": Q, "m": P})
    grouped = lf.grouped()
    assert grouped.blocks == ["m", "m", "q", "q", "q"] and grouped.delta_structure() == [("m", 2), ("q", 3)]
    for vals in lf.sample(6, rng=1):
        ref = lf.evaluate(vals, normalized=True)[3]
        dv = np.array([vals[b] for b in lf.blocks])
        dd = np.diag(dv)
        direct = m[5:, 5:] + m[5:, :5] @ dd @ np.linalg.solve(np.eye(5) - m[:5, :5] @ dd, m[:5, 5:])
        np.testing.assert_allclose(ref, direct, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(grouped.evaluate(vals, normalized=True)[3], direct, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(lf.T.evaluate(vals, normalized=True)[3], direct.T, rtol=1e-12, atol=1e-14)
    sq = _static(0.3 * rng.normal(size=(5 + 2, 5 + 2)), ["q", "m", "q", "m", "q"], {"q": Q, "m": P})  # square io part
    for vals in sq.sample(4, rng=2):
        np.testing.assert_allclose(sq.T.evaluate(vals, normalized=True)[3], sq.evaluate(vals, normalized=True)[3].T,
                                   rtol=1e-12, atol=1e-14)


def test_scalar_times_an_ill_conditioned_matrix_keeps_its_small_singular_directions():
    """``m * A`` with A of condition number 1e6 (rank 3 numerically, not 1): the product is ``m A`` exactly."""
    u, _ = np.linalg.qr(np.random.default_rng(11).normal(size=(3, 3)))
    v, _ = np.linalg.qr(np.random.default_rng(12).normal(size=(3, 3)))
    amat = u @ np.diag([1.0, 1e-3, 1e-6]) @ v.T
    prod = LFT.param(P) * amat
    assert prod.occurrences() == {"m": 3}
    for mv in (640.0, 900.0):
        np.testing.assert_allclose(prod.evaluate({"m": mv})[3], mv * amat, rtol=0, atol=1e-12 * mv)


def test_percent_parameter_of_a_negative_nominal():
    p = Parameter.percent("x", -5.0, 10.0)
    assert (p.low, p.high) == pytest.approx((-5.5, -4.5)) and p.nominal == -5.0


def test_lft_to_and_from_statespace_keep_the_realisation_and_name_the_channels():
    import control as ct

    q = Parameter.percent("q", 2.0, 50.0)
    s1 = stable_ss(3, 2, 2, rng=np.random.default_rng(5))
    g = LFT.from_ss(*s1) @ (np.eye(2) * (1.0 + 0.5 * LFT.param(q)))
    sys = g.to_ss(["u1", "u2"], ["y1", "y2"], name="G")
    assert isinstance(sys, ct.StateSpace) and sys.name == "G"
    assert sys.input_labels == ["w_q_0", "w_q_1", "u1", "u2"] and sys.output_labels == ["z_q_0", "z_q_1", "y1", "y2"]
    for x, y in zip((sys.A, sys.B, sys.C, sys.D), (g.a, g.b, g.c, g.d)):
        np.testing.assert_array_equal(x, y)
    back = LFT.from_ss(ct.ss(*s1))  # a StateSpace alone gives the same certain system as its matrices
    for x, y in zip((back.a, back.b, back.c, back.d), (LFT.from_ss(*s1).a, LFT.from_ss(*s1).b, LFT.from_ss(*s1).c, LFT.from_ss(*s1).d)):
        np.testing.assert_array_equal(x, y)
    with pytest.raises(ValueError, match="2 inputs"):
        g.to_ss(["u1"], ["y1", "y2"])
    with pytest.raises(ValueError, match="continuous-time"):
        LFT.from_ss(ct.ss(*s1, dt=0.1))
    with pytest.raises(ValueError, match="all four matrices"):
        LFT.from_ss(s1[0], s1[1])


def test_percent_parameter_refuses_a_range_reaching_zero():
    with pytest.raises(ValueError, match="below 100.*cross zero"):  # was [-400, 2000] kg: a negative hub mass
        Parameter.percent("M_SC", 800.0, 150.0)
    with pytest.raises(ValueError, match="below 100"):
        Parameter.percent("M_SC", 800.0, 100)
    p = Parameter.percent("M_SC", 800.0, 20.0)
    assert (p.low, p.high) == (640.0, 960.0)


def test_from_delta_refuses_extrapolation():
    p = Parameter.percent("m", 800.0, 20.0)
    for delta in (2.0, -1.5, np.nan):
        with pytest.raises(ValueError, match=r"delta must be a normalised value in \[-1, 1\]"):  # 2 was 1120 kg, out of range
            p.from_delta(delta)
    assert p.from_delta(1.0) == 960.0 and p.from_delta(-1.0) == 640.0
    assert p.from_delta(0.3) == p.center + p.half_range * 0.3 and p.from_delta(1 + 1e-13) == p.center + p.half_range * (1 + 1e-13)
