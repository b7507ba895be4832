"""The mass / pointing front: non-dominated points, their hypervolume, and the expected improvement of a candidate
whose mass is exact and whose J_c is a normal prediction, against brute force and Monte Carlo."""

from __future__ import annotations

import numpy as np
import pytest
from trusscodesign.study import pareto


def test_nondominated_keeps_the_front_and_drops_ties_and_dominated_points():
    m = np.array([1.0, 2.0, 3.0, 2.5, 1.0, 4.0])
    y = np.array([5.0, 3.0, 1.0, 3.5, 6.0, 1.0])
    assert pareto.nondominated(m, y).tolist() == [0, 1, 2]
    assert pareto.nondominated(np.array([]), np.array([])).tolist() == []


def _hypervolume_on_a_grid(m, y, ref, n=1500):
    xs = np.linspace(0.0, ref[0], n, endpoint=False) + ref[0] / (2 * n)
    ys = np.linspace(0.0, ref[1], n, endpoint=False) + ref[1] / (2 * n)
    gx, gy = np.meshgrid(xs, ys)
    covered = np.zeros(gx.shape, bool)
    for mi, yi in zip(m, y):
        covered |= (gx >= mi) & (gy >= yi)
    return covered.mean() * ref[0] * ref[1]


def test_hypervolume_equals_the_dominated_area_counted_on_a_grid():
    rng = np.random.default_rng(1)
    m, y = rng.uniform(0.1, 0.9, 12), rng.uniform(0.1, 0.9, 12)
    ref = (1.0, 1.0)
    assert pareto.hypervolume(m, y, ref) == pytest.approx(_hypervolume_on_a_grid(m, y, ref), abs=3e-3)
    assert pareto.hypervolume(np.array([0.5]), np.array([0.5]), ref) == pytest.approx(0.25, rel=1e-14)
    assert pareto.hypervolume(np.array([1.5]), np.array([0.5]), ref) == 0.0  # beyond the reference: nothing


@pytest.mark.parametrize("mass, mu, sigma", [(0.35, 0.4, 0.1), (0.05, 0.95, 0.3), (0.8, 0.05, 0.02), (0.6, 2.0, 0.5)])
def test_expected_improvement_with_an_exact_mass_equals_monte_carlo(mass, mu, sigma):
    rng = np.random.default_rng(2)
    m, y = np.array([0.2, 0.5, 0.7]), np.array([0.8, 0.5, 0.3])
    ref = (1.0, 1.2)
    base = pareto.hypervolume(m, y, ref)
    samples = rng.normal(mu, sigma, 40000)
    mc = np.mean([pareto.hypervolume(np.append(m, mass), np.append(y, s), ref) - base for s in samples])
    exact = pareto.expected_improvement(np.array([mass]), np.array([mu]), np.array([sigma]), m, y, ref)[0]
    assert exact == pytest.approx(mc, rel=2e-2, abs=1e-4)


def test_expected_improvement_without_uncertainty_is_the_improvement_and_zero_when_dominated():
    m, y, ref = np.array([0.5]), np.array([0.5]), (1.0, 1.0)
    ei = pareto.expected_improvement(np.array([0.25, 0.75]), np.array([0.25, 0.75]), np.array([1e-9, 1e-9]), m, y, ref)
    assert ei[0] == pytest.approx(0.75 * 0.75 - 0.25, rel=1e-6)  # new box 0.75 x 0.75 minus the overlap 0.5 x 0.5
    assert ei[1] == pytest.approx(0.0, abs=1e-9)
    # an empty front: the whole box of the candidate
    assert pareto.expected_improvement(np.array([0.5]), np.array([0.5]), np.array([1e-9]), np.array([]), np.array([]),
                                       ref)[0] == pytest.approx(0.25, rel=1e-6)


def test_bad_inputs_are_named():
    with pytest.raises(ValueError, match="sigma must be positive"):
        pareto.expected_improvement(np.array([0.5]), np.array([0.5]), np.array([0.0]), np.array([]), np.array([]), (1, 1))
    with pytest.raises(ValueError, match="mass and pointing must have the same length"):
        pareto.nondominated(np.array([1.0, 2.0]), np.array([1.0]))
