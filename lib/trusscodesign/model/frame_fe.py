"""Reference 3D Euler-Bernoulli frame finite elements (independent of the TITOP models).

A compact, classical beam-column finite-element code: 2-node 12-dof elements
(axial, torsion, bending in both planes; Przemieniecki's stiffness), consistent
or lumped mass, each member meshed with ``n_elements`` elements. It is used as
an independent reference for the TITOP mechanisms (notebook 02) and the cube
(notebook 03): it shares nothing with :mod:`trusscodesign.model.titop` except the section data
and the choice of the beam's local axes (:func:`trusscodesign.model.frames.beam_frame`).

Dofs per node: ``[ux, uy, uz, rx, ry, rz]`` in the common frame.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

from . import frames
from ..infra.checks import check_members, check_option
from .titop import Section

__all__ = ["FrameModel", "element_matrices", "build_frame", "FrameModes"]


def element_matrices(length: float, s: Section, mass: str = "consistent") -> tuple[NDArray, NDArray]:
    """Local 12x12 stiffness and mass matrices of one Euler-Bernoulli element.

    Local dofs ``[u1 v1 w1 tx1 ty1 tz1 u2 v2 w2 tx2 ty2 tz2]`` with x along the
    element; bending with v uses E Iz, bending with w uses E Iy (``ty = -w'``).
    """
    if mass not in ("consistent", "lumped"):
        raise ValueError(f"mass must be 'consistent' or 'lumped', got {mass!r}")
    check_option("length [m] (of the element)", length, 0.0, open_low=True, open_high=True)
    ell = float(length)
    e, g = s.young, s.shear_modulus
    k = np.zeros((12, 12))
    bar = np.array([[1.0, -1.0], [-1.0, 1.0]])
    k[np.ix_([0, 6], [0, 6])] = e * s.area / ell * bar
    k[np.ix_([3, 9], [3, 9])] = g * s.torsion_constant / ell * bar
    bend = np.array(
        [[12, 6 * ell, -12, 6 * ell], [6 * ell, 4 * ell**2, -6 * ell, 2 * ell**2],
         [-12, -6 * ell, 12, -6 * ell], [6 * ell, 2 * ell**2, -6 * ell, 4 * ell**2]]
    ) / ell**3
    flip = np.diag([1.0, -1.0, 1.0, -1.0])  # w-plane: rotation ty = -w'
    k[np.ix_([1, 5, 7, 11], [1, 5, 7, 11])] = e * s.iz * bend
    k[np.ix_([2, 4, 8, 10], [2, 4, 8, 10])] = e * s.iy * flip @ bend @ flip

    m = np.zeros((12, 12))
    mass_el = s.density * s.area * ell
    rot_el = s.density * s.polar * ell
    if mass == "consistent":
        m[np.ix_([0, 6], [0, 6])] = mass_el / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
        m[np.ix_([3, 9], [3, 9])] = rot_el / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
        mb = mass_el / 420.0 * np.array(
            [[156, 22 * ell, 54, -13 * ell], [22 * ell, 4 * ell**2, 13 * ell, -3 * ell**2],
             [54, 13 * ell, 156, -22 * ell], [-13 * ell, -3 * ell**2, -22 * ell, 4 * ell**2]]
        )
        m[np.ix_([1, 5, 7, 11], [1, 5, 7, 11])] = mb
        m[np.ix_([2, 4, 8, 10], [2, 4, 8, 10])] = flip @ mb @ flip
    else:
        # Lumped: half the translational mass and torsional inertia at each node,
        # no rotary inertia in bending (a common NASTRAN-style default).
        for i in (0, 1, 2, 6, 7, 8):
            m[i, i] = mass_el / 2.0
        for i in (3, 9):
            m[i, i] = rot_el / 2.0
    return k, m


@dataclass(frozen=True)
class FrameModes:
    """Modes of a clamped frame.

    Attributes
    ----------
    omega : ndarray
        Natural frequencies [rad/s] (ascending, finite ones only).
    participation : ndarray, shape (n_modes, 6)
        Modal participation factors at the clamped reference node (mass-normalised modes).
    rigid_mass : ndarray, shape (6, 6)
        Rigid mass matrix at the reference node.
    """

    omega: NDArray[np.float64]
    participation: NDArray[np.float64]
    rigid_mass: NDArray[np.float64]


@dataclass
class FrameModel:
    """Assembled frame: global stiffness and mass matrices and the node table."""

    positions: NDArray[np.float64]
    node_index: dict[str, int]
    stiffness: NDArray[np.float64]
    mass: NDArray[np.float64]

    def _dofs(self, names: Sequence[str]) -> NDArray[np.int64]:
        idx: list[int] = []
        for n in names:
            if n not in self.node_index:
                raise ValueError(f"unknown node {n!r}")
            i = self.node_index[n]
            idx.extend(range(6 * i, 6 * i + 6))
        return np.asarray(idx, dtype=np.int64)

    def modes(self, clamped: Sequence[str], reference: str | None = None, n_modes: int | None = None) -> FrameModes:
        """Natural frequencies and participation factors with the ``clamped`` nodes fixed.

        Parameters
        ----------
        clamped : sequence of str
            Clamped nodes.
        reference : str, optional
            Node at which participation factors and rigid mass are computed
            (default: the first clamped node).
        n_modes : int, optional
            Number of modes returned (default: all).
        """
        if not clamped:
            raise ValueError("clamped must name at least one node (a free-free frame has rigid modes)")
        reference = reference or clamped[0]
        fixed = self._dofs(clamped)
        n = self.stiffness.shape[0]
        free = np.setdiff1d(np.arange(n), fixed)
        # Rigid displacement field of the whole frame for unit motions of the reference node.
        r_ref = self.positions[self.node_index[reference]]
        rig = np.zeros((n, 6))
        for i, pos in enumerate(self.positions):
            rig[6 * i : 6 * i + 6] = frames.tau(r_ref - pos)  # node displacement = tau(r_node->ref) u_ref
        kff = self.stiffness[np.ix_(free, free)]
        mff = self.mass[np.ix_(free, free)]
        # Solve M v = mu K v (K > 0 once clamped, M >= 0): mu = 1/omega^2, and
        # massless directions of a lumped mass matrix give mu = 0 and are dropped.
        mu, vec = linalg.eigh(mff, kff)
        keep = mu > 1e-14 * mu.max()
        mu, vec = mu[keep][::-1], vec[:, keep][:, ::-1]
        phi = vec / np.sqrt(mu)  # mass-normalised: phi^T M phi = I
        omega = 1.0 / np.sqrt(mu)
        part = phi.T @ self.mass[np.ix_(free, np.arange(n))] @ rig
        rigid = rig.T @ self.mass @ rig
        if n_modes is not None:
            omega, part = omega[:n_modes], part[:n_modes]
        return FrameModes(omega=omega, participation=part, rigid_mass=rigid)


def build_frame(
    nodes: Mapping[str, ArrayLike],
    members: Sequence[tuple[str, str]],
    section: Section,
    n_elements: int = 10,
    mass: str = "consistent",
) -> FrameModel:
    """Assemble a frame of identical members, each meshed with ``n_elements`` elements.

    Parameters
    ----------
    nodes : mapping str -> array_like (3,)
        Structural nodes [m].
    members : sequence of (str, str)
        Members between nodes.
    section : Section
        Section and material (J used as given: compare J choices by passing two sections).
    n_elements : int
        Elements per member (>= 1).
    mass : {"consistent", "lumped"}
        Mass matrix formulation.
    """
    if isinstance(n_elements, bool) or not isinstance(n_elements, (int, np.integer)) or n_elements < 1:
        raise ValueError(f"n_elements must be an integer >= 1, got {n_elements!r}")
    check_members(nodes, members)
    node_index = {name: i for i, name in enumerate(nodes)}
    pos = [frames.as_vector3(nodes[name], f"position of {name}") for name in nodes]
    elements: list[tuple[int, int, NDArray]] = []
    for p, c in members:
        # one frame per member: from each sub-element's rounded end points the default axes could flip by 90 deg
        rot = frames.beam_frame(pos[node_index[p]], pos[node_index[c]])
        ids = [node_index[p]]
        for j in range(1, n_elements):
            pos.append(pos[node_index[p]] + (pos[node_index[c]] - pos[node_index[p]]) * j / n_elements)
            ids.append(len(pos) - 1)
        ids.append(node_index[c])
        elements.extend((i, j, rot) for i, j in zip(ids[:-1], ids[1:]))
    n = 6 * len(pos)
    kg = np.zeros((n, n))
    mg = np.zeros((n, n))
    for i, j, rot in elements:
        k_loc, m_loc = element_matrices(float(np.linalg.norm(pos[j] - pos[i])), section, mass)
        t = linalg.block_diag(*([rot.T] * 4))
        dofs = np.r_[6 * i : 6 * i + 6, 6 * j : 6 * j + 6]
        kg[np.ix_(dofs, dofs)] += t.T @ k_loc @ t
        mg[np.ix_(dofs, dofs)] += t.T @ m_loc @ t
    return FrameModel(np.asarray(pos), node_index, kg, mg)
