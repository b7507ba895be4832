"""Uncertainty scenarios of the synthesis: the box of (M_SC, Iyy_SC, omega1_SP) and the panel angle, the default
set, the search grid, and the generalized plant at a scenario.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...infra.checks import check_panel_angles
from ...infra.checks import check_real as _check_real
from ...model.lft import LFT
from ..closedloop import GeneralizedPlant, LoopSettings, generalized_plant

__all__ = ['Scenario', 'default_scenarios', 'plant_at', 'search_candidates']


@dataclass(frozen=True)
class Scenario:
    """One uncertainty scenario: normalised values in [-1, 1] of M_SC, Iyy_SC, omega1_SP and the panel angle.

    ``theta`` is the panel angle [rad] (``tau = tan(theta / 4)``).
    """

    d_mass: float = 0.0
    d_iyy: float = 0.0
    d_omega1: float = 0.0
    theta: float = 0.0

    def __post_init__(self) -> None:
        for name in ("d_mass", "d_iyy", "d_omega1", "theta"):
            _check_real(f"Scenario.{name}", getattr(self, name), "rad" if name == "theta" else "")
        for name in ("d_mass", "d_iyy", "d_omega1"):
            v = getattr(self, name)
            if not (np.isfinite(v) and abs(v) <= 1 + 1e-12):
                raise ValueError(f"Scenario.{name} is a normalised value and must be in [-1, 1], got {v!r}")
        check_panel_angles("Scenario.theta", self.theta)

    def normalized(self) -> dict[str, float]:
        """Normalised values for :meth:`trusscodesign.model.lft.LFT.substitute` (``normalized=True``)."""
        return {"M_SC": self.d_mass, "Iyy_SC": self.d_iyy, "omega1_SP": self.d_omega1, "tau": float(np.tan(self.theta / 4))}

    def physical(self, model: LFT) -> dict[str, float]:
        """Physical values: hub mass [kg], hub Iyy [kg m^2], first panel frequency [rad/s], theta [deg]."""
        out = {k: model.params[k].from_delta(v) for k, v in self.normalized().items() if k != "tau"}
        return {**out, "theta_deg": float(np.rad2deg(self.theta))}

    @classmethod
    def from_vector(cls, x: ArrayLike) -> "Scenario":
        """From ``[d_mass, d_iyy, d_omega1, theta]`` (clipped to the box)."""
        v = np.asarray(x, dtype=float)
        d = np.clip(v[:3], -1, 1)
        return cls(float(d[0]), float(d[1]), float(d[2]), float(np.clip(v[3], 0.0, np.pi)))

    def vector(self) -> NDArray[np.float64]:
        """``[d_mass, d_iyy, d_omega1, theta]``."""
        return np.array([self.d_mass, self.d_iyy, self.d_omega1, self.theta])


CORNERS = ((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0), (-1.0, 1.0, -1.0), (1.0, -1.0, 1.0))


def _thetas_deg(thetas_deg: object, name: str = "thetas_deg") -> NDArray[np.float64]:
    """Panel angles in degrees, checked: a non-empty 1-D list of finite angles in [-180, 180], and not a grid of several
    angles all within pi (radians given for degrees would search a sliver of 3 deg of the panel range, silently)."""
    try:
        thetas = np.atleast_1d(np.asarray(thetas_deg, dtype=float))
    except (TypeError, ValueError):
        thetas = np.full(0, np.nan)
    if thetas.ndim != 1 or not thetas.size or not np.all(np.isfinite(thetas)) or np.any(np.abs(thetas) > 180.0):
        raise ValueError(f"{name} must be a non-empty list of panel angles in [-180, 180] deg, got {thetas_deg!r}")
    if np.ptp(thetas) > 0 and np.max(np.abs(thetas)) <= np.pi + 1e-12:
        raise ValueError(f"{name} are panel angles in degrees; {thetas_deg!r} all lie within pi: radians? "
                         "(use np.rad2deg)")
    return thetas


def default_scenarios(thetas_deg: Sequence[float] = (0.0, 45.0, 90.0, 135.0, 180.0),
                      corners: Sequence[tuple[float, float, float]] = CORNERS) -> list[Scenario]:
    """Nominal, plus box corners of (M_SC, Iyy_SC, omega1_SP) at each panel angle [deg].

    The default corners are all-low, all-high and the two mixed ones that couple the hub's mass and
    inertia in opposite directions (the worst cases found by the searches at the paper's h).
    """
    out = [Scenario()]
    if len(thetas_deg):
        _thetas_deg(thetas_deg)
    for th in thetas_deg:
        for c in corners:
            out.append(Scenario(*c, float(np.deg2rad(th))))
    return out


def plant_at(model: LFT, scenario: Scenario, inertia_p1: ArrayLike, settings: LoopSettings, keep: Sequence[str] = ()) -> GeneralizedPlant:
    """Generalized plant at a scenario; the parameters in ``keep`` stay as open Delta channels.

    The pole check of :func:`trusscodesign.control.closedloop.generalized_plant` is skipped here: ``model`` comes from a modal
    reduction that removed the slow poles, and the worst-case search builds thousands of plants from it."""
    if isinstance(keep, str):
        raise TypeError(f"keep must be a sequence of parameter names, got the str {keep!r} (use [{keep!r}])")
    unknown = [k for k in keep if k not in model.params]
    if unknown:
        raise ValueError(f"keep names {unknown}, which are not parameters of the model; its parameters are {sorted(model.params)}")
    values = {k: v for k, v in scenario.normalized().items() if k not in keep}
    sub = model.substitute(values, normalized=True)
    return generalized_plant(sub.a, sub.b, sub.c, sub.d, inertia_p1, settings, n_delta=sub.n_delta, min_pole=0.0)


def search_candidates(thetas_deg: Sequence[float] | None = None) -> list[Scenario]:
    """The grid of :func:`worst_case`: the 8 corners of (M_SC, Iyy_SC, omega1_SP) and the nominal at each panel angle
    [deg] (default 10, every 20 deg from 0 to 180), angle by angle."""
    thetas = np.deg2rad(np.linspace(0.0, 180.0, 10) if thetas_deg is None else _thetas_deg(thetas_deg))
    corners = [np.array(c) for c in np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).T.reshape(-1, 3)] + [np.zeros(3)]
    return [Scenario(float(c[0]), float(c[1]), float(c[2]), float(th)) for th in thetas for c in corners]
