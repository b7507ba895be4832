"""Sizing the truss by parts: the design vector's groups, their sides, the mass, and the refusals."""

from __future__ import annotations

import numpy as np
import pytest
from trusscodesign.model import spacecraft, truss
from trusscodesign.study import sizing


def test_the_paper_grouping_covers_every_member_once_and_its_mass_is_the_closed_form():
    """Core longerons: 3 cubes x 4 m; arm longerons: 2 x 4 m; bracing: 5 cubes x (4 battens + 5 diagonals of sqrt 2)."""
    g = sizing.Grouping.of()
    assert g.names == ["core_longerons", "arm_longerons", "bracing"]
    sides = g.sides([0.03, 0.025, 0.02])
    per_member = truss.t_truss_cubes().sections(spacecraft.truss_sections(sides))
    assert len(per_member) == 65
    expected = 2700.0 * (0.03**2 * 12 + 0.025**2 * 8 + 0.02**2 * (20 + 25 * np.sqrt(2)))
    assert g.mass([0.03, 0.025, 0.02]) == pytest.approx(expected, rel=1e-13)
    assert g.mass([0.02139] * 3) == pytest.approx(spacecraft.truss_mass(0.02139), rel=1e-13)


def test_bad_groupings_and_design_vectors_are_named():
    with pytest.raises(ValueError, match=r"repeated: \['battens'\]"):
        sizing.Grouping.of({"a": ["battens"], "b": ["battens", "diagonals"]})
    with pytest.raises(ValueError, match="non-empty list of section keys"):
        sizing.Grouping.of({"a": "longerons"})
    g = sizing.Grouping.of()
    with pytest.raises(ValueError, match=r"theta must hold 3 finite sides \[m\], one per group"):
        g.sides([0.02, 0.02])
    with pytest.raises(ValueError, match=r"theta\['arm_longerons'\] must be a section side in \[0.015, 0.03\] m, got 2.5"):
        g.sides([0.02, 2.5, 0.02])
    incomplete = sizing.Grouping.of({"longerons": ["longerons"], "battens": ["battens"]})
    with pytest.raises(ValueError, match="no section for the members"):
        incomplete.mass([0.02, 0.02])


def test_the_mass_coefficients_give_the_mass_of_any_design_vector():
    g = sizing.Grouping.of()
    c = g.mass_coefficients()
    np.testing.assert_allclose(c, 2700.0 * np.array([12.0, 8.0, 20 + 25 * np.sqrt(2)]), rtol=1e-12)
    for theta in ([0.015, 0.03, 0.02], [0.0213, 0.0187, 0.0291]):
        assert np.asarray(theta) ** 2 @ c == pytest.approx(g.mass(theta), rel=1e-12)
