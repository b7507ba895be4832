"""The modal reduction's fast path against its naive reference.

``trusscodesign.model.reduction`` solves the block-diagonalising Sylvester equation with LAPACK ``dtrsyl`` on the Schur blocks it
already has, and ``trusscodesign.study.design.models_at`` no longer splits the slow part of ``G_r_low`` again before each cut. Both
are checked here against the straightforward computation (scipy's ``solve_sylvester``, ``modal_reduction`` of
``G_r_low``), on the frequency response of every input-output entry.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import linalg
from trusscodesign.model import reduction, spacecraft, statespace
from trusscodesign.model.cube import cube_cccc_ffff
from trusscodesign.model.titop import Section
from trusscodesign.study import design


def _rel_err(g: np.ndarray, ref: np.ndarray) -> float:
    """Largest error of every input-output entry over frequency, relative to that entry's own largest magnitude (an
    entry that is zero at every frequency, up to 1e-14 of the largest entry, is compared in absolute terms there)."""
    scale = np.maximum(np.abs(ref).max(axis=2), 1e-14 * np.abs(ref).max())
    return float((np.abs(g - ref).max(axis=2) / scale).max())


def test_sylvester_on_schur_blocks_matches_scipy():
    rng = np.random.default_rng(3)
    a = rng.standard_normal((40, 40))
    t, _, k = linalg.schur(a, output="real", sort=lambda re, im: re < 0)
    assert 0 < k < 40
    t1, t12, t2 = t[:k, :k], t[:k, k:], t[k:, k:]
    x = reduction.sylvester_schur(t1, t2, -t12)
    ref = reduction.sylvester_general(t1, t2, -t12)
    assert np.max(np.abs(t1 @ x - x @ t2 + t12)) < 1e-10 * np.max(np.abs(t12))
    assert np.max(np.abs(x - ref)) < 1e-9 * np.max(np.abs(ref))


def test_sylvester_warns_when_the_blocks_share_a_pole():
    with pytest.warns(RuntimeWarning, match="nearly singular"):
        reduction.sylvester_schur(np.array([[1.0]]), np.array([[1.0]]), np.array([[1.0]]))


def test_slow_poles_are_spurious_only_once_the_hub_closes_the_loop():
    """The 108 slow poles of a cube with imposed base accelerations carry an input-output contribution of order 1
    (the motion the imposed accelerations integrate to), so they cannot be removed on the cube; in the spacecraft G
    the 540 of the truss contribute at round-off level (tests/model/test_spacecraft.py)."""
    cube = cube_cccc_ffff(Section.square(0.015))
    split = reduction.split_slow(cube.a, cube.b, cube.c, cube.d)
    assert split.n_slow == 108 and split.contribution > 0.1


def test_residualize_above_rejects_a_bad_cut():
    a = -np.eye(2)
    with pytest.raises(ValueError, match="omega_max"):
        reduction.residualize_above(a, np.ones((2, 1)), np.ones((1, 2)), np.zeros((1, 1)), -1.0)


def test_models_at_matches_the_naive_reduction(monkeypatch):
    """G_r and the spillover model of ``models_at`` against G_r_low reduced with scipy's Sylvester solver: the
    same response on every entry (Delta channels open), relative to the entry's own size, to 1e-10, at the modes and
    between them."""
    h = 0.015
    fast = design.models_at(h)
    monkeypatch.setattr(reduction, "sylvester_schur", reduction.sylvester_general)
    low = (fast.g_r_low.a, fast.g_r_low.b, fast.g_r_low.c, fast.g_r_low.d)
    ref_r = reduction.modal_reduction(*low, omega_max=500.0)
    ref_spill = reduction.modal_reduction(*low, omega_max=1e4)
    assert ref_r.n_slow == 0 and fast.g_r.a.shape == ref_r.reduced[0].shape
    assert fast.g_check.a.shape == ref_spill.reduced[0].shape
    poles = np.abs(np.linalg.eigvals(fast.g_r.a))
    omega = np.r_[np.geomspace(0.05, 3e3, 60), poles[(poles > 0.05) & (poles < 500)][::7]]
    for model, ref in ((fast.g_r, ref_r), (fast.g_check, ref_spill)):
        g = statespace.frequency_response(model.a, model.b, model.c, model.d, omega)
        assert _rel_err(g, statespace.frequency_response(*ref.reduced, omega)) < 1e-10


def test_models_at_rejects_unordered_cut_frequencies():
    with pytest.raises(ValueError, match="omega_min < omega_max < omega_spill"):
        design.models_at(0.02, omega_max=2e4)


def test_slow_pole_check_refuses_nan_and_infinite_limits():
    """A NaN limit let a slow pole that carries the whole response through; an infinite omega_min failed deep in an SVD."""
    a, b, c, d = np.array([[-1e-3]]), np.array([[1.0]]), np.array([[1e-3]]), np.zeros((1, 1))  # DC gain 1, all slow
    with pytest.raises(ValueError, match="not spurious"):
        reduction.modal_reduction(a, b, c, d)
    for bad in (np.nan, -1.0, np.inf):
        with pytest.raises(ValueError, match="max_contribution"):
            reduction.modal_reduction(a, b, c, d, max_contribution=bad)
    with pytest.raises(ValueError, match="omega_min"):
        reduction.split_slow(a, b, c, d, omega_min=np.inf)


# ------------------------------------------------------------------ mutation-testing additions (review of 2026-12-03)
def _mixed_modal(seed, slow, fast):
    """Dense realisation (random similarity) of decoupled first- and second-order modes with known poles."""
    rng = np.random.default_rng(seed)
    blocks = [np.array([[-p]]) for p in slow]
    for w, z in fast:
        blocks.append(np.array([[0.0, 1.0], [-w**2, -2 * z * w]]))
    a0 = linalg.block_diag(*blocks)
    n = a0.shape[0]
    t = rng.normal(size=(n, n)) + 3 * np.eye(n)
    a = t @ a0 @ np.linalg.inv(t)
    return a, rng.normal(size=(n, 2)), rng.normal(size=(3, n)), rng.normal(size=(3, 2))


def test_split_slow_is_an_exact_decomposition_of_a_dense_realisation():
    """G = G_fast + C_s (sI - A_s)^-1 B_s at every frequency, the slow poles are the ones below omega_min, and
    residualising the fast part above a cut keeps its DC gain and the kept poles."""
    slow, fast = [1e-4, 3e-3], [(0.5, 0.02), (3.0, 0.01), (40.0, 0.05)]
    a, b, c, d = _mixed_modal(5, slow, fast)
    split = reduction.split_slow(a, b, c, d, omega_min=0.01)
    assert split.n_slow == 2
    np.testing.assert_allclose(np.sort(np.abs(split.slow_poles)), slow, rtol=1e-8)
    w = np.r_[0.0, np.geomspace(1e-4, 1e3, 25)]
    g = statespace.frequency_response(a, b, c, d, w)
    g_fast = statespace.frequency_response(*split.fast, w)
    g_slow = statespace.frequency_response(*split.slow, np.zeros_like(d), w)
    # exact to round-off, whose scale is eps cond(A) (1e8 here: poles from 1e-4 to 40 rad/s in a random basis); the
    # dense reference itself is off by 4e-10 relative at DC, and the split by 1.5e-9 on one AMD EPYC machine
    assert np.abs(g_fast + g_slow - g).max() < np.finfo(float).eps * np.linalg.cond(a) * np.abs(g).max()
    fa, fb, fc, fd = split.fast
    (ra, rb, rc, rd), n_high = reduction.residualize_above(fa, fb, fc, fd, 10.0)
    assert n_high == 2 and ra.shape[0] == 4 and np.abs(np.linalg.eigvals(ra)).max() < 10.0
    dc_fast = fd - fc @ np.linalg.solve(fa, fb)
    np.testing.assert_allclose(rd - rc @ np.linalg.solve(ra, rb), dc_fast, rtol=1e-9, atol=1e-12 * np.abs(dc_fast).max())
    # the modes kept by the cut are those of the fast part: the same residues there (low frequencies, away from 40 rad/s
    # the residualised mode's dynamic part is O((w / 40)^2) of its static part)
    g_res = statespace.frequency_response(ra, rb, rc, rd, np.array([0.05]))
    g_ref = statespace.frequency_response(fa, fb, fc, fd, np.array([0.05]))
    assert np.abs(g_res - g_ref).max() < 1e-4 * np.abs(g_ref).max()


def test_slow_contribution_is_relative_to_the_whole_response_from_omega_min():
    """G = G_slow + G_fast with G_slow = k a / (s + a) (a = 1e-3 rad/s) and G_fast = 1 / (s + 1): the contribution is
    max over omega_min * [1, 1e4] of |G_slow| / |G_slow + G_fast|, largest at omega_min itself."""
    k, p = 0.3, 1e-3
    a = np.diag([-p, -1.0])
    b, c, d = np.array([[k * p], [1.0]]), np.array([[1.0, 1.0]]), np.zeros((1, 1))
    split = reduction.split_slow(a, b, c, d, omega_min=0.01)
    s = 1j * 0.01 * np.logspace(0, 4, 9)
    g_slow, g_fast = k * p / (s + p), 1.0 / (s + 1.0)
    expected = np.max(np.abs(g_slow) / np.abs(g_slow + g_fast))
    assert split.n_slow == 1 and split.contribution == pytest.approx(expected, rel=1e-9)
    assert split.contribution == pytest.approx(abs(g_slow[0]) / abs(g_slow[0] + g_fast[0]), rel=1e-9)


def test_reduction_keeps_dc_and_removes_the_right_poles():
    g = spacecraft.open_loop(0.03).G
    low = reduction.modal_reduction(g.A, g.B, g.C, g.D)
    red = reduction.modal_reduction(g.A, g.B, g.C, g.D, omega_max=500.0)
    assert low.n_slow == 540 and low.reduced[0].shape[0] == 784
    poles = np.abs(np.linalg.eigvals(red.reduced[0]))
    assert poles.max() <= 500.0 and red.reduced[0].shape[0] + red.n_high == 784
    dc = [m[3] - m[2] @ np.linalg.solve(m[0], m[1]) for m in (low.reduced, red.reduced)]
    assert np.max(np.abs(dc[1] - dc[0])) < 1e-6 * np.max(np.abs(dc[0]))
    with pytest.raises(ValueError, match="omega_max"):
        reduction.modal_reduction(g.A, g.B, g.C, g.D, omega_max=0.001)
