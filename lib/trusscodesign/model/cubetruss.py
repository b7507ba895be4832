"""Any truss built from cubes: its description, its checks, its member groups and its TITOP model.

Paper: "complex truss structures ... by repetitions of the element" (section "3D Mechanisms"); the T-truss of
:mod:`trusscodesign.model.truss` is one instance (:func:`trusscodesign.model.truss.t_truss_cubes`).

A truss is a list of :class:`Cube` placements (origin, orientation, sides, diagonal layout), each the cube element of
:mod:`trusscodesign.model.cube` (13 beams, no beam on its bottom face). :func:`cube_truss` finds the shared nodes from
their positions, names every node ``N1, N2, ...`` in order of first appearance (cube by cube, each cube's N1..N8), and
builds each member once: a member two cubes share (the common edge of two cubes side by side) is one beam, in the
orientation and group of the first cube that has it. It refuses a description that would not be a truss of cubes:
overlapping cubes, cubes that touch without sharing the corners of their contact (different sides, an offset), a cube
connected to nothing, an orientation off the axes.

Each member belongs to a group (:data:`GROUPS`), by its role in its cube: ``"longerons"`` (the four edges along the
cube's z axis), ``"battens"`` (the four edges of its top face), ``"diagonals"`` (its side and top diagonals). Each
group, each cube and each group of one cube may have its own section (:meth:`CubeTruss.sections`).

:func:`truss_model` assembles the TITOP beams member by member (:func:`trusscodesign.model.interconnect.connect`):
each node is carried by the first member whose free end C is there, every other member's end at that node is
clamped by channel inversion (the loop closures, which leave their spurious poles at s = 0: removed by
:func:`trusscodesign.model.reduction.remove_slow_poles`); a node no member carries stays clamped. Then the ports are
inverted where the user's choice of clamped nodes differs. The T-truss built this way equals the cube-by-cube block
diagram of :func:`trusscodesign.model.truss.t_truss` to round-off (tests/model/test_cubetruss.py).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from itertools import combinations

import numpy as np
from numpy.typing import NDArray

from . import frames
from ..infra.checks import check_option
from .assembly import Modes, lowest_modes
from .cube import CUBE_GROUPS, SIDE_LAYOUTS, TOP_LAYOUTS, cube_members, cube_nodes
from .interconnect import connect
from .ports import MultiPortModel
from .titop import Section, beam

__all__ = ["GROUPS", "Cube", "Member", "CubeTruss", "cube_truss", "boom", "plate", "truss_model"]

GROUPS = ("longerons", "battens", "diagonals")
_AXES = {"x": frames.rot_y(np.pi / 2), "y": frames.rot_x(-np.pi / 2), "z": np.eye(3)}  # cube z along the axis


@dataclass(frozen=True)
class Cube:
    """One cube of a truss.

    Parameters
    ----------
    name : str
        Its name (in error messages and section keys).
    origin : array_like (3,)
        Position [m] of its node N1 in the truss frame.
    rotation : array_like (3, 3)
        DCM cube -> truss frame, a signed permutation (the cube's axes along the truss's); default the identity.
    sides : (float, float, float)
        Its sides lx, ly, lz [m] along its own axes (z: the longerons).
    side, top : str
        Diagonal layout (:data:`trusscodesign.model.cube.SIDE_LAYOUTS`, :data:`~trusscodesign.model.cube.TOP_LAYOUTS`).
    """

    name: str
    origin: tuple[float, float, float]
    rotation: tuple[tuple[float, ...], ...] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    sides: tuple[float, float, float] = (1.0, 1.0, 1.0)
    side: str = "forward"
    top: str = "N6-N8"

    def positions(self) -> dict[str, NDArray[np.float64]]:
        """Its nodes N1..N8 in the truss frame [m]."""
        rot, org = np.asarray(self.rotation, dtype=float), np.asarray(self.origin, dtype=float)
        return {n: rot @ r + org for n, r in cube_nodes(*self.sides).items()}


@dataclass(frozen=True)
class Member:
    """A beam of the truss: from node ``p`` (its clamped end P) to node ``c`` (C), its group and the cube it was
    built for."""

    p: str
    c: str
    group: str
    cube: str


@dataclass(frozen=True)
class CubeTruss:
    """A checked truss of cubes (built by :func:`cube_truss`): its cubes, nodes and members.

    Attributes
    ----------
    cubes : tuple of Cube
        The cubes, in order.
    nodes : dict str -> ndarray (3,)
        Node positions [m] in the truss frame, ``N1, N2, ...`` in order of first appearance.
    members : list of Member
        Every beam once.
    cube_nodes : dict str -> dict str -> str
        For each cube, its local node names N1..N8 -> the truss's.
    """

    cubes: tuple[Cube, ...]
    nodes: dict[str, NDArray[np.float64]]
    members: list[Member]
    cube_nodes: dict[str, dict[str, str]] = field(repr=False)

    def sections(self, sections: Section | Mapping[str, Section]) -> list[Section]:
        """The section of each member.

        Parameters
        ----------
        sections : Section or mapping str -> Section
            One section for every member, or sections by key: ``"<cube>/<group>"`` before ``"<cube>"`` before
            ``"<group>"`` before ``"all"`` (groups: :data:`GROUPS`).

        Raises
        ------
        ValueError
            If a key names no cube or group, or a member has no section.
        """
        if isinstance(sections, Section):
            return [sections] * len(self.members)
        names = [c.name for c in self.cubes]
        known = {"all", *GROUPS, *names, *(f"{c}/{g}" for c in names for g in GROUPS)}
        unknown = sorted(set(sections) - known)
        if unknown:
            raise ValueError(f"section keys {unknown} name no cube or group: use 'all', a group {list(GROUPS)}, a cube "
                             f"{names} or '<cube>/<group>'")
        out, missing = [], []
        for m in self.members:
            key = next((k for k in (f"{m.cube}/{m.group}", m.cube, m.group, "all") if k in sections), None)
            if key is None:
                missing.append(f"{m.cube}/{m.group}")
            else:
                out.append(sections[key])
        if missing:
            raise ValueError(f"no section for the members {sorted(set(missing))}: give one (or 'all')")
        return out

    def mass(self, sections: Section | Mapping[str, Section]) -> float:
        """Mass of the beams [kg]: rho S L summed over the members."""
        return float(sum(s.density * s.area * self.length(m) for m, s in zip(self.members, self.sections(sections))))

    def length(self, member: Member) -> float:
        """Length of a member [m]."""
        return float(np.linalg.norm(self.nodes[member.c] - self.nodes[member.p]))

    def modes(self, sections: Section | Mapping[str, Section], clamped: Sequence[str], k: int = 20, n_modes: int = 1) -> Modes:
        """The ``k`` lowest modes of the truss with ``clamped`` nodes fixed (sparse constrained assembly of the same
        TITOP beams: :func:`trusscodesign.model.assembly.lowest_modes`, linear in the truss's size)."""
        return lowest_modes(self.nodes, self.pairs(), self.sections(sections), clamped, k, n_modes)

    def pairs(self) -> list[tuple[str, str]]:
        """The members as (P node, C node) pairs (the form of :mod:`trusscodesign.model.assembly` and
        :mod:`trusscodesign.model.opensees_fe`)."""
        return [(m.p, m.c) for m in self.members]


def _check_cube(cube: Cube) -> None:
    if not isinstance(cube, Cube):
        raise TypeError(f"a truss is a sequence of Cube, got {type(cube).__name__}")
    frames.as_vector3(cube.origin, f"origin of cube {cube.name}")
    rot = np.asarray(cube.rotation, dtype=float)
    if rot.shape != (3, 3) or not (np.allclose(np.abs(rot), np.round(np.abs(rot))) and np.allclose(rot @ rot.T, np.eye(3))
                                   and np.isclose(np.linalg.det(rot), 1.0)):
        raise ValueError(f"cube {cube.name}: rotation must be a proper rotation with its axes along the truss's (a signed "
                         f"permutation, det +1), got {rot.tolist()}")
    if len(cube.sides) != 3:
        raise ValueError(f"cube {cube.name}: sides must be (lx, ly, lz) [m], got {cube.sides!r}")
    for val, nm in zip(cube.sides, ("lx", "ly", "lz")):
        if isinstance(val, bool) or not isinstance(val, (int, float, np.integer, np.floating)) or not (np.isfinite(val) and val > 0):
            raise ValueError(f"cube {cube.name}: side {nm} must be a positive length [m], got {val!r}")
    if cube.side not in SIDE_LAYOUTS or cube.top not in TOP_LAYOUTS:
        raise ValueError(f"cube {cube.name}: side must be one of {SIDE_LAYOUTS} and top one of {TOP_LAYOUTS}, got "
                         f"{cube.side!r}, {cube.top!r}")


def _box(points: Sequence[NDArray]) -> tuple[NDArray, NDArray]:
    arr = np.array(points)
    return arr.min(axis=0), arr.max(axis=0)


def _check_contacts(cubes: Sequence[Cube], positions: Sequence[dict[str, NDArray]], tol: float) -> None:
    """Overlaps and contacts that do not share their corners; a cube connected to nothing."""
    boxes = [_box(list(p.values())) for p in positions]
    touching: dict[int, set[int]] = {i: set() for i in range(len(cubes))}
    for i, j in combinations(range(len(cubes)), 2):
        lo, hi = np.maximum(boxes[i][0], boxes[j][0]), np.minimum(boxes[i][1], boxes[j][1])
        extent = hi - lo
        if np.any(extent < -tol):
            continue
        if np.all(extent > tol):
            raise ValueError(f"cubes {cubes[i].name} and {cubes[j].name} overlap (common volume from {lo} to {hi} m)")
        flat = np.abs(extent) <= tol
        corners = [np.where(flat, lo, np.where(bits, hi, lo)) for bits in np.ndindex(*(2,) * 3)]
        for pos, cube in ((positions[i], cubes[i]), (positions[j], cubes[j])):
            if not all(any(np.allclose(c, r, atol=tol) for r in pos.values()) for c in corners):
                raise ValueError(f"cubes {cubes[i].name} and {cubes[j].name} touch (from {lo} to {hi} m) without sharing "
                                 f"the corners of their contact: cube {cube.name} has no node at some of them (sides "
                                 "differ or the cubes are offset)")
        touching[i].add(j)
        touching[j].add(i)
    seen, todo = {0}, [0]
    while todo:
        for k in touching[todo.pop()] - seen:
            seen.add(k)
            todo.append(k)
    alone = [cubes[k].name for k in range(len(cubes)) if k not in seen]
    if alone:
        raise ValueError(f"cubes {alone} are connected to nothing of cube {cubes[0].name}: a truss is one piece")


def cube_truss(cubes: Sequence[Cube]) -> CubeTruss:
    """Check a description of cubes and find its nodes and members (module docstring).

    Parameters
    ----------
    cubes : sequence of Cube
        The cubes; their names must differ.

    Returns
    -------
    CubeTruss

    Raises
    ------
    ValueError
        For an empty list, repeated names, a bad placement, overlapping cubes, a contact without shared corners, or a
        cube connected to nothing; the message names the cubes.
    """
    cubes = tuple(cubes)
    if not cubes:
        raise ValueError("a truss needs at least one cube")
    for cube in cubes:
        _check_cube(cube)
    names = [c.name for c in cubes]
    if len(set(names)) != len(names):
        raise ValueError(f"cube names must differ, got {names}")
    largest = max(max(c.sides) for c in cubes)
    if min(min(c.sides) for c in cubes) < 1e-3 * largest:
        raise ValueError(f"cube sides range from {min(min(c.sides) for c in cubes):g} to {largest:g} m: the shortest must be "
                         "at least 1e-3 of the longest (nodes are merged within 1e-9 of the longest side)")
    tol = 1e-9 * largest
    positions = [c.positions() for c in cubes]
    _check_contacts(cubes, positions, tol)
    # nodes merged by distance (a rounding grid would split points that straddle a grid line)
    nodes: dict[str, NDArray[np.float64]] = {}
    found = np.zeros((0, 3))
    local: dict[str, dict[str, str]] = {}
    for cube, pos in zip(cubes, positions):
        local[cube.name] = {}
        for n, r in pos.items():
            near = np.flatnonzero(np.max(np.abs(found - r), axis=1) <= tol) if len(found) else np.zeros(0, int)
            if near.size:
                local[cube.name][n] = f"N{near[0] + 1}"
            else:
                nodes[f"N{len(nodes) + 1}"] = r
                found = np.vstack([found, r])
                local[cube.name][n] = f"N{len(nodes)}"
    members: list[Member] = []
    built: set[frozenset[str]] = set()
    centres = np.zeros((0, 3))
    for cube in cubes:
        for (p, c), group in zip(cube_members(cube.side, cube.top), CUBE_GROUPS):
            gp, gc = local[cube.name][p], local[cube.name][c]
            if frozenset((gp, gc)) in built:
                continue
            centre = (nodes[gp] + nodes[gc]) / 2
            same = np.flatnonzero(np.max(np.abs(centres - centre), axis=1) <= tol) if len(centres) else np.zeros(0, int)
            if same.size:  # two different members through one point: crossing diagonals of a shared face
                other = members[same[0]]
                raise ValueError(f"member {gp}-{gc} of cube {cube.name} crosses member {other.p}-{other.c} of cube "
                                 f"{other.cube} at their midpoint, without a node: give the two cubes mirror side "
                                 f"layouts ({SIDE_LAYOUTS}) so that their shared face has one diagonal")
            built.add(frozenset((gp, gc)))
            members.append(Member(gp, gc, group, cube.name))
            centres = np.vstack([centres, centre])
    return CubeTruss(cubes, nodes, members, local)


def boom(n: int, a: float = 1.0, axis: str = "z") -> CubeTruss:
    """A boom of ``n`` cubes of side ``a`` [m] stacked along ``axis`` (``"x"``, ``"y"`` or ``"z"``) from the origin.

    The cubes are named C1..Cn; each one's longerons run along the axis and its bottom face is the previous one's top.
    The boom's base is cube C1's N1..N4, the truss's N1..N4.
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n (number of cubes) must be an integer >= 1, got {n!r}")
    check_option("a (cube side)", a, 0.0, 1e3, open_low=True, unit="m")
    if axis not in _AXES:
        raise ValueError(f"axis must be one of {list(_AXES)}, got {axis!r}")
    rot = _AXES[axis]
    step = rot @ np.array([0.0, 0.0, a])
    rows = tuple(tuple(float(v) for v in np.round(row)) for row in rot)
    return cube_truss([Cube(f"C{k + 1}", tuple(k * step), rows, (a, a, a)) for k in range(n)])


def plate(n: int, m: int, a: float = 1.0) -> CubeTruss:
    """A plate of ``n`` x ``m`` cubes of side ``a`` [m] side by side in the x-y plane, one layer thick.

    Cube ``C<i>_<j>`` has its N1 at ``(i a, j a, 0)``. Neighbours alternate the side-diagonal layout (a checkerboard of
    ``"forward"`` and ``"backward"``), so that a face two cubes share has one diagonal, built once, like its edges.
    """
    for val, nm in ((n, "n"), (m, "m")):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < 1:
            raise ValueError(f"{nm} (cubes along {'x' if nm == 'n' else 'y'}) must be an integer >= 1, got {val!r}")
    check_option("a (cube side)", a, 0.0, 1e3, open_low=True, unit="m")
    return cube_truss([Cube(f"C{i + 1}_{j + 1}", (i * a, j * a, 0.0), sides=(a, a, a),
                            side=SIDE_LAYOUTS[(i + j) % 2]) for i in range(n) for j in range(m)])


def _carriers(truss: CubeTruss) -> dict[str, int]:
    """For each node carried by a member, the index of the first member whose free end C is there; checked free of
    loops (a node carried, through its member's P end, by itself would be an algebraic loop)."""
    carrier: dict[str, int] = {}
    for i, m in enumerate(truss.members):
        carrier.setdefault(m.c, i)
    for start in carrier:
        node, seen = start, set[str]()
        while node in carrier:
            if node in seen:
                raise ValueError(f"the members carrying node {start} form a loop through {sorted(seen)}: reverse one of them")
            seen.add(node)
            node = truss.members[carrier[node]].p
    return carrier


def truss_model(truss: CubeTruss, sections: Section | Mapping[str, Section], clamped: Sequence[str],
                ports: Sequence[str] = (), n_modes: int = 1, h_param=None, name: str = "truss") -> MultiPortModel:
    """TITOP model of a truss of cubes, assembled member by member (module docstring).

    Parameters
    ----------
    truss : CubeTruss
        The truss (:func:`cube_truss`, :func:`boom`, :func:`plate`).
    sections : Section or mapping str -> Section
        Sections of the members (:meth:`CubeTruss.sections`).
    clamped : sequence of str
        Nodes whose accelerations are imposed (inputs; their reaction wrenches are outputs); at least one.
    ports : sequence of str
        Free nodes that take external wrenches (inputs; their accelerations are outputs); the other free nodes are
        unloaded.
    n_modes : int
        Ritz enrichment of each beam (1: order 20 per beam).
    h_param : trusscodesign.model.lft.Parameter, optional
        The section side of every member as an LFT parameter (one section for all members only), as
        :func:`trusscodesign.model.truss.t_truss`.
    name : str
        Name of the model.

    Returns
    -------
    MultiPortModel
        Ports ``clamped`` then ``ports``, in the truss frame; order ``20 n_modes`` per member.

    Raises
    ------
    ValueError
        If a node is unknown, clamped is empty, a node is both clamped and a port, or ``h_param`` is given with several
        sections.
    """
    if not isinstance(truss, CubeTruss):
        raise TypeError(f"truss must be a CubeTruss (from cube_truss, boom or plate), got {type(truss).__name__}")
    clamped, ports = list(clamped), list(ports)
    unknown = sorted(set(clamped + ports) - set(truss.nodes), key=lambda s: int(s[1:]) if s[1:].isdigit() else 0)
    if unknown:
        raise ValueError(f"nodes {unknown} are not nodes of the truss (N1..N{len(truss.nodes)})")
    if not clamped:
        raise ValueError("clamped must name at least one node: a free-free truss has rigid-body modes")
    both = sorted(set(clamped) & set(ports))
    if both:
        raise ValueError(f"nodes {both} are both clamped and ports: a node takes an acceleration or a wrench")
    secs = truss.sections(sections)
    if h_param is not None and len(set(secs)) > 1:
        raise ValueError("h_param scales one section side: give one section for all members with it")
    carrier = _carriers(truss)
    blocks = []
    for i, (m, sec) in enumerate(zip(truss.members, secs)):
        block = beam((m.p, truss.nodes[m.p]), (m.c, truss.nodes[m.c]), sec, n_modes, name=f"{m.cube}:{m.p}-{m.c}",
                     h_param=h_param)
        blocks.append(block if carrier[m.c] == i else block.invert_ports(m.c))
    model = connect(blocks, name=name, order=list(truss.nodes))
    # carried nodes are free, the others clamped: invert where the user's choice differs
    flip = [n for n in truss.nodes if (n in carrier) == (n in clamped)]
    if flip:
        model = model.invert_ports(*flip, name=name)
    model = model.select(clamped + ports, name=name)
    return model if h_param is None else model.unscale_signals_lft(h_param, clamped + ports)
