"""Removal of the spurious slow poles left by loop-closing channel inversions.

Paper: section "System Reduction". Every 6-channel inversion that closes a
kinematic loop leaves 12 poles at s = 0 that are uncontrollable or unobservable
(``docs/titop.md`` section d); numerically they land at ``|s|`` ~ 1e-6..1e-3 on
either side of the imaginary axis. They are selected here by *what they are*:
the slow invariant subspace is split off with an ordered real Schur form and a
Sylvester block-diagonalisation, and its input-output contribution is measured
before it is dropped. A raw eigenvector basis is never used.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import linalg

from .ports import MultiPortModel
from .statespace import frequency_response

__all__ = ["SlowSplit", "split_slow", "ModalReduction", "modal_reduction", "residualize_above", "remove_slow_poles", "static_gain",
           "sylvester_schur", "sylvester_general"]


@dataclass(frozen=True)
class SlowSplit:
    """Result of :func:`split_slow`.

    Attributes
    ----------
    fast : tuple of ndarray
        ``(A, B, C, D)`` of the model without the slow modes.
    n_slow : int
        Number of removed poles (``|s| < omega_min``).
    slow_poles : ndarray
        The removed poles [rad/s].
    contribution : float
        Largest relative size, over frequencies ``omega_min`` to ``1e4 omega_min``,
        of the removed part's frequency response: ``||G_slow|| / ||G||`` (2-norms).
        Close to machine precision when the slow modes are spurious. Relative to the whole transfer matrix: a
        channel many orders of magnitude smaller than the largest can hide a slow pole that carries it (a review built
        one: a pole carrying all of a channel 1e6 times smaller than another passed at 1e-7), so scale the channels
        first when they differ that much. An entry-by-entry measure is no remedy: the entries at rounding level
        make it 1e-8 on the spacecraft and 7e-6 on the cube of notebook 03, whose slow poles are spurious.
    slow : tuple of ndarray or None
        ``(A_s, B_s, C_s)`` of the removed part: ``G = G_fast + C_s (sI - A_s)^-1 B_s`` exactly.
    """

    fast: tuple[NDArray, NDArray, NDArray, NDArray]
    n_slow: int
    slow_poles: NDArray[np.complex128]
    contribution: float
    slow: tuple[NDArray, NDArray, NDArray] | None = None

    def spurious(self, max_contribution: float) -> bool:
        """Whether the removed part carries no more than ``max_contribution`` of the response (a NaN never passes)."""
        if not (np.isfinite(max_contribution) and max_contribution > 0):
            raise ValueError(f"max_contribution must be a finite positive fraction, got {max_contribution!r}")
        return bool(self.contribution <= max_contribution)


def _block_split(a: NDArray, b: NDArray, c: NDArray, select) -> tuple[int, tuple[NDArray, NDArray, NDArray], tuple[NDArray, NDArray, NDArray]]:
    """Block-diagonalise ``(A, B, C)`` into the eigenvalues selected by ``select(re, im)`` and the rest.

    A is balanced by a diagonal similarity first (TITOP models mix states of very
    different scales: ||A|| ~ 1e10 for the T-truss, 3e5 once balanced, and the split
    is then accurate to 1e-11 instead of 1e-5). The ordered real Schur form
    ``A = Z [[T_1, T_12], [0, T_2]] Z^T`` is made block diagonal by solving
    ``T_1 X - X T_2 = -T_12``. Returns ``k`` and ``(T_1, B_1, C_1)``, ``(T_2, B_2, C_2)``.
    """
    _, (scale, _) = linalg.matrix_balance(a, permute=False, separate=True)
    a = (a / scale[:, None]) * scale[None, :]
    b = b / scale[:, None]
    c = c * scale[None, :]
    t, z, k = linalg.schur(a, output="real", sort=select)
    if k == 0 or k == a.shape[0]:
        bz, cz = z.T @ b, c @ z
        return k, (t[:k, :k], bz[:k], cz[:, :k]), (t[k:, k:], bz[k:], cz[:, k:])
    t1, t12, t2 = t[:k, :k], t[:k, k:], t[k:, k:]
    x = sylvester_schur(t1, t2, -t12)
    bz, cz = z.T @ b, c @ z
    # Similarity [[I, X], [0, I]]: B -> [[I, -X], [0, I]] B, C -> C [[I, X], [0, I]].
    return k, (t1, bz[:k] - x @ bz[k:], cz[:, :k]), (t2, bz[k:], cz[:, k:] + cz[:, :k] @ x)


def sylvester_schur(t1: NDArray, t2: NDArray, rhs: NDArray) -> NDArray:
    """Solve ``T_1 X - X T_2 = rhs`` for ``T_1``, ``T_2`` already in real Schur form (LAPACK ``dtrsyl``).

    Not :func:`scipy.linalg.solve_sylvester`: it computes the Schur forms of both matrices again, which here they
    already are (6 of the 11 Schur decompositions of :func:`trusscodesign.study.design.models_at`, about a third of its time).
    """
    x, scale, info = linalg.lapack.dtrsyl(t1, t2, rhs, isgn=-1)
    if info < 0:
        raise ValueError(f"dtrsyl: argument {-info} is invalid")
    if info == 1:  # a kept and a removed pole within about eps ||T|| of each other: X is large and inaccurate
        warnings.warn("the block-diagonalising Sylvester equation is nearly singular: a pole on one side of the cut "
                      "(nearly) coincides with one on the other; move the cut frequency away from it", RuntimeWarning, stacklevel=3)
    return x / scale


def sylvester_general(t1: NDArray, t2: NDArray, rhs: NDArray) -> NDArray:
    """The same equation by scipy's general solver (which computes both Schur forms again): the naive path that
    :func:`sylvester_schur` is tested and benchmarked against (substituted for it there)."""
    return linalg.solve_sylvester(t1, -t2, rhs)


def split_slow(a: NDArray, b: NDArray, c: NDArray, d: NDArray, omega_min: float = 0.01) -> SlowSplit:
    """Split a model into its slow (``|s| < omega_min`` rad/s) and fast parts.

    See :func:`_block_split`; the fast part keeps ``(T_f, B_f, C_f, D)`` exactly and
    the slow part's frequency response is measured before it is dropped.
    """
    if not (np.isfinite(omega_min) and omega_min > 0):
        raise ValueError(f"omega_min must be a finite positive frequency [rad/s], got {omega_min!r}")
    n = a.shape[0]
    if n == 0:
        return SlowSplit((a, b, c, d), 0, np.zeros(0, complex), 0.0)
    k, (ts, b_s, c_s), (tf, b_f, c_f) = _block_split(a, b, c, lambda re, im: np.hypot(re, im) < omega_min)
    if k == 0:
        return SlowSplit((tf, b_f, c_f, d.copy()), 0, np.zeros(0, complex), 0.0)
    omega = omega_min * np.logspace(0, 4, 9)
    g_slow = frequency_response(ts, b_s, c_s, np.zeros_like(d), omega)
    g_all = frequency_response(tf, b_f, c_f, d, omega) + g_slow
    contrib = max(float(np.linalg.norm(g_slow[:, :, i], 2)) / max(float(np.linalg.norm(g_all[:, :, i], 2)), 1e-300)
                  for i in range(omega.size))
    return SlowSplit((tf, b_f, c_f, d.copy()), k, linalg.eigvals(ts), float(contrib), (ts, b_s, c_s))


@dataclass(frozen=True)
class ModalReduction:
    """Result of :func:`modal_reduction`.

    Attributes
    ----------
    reduced : tuple of ndarray
        ``(A, B, C, D)`` of the reduced model.
    n_slow, n_high : int
        Poles removed below ``omega_min`` (spurious) and above ``omega_max``.
    slow_contribution : float
        Relative input-output contribution of the removed slow part (see :class:`SlowSplit`).
    """

    reduced: tuple[NDArray, NDArray, NDArray, NDArray]
    n_slow: int
    n_high: int
    slow_contribution: float


def modal_reduction(a: NDArray, b: NDArray, c: NDArray, d: NDArray, omega_min: float = 0.01,
                    omega_max: float | None = None, max_contribution: float = 1e-6) -> ModalReduction:
    """Modal reduction of the paper: ``G_r_low`` (``omega_max=None``) or ``G_r``.

    The spurious slow poles (``|s| < omega_min``) are removed after checking that they
    carry no input-output contribution; the modes above ``omega_max`` [rad/s] are removed
    by residualisation (their static contribution ``-C_h A_h^-1 B_h`` is added to D), so
    that the DC gain, hence the mass seen by the model, is unchanged.

    Raises
    ------
    ValueError
        If the slow part is not spurious (contribution above ``max_contribution``).
    """
    split = split_slow(a, b, c, d, omega_min)
    if not split.spurious(max_contribution):
        raise ValueError(f"the {split.n_slow} poles below {omega_min} rad/s contribute {split.contribution:.1e} "
                         f"(> {max_contribution:.0e}) of the response: they are not spurious")
    if omega_max is None:
        return ModalReduction(split.fast, split.n_slow, 0, split.contribution)
    if not omega_max > omega_min:
        raise ValueError(f"omega_max must exceed omega_min = {omega_min} rad/s, got {omega_max!r}")
    reduced, n_high = residualize_above(*split.fast, omega_max)
    return ModalReduction(reduced, split.n_slow, n_high, split.contribution)


def residualize_above(a: NDArray, b: NDArray, c: NDArray, d: NDArray, omega_max: float) -> tuple[tuple[NDArray, NDArray, NDArray, NDArray], int]:
    """Residualise the modes above ``omega_max`` [rad/s] of a model without slow poles.

    The modes with ``|s| > omega_max`` are split off (see :func:`_block_split`) and their static contribution
    ``-C_h A_h^-1 B_h`` is added to D, so that the DC gain is unchanged. For a model that
    :func:`modal_reduction` already freed of its spurious slow poles: reducing it again at several cut
    frequencies need not split (and check) the slow part each time. Returns ``((A, B, C, D), n_high)``.
    """
    if not (np.isfinite(omega_max) and omega_max > 0):
        raise ValueError(f"omega_max must be a positive frequency [rad/s], got {omega_max!r}")
    _, (tk, bk, ck), (th, bh, ch) = _block_split(a, b, c, lambda re, im: np.hypot(re, im) <= omega_max)
    dr = d - ch @ np.linalg.solve(th, bh) if th.shape[0] else d.copy()
    return (tk, bk, ck, dr), th.shape[0]


def remove_slow_poles(model: MultiPortModel, omega_min: float = 0.01, max_contribution: float = 1e-6) -> MultiPortModel:
    """Model without its spurious slow poles (``|s| < omega_min``).

    Raises
    ------
    ValueError
        If the slow part is not spurious (its relative contribution exceeds
        ``max_contribution``): those poles carry real dynamics and must be kept.
    """
    split = split_slow(model.a, model.b, model.c, model.d, omega_min)
    if not split.spurious(max_contribution):
        raise ValueError(
            f"the {split.n_slow} poles below {omega_min} rad/s of {model.name!r} contribute "
            f"{split.contribution:.1e} of the response (> {max_contribution:.0e}): they are not "
            "spurious loop-closure poles; lower omega_min or keep them"
        )
    a, b, c, d = split.fast
    return MultiPortModel(a, b, c, d, model.ports, model.name, model.params)


def static_gain(model: MultiPortModel, omega_min: float = 0.01) -> NDArray[np.float64]:
    """DC gain ``D - C A^-1 B`` after removal of the spurious slow poles."""
    red = remove_slow_poles(model, omega_min)
    return red.d - red.c @ np.linalg.solve(red.a, red.b) if red.nstates else red.d.copy()
