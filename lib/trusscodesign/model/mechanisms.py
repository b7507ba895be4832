"""2D mechanisms built from TITOP beams by block-diagram interconnection.

Paper: section "2D Mechanisms" (L-chain, triangle, square). Mathematics:
``docs/titop.md`` section e. All ports are projected in one common frame;
the frame changes are inside the beam blocks (:func:`trusscodesign.model.titop.beam`).

Nodes are given as ``(name, position)`` pairs; positions in metres. Every builder takes an
optional ``h_param`` (:class:`trusscodesign.model.lft.Parameter`): the square-section side as an LFT parameter,
the model then working on scaled signals (see :func:`trusscodesign.model.titop.clamped_free_lft`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .interconnect import connect
from .ports import MultiPortModel
from .titop import Section, beam

__all__ = [
    "l_chain",
    "triangle",
    "square_cfff",
    "square_cccc",
    "planar_l_nodes",
    "unit_square_nodes",
]

Node = tuple[str, ArrayLike]


def l_chain(a: Node, b: Node, c: Node, section: Section, n_modes: int = 1, name: str = "L", h_param=None) -> MultiPortModel:
    """Clamped-free-clamped L-chain ``L^CFC``: beams A->B and C->B joined at B.

    Block diagram (paper, L-chain figure): beam ``A1 = D_{A,B}`` clamped at A,
    free at B; beam ``A2 = [D_{C,B}]^{-1_[1:6]}`` clamped at C and at B. Loop
    closure at B: beam 2 takes the acceleration of B from beam 1, beam 1
    receives the external wrench at B plus beam 2's reaction.

    Returns
    -------
    MultiPortModel
        Ports (A clamped, B free, C clamped), 18x18, 40 states (n_modes = 1).
        ``L^CCC = .invert_ports(B)``, ``L^FFC = .invert_ports(A)``, ...
    """
    b_name = b[0]
    beam1 = beam(a, b, section, n_modes, name=f"{name}:{a[0]}{b_name}", h_param=h_param)
    beam2 = beam(c, b, section, n_modes, name=f"{name}:{c[0]}{b_name}", h_param=h_param).invert_ports(b_name)
    return connect([beam1, beam2], name=name, order=[a[0], b_name, c[0]])


def triangle(a: Node, b: Node, c: Node, section: Section, n_modes: int = 1, name: str = "T", h_param=None) -> MultiPortModel:
    """Clamped-free-free triangle ``T^CFF`` on nodes A, B, C.

    Block diagram (paper, triangle figure): the L-chain ``L^CFC`` on (A, B, C)
    plus beam ``A3 = D_{A,C}``. Constraints: A shared (reactions add), C's
    acceleration from beam 3 drives the L-chain, beam 3 receives the external
    wrench at C plus the L-chain's reaction. The paper uses a right isosceles
    triangle, whose L-chain has alpha = pi/4 at B (its beam CB is the diagonal).

    Returns
    -------
    MultiPortModel
        Ports (A clamped, B free, C free).
    """
    chain = l_chain(a, b, c, section, n_modes, name=f"{name}:L", h_param=h_param)
    side = beam(a, c, section, n_modes, name=f"{name}:{a[0]}{c[0]}", h_param=h_param)
    return connect([chain, side], name=name, order=[a[0], b[0], c[0]])


def square_cfff(a: Node, b: Node, c: Node, d: Node, section: Section, n_modes: int = 1, name: str = "S", h_param=None) -> MultiPortModel:
    """Clamped-free-free-free square ``S^CFFF``: sides AB, AC, BD, CD and diagonal BC.

    Block diagram (paper, square figure): triangle ``T^CFF`` on (A, B, C) and
    L-chain ``L'^CFC`` clamped at B and C with vertex D, joined at B and C.

    Returns
    -------
    MultiPortModel
        Ports (A clamped, B, C, D free).
    """
    tri = triangle(a, b, c, section, n_modes, name=f"{name}:T", h_param=h_param)
    chain = l_chain(b, d, c, section, n_modes, name=f"{name}:L", h_param=h_param)
    return connect([tri, chain], name=name, order=[a[0], b[0], c[0], d[0]])


def square_cccc(a: Node, b: Node, c: Node, d: Node, section: Section, n_modes: int = 1, name: str = "S", h_param=None) -> MultiPortModel:
    """Square clamped at its four nodes: ``S^CCCC = [S^CFFF]^{-1_[7:24]}``."""
    return square_cfff(a, b, c, d, section, n_modes, name, h_param).invert_ports(b[0], c[0], d[0], name=name)


def planar_l_nodes(alpha: float, l_ab: float = 1.0, l_cb: float = 1.0) -> tuple[Node, Node, Node]:
    """Nodes of a planar L-chain in the x-y plane: A at the origin, B on x, angle ``alpha`` [rad] at B.

    ``C = B + l_cb (-cos alpha, sin alpha, 0)``; ``alpha = pi/2`` gives the right-angle
    L of the paper's figure, ``alpha = pi/4`` with ``l_cb = sqrt(2) l_ab`` the
    triangle's L-chain (C above A).
    """
    if not (0.0 < alpha < np.pi):
        raise ValueError(f"alpha must be in (0, pi) rad, got {alpha!r}")
    for val, nm in ((l_ab, "l_ab"), (l_cb, "l_cb")):
        if not (np.isfinite(val) and val > 0):
            raise ValueError(f"{nm} must be a positive length [m], got {val!r}")
    rb = np.array([l_ab, 0.0, 0.0])
    rc = rb + l_cb * np.array([-np.cos(alpha), np.sin(alpha), 0.0])
    return ("A", np.zeros(3)), ("B", rb), ("C", rc)


def unit_square_nodes(side: float = 1.0) -> tuple[Node, Node, Node, Node]:
    """Nodes of the paper's square: A (0,0), B (side,0), C (0,side), D (side,side); diagonal BC."""
    if not (np.isfinite(side) and side > 0):
        raise ValueError(f"side must be a positive length [m], got {side!r}")
    return (
        ("A", np.zeros(3)),
        ("B", np.array([side, 0.0, 0.0])),
        ("C", np.array([0.0, side, 0.0])),
        ("D", np.array([side, side, 0.0])),
    )
