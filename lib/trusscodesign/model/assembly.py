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

The constraints are eliminated with an orthonormal null-space basis; the undamped natural frequencies follow from a
symmetric generalised eigenproblem, the damped poles from the first-order form. Any member may be given either way
round and in any order: the assembled structure is the same, and so are its poles unless the damping model depends on
which end of a beam is P (the paper's ``"clamped_modes"``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

from . import frames
from ..infra.checks import check_members
from .titop import Section, member_sections, modal_data

__all__ = ["constrained_frequencies", "constrained_poles"]


Lumped = Mapping[str, tuple[float, ArrayLike]]  # node -> (mass [kg], 3x3 inertia [kg m^2] about the node)


def _assemble(nodes: Mapping[str, ArrayLike], members: Sequence[tuple[str, str]], section: Section | Sequence[Section],
              clamped: Sequence[str], n_modes: int, lumped: Lumped | None = None) -> tuple[NDArray, NDArray, NDArray]:
    """Mass, damping and stiffness matrices of the structure, on an orthonormal basis of the coordinates that satisfy the
    constraints (module docstring)."""
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
    beams = []
    n_q = 6 * len(free_nodes)
    for (p, c), sec in zip(members, sections):
        rp, rc = np.asarray(nodes[p], float), np.asarray(nodes[c], float)
        md = modal_data(float(np.linalg.norm(rc - rp)), sec, n_modes)
        beams.append((p, c, frames.twice_dcm(frames.beam_frame(rp, rc)), md, n_q))
        n_q += md.omega.size

    mass, damp, stiff = np.zeros((n_q, n_q)), np.zeros((n_q, n_q)), np.zeros((n_q, n_q))
    for node, (m, inertia) in (lumped or {}).items():
        i = col[node]
        mass[i:i + 3, i:i + 3] += float(m) * np.eye(3)
        mass[i + 3:i + 6, i + 3:i + 6] += np.asarray(inertia, dtype=float)
    cons = []
    for p, c, r6, md, eo in beams:
        n = md.omega.size
        # Selection of [u_P (beam frame); eta] from the global coordinates.
        sel = np.zeros((6 + n, n_q))
        if p in col:
            sel[:6, col[p] : col[p] + 6] = r6.T
        sel[6:, eo : eo + n] = np.eye(n)
        m_b = np.block([[md.d_p, md.l_p.T], [md.l_p, np.eye(n)]])
        mass += sel.T @ m_b @ sel
        stiff += sel.T @ linalg.block_diag(np.zeros((6, 6)), np.diag(md.omega**2)) @ sel
        damp += sel.T @ linalg.block_diag(np.zeros((6, 6)), np.diag(2.0 * md.damping * md.omega)) @ sel
        # Tip constraint: R6 (tau_CP u_P + Phi_C eta) - U_c = 0.
        g = r6 @ np.hstack([frames.tau(-md.r_pc), md.phi_c]) @ sel
        if c in col:
            g[:, col[c] : col[c] + 6] -= np.eye(6)
        cons.append(g)
    basis = linalg.null_space(np.vstack(cons)) if cons else np.eye(n_q)
    return basis.T @ mass @ basis, basis.T @ damp @ basis, basis.T @ stiff @ basis


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
    lam = linalg.eigh(stiff, mass, eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None))


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
    mass, damp, stiff = _assemble(nodes, members, section, clamped, n_modes, lumped)
    n = mass.shape[0]
    m_inv = np.linalg.inv(mass)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-m_inv @ stiff, -m_inv @ damp]])
    lam = np.linalg.eigvals(a)
    lam = lam[lam.imag > 0]
    return lam[np.argsort(np.abs(lam))]
