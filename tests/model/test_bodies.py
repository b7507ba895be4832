"""The bodies attached to the truss: hub, antenna, PMA, solar panel on its SADM."""

import numpy as np
import pytest
from trusscodesign.model import bodies
from trusscodesign.model.lft import Parameter


def test_rigid_hub_needs_a_positive_definite_inertia_and_mass_range():
    pts = {"P1": [0.0, 0.0, 0.0], "A": [1.0, 0.0, 0.0]}
    for inertia in (np.zeros((3, 3)), np.diag([1.0, 0.0, 1.0])):
        with pytest.raises(ValueError, match="positive-definite"):  # was a LinAlgError (singular matrix)
            bodies.rigid_hub(800.0, inertia, pts)
    with pytest.raises(ValueError, match="positive range"):
        bodies.rigid_hub(Parameter("M_SC", 1.0, -1.0, 3.0), np.eye(3), pts)
    assert bodies.rigid_hub(800.0, np.diag([500.0, 600.0, 700.0]), pts).d.shape == (12, 12)
