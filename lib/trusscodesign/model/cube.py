"""The cube element ``C^{CCCC-FFFF}`` (13 beams, 8 nodes) from four L-chains and one square.

Paper: section "3D Mechanisms / Cube Mechanism" and its block diagram; validation in
"System Validation". Nodes (cube frame N1, x, y, z): N1 (0, 0, 0), N2 (lx, 0, 0),
N3 (lx, ly, 0), N4 (0, ly, 0), and N5..N8 above them at z = lz. No beam on the
bottom face (cubes stack on each other).

The paper's drawing of the cube is not available; the diagonal layout is a choice:

* side diagonals ``"forward"``: top node N(i+4) receives its side diagonal from the
  bottom node N(i-1): N1-N6, N2-N7, N3-N8, N4-N5; ``"backward"``: from N(i+1):
  N2-N5, N3-N6, N4-N7, N1-N8 (the mirror image);
* top diagonal ``"N6-N8"`` or ``"N5-N7"``.

Notebook 03 shows that the stored Nastran frequencies and participation factors
single out ``("forward", "N6-N8")``, the default.

Block diagram: the L-chain of top node N(i+4) has its two beams (the vertical
Ni -> N(i+4) and the side diagonal) clamped at the bottom and its free vertex at the
top; the top square ``S^CCCC`` is clamped at the four top nodes. Each L-chain's vertex
receives the external wrench minus the square's reaction, the square receives the
vertex accelerations, and the bottom nodes' wrenches are the sums of the two
L-chains meeting there (``trusscodesign.model.interconnect.connect`` applies these rules).
"""

from __future__ import annotations

import numpy as np

from .mechanisms import l_chain, square_cccc
from .interconnect import connect
from .ports import MultiPortModel
from .titop import Section

__all__ = ["SIDE_LAYOUTS", "TOP_LAYOUTS", "CUBE_GROUPS", "cube_nodes", "cube_members", "cube_cccc_ffff", "cube_cfff_ffff"]

SIDE_LAYOUTS = ("forward", "backward")
TOP_LAYOUTS = ("N6-N8", "N5-N7")
# the group of each member of cube_members(), whatever the layout: the verticals along the cube's z are longerons, the
# top face's four edges battens, the side diagonals and the top one diagonals
CUBE_GROUPS = ("longerons", "diagonals") * 4 + ("battens", "diagonals", "battens", "battens", "battens")


def _check(lx: float, ly: float, lz: float, side: str, top: str) -> None:
    for val, name in ((lx, "lx"), (ly, "ly"), (lz, "lz")):
        if isinstance(val, bool) or not isinstance(val, (int, float, np.integer, np.floating)):
            raise TypeError(f"{name} must be a real number [m], got {type(val).__name__}")
        if not (np.isfinite(val) and val > 0):
            raise ValueError(f"{name} must be a positive length [m], got {val!r}")
    if side not in SIDE_LAYOUTS:
        raise ValueError(f"side must be one of {SIDE_LAYOUTS}, got {side!r}")
    if top not in TOP_LAYOUTS:
        raise ValueError(f"top must be one of {TOP_LAYOUTS}, got {top!r}")


def cube_nodes(lx: float = 1.0, ly: float = 1.0, lz: float = 1.0) -> dict[str, np.ndarray]:
    """Positions [m] of N1..N8 in the cube frame."""
    _check(lx, ly, lz, "forward", "N6-N8")
    base = [(0.0, 0.0), (lx, 0.0), (lx, ly), (0.0, ly)]
    nodes = {f"N{i + 1}": np.array([x, y, 0.0]) for i, (x, y) in enumerate(base)}
    nodes.update({f"N{i + 5}": np.array([x, y, lz]) for i, (x, y) in enumerate(base)})
    return nodes


def _chains(side: str) -> list[tuple[str, str, str]]:
    """(vertical bottom node, top node, diagonal bottom node) of the four L-chains."""
    shift = -1 if side == "forward" else 1
    return [(f"N{i}", f"N{i + 4}", f"N{(i - 1 + shift) % 4 + 1}") for i in range(1, 5)]


def _square(top: str) -> tuple[str, str, str, str]:
    """Square nodes (A, B, C, D) with the diagonal B-C."""
    return ("N5", "N6", "N8", "N7") if top == "N6-N8" else ("N6", "N5", "N7", "N8")


def cube_members(side: str = "forward", top: str = "N6-N8") -> list[tuple[str, str]]:
    """The 13 beams as (P node, C node) pairs, in the orientation used by the block diagram."""
    _check(1.0, 1.0, 1.0, side, top)
    members = []
    for bottom, top_node, diag in _chains(side):
        members += [(bottom, top_node), (diag, top_node)]
    a, b, c, d = _square(top)
    members += [(a, b), (c, b), (a, c), (b, d), (c, d)]
    return members


def cube_cccc_ffff(section: Section, lx: float = 1.0, ly: float = 1.0, lz: float = 1.0, side: str = "forward",
                   top: str = "N6-N8", n_modes: int = 1, name: str = "cube", h_param=None) -> MultiPortModel:
    """Cube ``C^{CCCC-FFFF}``: accelerations imposed at N1..N4, wrenches applied at N5..N8.

    Parameters
    ----------
    section : Section
        Section and material of all 13 beams.
    lx, ly, lz : float
        Cube sides [m].
    side, top : str
        Diagonal layout (see module docstring).
    n_modes : int
        Beam basis enrichment (1: order-20 beams, 260 states in all).
    h_param : trusscodesign.model.lft.Parameter, optional
        Square-section side as an LFT parameter (scaled signals, see :func:`trusscodesign.model.titop.clamped_free_lft`).

    Returns
    -------
    MultiPortModel
        48x48 model, ports N1..N4 clamped and N5..N8 free, all in the cube frame.
    """
    _check(lx, ly, lz, side, top)
    nodes = cube_nodes(lx, ly, lz)
    blocks = []
    for bottom, top_node, diag in _chains(side):
        blocks.append(l_chain((bottom, nodes[bottom]), (top_node, nodes[top_node]), (diag, nodes[diag]), section, n_modes,
                              name=f"L_{top_node}", h_param=h_param))
    a, b, c, d = ((n, nodes[n]) for n in _square(top))
    blocks.append(square_cccc(a, b, c, d, section, n_modes, name="S_top", h_param=h_param))
    return connect(blocks, name=name, order=[f"N{i}" for i in range(1, 9)])


def cube_cfff_ffff(section: Section, lx: float = 1.0, ly: float = 1.0, lz: float = 1.0, side: str = "forward",
                   top: str = "N6-N8", n_modes: int = 1) -> MultiPortModel:
    """Validation model ``C^{CFFF-FFFF} = [C^{CCCC-FFFF}]^{-1_[7:24]}``: clamped at N1 only."""
    cube = cube_cccc_ffff(section, lx, ly, lz, side, top, n_modes)
    return cube.invert(range(7, 25), one_based=True, name="cube CFFF-FFFF")
