"""Modal data <-> single-port models: participation factors of a state-space model, and
the model of a cantilevered body rebuilt from its modal data (the NASTRAN/SDT interface).

Paper: section "System Validation" (the P/N model built from the Nastran ``.f06``
modal data; the participation factors of the cube table). For a body clamped at P
with mass-normalised modes (frequency w_k, damping xi_k, participation factors L_k,
a 1x6 row), the transfer from the imposed acceleration at P to the wrench the body
applies on its parent is

    G(s) = -D_P + sum_k L_k^T L_k s^2 / (s^2 + 2 xi_k w_k s + w_k^2),

so ``G(0) = -D_P`` (rigid mass) and the residue of G at a pole p_k is
``L_k^T L_k p_k^2 / (2 j Im p_k)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

from .ports import MultiPortModel, delta_port, node_port
from .reduction import remove_slow_poles

__all__ = ["ModalParticipation", "participation_factors", "cantilever_from_modes", "align_signs", "effective_mass"]


@dataclass(frozen=True)
class ModalParticipation:
    """Modes seen at a clamped port.

    Attributes
    ----------
    omega : ndarray, shape (n,)
        Natural frequencies ``|p_k|`` [rad/s], ascending.
    damping : ndarray, shape (n,)
        Damping ratios ``-Re(p_k) / |p_k|``.
    factors : ndarray, shape (n, 6)
        Participation factors at the port (sign of each row arbitrary).
    rank_one_residual : ndarray, shape (n,)
        Second-largest / largest eigenvalue of the summed residue matrices of the modes at the same frequency as
        this one (to 1e-6 relative): about 0 for an isolated mode, O(1) for a repeated (degenerate) pair whose
        factors are then not unique (one mode's residue alone is rank one by construction).
    """

    omega: NDArray[np.float64]
    damping: NDArray[np.float64]
    factors: NDArray[np.float64]
    rank_one_residual: NDArray[np.float64]


def participation_factors(model: MultiPortModel, port: str, n_modes: int = 10, omega_min: float = 0.01) -> ModalParticipation:
    """Modal participation factors at a clamped port, from the state-space model.

    The spurious slow poles are removed first (:func:`trusscodesign.model.reduction.remove_slow_poles`);
    the residue of the port's 6x6 transfer at each of the first ``n_modes`` poles
    gives ``L_k^T L_k``, whose dominant eigenvector is ``L_k``.

    Raises
    ------
    ValueError
        If the port is not clamped or the model has fewer than ``n_modes`` modes.
    """
    if model.port(port).kind != "clamped":
        raise ValueError(f"port {port!r} is {model.port(port).kind}: participation factors need a clamped port")
    red = remove_slow_poles(model, omega_min)
    idx = red.channels(port)
    lam, vr = linalg.eig(red.a)
    upper = np.where(lam.imag > 0)[0]
    if upper.size < n_modes:
        raise ValueError(f"{model.name!r} has {upper.size} oscillating modes, fewer than n_modes = {n_modes}")
    upper = upper[np.argsort(np.abs(lam[upper]))][:n_modes]
    left = linalg.solve(vr, red.b[:, idx])  # rows: modal input vectors
    omega, zeta, facs, ltls = [], [], [], []
    for k in upper:
        p = lam[k]
        residue = np.outer(red.c[idx, :] @ vr[:, k], left[k])
        ltl = (residue * 2j * p.imag / p**2).real
        ltl = 0.5 * (ltl + ltl.T)
        ev, vec = np.linalg.eigh(ltl)
        facs.append(np.sqrt(max(ev[-1], 0.0)) * vec[:, -1])
        ltls.append(ltl)
        omega.append(abs(p))
        zeta.append(-p.real / abs(p))
    w = np.array(omega)
    resid = []
    for wk in w:  # a repeated mode: the residues of its group add up to a matrix of rank > 1
        ev = np.linalg.eigvalsh(sum(m for m, wj in zip(ltls, w) if abs(wj - wk) <= 1e-6 * wk))
        resid.append(abs(ev[-2]) / max(abs(ev[-1]), 1e-300))
    return ModalParticipation(w, np.array(zeta), np.array(facs), np.array(resid))


def align_signs(factors: ArrayLike, reference: ArrayLike) -> NDArray[np.float64]:
    """Flip the sign of each row of ``factors`` to best match the same row of ``reference``."""
    f = np.array(factors, dtype=float)
    r = np.asarray(reference, dtype=float)
    if f.shape != r.shape:
        raise ValueError(f"factors {f.shape} and reference {r.shape} must have the same shape")
    sign = np.where(np.sum(f * r, axis=1) < 0, -1.0, 1.0)
    return f * sign[:, None]


def effective_mass(factors: ArrayLike) -> NDArray[np.float64]:
    """Effective mass per direction summed over the modes: ``sum_k L_kj^2`` [kg or kg m^2]."""
    return np.sum(np.asarray(factors, dtype=float) ** 2, axis=0)


def cantilever_from_modes(rigid_mass: ArrayLike, omega: ArrayLike, factors: ArrayLike, damping: float | ArrayLike = 0.001,
                          node: str = "P", position: ArrayLike = (0.0, 0.0, 0.0), name: str = "modal",
                          omega1=None) -> MultiPortModel:
    """Single clamped-port model of a body from its rigid mass and modal data.

    Inputs: acceleration twist at the port; outputs: wrench applied by the body
    on its parent. State ``[eta; eta_dot]``; ``A = [[0, I], [-W^2, -2 Xi W]]``,
    ``B = [0; -L]``, ``C = [L^T W^2, 2 L^T Xi W]``, ``D = -(D_P - L^T L)``.

    Parameters
    ----------
    rigid_mass : array_like, shape (6, 6)
        Rigid mass matrix at the port [kg, kg m, kg m^2].
    omega : array_like, shape (n,)
        Natural frequencies [rad/s] (> 0).
    factors : array_like, shape (n, 6)
        Participation factors at the port.
    damping : float or array_like
        Modal damping ratio(s) in [0, 1).
    omega1 : trusscodesign.model.lft.Parameter, optional
        Makes the first frequency uncertain (its centre replaces ``omega[0]``), exactly,
        with 2 occurrences: ``v = w1 eta1 + 2 xi eta1'`` and ``s = w1 v`` give the
        restoring term ``w1^2 eta1 + 2 xi w1 eta1'`` of both the state equation and ``W``.
    """
    d_p = np.asarray(rigid_mass, dtype=float)
    w = np.asarray(omega, dtype=float).reshape(-1)
    lp = np.asarray(factors, dtype=float)
    if lp.ndim == 1 and w.size == 1:  # one mode: a row of 6
        lp = lp.reshape(1, -1)
    if lp.shape != (w.size, 6):  # a transposed (6, n) array must not be reshaped (scrambled) silently
        raise ValueError(f"factors must have shape (n, 6) = ({w.size}, 6), one row of participation factors per mode "
                         f"(Tx Ty Tz Rx Ry Rz), got shape {lp.shape}")
    z = np.broadcast_to(np.asarray(damping, dtype=float), w.shape)
    if d_p.shape != (6, 6):
        raise ValueError(f"rigid_mass must be 6x6, got {d_p.shape}")
    if np.any(w <= 0) or not np.all(np.isfinite(w)):
        raise ValueError("omega must be finite positive frequencies [rad/s]")
    if np.any((z < 0) | (z >= 1)):
        raise ValueError(f"damping must be in [0, 1), got {damping!r}")
    n = w.size
    if omega1 is not None:
        w = w.copy()
        w[0] = omega1.center
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-np.diag(w**2), -np.diag(2 * z * w)]])
    b = np.vstack([np.zeros((n, 6)), -lp])
    c = np.hstack([lp.T @ np.diag(w**2), lp.T @ np.diag(2 * z * w)])
    d = -(d_p - lp.T @ lp)
    port = node_port(node, position, "clamped")
    if omega1 is None:
        return MultiPortModel(a, b, c, d, [port], name)
    # Delta channels: z1 = eta1, z2 = v = c eta1 + 2 xi eta1' + r w1; s = c v + r w2.
    cen, r, xi = omega1.center, omega1.half_range, z[0]
    b = np.hstack([b, np.zeros((2 * n, 2))])
    b[n, 6:] = [-cen * r, -r]
    c_z = np.zeros((2, 2 * n))
    c_z[0, 0] = 1.0
    c_z[1, 0], c_z[1, n] = cen, 2 * xi
    c = np.vstack([c, c_z])
    d_full = np.zeros((8, 8))
    d_full[:6, :6] = d
    d_full[:6, 6:] = np.outer(lp[0], [cen * r, r])
    d_full[7, 6] = r
    ports = [port, delta_port(omega1.name), delta_port(omega1.name)]
    return MultiPortModel(a, b, c, d_full, ports, name, {omega1.name: omega1})
