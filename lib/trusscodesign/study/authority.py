"""The PMAs' authority over the SADM disturbance: the share of ``u_max`` needed to cancel its line-of-sight response.

Beyond the paper. On the loop with the ACS closed and the PMAs passive (``K_PMA = 0``), the LOS response to the SADM
torques ``p`` and to the PMA forces ``u`` at a frequency w are ``H_p(jw)`` and ``H_u(jw)``. The PMA forces that cancel the
disturbance's LOS response with the least 2-norm are ``u = -H_u^+ H_p p``; over ``||p|| <= p_max`` their largest 2-norm
over ``u_max`` is the **authority share**

``share(w) = sigma_max(H_u(jw)^+ H_p(jw)) p_max / u_max``.

A share below 1 means the PMAs can, with forces inside their bound, cancel the worst disturbance at that frequency; a
share far above 1 that the effort bound decides what pointing the loop reaches there.

At a lightly damped mode k (pole ``lambda_k``, right and left eigenvectors ``v_k``, ``w_k``) both responses are
dominated by the mode, ``H(jw) ~ C v_k w_k^* B / (jw - lambda_k)``: the LOS sees it through the same ``C v_k``, and the
share at the resonance is the ratio of the **modal forcings** of the disturbance at ``p_max`` and of the PMAs at
``u_max``, ``||w_k^* B_p|| p_max / (||w_k^* B_u|| u_max)`` (:func:`modal_authority`), which does not depend on the
mode's damping.

The plant is a :class:`trusscodesign.control.closedloop.GeneralizedPlant`, whose inputs are the SADM torques over ``p_max``
(``p~``) and the PMA commands ``v`` before the PMA filter ``u = F_PMA(s) v``; the RPE output is the LOS through the RPE
weight, which multiplies both responses on the left by the same invertible weight and so leaves the share unchanged.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..control.closedloop import GeneralizedPlant

__all__ = ["authority_share", "ModeAuthority", "modal_authority"]


def _filter(plant: GeneralizedPlant, s: ArrayLike) -> NDArray[np.complex128]:
    """The PMA filter ``F_PMA(s) = s / (s^2 + 2 xi w s + w^2)`` at the complex frequencies ``s``."""
    st = plant.settings
    z = np.asarray(s, dtype=np.complex128)
    return np.asarray(z / (z**2 + 2 * st.xi_pma * st.omega_pma * z + st.omega_pma**2), dtype=np.complex128)


def _columns(plant: GeneralizedPlant) -> tuple[slice, slice, slice]:
    """Rows of the RPE, columns of p~ and of the PMA commands v."""
    sl = plant.slices()
    return sl["rpe"], sl["p"], slice(plant.n_exo, plant.n_exo + plant.N_V)


def authority_share(plant: GeneralizedPlant, omega: ArrayLike) -> NDArray[np.float64]:
    """The share of ``u_max`` needed to cancel the disturbance's LOS response at each frequency of ``omega`` [rad/s].

    Parameters
    ----------
    plant : GeneralizedPlant
        The loop at one scenario (e.g. :func:`trusscodesign.control.synthesis.plant_at`), with no open Delta channel.
    omega : array_like
        Frequencies [rad/s], positive.

    Returns
    -------
    ndarray
        ``sigma_max(H_u^+ H_p) p_max / u_max`` at each frequency (dimensionless).

    Raises
    ------
    ValueError
        For a plant with open Delta channels or a frequency that is not positive and finite.
    """
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    if plant.n_delta:
        raise ValueError(f"the plant has {plant.n_delta} open Delta channels: substitute a scenario first (synthesis.plant_at)")
    if w.ndim != 1 or not np.all(np.isfinite(w) & (w > 0)):
        raise ValueError(f"omega must be positive finite frequencies [rad/s], got {omega!r}")
    rpe, p, v = _columns(plant)
    resp = plant.freqresp(w)
    out = np.empty(w.size)
    for i, f in enumerate(_filter(plant, 1j * w)):
        h_u = resp[rpe, v, i] / f  # LOS (weighted) per newton of PMA force
        h_p = resp[rpe, p, i]  # per unit p~, i.e. per p_max
        out[i] = np.linalg.svd(np.linalg.pinv(h_u) @ h_p, compute_uv=False)[0] / plant.settings.u_max
    return out


@dataclass(frozen=True)
class ModeAuthority:
    """The authority share at one lightly damped mode of the passive loop.

    Attributes
    ----------
    omega : float
        Natural frequency ``|lambda|`` [rad/s].
    damping : float
        Damping ratio ``-Re lambda / |lambda|``.
    disturbance_forcing : float
        ``||w^* B_p|| p_max``: how hard the worst SADM torques of 2-norm ``p_max`` drive the mode (modal units, those of
        the eigenvector normalisation, the same for both forcings).
    pma_forcing : float
        ``||w^* B_u|| u_max``: how hard PMA forces of 2-norm ``u_max`` can drive it.
    share : float
        Their ratio, the authority share at the resonance.
    los_peak : float
        Peak of the mode's own contribution to the weighted LOS response to ``p~``, ``||C_rpe v|| ||w^* B_p~|| / |Re lambda|``
        (over ``eps_max``): how much the mode matters to the pointing.
    """

    omega: float
    damping: float
    disturbance_forcing: float
    pma_forcing: float
    share: float
    los_peak: float


def modal_authority(plant: GeneralizedPlant, band: Sequence[float] = (1.0, 500.0), max_damping: float = 0.05) -> list[ModeAuthority]:
    """The modal forcings and authority share of every lightly damped mode of the passive loop in a frequency band.

    Parameters
    ----------
    plant : GeneralizedPlant
        As :func:`authority_share`.
    band : (float, float)
        Natural frequencies [rad/s] kept, ``band[0] <= |lambda| <= band[1]``.
    max_damping : float
        Modes with a larger damping ratio are left out (the rigid ACS poles, the PMA filters).

    Returns
    -------
    list of ModeAuthority
        By increasing frequency, one per complex-conjugate pair.
    """
    if plant.n_delta:
        raise ValueError(f"the plant has {plant.n_delta} open Delta channels: substitute a scenario first (synthesis.plant_at)")
    lo, hi = (float(x) for x in band)
    if not 0 < lo < hi:
        raise ValueError(f"band must be (low, high) in rad/s with 0 < low < high, got {band!r}")
    rpe, p, v = _columns(plant)
    lam, vec = np.linalg.eig(plant.a)
    left = np.linalg.inv(vec)  # rows: left eigenvectors w_k^*, normalised so that w_k^* v_k = 1
    st = plant.settings
    out = []
    for k in np.flatnonzero(lam.imag > 0):
        wn, zeta = abs(lam[k]), -lam[k].real / abs(lam[k])
        if not (lo <= wn <= hi and zeta <= max_damping):
            continue
        beta_p = left[k] @ plant.b[:, p]  # per unit p~ (p_max)
        beta_u = left[k] @ plant.b[:, v] / _filter(plant, lam[k])  # per newton of PMA force
        dist, pma = float(np.linalg.norm(beta_p)), float(np.linalg.norm(beta_u)) * st.u_max
        los = float(np.linalg.norm(plant.c[rpe] @ vec[:, k]) * np.linalg.norm(beta_p) / abs(lam[k].real))
        out.append(ModeAuthority(float(wn), float(zeta), dist, pma, dist / pma if pma > 0 else np.inf, los))
    return sorted(out, key=lambda m: m.omega)
