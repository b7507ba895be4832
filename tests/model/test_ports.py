"""Multi-port models: inversion errors, frame change, transport, interconnection rules."""

import numpy as np
import pytest
from trusscodesign.model import frames, interconnect, ports, titop

SEC = titop.Section.square(0.03)
OMEGA = np.logspace(0, 4, 40)


def assert_same_response(g1, g0, tol=1e-10):
    """Largest entry error relative to the largest entry, per frequency."""
    err = np.max(np.abs(g1 - g0), axis=(0, 1)) / np.max(np.abs(g0), axis=(0, 1))
    assert err.max() < tol, err.max()


def test_reprojected_beam_equals_beam_built_in_that_direction():
    # Beam along x re-projected by a rotation of +90 deg about z lies along y.
    along_x = titop.clamped_free(1.0, SEC, p="P", c="C")
    rot = frames.rot_z(np.pi / 2)
    turned = along_x.reproject(rot)
    direct = titop.beam(("P", [0, 0, 0]), ("C", [0, 1, 0]), SEC, y_hint=rot @ [0, 1, 0])
    np.testing.assert_allclose(turned.port("C").position, [0, 1, 0], atol=1e-15)
    assert_same_response(turned.freqresp(OMEGA), direct.freqresp(OMEGA))


def test_transport_clamped_port_gives_rigid_mass_at_new_point():
    model = titop.clamped_free(1.0, SEC)
    q = np.array([-0.3, 0.2, 0.5])
    moved = model.transport("P", q)
    dc = moved.d - moved.c @ np.linalg.solve(moved.a, moved.b)
    p = moved.channels("P")
    t = frames.tau(q)  # a_P = tau_PQ a_Q, r_PQ = q - 0
    expected = -t.T @ titop.rigid_mass(1.0, SEC) @ t
    np.testing.assert_allclose(dc[np.ix_(p, p)], expected, rtol=1e-9, atol=1e-12)
    # Transport back is the identity.
    back = moved.transport("P", np.zeros(3))
    assert_same_response(back.freqresp(OMEGA), model.freqresp(OMEGA))


def test_transport_free_port_preserves_power_pairing():
    model = titop.clamped_free(1.0, SEC)
    moved = model.transport("C", [1.0, 0.1, 0.0])
    back = moved.transport("C", [1.0, 0.0, 0.0])
    assert_same_response(back.freqresp(OMEGA), model.freqresp(OMEGA))


def test_inversion_sign_convention_makes_dc_gain_minus_mass_on_both_sides():
    # Free-clamped (invert both ports): clamped at C, free at P; DC a_C -> W_C is minus the mass at C.
    model = titop.clamped_free(1.0, SEC).invert_ports("C", "P")
    assert [p.kind for p in model.ports] == ["clamped", "free"]
    dc = model.d - model.c @ np.linalg.solve(model.a, model.b)
    c = model.channels("C")
    t = frames.tau([1.0, 0.0, 0.0])  # a_P = tau_PC a_C, r_PC = (l, 0, 0)
    np.testing.assert_allclose(dc[np.ix_(c, c)], -t.T @ titop.rigid_mass(1.0, SEC) @ t, rtol=1e-8, atol=1e-10)


def test_bad_channel_sets_and_ports_raise():
    model = titop.clamped_free(1.0, SEC)
    with pytest.raises(ValueError, match="does not exist"):
        model.invert([12])
    with pytest.raises(ValueError, match="does not exist"):
        model.invert([0], one_based=True)
    # A mass on a spring driven by a force, measured in displacement: no
    # feedthrough, so the force cannot be made an output.
    spring_mass = ports.MultiPortModel(
        [[0.0, 1.0], [-4.0, 0.0]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.0]], [ports.scalar_port("x", "F", "x")]
    )
    with pytest.raises(ValueError, match="cannot be inverted"):
        spring_mass.invert([0])
    with pytest.raises(ValueError, match="no port"):
        model.invert_ports("Z")
    with pytest.raises(ValueError, match="component"):
        model.channels("C", ["Qx"])
    with pytest.raises(ValueError, match="mixed"):
        model.invert([0]).transport("C", [0, 0, 0])


def test_statespace_conversion_has_named_signals():
    model = titop.clamped_free(1.0, SEC)
    sys = model.to_statespace()
    assert sys.input_labels[:2] == ["W_C_Tx", "W_C_Ty"]
    assert sys.output_labels[6:8] == ["W_P_Tx", "W_P_Ty"]
    g = sys(1j * 10.0)
    # python-control evaluates through SLICOT (tb05ad) when slycot is installed: agreement to 1e-12 of the largest
    # entry (entries near zero differ by 1e-10 of themselves, round-off of an independent evaluation)
    ref = model.freqresp([10.0])[:, :, 0]
    np.testing.assert_allclose(g, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())


# ---------------------------------------------------------------- mutation-testing additions (review of 2026-12-03)
def test_transport_free_port_along_a_rigid_arm_gives_the_cantilever_with_arm_compliance():
    """Tip C of a cantilever (length l, along x) moved by e to Q = (l + e, 0, 0) on a rigid arm: a force F_y at Q
    deflects Q by F (l^3/3 + l^2 e + l e^2) / (E Iz) (tip force F plus tip moment F e, then the arm's rotation);
    a moment M_z at Q rotates it by M l / (E Iz) and deflects it by M (l^2/2 + l e) / (E Iz)."""
    length, e = 1.0, 0.4
    model = titop.clamped_free(length, SEC).transport("C", [length + e, 0.0, 0.0])
    np.testing.assert_allclose(model.port("C").position, [length + e, 0.0, 0.0])
    comp = model.static_compliance("C")
    ei = SEC.young * SEC.iz
    np.testing.assert_allclose(comp[1, 1], (length**3 / 3 + length**2 * e + length * e**2) / ei, rtol=1e-9)
    np.testing.assert_allclose(comp[5, 5], length / ei, rtol=1e-9)
    np.testing.assert_allclose([comp[1, 5], comp[5, 1]], (length**2 / 2 + length * e) / ei, rtol=1e-9)
    ei_y = SEC.young * SEC.iy  # w-plane: ry = -w', a force F_z at Q deflects Q by the same formula, ry and w of opposite signs
    np.testing.assert_allclose(comp[2, 2], (length**3 / 3 + length**2 * e + length * e**2) / ei_y, rtol=1e-9)
    np.testing.assert_allclose(comp[2, 4], -(length**2 / 2 + length * e) / ei_y, rtol=1e-9)


def test_ports_refuse_fractional_channels_complex_matrices_and_bad_atol():
    beam = titop.clamped_free(1.0, titop.Section.square(0.02))
    with pytest.raises(TypeError, match="integer"):  # was channel 5
        beam.invert([5.7])
    with pytest.raises(TypeError, match="integer"):
        beam.invert([1.0, 2.0], one_based=True)
    assert beam.invert(np.arange(6)).nstates == beam.nstates
    port = ports.scalar_port("s", "f", "x")
    with pytest.raises(TypeError, match="A must be real"):  # was a ComplexWarning and the imaginary part dropped
        ports.MultiPortModel([[-1.0 + 2.0j]], [[1.0]], [[1.0]], [[0.0]], [port])
    for atol in (-1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="atol"):
            interconnect.connect([beam], atol=atol)
    with pytest.raises(TypeError, match="atol"):
        interconnect.connect([beam], atol="1e-9")
    interconnect.connect([beam], atol=0)
