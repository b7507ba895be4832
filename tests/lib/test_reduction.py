"""The modal reduction's fast path against its naive reference.

``lib.reduction`` solves the block-diagonalising Sylvester equation with LAPACK ``dtrsyl`` on the Schur blocks it
already has, and ``lib.design.models_at`` no longer splits the slow part of ``G_r_low`` again before each cut. Both
are checked here against the straightforward computation (scipy's ``solve_sylvester``, ``modal_reduction`` of
``G_r_low``), on the frequency response of every input-output entry.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import linalg

from lib import design, ports, reduction
from lib.cube import cube_cccc_ffff
from lib.titop import Section


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
    x = reduction._sylvester_schur(t1, t2, -t12)
    ref = reduction._sylvester_general(t1, t2, -t12)
    assert np.max(np.abs(t1 @ x - x @ t2 + t12)) < 1e-10 * np.max(np.abs(t12))
    assert np.max(np.abs(x - ref)) < 1e-9 * np.max(np.abs(ref))


def test_sylvester_warns_when_the_blocks_share_a_pole():
    with pytest.warns(RuntimeWarning, match="nearly singular"):
        reduction._sylvester_schur(np.array([[1.0]]), np.array([[1.0]]), np.array([[1.0]]))


def test_slow_poles_are_spurious_only_once_the_hub_closes_the_loop():
    """The 108 slow poles of a cube with imposed base accelerations carry an input-output contribution of order 1
    (the motion the imposed accelerations integrate to), so they cannot be removed on the cube; in the spacecraft G
    the 540 of the truss contribute at round-off level (tests/lib/test_spacecraft.py)."""
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
    monkeypatch.setattr(reduction, "_sylvester_schur", reduction._sylvester_general)
    low = (fast.g_r_low.a, fast.g_r_low.b, fast.g_r_low.c, fast.g_r_low.d)
    ref_r = reduction.modal_reduction(*low, omega_max=500.0)
    ref_spill = reduction.modal_reduction(*low, omega_max=1e4)
    assert ref_r.n_slow == 0 and fast.g_r.a.shape == ref_r.reduced[0].shape
    assert fast.g_check.a.shape == ref_spill.reduced[0].shape
    poles = np.abs(np.linalg.eigvals(fast.g_r.a))
    omega = np.r_[np.geomspace(0.05, 3e3, 60), poles[(poles > 0.05) & (poles < 500)][::7]]
    for model, ref in ((fast.g_r, ref_r), (fast.g_check, ref_spill)):
        g = ports.frequency_response(model.a, model.b, model.c, model.d, omega)
        assert _rel_err(g, ports.frequency_response(*ref.reduced, omega)) < 1e-10


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
