"""Certified H-infinity norms and singular-value curves of a closed loop with a static gain.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from threadpoolctl import threadpool_limits

from ..closedloop import GeneralizedPlant
from ..hinf import hinf_norm
from .peaks import GROUPS

__all__ = ['exact_norms', 'sigma_curve']


def exact_norms(plant: GeneralizedPlant, gain: ArrayLike, rtol: float = 1e-7) -> dict[str, tuple[float, float, bool]]:
    """Certified H-infinity norms of both transfers (Hamiltonian method, :func:`trusscodesign.control.hinf.hinf_norm`).

    Returns ``{"rpe": (norm, omega [rad/s], certified), "effort": (...)}``. The channels are already
    scaled by the weights (RPE weight 1/eps_max = 2e4, effort 1/u_max); the state is balanced inside.
    """
    a, b, c, d = plant.closed_loop_matrices(gain)
    sl = plant.slices()
    out = {}
    with threadpool_limits(1):
        for group in GROUPS:
            r = hinf_norm(a, b[:, sl["p"]], c[sl[group]], d[sl[group], sl["p"]], rtol=rtol)
            out[group] = (r.norm, r.omega, r.certified)
    return out


def sigma_curve(plant: GeneralizedPlant, gain: ArrayLike, group: str, omega_range: tuple[float, float] = (1e-2, 3e3),
                n_log: int = 400) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Largest singular value of ``T_{p~ -> group}`` on a peak-aware grid [rad/s] (for figures).

    Returns ``(omega, sigma)``; the grid holds the log points and points around every lightly damped pole.
    """
    from ..hinf import peak_grid, sigma_max

    a, b, c, d = plant.closed_loop_matrices(gain)
    sl = plant.slices()
    w = peak_grid(a, omega_range[0], omega_range[1], n_log=n_log)
    with threadpool_limits(1):
        return w, sigma_max(a, b[:, sl["p"]], c[sl[group]], d[sl[group], sl["p"]], w)
