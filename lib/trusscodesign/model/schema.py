"""The spacecraft parameters' schema: every field the models read, with its kind, unit and allowed range.

:func:`check_parameters` walks a parameters dictionary (the package's ``data/spacecraft/parameters.json`` or one a user
edits or builds) and raises at the first field that is missing, of the wrong kind, not finite or out of its range, with
the file and the field's path named (``hub.inertia``), the unit and what is allowed. Keys that start with ``_`` are
notes; the ``choices`` entries that only document a derivation are not read and not checked.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from .titop import DAMPING_MODELS

__all__ = ["check_parameters"]

HUB_POINTS = ("P1", "P2", "P3", "P4", "P5", "P6", "P7")


def _number(low: float = -np.inf, high: float = np.inf, open_low: bool = False, open_high: bool = False) -> Callable:
    def check(value: Any) -> str | None:
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
            return f"a number, got {type(value).__name__} {value!r}"
        inside = np.isfinite(value) and (value > low if open_low else value >= low) and (value < high if open_high else value <= high)
        if not inside:
            return f"a finite number in {'(' if open_low else '['}{low:g}, {high:g}{')' if open_high or high == np.inf else ']'}, got {value!r}"
        return None
    return check


POSITIVE = _number(0.0, open_low=True)
RATIO = _number(0.0, 1.0, open_high=True)  # an uncertainty or a damping ratio


def _vector(n: int) -> Callable:
    def check(value: Any) -> str | None:
        a = np.asarray(value, dtype=object)
        if a.shape != (n,) or any(_number()(v) for v in a):
            return f"a list of {n} finite numbers, got {value!r}"
        return None
    return check


def _inertia(value: Any) -> str | None:
    a = np.asarray(value, dtype=object)
    if a.shape != (3, 3) or any(_number()(v) for v in a.ravel()):
        return f"a 3x3 list of finite numbers, got {value!r}"
    m = a.astype(float)
    if not np.allclose(m, m.T, rtol=0.0, atol=1e-12 * np.abs(m).max()) or np.linalg.eigvalsh(m).min() <= 0:
        return f"a symmetric positive definite 3x3 inertia, got {value!r}"
    return None


def _one_of(*choices: str) -> Callable:
    return lambda value: None if value in choices else f"one of {list(choices)}, got {value!r}"


def _names(keys: tuple[str, ...], values: tuple[str, ...] | None = None) -> Callable:
    """A mapping whose keys are exactly ``keys`` (each value one of ``values`` if given)."""
    def check(value: Any) -> str | None:
        if not isinstance(value, Mapping) or sorted(value) != sorted(keys):
            return f"a mapping with the keys {list(keys)}, got {value!r}"
        if values is not None and any(v not in values for v in value.values()):
            return f"a mapping whose values are among {list(values)}, got {value!r}"
        return None
    return check


def _points(value: Any) -> str | None:
    if not isinstance(value, Mapping) or sorted(value) != sorted(HUB_POINTS):
        return f"a mapping of the hub points {list(HUB_POINTS)} to positions, got {value!r}"
    bad = [k for k, v in value.items() if _vector(3)(v)]
    return f"positions as lists of 3 finite numbers; not so for {bad}" if bad else None


def _increasing_positive(value: Any) -> str | None:
    a = np.asarray(value, dtype=object)
    if a.ndim != 1 or not len(a) or any(POSITIVE(v) for v in a) or np.any(np.diff(a.astype(float)) <= 0):
        return f"a list of positive, increasing numbers, got {value!r}"
    return None


def _factors(value: Any) -> str | None:
    a = np.asarray(value, dtype=object)
    if a.ndim != 2 or a.shape[1] != 6 or any(_number()(v) for v in a.ravel()):
        return f"a list of participation-factor rows of 6 finite numbers (one row per panel mode), got {value!r}"
    return None


def _pma_layout(value: Any) -> str | None:
    ok = isinstance(value, list) and len(value) == 4 and all(
        isinstance(s, Mapping) and isinstance(s.get("node"), str) and s.get("direction") in ("x", "y") for s in value)
    return None if ok else f"a list of 4 {{'node': 'N..', 'direction': 'x' or 'y'}} entries, got {value!r}"


# (path, unit, check)
FIELDS: tuple[tuple[str, str, Callable], ...] = (
    ("hub.mass", "kg", POSITIVE), ("hub.mass_uncertainty", "-", RATIO), ("hub.inertia", "kg m^2", _inertia),
    ("hub.iyy_uncertainty", "-", RATIO), ("hub.points", "m", _points),
    ("truss.cube_side", "m", POSITIVE), ("truss.young", "Pa", POSITIVE), ("truss.poisson", "-", _number(-1.0, 0.5, True, True)),
    ("truss.density", "kg/m^3", POSITIVE), ("truss.damping", "-", RATIO),
    ("truss.damping_model", "-", _one_of(*DAMPING_MODELS)), ("truss.h_range", "m", _vector(2)),
    ("truss.h_nominal", "m", POSITIVE), ("truss.torsion", "-", _one_of("polar", "exact")),
    ("truss.base_points", "-", _names(("N1", "N2", "N3", "N4"), HUB_POINTS)),
    ("solar_panel.mass", "kg", POSITIVE), ("solar_panel.r_og", "m", _vector(3)), ("solar_panel.inertia_g", "kg m^2", _inertia),
    ("solar_panel.omega", "rad/s", _increasing_positive), ("solar_panel.omega1_uncertainty", "-", RATIO),
    ("solar_panel.damping", "-", RATIO), ("solar_panel.factors", "kg, kg m", _factors),
    ("solar_panel.points", "-", _names(("SP1", "SP2"), HUB_POINTS)),
    ("antenna.mass", "kg", POSITIVE), ("antenna.inertia", "kg m^2", _inertia),
    ("antenna.node", "-", lambda v: None if isinstance(v, str) else f"a truss node name, got {v!r}"),
    ("pma.casing_mass", "kg", POSITIVE), ("pma.casing_inertia", "kg m^2", _inertia), ("pma.r_og", "m", _vector(3)),
    ("pma.r_op", "m", _vector(3)), ("pma.axis", "-", _vector(3)), ("pma.proof_mass", "kg", POSITIVE),
    ("pma.stiffness", "N/m", POSITIVE), ("pma.damping", "N s/m", _number(0.0)),
    ("closed_loop.omega_acs", "rad/s", POSITIVE), ("closed_loop.xi_acs", "-", POSITIVE), ("closed_loop.omega_pma", "rad/s", POSITIVE),
    ("closed_loop.eps_max", "rad", POSITIVE), ("closed_loop.t_delta", "s", POSITIVE), ("closed_loop.p_max", "N m", POSITIVE),
    ("closed_loop.u_max", "N", POSITIVE), ("closed_loop.gamma_u", "-", POSITIVE),
    ("choices.panel_turn_z_deg", "deg", lambda v: _names(("SP1", "SP2"))(v) or next(
        (f"finite angles, got {v!r}" for x in v.values() if _number()(x)), None)),
    ("choices.sadm_stiffness", "N m/rad", POSITIVE), ("choices.sadm_friction", "N m s/rad", _number(0.0)),
    ("choices.pma_layout", "-", _pma_layout), ("choices.xi_pma", "-", POSITIVE),
    ("choices.effort", "-", _one_of("command", "transmitted")),
)


def check_parameters(params: Mapping, source: str = "the spacecraft parameters") -> None:
    """Raise a ValueError at the first field of ``params`` that is missing or not what the models need.

    Parameters
    ----------
    params : mapping
        The parameters (the layout of the package's ``data/spacecraft/parameters.json``).
    source : str
        Where they come from (a file name), for the message.

    Raises
    ------
    ValueError
        Naming ``source``, the field's path, its unit and what is allowed.
    """
    for path, unit, check in FIELDS:
        node: Any = params
        for i, key in enumerate(path.split(".")):
            if not isinstance(node, Mapping) or key not in node:
                raise ValueError(f"{source}: the field {path} is missing ({'.'.join(path.split('.')[:i + 1])} not found); "
                                 f"every field the models read must be given")
            node = node[key]
        problem = check(node)
        if problem:
            raise ValueError(f"{source}: {path} [{unit}] must be {problem}")
    low, high = params["truss"]["h_range"]
    if not 0 < low < high:
        raise ValueError(f"{source}: truss.h_range [m] must be (low, high) with 0 < low < high, got {[low, high]}")
    panel = params["solar_panel"]
    if len(panel["factors"]) != len(panel["omega"]):
        raise ValueError(f"{source}: solar_panel.factors must have one row per mode of solar_panel.omega "
                         f"({len(panel['omega'])}), got {len(panel['factors'])}")
