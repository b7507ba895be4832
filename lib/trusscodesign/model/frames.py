"""Frames and rigid kinematics: skew matrices, DCMs and the kinematic model tau.

Conventions (paper, section "TITOP Approach"; ``docs/titop.md`` section a):

* an acceleration twist at a point P is ``a_P = [linear (3); angular (3)]``,
  a wrench is ``W = [force (3); moment about the point (3)]``;
* ``R_ab`` (3x3) maps components in frame b to components in frame a; the
  "twice DCM" ``diag(R_ab, R_ab)`` maps twists and wrenches;
* the kinematic model between two points A, B of one rigid body is
  ``tau_AB = [[I, [r_AB]x], [0, I]]`` with ``r_AB`` the vector from A to B, so that
  ``a_A = tau_AB a_B`` and a wrench ``W_A`` applied at A is equivalent to
  ``tau_AB^T W_A`` applied at B.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..infra.checks import check_real
from .lft import LFT

__all__ = [
    "skew",
    "tau",
    "twice_dcm",
    "rot_x",
    "rot_y",
    "rot_z",
    "beam_frame",
    "as_vector3",
    "rot_x_lft",
    "twice_dcm_lft",
]


def as_vector3(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """Return ``value`` as a finite float vector of length 3.

    Raises
    ------
    ValueError
        If ``value`` does not have 3 finite components.
    """
    vec = np.asarray(value, dtype=float).reshape(-1)
    if vec.shape != (3,) or not np.all(np.isfinite(vec)):
        raise ValueError(f"{name} must be 3 finite numbers [m], got {value!r}")
    return vec


def skew(r: ArrayLike) -> NDArray[np.float64]:
    """Skew-symmetric matrix ``[r]x`` such that ``[r]x @ v == cross(r, v)``."""
    x, y, z = as_vector3(r, "r")
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def tau(r_ab: ArrayLike) -> NDArray[np.float64]:
    """Kinematic model ``tau_AB`` (6x6) of the rigid link from A to B.

    Parameters
    ----------
    r_ab : array_like, shape (3,)
        Vector from point A to point B [m].

    Returns
    -------
    ndarray, shape (6, 6)
        ``[[I3, [r_AB]x], [0, I3]]``: ``a_A = tau_AB @ a_B`` for twists, and
        ``tau_AB.T @ W_A`` is the wrench at B equivalent to ``W_A`` at A.
    """
    out = np.eye(6)
    out[:3, 3:] = skew(r_ab)
    return out


def _check_rotation(rot: ArrayLike, name: str = "R") -> NDArray[np.float64]:
    mat = np.asarray(rot, dtype=float)
    if mat.shape != (3, 3):
        raise ValueError(f"{name} must be a 3x3 direction-cosine matrix, got shape {mat.shape}")
    if not np.allclose(mat @ mat.T, np.eye(3), atol=1e-9) or np.linalg.det(mat) < 0:
        raise ValueError(f"{name} must be a proper rotation (orthonormal, det = +1)")
    return mat


def twice_dcm(rot: ArrayLike) -> NDArray[np.float64]:
    """Twice DCM ``diag(R, R)`` (6x6) acting on twists and wrenches.

    Parameters
    ----------
    rot : array_like, shape (3, 3)
        Direction-cosine matrix ``R_ab`` (components in b -> components in a).
    """
    mat = _check_rotation(rot)
    out = np.zeros((6, 6))
    out[:3, :3] = mat
    out[3:, 3:] = mat
    return out


def _angle(angle: float) -> None:
    """A TypeError / ValueError unless ``angle`` is a finite real number [rad] (NaN would give a NaN matrix)."""
    check_real("angle", angle, "rad")
    if not np.isfinite(angle):
        raise ValueError(f"angle must be a finite number [rad], got {angle!r}")


def rot_x(angle: float) -> NDArray[np.float64]:
    """DCM of a rotation by ``angle`` [rad] about x: components in the rotated frame -> base."""
    _angle(angle)
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(angle: float) -> NDArray[np.float64]:
    """DCM of a rotation by ``angle`` [rad] about y: components in the rotated frame -> base."""
    _angle(angle)
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(angle: float) -> NDArray[np.float64]:
    """DCM of a rotation by ``angle`` [rad] about z: components in the rotated frame -> base."""
    _angle(angle)
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def beam_frame(r_p: ArrayLike, r_c: ArrayLike, y_hint: ArrayLike | None = None) -> NDArray[np.float64]:
    """DCM from a beam's frame to the common frame.

    The beam frame has x along P -> C. Its y axis is ``y_hint`` made orthogonal
    to x; by default the common-frame axis least aligned with the beam is used
    as the hint (z for a beam in the x-y plane gives y = z x x, ...). For the
    square sections of this project (Iy = Iz) the choice does not change the
    dynamics; it matters for rectangular sections.

    Parameters
    ----------
    r_p, r_c : array_like, shape (3,)
        Positions of P and C in the common frame [m]; they must differ.
    y_hint : array_like, shape (3,), optional
        Approximate direction of the beam's y axis in the common frame.

    Returns
    -------
    ndarray, shape (3, 3)
        ``R`` whose columns are the beam axes x, y, z in the common frame.
    """
    p = as_vector3(r_p, "r_p")
    c = as_vector3(r_c, "r_c")
    axis = c - p
    length = np.linalg.norm(axis)
    if length <= 0.0:
        raise ValueError("beam end points P and C coincide: a beam needs a positive length")
    ex = axis / length
    if y_hint is None:
        # Common-frame axis least aligned with the beam, made orthogonal to it.
        hint = np.eye(3)[int(np.argmin(np.round(np.abs(ex), 12)))]  # rounding must not break a tie
        ez = np.cross(ex, hint)
        ez /= np.linalg.norm(ez)
        ey = np.cross(ez, ex)
    else:
        hint = as_vector3(y_hint, "y_hint")
        ey = hint - ex * (ex @ hint)
        if np.linalg.norm(ey) < 1e-9 * max(1.0, float(np.linalg.norm(hint))):
            raise ValueError("y_hint is parallel to the beam axis: choose a transverse direction")
        ey /= np.linalg.norm(ey)
        ez = np.cross(ex, ey)
    return np.column_stack([ex, ey, ez])


def rot_x_lft(tau_param):
    """Rotation about x by ``theta = 4 arctan(tau)`` as an exact LFT in ``tau`` (4 occurrences).

    With ``J = [[0, -1], [1, 0]]`` the Cayley transform ``(I + tau J)(I - tau J)^-1 =
    -I + 2 (I - tau J)^-1`` is the plane rotation by ``2 arctan(tau) = theta / 2``
    (2 occurrences of tau); its square is the rotation by theta. ``tau`` in [-1, 1]
    covers ``theta`` in [-pi, pi]. Same convention as :func:`rot_x`.

    Parameters
    ----------
    tau_param : trusscodesign.model.lft.Parameter
        The parameter tau = tan(theta / 4).
    """

    tau = LFT.param(tau_param)
    jmat = np.array([[0.0, -1.0], [1.0, 0.0]])
    half = -1.0 * LFT.constant(np.eye(2)) + 2.0 * (LFT.constant(np.eye(2)) - tau * jmat).inv()
    return LFT.blkdiag(LFT.constant([[1.0]]), half @ half)


def twice_dcm_lft(tau_param, base: ArrayLike | None = None):
    """Twice DCM ``diag(R, R)`` with ``R = rot_x(theta) @ base`` as an LFT in tau (8 occurrences)."""

    rx = rot_x_lft(tau_param)
    r3 = rx if base is None else rx @ _check_rotation(base, "base")
    return LFT.blkdiag(r3, r3)
