"""Direct constrained (Lagrangian) assembly of TITOP beam models: an independent check.

The block-diagram models of :mod:`trusscodesign.mechanisms` are built by feedback loops and
channel inversions. This module assembles *the same* beam superelements a second
way, as a mechanical system with generalised coordinates and constraints:

* coordinates: the 6-dof displacement ``U_n`` of every node (common frame) and the
  modal coordinates ``eta_b`` of every beam;
* beam b (P at node p, C at node c, DCM ``R_b`` beam -> common) has kinetic energy
  ``1/2 [u_P; eta]^T [[D_P, L_P^T], [L_P, I]] [u_P; eta]`` with ``u_P = R6^T U_p``
  and strain energy ``1/2 eta^T Omega^2 eta``;
* the tip of beam b coincides with node c: ``R6 (tau_CP u_P + Phi_C eta) = U_c``;
* clamped nodes have ``U = 0``.

The constraints are eliminated with an orthonormal null-space basis and the
undamped natural frequencies follow from a symmetric generalised eigenproblem.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

from . import frames
from .checks import check_members
from .titop import Section, modal_data

__all__ = ["constrained_frequencies"]


def constrained_frequencies(
    nodes: Mapping[str, ArrayLike],
    members: Sequence[tuple[str, str]],
    section: Section,
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
    section : Section
        Section and material of every beam.
    clamped : sequence of str
        Nodes with zero displacement.
    n_modes : int
        Ritz enrichment of the beam model (see :func:`trusscodesign.titop.modal_data`).

    Returns
    -------
    ndarray
        Ascending natural frequencies of the constrained structure.
    """
    names = list(nodes)
    check_members(nodes, members, clamped)
    if not section.symmetric:
        raise ValueError("constrained_frequencies takes square sections only (Iy = Iz): it uses the default beam frames")
    free_nodes = [n for n in names if n not in clamped]
    col = {n: 6 * i for i, n in enumerate(free_nodes)}
    beams = []
    n_q = 6 * len(free_nodes)
    for p, c in members:
        rp, rc = np.asarray(nodes[p], float), np.asarray(nodes[c], float)
        md = modal_data(float(np.linalg.norm(rc - rp)), section, n_modes)
        beams.append((p, c, frames.twice_dcm(frames.beam_frame(rp, rc)), md, n_q))
        n_q += md.omega.size

    mass = np.zeros((n_q, n_q))
    stiff = np.zeros((n_q, n_q))
    cons = []
    for p, c, r6, md, eo in beams:
        n = md.omega.size
        # Selection of [u_P (beam frame); eta] from the global coordinates.
        sel = np.zeros((6 + n, n_q))
        if p in col:
            sel[:6, col[p] : col[p] + 6] = r6.T
        sel[6:, eo : eo + n] = np.eye(n)
        m_b = np.block([[md.d_p, md.l_p.T], [md.l_p, np.eye(n)]])
        k_b = linalg.block_diag(np.zeros((6, 6)), np.diag(md.omega**2))
        mass += sel.T @ m_b @ sel
        stiff += sel.T @ k_b @ sel
        # Tip constraint: R6 (tau_CP u_P + Phi_C eta) - U_c = 0.
        g = r6 @ np.hstack([frames.tau(-md.r_pc), md.phi_c]) @ sel
        if c in col:
            g[:, col[c] : col[c] + 6] -= np.eye(6)
        cons.append(g)
    basis = linalg.null_space(np.vstack(cons)) if cons else np.eye(n_q)
    lam = linalg.eigh(basis.T @ stiff @ basis, basis.T @ mass @ basis, eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None))
