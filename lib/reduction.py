"""Removal of the spurious slow poles left by loop-closing channel inversions.

Paper: section "System Reduction". Every 6-channel inversion that closes a
kinematic loop leaves 12 poles at s = 0 that are uncontrollable or unobservable
(``docs/titop_math.md`` section d); numerically they land at |s| ~ 1e-6..1e-3 on
either side of the imaginary axis. They are selected here by *what they are*:
the slow invariant subspace is split off with an ordered real Schur form and a
Sylvester block-diagonalisation, and its input-output contribution is measured
before it is dropped. A raw eigenvector basis is never used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import linalg

from .ports import MultiPortModel, frequency_response

__all__ = ["SlowSplit", "split_slow", "remove_slow_poles", "static_gain"]


@dataclass(frozen=True)
class SlowSplit:
    """Result of :func:`split_slow`.

    Attributes
    ----------
    fast : tuple of ndarray
        ``(A, B, C, D)`` of the model without the slow modes.
    n_slow : int
        Number of removed poles (|s| < ``omega_min``).
    slow_poles : ndarray
        The removed poles [rad/s].
    contribution : float
        Largest relative size, over frequencies ``omega_min`` to ``1e4 omega_min``,
        of the removed part's frequency response: ``||G_slow|| / ||G||`` (2-norms).
        Close to machine precision when the slow modes are spurious.
    """

    fast: tuple[NDArray, NDArray, NDArray, NDArray]
    n_slow: int
    slow_poles: NDArray[np.complex128]
    contribution: float


def split_slow(a: NDArray, b: NDArray, c: NDArray, d: NDArray, omega_min: float = 0.01) -> SlowSplit:
    """Split a model into its slow (|s| < ``omega_min`` rad/s) and fast parts.

    A is first balanced by a diagonal similarity (TITOP models mix states of very
    different scales: ||A|| ~ 1e10 for the T-truss, 3e5 once balanced, and the
    split is then accurate to 1e-11 instead of 1e-5). The ordered real Schur form
    ``A = Z [[T_s, T_sf], [0, T_f]] Z^T`` is made block diagonal by solving
    ``T_s X - X T_f = -T_sf``; the fast part keeps ``(T_f, B_f, C_f, D)`` exactly.
    """
    if not omega_min > 0:
        raise ValueError(f"omega_min must be positive [rad/s], got {omega_min!r}")
    n = a.shape[0]
    if n == 0:
        return SlowSplit((a, b, c, d), 0, np.zeros(0, complex), 0.0)
    _, (scale, _) = linalg.matrix_balance(a, permute=False, separate=True)
    a = (a / scale[:, None]) * scale[None, :]
    b = b / scale[:, None]
    c = c * scale[None, :]
    t, z, k = linalg.schur(a, output="real", sort=lambda re, im: np.hypot(re, im) < omega_min)
    if k == 0:
        return SlowSplit((a, b, c, d), 0, np.zeros(0, complex), 0.0)
    ts, tsf, tf = t[:k, :k], t[:k, k:], t[k:, k:]
    x = linalg.solve_sylvester(ts, -tf, -tsf)
    bz, cz = z.T @ b, c @ z
    # Block-diagonalising similarity [[I, X], [0, I]]: B -> [[I, -X], [0, I]] B, C -> C [[I, X], [0, I]].
    b_s = bz[:k] - x @ bz[k:]
    b_f = bz[k:]
    c_s = cz[:, :k]
    c_f = cz[:, k:] + cz[:, :k] @ x
    omega = omega_min * np.logspace(0, 4, 9)
    g_slow = frequency_response(ts, b_s, c_s, np.zeros_like(d), omega)
    g_all = frequency_response(tf, b_f, c_f, d, omega) + g_slow
    contrib = max(np.linalg.norm(g_slow[:, :, i], 2) / max(np.linalg.norm(g_all[:, :, i], 2), 1e-300) for i in range(omega.size))
    return SlowSplit((tf, b_f, c_f, d.copy()), k, linalg.eigvals(ts), float(contrib))


def remove_slow_poles(model: MultiPortModel, omega_min: float = 0.01, max_contribution: float = 1e-6) -> MultiPortModel:
    """Model without its spurious slow poles (|s| < ``omega_min``).

    Raises
    ------
    ValueError
        If the slow part is not spurious (its relative contribution exceeds
        ``max_contribution``): those poles carry real dynamics and must be kept.
    """
    split = split_slow(model.a, model.b, model.c, model.d, omega_min)
    if split.contribution > max_contribution:
        raise ValueError(
            f"the {split.n_slow} poles below {omega_min} rad/s of {model.name!r} contribute "
            f"{split.contribution:.1e} of the response (> {max_contribution:.0e}): they are not "
            "spurious loop-closure poles; lower omega_min or keep them"
        )
    a, b, c, d = split.fast
    return MultiPortModel(a, b, c, d, model.ports, model.name)


def static_gain(model: MultiPortModel, omega_min: float = 0.01) -> NDArray[np.float64]:
    """DC gain ``D - C A^-1 B`` after removal of the spurious slow poles."""
    red = remove_slow_poles(model, omega_min)
    return red.d - red.c @ np.linalg.solve(red.a, red.b) if red.nstates else red.d.copy()
