import numpy as np
import pytest
from trusscodesign.model import frames


def test_tau_transports_twists_and_wrenches_consistently():
    rng = np.random.default_rng(0)
    r_a, r_b = rng.normal(size=3), rng.normal(size=3)
    alpha = rng.normal(size=3)
    a_b = np.r_[rng.normal(size=3), alpha]
    # a_A = a_B + alpha x (r_A - r_B)
    expected = a_b[:3] + np.cross(alpha, r_a - r_b)
    np.testing.assert_allclose((frames.tau(r_b - r_a) @ a_b)[:3], expected, rtol=1e-14)
    # Power is invariant: W_A . a_A == (tau^T W_A) . a_B
    w_a = rng.normal(size=6)
    t = frames.tau(r_b - r_a)
    assert np.isclose(w_a @ (t @ a_b), (t.T @ w_a) @ a_b)
    np.testing.assert_allclose(np.linalg.inv(t), frames.tau(r_a - r_b), atol=1e-14)


def test_beam_frame_is_a_rotation_with_x_along_the_beam():
    rot = frames.beam_frame([0, 0, 0], [0.3, 0.4, 1.2])
    np.testing.assert_allclose(rot @ rot.T, np.eye(3), atol=1e-14)
    assert np.isclose(np.linalg.det(rot), 1.0)
    np.testing.assert_allclose(rot[:, 0], np.array([0.3, 0.4, 1.2]) / 1.3, rtol=1e-14)
    rot2 = frames.beam_frame([0, 0, 0], [1, 0, 0], y_hint=[0, 0, 1])
    np.testing.assert_allclose(rot2, [[1, 0, 0], [0, 0, -1], [0, 1, 0]], atol=1e-15)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: frames.beam_frame([0, 0, 0], [0, 0, 0]), "positive length"),
        (lambda: frames.beam_frame([0, 0, 0], [1, 0, 0], y_hint=[2, 0, 0]), "parallel"),
        (lambda: frames.twice_dcm(np.diag([1.0, 1.0, -1.0])), "proper rotation"),
        (lambda: frames.tau([1.0, np.nan, 0.0]), "finite"),
        (lambda: frames.skew([1.0, 2.0]), "3 finite"),
    ],
)
def test_bad_input_raises_clear_errors(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ---------------------------------------------------------------- mutation-testing additions (review of 2026-12-03)
@pytest.mark.parametrize("rot, axis", [(frames.rot_x, 0), (frames.rot_y, 1), (frames.rot_z, 2)])
def test_elementary_rotations_follow_rodrigues_right_hand_rule(rot, axis):
    """R(angle) v = v cos + (k x v) sin + k (k . v)(1 - cos) for the unit axis k (right-hand rule, Rodrigues)."""
    k = np.eye(3)[axis]
    rng = np.random.default_rng(3)
    for angle in (0.3, np.pi / 2, -2.1):
        for v in rng.normal(size=(3, 3)):
            expected = v * np.cos(angle) + np.cross(k, v) * np.sin(angle) + k * (k @ v) * (1 - np.cos(angle))
            np.testing.assert_allclose(rot(angle) @ v, expected, atol=1e-14)


@pytest.mark.parametrize("rot", [frames.rot_x, frames.rot_y, frames.rot_z])
def test_rotations_refuse_non_finite_angles(rot):
    for angle in (np.nan, np.inf):
        with pytest.raises(ValueError, match="angle must be a finite"):  # was a NaN matrix
            rot(angle)
    with pytest.raises(TypeError, match="angle must be a real number"):
        rot("0.5")
    assert np.array_equal(rot(0.5), rot(np.float64(0.5)))
