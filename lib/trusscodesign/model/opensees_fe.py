"""Frame modal analysis with a real finite-element engine, OpenSeesPy.

Used in notebook 03 as an independent cross-check of the TITOP cube and to explain
the gap between the paper's SDT and Patran/Nastran columns. Each member is meshed
with ``n_elements`` ``elasticBeamColumn`` elements (Euler-Bernoulli, linear
geometric transformation whose local axes are those of
:func:`trusscodesign.model.frames.beam_frame`).

Mass: ``"consistent"`` uses OpenSees' consistent matrix (``-cMass``; its torsional
inertia is rho J per length, i.e. rho Ip when J = Iy + Iz); ``"lumped"`` uses
OpenSees' lumped matrix (translational mass rho S L / 2 per node, no rotary or
torsional inertia).

OpenSeesPy needs the system BLAS/LAPACK runtime (Debian: ``libblas3 liblapack3``,
installed by ``scripts/install.sh``) and, on Python 3.11, openseespy 3.7.1.2
(3.8 requires Python >= 3.12).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import frames
from ..infra.checks import check_members
from .titop import Section, member_sections

__all__ = ["available", "frame_frequencies"]


def available() -> bool:
    """True if OpenSeesPy imports on this machine."""
    try:
        import openseespy.opensees  # noqa: F401
    except Exception:  # pragma: no cover - depends on the machine
        return False
    return True


def frame_frequencies(
    nodes: Mapping[str, ArrayLike],
    members: Sequence[tuple[str, str]],
    section: Section | Sequence[Section],
    clamped: Sequence[str],
    n_elements: int = 10,
    mass: str = "consistent",
    n_modes: int = 10,
) -> NDArray[np.float64]:
    """First ``n_modes`` natural frequencies [rad/s] of a frame computed by OpenSees.

    Parameters
    ----------
    nodes : mapping str -> array_like (3,)
        Structural nodes [m].
    members : sequence of (str, str)
        Members between nodes.
    section : Section or sequence of Section
        Section and material of every member, or of each member in the order of ``members`` (J as given).
    clamped : sequence of str
        Nodes with all six dofs fixed.
    n_elements : int
        Elements per member.
    mass : {"consistent", "lumped"}
        Mass formulation.
    n_modes : int
        Number of frequencies returned.

    Raises
    ------
    ImportError
        If OpenSeesPy cannot be imported (install ``libblas3 liblapack3``).
    """
    if mass not in ("consistent", "lumped"):
        raise ValueError(f"mass must be 'consistent' or 'lumped', got {mass!r}")
    if isinstance(n_elements, bool) or not isinstance(n_elements, (int, np.integer)) or n_elements < 1:
        raise ValueError(f"n_elements must be an integer >= 1, got {n_elements!r}")
    try:
        import openseespy.opensees as ops
    except Exception as exc:  # pragma: no cover - depends on the machine
        raise ImportError(
            "OpenSeesPy is not importable: pip install openseespy==3.7.1.2 and, on Debian, "
            "apt-get install -y libblas3 liblapack3 (scripts/install.sh does both)"
        ) from exc
    names = list(nodes)
    tag = {n: i + 1 for i, n in enumerate(names)}
    check_members(nodes, members, clamped)  # OpenSees would only print warnings and return plausible numbers
    sections = member_sections(section, len(members))
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for n in names:
        ops.node(tag[n], *map(float, frames.as_vector3(nodes[n], f"position of {n}")))
    for n in clamped:
        ops.fix(tag[n], 1, 1, 1, 1, 1, 1)
    next_node, next_ele = len(names) + 1, 1
    for k, ((p, c), sec) in enumerate(zip(members, sections)):
        rp, rc = np.asarray(nodes[p], float), np.asarray(nodes[c], float)
        rot = frames.beam_frame(rp, rc)
        ops.geomTransf("Linear", k + 1, *map(float, rot[:, 2]))  # vector in the local x-z plane: local z
        chain = [tag[p]]
        for j in range(1, n_elements):
            r = rp + (rc - rp) * j / n_elements
            ops.node(next_node, *map(float, r))
            chain.append(next_node)
            next_node += 1
        chain.append(tag[c])
        for i, j in zip(chain[:-1], chain[1:]):
            args = [next_ele, i, j, sec.area, sec.young, sec.shear_modulus, sec.torsion_constant,
                    sec.iy, sec.iz, k + 1, "-mass", sec.density * sec.area]
            if mass == "consistent":
                args.append("-cMass")
            ops.element("elasticBeamColumn", *args)
            next_ele += 1
    lam = np.asarray(ops.eigen(n_modes), dtype=float)
    ops.wipe()
    return np.sqrt(np.clip(lam, 0.0, None))
