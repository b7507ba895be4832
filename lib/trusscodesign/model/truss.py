"""The T-shaped truss ``T_str``: five cubes, 65 beams, 24 nodes, by sub-structuring.

Paper: section "Flexible T-Truss Structure". The drawing is missing from the text;
the geometry and numbering chosen here (truss frame: origin at N1, axes those of the
spacecraft; cube side ``a``, 1 m in the paper):

* three cubes stacked along z: C1 on the base N1..N4 (z = 0), C2, C3; levels
  z = a, 2a, 3a hold N5..N8, N9..N12, N13..N16, each level numbered like the
  cube's N1..N4 (x-y corners (0,0), (a,0), (a,a), (0,a));
* C4 on the -y face of C3, the cube rotated by +90 deg about x (its local z along
  -y), clamped at N9, N10, N14, N13 and free at its outer face N17..N20 (the cube's
  N5..N8 in order): N17 = (0, -a, 2a), N18 = (a, -a, 2a), N19 = (a, -a, 3a),
  N20 = (0, -a, 3a);
* C5 on the +y face of C3, rotated by -90 deg about x, clamped at N16, N15, N11,
  N12, free at N21..N24.

With this numbering N20 lies on the top plane (antenna) and N17 directly below it:
two couples of PMAs along x and y at N17 and N20 then produce, in phase, the two
translations orthogonal to the LOS and, in opposition, the two moments about x and y
(LOS elevation and azimuth), as the paper requires. Envelope a x 3a x 3a.

Assembly: ``trusscodesign.model.interconnect.connect`` of the five cube blocks (each ``C^{CCCC-FFFF}``,
re-projected with its DCM); at every shared node one cube is free (it carries the
node) and the others are clamped there. 45 loop-closing inversions (9 per cube)
leave 540 spurious poles at s = 0.
"""

from __future__ import annotations

import numpy as np

from . import frames
from ..infra.checks import check_real
from .cube import cube_cccc_ffff, cube_members, cube_nodes
from .cubetruss import Cube, CubeTruss, cube_truss
from .interconnect import connect
from .ports import MultiPortModel
from .titop import Section

__all__ = ["CUBES", "truss_nodes", "truss_members", "t_truss_all_ports", "t_truss", "t_truss_cubes"]

# (DCM cube -> truss frame as a function of the rotation about x [rad], origin in units of a)
CUBES: dict[str, tuple[float, tuple[float, float, float]]] = {
    "C1": (0.0, (0.0, 0.0, 0.0)),
    "C2": (0.0, (0.0, 0.0, 1.0)),
    "C3": (0.0, (0.0, 0.0, 2.0)),
    "C4": (np.pi / 2, (0.0, 0.0, 2.0)),
    "C5": (-np.pi / 2, (0.0, 1.0, 3.0)),
}


def truss_nodes(a: float = 1.0) -> dict[str, np.ndarray]:
    """Positions [m] of N1..N24 in the truss frame (origin N1)."""
    check_real("cube side a", a, "m")
    if not (np.isfinite(a) and a > 0):
        raise ValueError(f"cube side a must be a positive length [m], got {a!r}")
    corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    nodes = {}
    for level in range(4):
        for i, (x, y) in enumerate(corners):
            nodes[f"N{4 * level + i + 1}"] = a * np.array([x, y, float(level)])
    for k, (y, z) in enumerate([(-1, 2), (-1, 2), (-1, 3), (-1, 3)]):
        nodes[f"N{17 + k}"] = a * np.array([corners[k % 2 if k < 2 else 3 - k][0], y, z], dtype=float)
    for k, (x, z) in enumerate([(0, 3), (1, 3), (1, 2), (0, 2)]):
        nodes[f"N{21 + k}"] = a * np.array([x, 2.0, z], dtype=float)
    return nodes


def _cube_placement(cube: str, a: float, nodes: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, dict[str, str]]:
    """DCM, origin and local -> truss node names of one cube (names matched by position)."""
    angle, origin = CUBES[cube]
    rot = frames.rot_x(angle)
    org = a * np.asarray(origin)
    mapping = {}
    for local, pos in cube_nodes(a, a, a).items():
        target = rot @ pos + org
        match = [n for n, r in nodes.items() if np.allclose(r, target, atol=1e-9 * a)]
        if len(match) != 1:  # pragma: no cover - geometry table is fixed
            raise RuntimeError(f"cube {cube} node {local} at {target} matches {match}")
        mapping[local] = match[0]
    return rot, org, mapping


def truss_members(a: float = 1.0) -> list[tuple[str, str]]:
    """The 65 beams as (P node, C node) pairs in truss numbering."""
    nodes = truss_nodes(a)
    out = []
    for cube in CUBES:
        _, _, mapping = _cube_placement(cube, a, nodes)
        out += [(mapping[p], mapping[c]) for p, c in cube_members()]
    return out


def t_truss_all_ports(section: Section, a: float = 1.0, n_modes: int = 1, h_param=None) -> MultiPortModel:
    """T-truss with all 24 nodes as ports (N1..N4 clamped, the others free), truss frame."""
    nodes = truss_nodes(a)
    blocks = []
    for cube in CUBES:
        rot, org, mapping = _cube_placement(cube, a, nodes)
        block = cube_cccc_ffff(section, a, a, a, n_modes=n_modes, name=cube, h_param=h_param)
        if cube in ("C4", "C5"):
            block = block.reproject(rot)
        blocks.append(block.translate(org).rename(mapping))
    return connect(blocks, name="T_str (all nodes)", order=list(nodes))


def t_truss(section: Section, a: float = 1.0, n_modes: int = 1, ports: tuple[str, ...] = ("N1", "N2", "N3", "N4", "N17", "N20"),
            h_param=None) -> MultiPortModel:
    """The paper's 6-port T-truss ``T_str`` (36x36, order 1300 with order-20 beams).

    Ports N1..N4 (accelerations imposed by the hub) and N17, N20 (wrenches of the
    PMAs and the antenna); the other nodes are unloaded. With ``h_param`` (an LFT
    parameter for the section side) the beams work on scaled signals, converted back
    to physical ones at the truss ports (``a = a_scaled / r``, ``W = r W_scaled``,
    ``r = h / h_param.center``).
    """
    model = t_truss_all_ports(section, a, n_modes, h_param).select(list(ports), name="T_str")
    if h_param is None:
        return model
    return model.unscale_signals_lft(h_param, list(ports))


def t_truss_cubes(a: float = 1.0) -> CubeTruss:
    """The T-truss as a truss of cubes (:mod:`trusscodesign.model.cubetruss`): :data:`CUBES`, nodes N1..N24 and members
    as :func:`truss_nodes` and :func:`truss_members`.

    Its member-by-member model (:func:`trusscodesign.model.cubetruss.truss_model`) equals :func:`t_truss` to round-off;
    :func:`t_truss` keeps the paper's cube-by-cube block diagram, on which the stored results were computed.
    """
    check_real("cube side a", a, "m")
    cubes = []
    for name, (angle, origin) in CUBES.items():
        rot = tuple(tuple(float(v) for v in np.round(row)) for row in frames.rot_x(angle))
        cubes.append(Cube(name, (a * origin[0], a * origin[1], a * origin[2]), rot, (a, a, a)))
    return cube_truss(cubes)
