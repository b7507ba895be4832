"""State-space arrays: checked ``(A, B, C, D)``, channel inversion, static feedback closure and frequency responses.

The array-level operations under the multi-port models (:mod:`trusscodesign.model.ports`) and the LFT algebra
(:mod:`trusscodesign.model.lft`): both build on this module, neither on the other's internals. Mathematics: ``docs/titop.md``
sections a and d.
"""

from __future__ import annotations

from collections.abc import Sequence

import control as ct
import numpy as np
from scipy import linalg
from numpy.typing import ArrayLike, NDArray

__all__ = ["state_space_arrays", "ss_matrices", "invert_channels", "close_static", "frequency_response",
           "modal_frequency_response"]

def state_space_arrays(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """``(A, B, C, D)`` as 2-D float arrays, checked: A square, B and C consistent with A and D (only an empty B or C
    is reshaped: a transposed one of the right size must not be scrambled silently), all finite."""
    for x, nm in ((a, "A"), (b, "B"), (c, "C"), (d, "D")):
        if np.iscomplexobj(x):  # converting to float would drop the imaginary part with only a ComplexWarning
            raise TypeError(f"{nm} must be real, got a complex array (a real-coefficient model; take .real if the imaginary "
                            "part is round-off)")
    a = np.atleast_2d(np.asarray(a, float)) if np.size(a) else np.zeros((0, 0))
    d = np.atleast_2d(np.asarray(d, float))
    n = a.shape[0]
    if a.shape != (n, n):
        raise ValueError(f"A must be square, got shape {a.shape}")
    b, c = np.asarray(b, float), np.asarray(c, float)
    b = b.reshape(n, d.shape[1]) if b.size == 0 else b
    c = c.reshape(d.shape[0], n) if c.size == 0 else c
    if not all(np.all(np.isfinite(x)) for x in (a, b, c, d)):
        raise ValueError("A, B, C and D must be finite (no NaN or inf)")
    if b.shape != (n, d.shape[1]) or c.shape != (d.shape[0], n):
        raise ValueError(f"with {n} states and D of shape {d.shape}, B must be {(n, d.shape[1])} and C {(d.shape[0], n)}; "
                         f"got B {b.shape} and C {c.shape}")
    return a, b, c, d


def ss_matrices(system: ArrayLike | ct.StateSpace, b: ArrayLike | None = None, c: ArrayLike | None = None,
                d: ArrayLike | None = None, name: str = "system") -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """``(A, B, C, D)``, checked as :func:`state_space_arrays`, from a continuous-time ``control.StateSpace`` given alone
    or from the four matrices.

    Raises
    ------
    ValueError
        A discrete-time system, or matrices given only in part.
    """
    if isinstance(system, ct.LTI) and not isinstance(system, ct.StateSpace):
        raise ValueError(f"{name}: got a {type(system).__name__}; convert it first with control.ss(...)")
    if isinstance(system, ct.StateSpace):
        if b is not None or c is not None or d is not None:
            raise ValueError(f"{name}: give a control.StateSpace alone, or the four matrices A, B, C, D")
        if system.isdtime(strict=True):
            raise ValueError(f"{name} must be a continuous-time system, got sampling time dt = {system.dt}")
        return state_space_arrays(system.A, system.B, system.C, system.D)
    if b is None or c is None or d is None:
        raise ValueError(f"{name}: give a control.StateSpace, or all four matrices A, B, C, D (got A alone or in part)")
    return state_space_arrays(system, b, c, d)


def _balanced_rcond(m: NDArray) -> float:
    """Reciprocal condition number after a diagonal balancing similarity.

    Singularity is invariant under ``S^-1 M S``; balancing removes the false alarms of
    matrices that mix physical units (masses next to compliances, a unit-triangular
    series connection with large gains) without hiding a true singularity.
    """
    if m.size == 0:
        return 1.0
    mb, _ = linalg.matrix_balance(m, permute=False)
    with np.errstate(divide="ignore"):
        return float(1.0 / np.linalg.cond(mb))


def invert_channels(
    a: NDArray, b: NDArray, c: NDArray, d: NDArray, idx: Sequence[int], rcond: float = 1e-12
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Invert the conjugated channels ``idx`` of a square state-space model.

    The inputs ``u_I`` and outputs ``y_I`` of the channels in ``idx`` swap roles
    (new input ``y_I``, new output ``u_I``), staying in the same slots; this is
    the paper's ``[M(s)]^{-1_I}`` (``docs/titop.md`` section d).

    Parameters
    ----------
    a, b, c, d : ndarray
        State-space matrices; ``d`` must be square.
    idx : sequence of int
        0-based channel indices to invert.
    rcond : float
        Smallest accepted reciprocal condition number of ``D_II``.

    Returns
    -------
    tuple of ndarray
        ``(A', B', C', D')``.

    Raises
    ------
    ValueError
        If ``D_II`` is singular: the channel set cannot be inverted.
    """
    n_ch = d.shape[0]
    if d.shape[0] != d.shape[1]:
        raise ValueError(f"channel inversion needs a square model, got D of shape {d.shape}")
    ii = np.asarray(sorted(set(int(i) for i in idx)), dtype=int)
    if ii.size != len(list(idx)):
        raise ValueError(f"channel indices must be distinct, got {list(idx)}")
    if ii.size == 0:
        return a.copy(), b.copy(), c.copy(), d.copy()
    if ii.min() < 0 or ii.max() >= n_ch:
        raise ValueError(f"channel indices must be in [0, {n_ch - 1}], got {list(idx)}")
    jj = np.setdiff1d(np.arange(n_ch), ii)
    d_ii = d[np.ix_(ii, ii)]
    rc = _balanced_rcond(d_ii) if np.all(np.isfinite(d_ii)) else 0.0
    if not rc > rcond:
        raise ValueError(
            f"channels {list(ii)} cannot be inverted: their direct feedthrough D_II is singular "
            f"(reciprocal condition number {rc:.1e}). Invert a set of channels whose "
            "feedthrough is invertible, e.g. all six channels of a free port of a beam with "
            "at least two bending modes per plane."
        )
    delta = np.linalg.inv(d_ii)
    b_i, b_j = b[:, ii], b[:, jj]
    c_i, c_j = c[ii, :], c[jj, :]
    d_ij, d_ji, d_jj = d[np.ix_(ii, jj)], d[np.ix_(jj, ii)], d[np.ix_(jj, jj)]
    a2 = a - b_i @ delta @ c_i
    b2 = np.empty_like(b)
    c2 = np.empty_like(c)
    d2 = np.empty_like(d)
    b2[:, ii] = b_i @ delta
    b2[:, jj] = b_j - b_i @ delta @ d_ij
    c2[ii, :] = -delta @ c_i
    c2[jj, :] = c_j - d_ji @ delta @ c_i
    d2[np.ix_(ii, ii)] = delta
    d2[np.ix_(ii, jj)] = -delta @ d_ij
    d2[np.ix_(jj, ii)] = d_ji @ delta
    d2[np.ix_(jj, jj)] = d_jj - d_ji @ delta @ d_ij
    return a2, b2, c2, d2


def close_static(
    a: NDArray,
    b: NDArray,
    c: NDArray,
    d: NDArray,
    k: NDArray,
    e: NDArray,
    f: NDArray,
    h: NDArray,
    rcond: float = 1e-12,
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Close static loops ``u = K y + E w``, ``z = F y + H w`` around ``(A, B, C, D)``.

    This is the block-diagram interconnection of the paper. It is written here
    because ``control.interconnect`` refuses the algebraic loops (direct
    feedthrough inside every loop) that all TITOP assemblies contain.

    Returns
    -------
    tuple of ndarray
        State-space matrices from ``w`` to ``z``.

    Raises
    ------
    ValueError
        If ``I - D K`` is singular (an ill-posed interconnection).
    """
    m = np.eye(d.shape[0]) - d @ k
    rc = _balanced_rcond(m)
    if not rc > rcond:
        raise ValueError(
            f"ill-posed interconnection: I - D K is singular (reciprocal condition {rc:.1e}); "
            "two blocks impose the same variable at a node, e.g. two free ports joined "
            "without inverting one of them"
        )
    # Solve on the balanced matrix (S^-1 M S): same solution, better accuracy when the
    # channels mix units (masses, compliances, scaled LFT channels).
    _, (scale, _) = linalg.matrix_balance(m, permute=False, separate=True)
    mb = (m / scale[:, None]) * scale[None, :]
    rhs = np.hstack([c, d @ e]) / scale[:, None]
    lu = linalg.lu_factor(mb)
    sol = linalg.lu_solve(lu, rhs)
    sol += linalg.lu_solve(lu, rhs - mb @ sol)  # one step of iterative refinement
    sol = scale[:, None] * sol
    y_x, y_w = sol[:, : c.shape[1]], sol[:, c.shape[1] :]
    return a + b @ k @ y_x, b @ (e + k @ y_w), f @ y_x, f @ y_w + h


def frequency_response(a: NDArray, b: NDArray, c: NDArray, d: NDArray, omega: ArrayLike) -> NDArray[np.complex128]:
    """Frequency response ``C (j w I - A)^-1 B + D`` for each ``w`` in ``omega`` [rad/s].

    Returns an array of shape ``(n_outputs, n_inputs, len(omega))``. Uses a
    Hessenberg-free direct solve per frequency (fine up to a few hundred states).
    """
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    n = a.shape[0]
    out = np.empty((c.shape[0], b.shape[1], w.size), dtype=complex)
    eye = np.eye(n)
    for i, wi in enumerate(w):
        out[:, :, i] = d + (c @ np.linalg.solve(1j * wi * eye - a, b) if n else 0.0)
    return out


def modal_frequency_response(a: NDArray, b: NDArray, c: NDArray, d: NDArray, omega: ArrayLike, check: int = 3,
                             rtol: float = 1e-6) -> NDArray[np.complex128]:
    """Fast frequency response through the eigen-decomposition of A, checked against a direct solve.

    ``G(jw) = D + (C V) diag(1 / (jw - lambda)) (V^-1 B)``: one eigen-decomposition,
    then each frequency costs a small matrix product, against an O(n^3) solve per
    frequency for :func:`frequency_response` (the reference this is tested against).
    ``check`` frequencies of ``omega`` (spread over the grid) are recomputed by the
    direct solve.

    Raises
    ------
    ValueError
        If the modal and direct results differ by more than ``rtol`` (relative to the
        largest entry) at a checked frequency, e.g. for a defective or ill-conditioned A
        (poles at s = 0 left by inversions: remove them first with ``trusscodesign.model.reduction``).
    """
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    lam, vec = np.linalg.eig(a)
    cv = c @ vec
    vb = np.linalg.solve(vec, b)
    out = np.empty((c.shape[0], b.shape[1], w.size), dtype=complex)
    for i, wi in enumerate(w):
        out[:, :, i] = d + (cv / (1j * wi - lam)) @ vb
    for i in np.unique(np.linspace(0, w.size - 1, min(check, w.size)).astype(int)):
        ref = frequency_response(a, b, c, d, w[i : i + 1])[:, :, 0]
        err = np.max(np.abs(out[:, :, i] - ref)) / max(np.max(np.abs(ref)), 1e-300)
        if err > rtol:
            raise ValueError(
                f"modal frequency response differs from the direct solve by {err:.1e} at {w[i]:.4g} rad/s: "
                "A is defective or ill-conditioned (remove spurious slow poles first, or use frequency_response)"
            )
    return out
