"""Checks of scalar options shared by the modules (synthesis, design, co-design, swarm): one wording of the errors."""

from __future__ import annotations

import numpy as np

__all__ = ["check_option", "check_real", "check_flag", "check_choice", "check_frequency_grid", "check_panel_angles", "check_members"]


def check_option(name: str, value: object, low: float, high: float = np.inf, integer: bool = False,
                 open_low: bool = False, open_high: bool = False, unit: str = "") -> None:
    """Raise a ValueError (TypeError for a non-number; an integer is required with ``integer``) naming an option, its
    unit and its range ``[low, high]`` (``open_low``/``open_high``: that end excluded)."""
    kind = "an integer" if integer else "a number"
    number = value if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool) else None
    if number is None or (integer and not isinstance(number, (int, np.integer))):
        raise TypeError(f"{name} must be {kind}{f' [{unit}]' if unit else ''}, got {type(value).__name__} {value!r}")
    v = float(number)
    inside = (np.isfinite(v) or high == np.inf and v == np.inf) and (v > low if open_low else v >= low) and (
        v < high if open_high else v <= high)
    if not inside:
        lo_b, hi_b = "(" if open_low else "[", ")" if open_high or high == np.inf else "]"
        raise ValueError(f"{name} must be {kind} in {lo_b}{low:g}, {high:g}{hi_b}{f' {unit}' if unit else ''}, got {value!r}")


def check_real(name: str, value: object, unit: str = "") -> None:
    """Raise a TypeError naming ``name`` unless ``value`` is a real number (int, float or their numpy kinds; not a bool,
    a string or an array): the check of type that :func:`check_option` does, for values whose range is checked apart."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number{f' [{unit}]' if unit else ''}, got {type(value).__name__} {value!r}")


def check_flag(name: str, value: object) -> None:
    """Raise a TypeError naming ``name`` unless ``value`` is True or False (a string such as ``"False"`` is truthy)."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {type(value).__name__} {value!r}")


def check_choice(name: str, value: object, choices: tuple) -> None:
    """Raise a ValueError naming ``name`` and the allowed values unless ``value`` is one of ``choices``."""
    if isinstance(value, (list, dict, set)) or value not in choices:
        raise ValueError(f"{name} must be one of {list(choices)}, got {value!r}")


def check_frequency_grid(omega_min: object, omega_max: object, n_omega: object,
                         names: tuple[str, str, str] = ("omega_min", "omega_max", "n_omega")) -> None:
    """Raise (naming the parameter, in rad/s) unless ``0 < omega_min < omega_max`` and ``n_omega >= 2`` points."""
    check_option(names[0], omega_min, 0.0, open_low=True, unit="rad/s")
    check_option(names[1], omega_max, float(omega_min), open_low=True, unit="rad/s")  # type: ignore[arg-type]
    check_option(names[2], n_omega, 2, integer=True)


def check_panel_angles(name: str, values: object) -> None:
    """Raise a ValueError naming ``name`` unless every value is a finite panel angle in [-pi, pi] rad (1e-12 tolerance):
    an angle in degrees is the likely mistake, and the message says so."""
    angles = np.atleast_1d(np.asarray(values, dtype=float))
    if not (np.all(np.isfinite(angles)) and np.all(np.abs(angles) <= np.pi + 1e-12)):
        raise ValueError(f"{name} must be panel angles in [-pi, pi] rad, got {values!r}: in degrees? (use np.deg2rad)")


def check_members(nodes, members, clamped=None) -> None:
    """Raise a ValueError unless every member and clamped node is a known node, every node belongs to a member and
    (if ``clamped`` is given) at least one node is clamped and every node is held by a clamped one through the members
    (a frame with an unused node, none clamped or a loose part has a singular stiffness)."""
    names = list(nodes)
    unknown = sorted({n for m in members for n in m if n not in nodes} | {n for n in clamped or () if n not in nodes})
    if unknown:
        raise ValueError(f"unknown node(s) {unknown}; nodes are {names}")
    unused = sorted(set(names) - {n for m in members for n in m})
    if unused:
        raise ValueError(f"node(s) {unused} belong to no member: their stiffness matrix would be singular; drop them")
    if clamped is not None and not len(clamped):
        raise ValueError("clamped must name at least one node (a free-free frame has rigid modes)")
    if clamped is not None:  # every node held through members by a clamped one, or a loose part moves rigidly
        links: dict[str, set[str]] = {n: set() for n in names}
        for p, c in members:
            links[p].add(c)
            links[c].add(p)
        held, todo = set(clamped), list(clamped)
        while todo:
            for n in links[todo.pop()] - held:
                held.add(n)
                todo.append(n)
        loose = [n for n in names if n not in held]
        if loose:
            raise ValueError(f"node(s) {loose} are connected to no clamped node through the members: that part would move "
                             "as a rigid body; connect it or clamp one of its nodes")
