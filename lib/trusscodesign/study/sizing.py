"""Sizing the truss by parts: a design vector ``theta`` of k section sides, one per named group of members.

Beyond the paper, whose design variable is one side h for all 65 beams. A :class:`Grouping` names k groups, each a set
of section keys of :meth:`trusscodesign.model.cubetruss.CubeTruss.sections` (a member group such as ``"longerons"``, a
cube ``"C4"``, or a group of one cube ``"C4/longerons"``, the most specific key winning); ``theta[i]`` is the side [m]
of group i. The default, :data:`PAPER_GROUPS`, separates what carries the arm's bending from the rest: the longerons of
the core cubes C1-C3, those of the arm cubes C4-C5, and the bracing (battens and diagonals). With all sides equal the
truss is the paper's (assembled member by member: its models equal the one-side path to round-off).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..model import spacecraft

__all__ = ["PAPER_GROUPS", "Grouping"]

#: The default grouping (k = 3): core longerons, arm longerons, bracing.
PAPER_GROUPS: dict[str, tuple[str, ...]] = {
    "core_longerons": ("C1/longerons", "C2/longerons", "C3/longerons"),
    "arm_longerons": ("C4/longerons", "C5/longerons"),
    "bracing": ("battens", "diagonals"),
}


@dataclass(frozen=True)
class Grouping:
    """k named groups of section keys; :meth:`sides` turns a design vector into the sides by key.

    Parameters
    ----------
    groups : mapping str -> sequence of str
        Group name -> the section keys it sets (each key in one group only).
    """

    groups: tuple[tuple[str, tuple[str, ...]], ...]

    @classmethod
    def of(cls, groups: Mapping[str, Sequence[str]] | None = None) -> "Grouping":
        """A grouping from a mapping (default :data:`PAPER_GROUPS`), checked: names and keys given once each."""
        groups = PAPER_GROUPS if groups is None else groups
        if not groups:
            raise ValueError("groups must name at least one group of section keys")
        keys = [key for members in groups.values() for key in members]
        repeated = sorted({key for key in keys if keys.count(key) > 1})
        if repeated or any(isinstance(m, str) or not len(m) for m in groups.values()):
            raise ValueError(f"each group must be a non-empty list of section keys, each key in one group only (repeated: "
                             f"{repeated}), got {dict(groups)!r}")
        return cls(tuple((str(name), tuple(members)) for name, members in groups.items()))

    @property
    def names(self) -> list[str]:
        """The group names, in the order of ``theta``."""
        return [name for name, _ in self.groups]

    def sides(self, theta: ArrayLike, params: dict | None = None) -> dict[str, float]:
        """The sides [m] by section key for the design vector ``theta`` (one side per group, in :attr:`names` order).

        Raises
        ------
        ValueError
            If ``theta`` does not have one finite side per group, or a side is outside the design range of the
            parameters (paper: [0.015, 0.03] m); the message names the group.
        """
        values: NDArray[np.float64] = np.asarray(theta, dtype=float)
        if values.shape != (len(self.groups),) or not np.all(np.isfinite(values)):
            raise ValueError(f"theta must hold {len(self.groups)} finite sides [m], one per group {self.names}, got {theta!r}")
        low, high = (params or spacecraft.load_parameters())["truss"]["h_range"]
        for name, side in zip(self.names, values):
            if not low - 1e-12 <= side <= high + 1e-12:
                raise ValueError(f"theta[{name!r}] must be a section side in [{low}, {high}] m, got {float(side)!r}")
        return {key: float(side) for (_, keys), side in zip(self.groups, values) for key in keys}

    def mass(self, theta: ArrayLike, params: dict | None = None) -> float:
        """Truss mass [kg] at ``theta`` (rho side^2 times the beams' length, summed over the members)."""
        p = params or spacecraft.load_parameters()
        return spacecraft.truss_mass(self.sides(theta, p), p)

    def mass_coefficients(self, params: dict | None = None) -> NDArray[np.float64]:
        """``c`` [kg/m^2] with ``mass(theta) = sum(c * theta**2)``: each group's rho times its members' length, from
        two masses per group (the mass is exactly quadratic in each side), for the many candidates of a search."""
        p = params or spacecraft.load_parameters()
        low, high = p["truss"]["h_range"]
        base = np.full(len(self.groups), low)
        m_low = self.mass(base, p)
        out = np.empty(len(self.groups))
        for i in range(len(self.groups)):
            theta = base.copy()
            theta[i] = high
            out[i] = (self.mass(theta, p) - m_low) / (high**2 - low**2)
        return out
