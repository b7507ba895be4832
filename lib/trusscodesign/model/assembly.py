"""Direct constrained (Lagrangian) assembly of TITOP beam models: an independent check.

The block-diagram models of :mod:`trusscodesign.model.mechanisms` are built by feedback loops and
channel inversions. This module assembles *the same* beam superelements a second
way, as a mechanical system with generalised coordinates and constraints:

* coordinates: the 6-dof displacement ``U_n`` of every node (common frame) and the
  modal coordinates ``eta_b`` of every beam;
* beam b (P at node p, C at node c, DCM ``R_b`` beam -> common) has kinetic energy
  ``1/2 [u_P; eta]^T [[D_P, L_P^T], [L_P, I]] [u_P; eta]`` with ``u_P = R6^T U_p``
  and strain energy ``1/2 eta^T Omega^2 eta``;
* the tip of beam b coincides with node c: ``R6 (tau_CP u_P + Phi_C eta) = U_c``;
* clamped nodes have ``U = 0``;
* beam b dissipates ``1/2 eta_dot^T diag(2 xi_k omega_k) eta_dot`` (its section's damping model, see
  :class:`trusscodesign.model.titop.Section`), and rigid bodies lumped at nodes add their mass and inertia.

The constraints are eliminated beam by beam: a beam's tip constraint (6 equations in its modal coordinates, of full
row rank) is solved for the part of ``eta`` it fixes, given the displacements of its two nodes, and the rest of ``eta``
is free. The coordinates are then the free nodes' displacements and each beam's free modal coordinates, and the mass,
damping and stiffness matrices are sparse, a beam coupling its two nodes and its own coordinates only, as a finite
element (without a global null space, whose cost is cubic in the number of beams). The undamped natural frequencies
follow from a symmetric generalised eigenproblem (all of them, or the lowest by sparse shift-invert:
:func:`lowest_modes`), the damped poles from the first-order form. Any member may be given either way
round and in any order: the assembled structure is the same, and so are its poles unless the damping model depends on
which end of a beam is P (the paper's ``"clamped_modes"``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg, sparse
from scipy.sparse.linalg import eigsh

from . import frames
from ..infra.checks import check_members
from .titop import Section, member_sections, modal_data

__all__ = ["Modes", "constrained_frequencies", "lowest_modes", "constrained_poles"]


Lumped = Mapping[str, tuple[float, ArrayLike]]  # node -> (mass [kg], 3x3 inertia [kg m^2] about the node)


def _beam_basis(phi_c: NDArray, tau_cp: NDArray, r6: NDArray) -> tuple[NDArray, NDArray]:
    """The beam's coordinates ``[u_P; eta]`` as ``T [U_p; U_c; z]`` on its constraint (module docstring).

    ``Phi_C eta = R6^T U_c - tau_CP R6^T U_p`` (6 equations, ``Phi_C`` of full row rank) is solved by the
    minimum-norm part and the null space ``N`` of ``Phi_C``: ``eta = Phi_C^+ R6^T (U_c - R6 tau_CP R6^T U_p) + N z``.
    Returns ``T`` (``(6 + n) x (12 + n - 6)``) and ``N``.
    """
    n = phi_c.shape[1]
    pinv = np.linalg.pinv(phi_c)
    null = linalg.null_space(phi_c)
    if null.shape[1] != n - 6:
        raise ValueError(f"a beam's tip modal matrix has rank {n - null.shape[1]} < 6: its tip cannot follow its node")
    t = np.zeros((6 + n, 12 + null.shape[1]))
    t[:6, :6] = r6.T
    t[6:, :6] = -pinv @ tau_cp @ r6.T
    t[6:, 6:12] = pinv @ r6.T
    t[6:, 12:] = null
    return t, null


def _assemble(nodes: Mapping[str, ArrayLike], members: Sequence[tuple[str, str]], section: Section | Sequence[Section],
              clamped: Sequence[str], n_modes: int, lumped: Lumped | None = None) -> tuple[sparse.csr_array, sparse.csr_array, sparse.csr_array]:
    """Mass, damping and stiffness matrices of the structure (sparse) on coordinates that satisfy the constraints: the
    six displacements of every free node and, for each beam, the modal coordinates its tip constraint leaves free
    (:func:`_beam_basis`). A beam couples its two nodes and its own coordinates only, as a finite element does."""
    names = list(nodes)
    check_members(nodes, members, clamped)
    sections = member_sections(section, len(members))
    if not all(s.symmetric for s in sections):
        raise ValueError("the constrained assembly takes square sections only (Iy = Iz): it uses the default beam frames")
    free_nodes = [n for n in names if n not in clamped]
    col = {n: 6 * i for i, n in enumerate(free_nodes)}
    unknown = sorted(set(lumped or {}) - set(free_nodes))
    if unknown:
        raise ValueError(f"lumped masses at {unknown}: not free nodes of the structure (free nodes: {free_nodes})")
    n_q = 6 * len(free_nodes)
    rows: dict[str, list] = {"m": [], "c": [], "k": []}
    for node, (m, inertia) in (lumped or {}).items():
        i = col[node]
        block = linalg.block_diag(float(m) * np.eye(3), np.asarray(inertia, dtype=float))
        rows["m"].append((np.arange(i, i + 6), block))
    for (p, c), sec in zip(members, sections):
        rp, rc = np.asarray(nodes[p], float), np.asarray(nodes[c], float)
        md = modal_data(float(np.linalg.norm(rc - rp)), sec, n_modes)
        r6 = frames.twice_dcm(frames.beam_frame(rp, rc))
        t, null = _beam_basis(md.phi_c, frames.tau(-md.r_pc), r6)
        n = md.omega.size
        idx = np.concatenate([np.arange(col[p], col[p] + 6) if p in col else np.full(6, -1),
                              np.arange(col[c], col[c] + 6) if c in col else np.full(6, -1),
                              np.arange(n_q, n_q + null.shape[1])])
        n_q += null.shape[1]
        keep = idx >= 0  # a clamped node's displacement is zero: its columns drop out
        t, idx = t[:, keep], idx[keep]
        m_b = np.block([[md.d_p, md.l_p.T], [md.l_p, np.eye(n)]])
        k_b = linalg.block_diag(np.zeros((6, 6)), np.diag(md.omega**2))
        c_b = linalg.block_diag(np.zeros((6, 6)), np.diag(2.0 * md.damping * md.omega))
        for key, mat in (("m", m_b), ("k", k_b), ("c", c_b)):
            rows[key].append((idx, t.T @ mat @ t))

    def scatter(blocks: list) -> sparse.csr_array:
        if not blocks:
            return sparse.csr_array((n_q, n_q))
        i = np.concatenate([np.repeat(ix, ix.size) for ix, _ in blocks])
        j = np.concatenate([np.tile(ix, ix.size) for ix, _ in blocks])
        v = np.concatenate([blk.ravel() for _, blk in blocks])
        return sparse.coo_array((v, (i, j)), shape=(n_q, n_q)).tocsr()

    return scatter(rows["m"]), scatter(rows["c"]), scatter(rows["k"])


def constrained_frequencies(
    nodes: Mapping[str, ArrayLike],
    members: Sequence[tuple[str, str]],
    section: Section | Sequence[Section],
    clamped: Sequence[str],
    n_modes: int = 1,
) -> NDArray[np.float64]:
    """Undamped natural frequencies [rad/s] of beams assembled by explicit constraints.

    Parameters
    ----------
    nodes : mapping str -> array_like (3,)
        Node positions [m].
    members : sequence of (str, str)
        Beams as (P node, C node); each beam's modal data is clamped at P.
    section : Section or sequence of Section
        Section and material of every beam, or of each beam (in the order of ``members``).
    clamped : sequence of str
        Nodes with zero displacement.
    n_modes : int
        Ritz enrichment of the beam model (see :func:`trusscodesign.model.titop.modal_data`).

    Returns
    -------
    ndarray
        Ascending natural frequencies of the constrained structure.
    """
    mass, _, stiff = _assemble(nodes, members, section, clamped, n_modes)
    lam = linalg.eigh(stiff.toarray(), mass.toarray(), eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None))


@dataclass(frozen=True)
class Modes:
    """The lowest modes of a constrained structure (:func:`lowest_modes`).

    Attributes
    ----------
    frequencies : ndarray, shape (k,)
        Undamped natural frequencies [rad/s], ascending.
    shapes : ndarray, shape (k, n_nodes, 6)
        Each mode's node displacements (translations [m], rotations [rad], common frame; mass-normalised modes), in
        the order of the nodes given; zero at the clamped nodes.
    nodes : list of str
        The nodes, in the order of ``shapes``.
    """

    frequencies: NDArray[np.float64]
    shapes: NDArray[np.float64]
    nodes: list[str]


def lowest_modes(
    nodes: Mapping[str, ArrayLike],
    members: Sequence[tuple[str, str]],
    section: Section | Sequence[Section],
    clamped: Sequence[str],
    k: int = 20,
    n_modes: int = 1,
) -> Modes:
    """The ``k`` lowest undamped modes of beams assembled by explicit constraints, by sparse shift-invert Lanczos
    (``scipy.sparse.linalg.eigsh`` about 0): for large trusses, where :func:`constrained_frequencies` (every
    frequency, dense) is cubic in the size.

    Parameters
    ----------
    nodes, members, section, clamped, n_modes
        As :func:`constrained_frequencies`.
    k : int
        Number of modes, fewer than the structure's coordinates.

    Returns
    -------
    Modes
    """
    mass, _, stiff = _assemble(nodes, members, section, clamped, n_modes)
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 1 <= k < mass.shape[0]:
        raise ValueError(f"k must be an integer in [1, {mass.shape[0] - 1}] (the structure has {mass.shape[0]} "
                         f"coordinates), got {k!r}")
    lam, vec = eigsh(stiff.tocsc(), k=k, M=mass.tocsc(), sigma=0.0, which="LM")
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    names = list(nodes)
    shapes = np.zeros((k, len(names), 6))
    free = [i for i, n in enumerate(names) if n not in clamped]
    shapes[:, free, :] = vec[: 6 * len(free)].T.reshape(k, len(free), 6)
    return Modes(np.sqrt(np.clip(lam, 0.0, None)), shapes, names)


def constrained_poles(
    nodes: Mapping[str, ArrayLike],
    members: Sequence[tuple[str, str]],
    section: Section | Sequence[Section],
    clamped: Sequence[str],
    n_modes: int = 1,
    lumped: Lumped | None = None,
) -> NDArray[np.complex128]:
    """Damped poles of beams (and rigid bodies lumped at nodes) assembled by explicit constraints: one per mode, with
    positive imaginary part, sorted by modulus [rad/s].

    Parameters
    ----------
    nodes, members, section, clamped, n_modes
        As :func:`constrained_frequencies`; the damping is the section's (``section.damping_model``).
    lumped : mapping str -> (float, array_like (3, 3)), optional
        Rigid bodies at free nodes: mass [kg] and inertia about the node [kg m^2] (centre of mass at the node).

    Returns
    -------
    ndarray of complex
        ``-zeta omega + j omega sqrt(1 - zeta^2)`` for each underdamped mode; natural frequency ``abs(p)`` [rad/s],
        damping ratio ``-p.real / abs(p)``.
    """
    mass, damp, stiff = (x.toarray() for x in _assemble(nodes, members, section, clamped, n_modes, lumped))
    n = mass.shape[0]
    m_inv = np.linalg.inv(mass)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-m_inv @ stiff, -m_inv @ damp]])
    lam = np.linalg.eigvals(a)
    lam = lam[lam.imag > 0]
    return lam[np.argsort(np.abs(lam))]
