"""The reference 3D frame finite elements: rigid mass, refused inputs."""

import numpy as np
import pytest
from trusscodesign.model import frame_fe, frames, titop


SEC0 = titop.Section.square(0.03, damping=0.0)  # undamped: poles give natural frequencies exactly


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_frame_fe_rigid_mass_of_a_beam_is_that_of_the_homogeneous_rod(mass):
    """Rigid mass of one member (6 elements) at its clamped end: translations m I (m = rho S l), first moment m l / 2
    (G at mid-length) and torsional inertia rho Ip l for both mass formulations; with the consistent mass (exact for
    rigid motions) also the bending inertia m l^2 / 3 = m l^2 / 12 + m (l / 2)^2 (parallel-axis theorem)."""
    length = 1.5
    fem = frame_fe.build_frame({"A": [0.0, 0.0, 0.0], "B": [length, 0.0, 0.0]}, [("A", "B")], SEC0, 6, mass)
    rigid = fem.modes(["A"], n_modes=2).rigid_mass
    m = SEC0.density * SEC0.area * length
    np.testing.assert_allclose(rigid[:3, :3], m * np.eye(3), rtol=1e-12)
    np.testing.assert_allclose(rigid[:3, 3:], m * frames.skew([length / 2, 0.0, 0.0]).T, atol=1e-12 * m)
    assert np.isclose(rigid[3, 3], SEC0.density * SEC0.polar * length, rtol=1e-12)
    if mass == "consistent":
        np.testing.assert_allclose(np.diag(rigid)[4:], m * length**2 / 3, rtol=1e-12)


@pytest.mark.parametrize("length", [-1.0, 0.0, float("nan"), float("inf")])
def test_frame_element_refuses_a_length_that_is_not_positive(length):
    """A negative element length gave negative stiffness and mass without a word."""
    from trusscodesign.model import frame_fe, titop

    with pytest.raises(ValueError, match=r"length \[m\] \(of the element\) must be a number in \(0, inf\)"):
        frame_fe.element_matrices(length, titop.Section.square(0.03))
