"""Worst-case gain of an upper LFT over repeated real scalar parameters (a replacement for MATLAB's ``wcgain``).

At one frequency ``w`` [rad/s], ``M = M(jw)`` is partitioned as ``[z; e] = [[M11, M12], [M21, M22]] [w; p]`` and
closed by ``w = Delta z``, ``Delta = diag(delta_1 I_k1, ..., delta_m I_km)``, ``delta_i`` real in ``[-1, 1]``:
``F_u(M, Delta) = M22 + M21 Delta (I - M11 Delta)^-1 M12``. The worst-case gain is ``max_Delta sigma_max(F_u)``.

* :func:`lft_upper` evaluates ``F_u`` (for one or many delta vectors).
* :func:`wc_gain_upper` bounds it from above with mixed-mu D-G scalings (S-procedure): the LMI
  ``Z^H Pi Z + E^H E - t P^H P <= -eps I``, ``Z = [[M11, M12], [I, 0]]``, ``E = [M21, M22]``, ``P = [0, I]``,
  ``Pi = [[D, jG], [-jG, -D]]``, ``D = blkdiag(D_i) >= 0``, ``G = blkdiag(G_i)`` Hermitian (full ``k_i x k_i``
  blocks). A real ``Delta`` commutes with ``D`` and ``G``, so ``[z; w]^H Pi [z; w] = z^H D (I - Delta^2) z >= 0``
  and the LMI gives ``|e|^2 <= t |p|^2``; its negative definite ``(1, 1)`` block gives well-posedness. The SDP
  (cvxpy, built once per block structure with the data as parameters) minimises ``t``; the bound is then
  *re-certified* in floating point from the scalings alone (``t = lambda_max`` of a Schur complement), so an
  inaccurate solve can only loosen the bound, never make it invalid.
* :func:`wc_gain_upper_bb` tightens it by branch and bound over the parameter box (as ``wcgain`` does): the box is
  split in halves, each sub-box's LFT is re-centred (:func:`recentre`) and bounded on its own; the bound is the
  largest over the leaves. On a lightly damped mode whose frequency the parameters move over many bandwidths, the
  D-G bound over the whole box is very conservative (often infinite); on small sub-boxes it is not.
* :func:`wc_gain_upper_sweep` applies it on a frequency grid (nothing is claimed between grid points).
* :func:`wc_gain_lower` returns an *achieved* gain: corners and random points on the grid, then L-BFGS-B
  over ``(delta, log w)``.
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import cvxpy as cp
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import minimize

__all__ = ["UpperBound", "UpperSweep", "LowerBound", "BranchBound", "lft_upper", "recentre", "wc_gain_upper", "wc_gain_upper_bb",
           "wc_gain_upper_sweep", "wc_gain_lower"]

_EPS_LMI = 1e-7  # strictness of the LMI, in the normalised coordinates
_MAX_COND = 1e14  # I - M11 Delta (of the balanced M) with a larger condition number is singular (ill-posed)
MOfW = Callable[[float], ArrayLike] | ArrayLike


@dataclass(frozen=True)
class UpperBound:
    """Certified upper bound ``beta >= max_Delta sigma_max(F_u(M, Delta))`` at one frequency.

    ``d``, ``g`` are the D-G scalings (block diagonal, in the coordinates of the given ``M``) for which the LMI
    holds with ``t = beta**2``; ``well_posed_margin = -lambda_max`` of the LMI's ``(1, 1)`` block in the
    normalised coordinates (positive: well-posedness certified). ``beta = inf`` (and NaN scalings) when the
    solver fails or the certificate does not hold; ``status`` is the cvxpy status (plus the reason).
    """

    beta: float
    d: NDArray[np.complex128]
    g: NDArray[np.complex128]
    status: str
    well_posed_margin: float


@dataclass(frozen=True)
class UpperSweep:
    """Upper bounds on a frequency grid [rad/s]; ``beta_max`` at ``omega_max`` (a grid maximum)."""

    omegas: NDArray[np.float64]
    betas: NDArray[np.float64]
    statuses: tuple[str, ...]
    beta_max: float
    omega_max: float


@dataclass(frozen=True)
class LowerBound:
    """Achieved gain ``sigma_max(F_u(M(j omega), Delta(deltas)))`` (``omega`` in rad/s) after ``evaluations``;
    ``corner_gains``: at each frequency of the grid, the largest gain at the nominal point and the box corners (1024
    random corners beyond 10 blocks)."""

    gain: float
    omega: float
    deltas: NDArray[np.float64]
    evaluations: int
    corner_gains: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))


def _block_sizes(blocks: Sequence) -> tuple[int, ...]:
    """Repetitions ``k_i`` from ints or ``(name, k)`` pairs (as :meth:`trusscodesign.model.lft.LFT.delta_structure`)."""
    sizes = tuple(b[-1] if isinstance(b, (tuple, list)) else b for b in blocks)
    if not sizes or not all(isinstance(k, (int, np.integer)) and not isinstance(k, bool) and k > 0 for k in sizes):
        raise ValueError(f"blocks: need a non-empty sequence of positive ints or (name, int) pairs, got {blocks!r}")
    return tuple(int(k) for k in sizes)


def _check_m(m: ArrayLike, sizes: tuple[int, ...], name: str = "m") -> NDArray[np.complex128]:
    m = np.asarray(m, dtype=complex)
    n = sum(sizes)
    if m.ndim != 2 or m.shape[0] <= n or m.shape[1] <= n:
        raise ValueError(f"{name}: need a 2-D matrix larger than the {n} Delta channels of blocks {sizes} in both "
                         f"dimensions (at least one performance input and output), got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise ValueError(f"{name}: entries must be finite")
    return m


def _balanced(m: ArrayLike, sizes: tuple[int, ...], name: str = "m") -> tuple[NDArray[np.complex128], float]:
    """Checked and balanced ``M'`` (see :func:`_balance`) and the factor ``s`` with ``F_u(M) = s F_u(M')``."""
    ms, _, ce, cpv = _balance(_check_m(m, sizes, name), sum(sizes))
    return ms, 1.0 / (ce * cpv)


def _fu(m: NDArray, sizes: tuple[int, ...], d2: NDArray) -> NDArray[np.complex128]:
    """``F_u`` for the rows of ``d2`` (shape ``(N, n_blocks)``); raises on ill-posedness (``m`` balanced)."""
    n = sum(sizes)
    dv = np.repeat(d2, sizes, axis=1)
    r = np.eye(n) - m[None, :n, :n] * dv[:, None, :]
    try:
        inv = np.linalg.inv(r)
    except np.linalg.LinAlgError:  # one of them exactly singular: name the worst
        bad = d2[np.argmax(np.nan_to_num(np.linalg.cond(r), nan=np.inf))]
        raise ValueError(f"ill-posed LFT: I - M11 Delta is singular for deltas = {bad.tolist()}") from None
    # the condition number in the 1-norm (within a factor n of the 2-norm's), from the inverse the LFT needs anyway:
    # np.linalg.cond's SVD of every matrix cost a sixth of a mu sweep (notebook 08: -17 % without it, same bounds)
    cond = np.abs(r).sum(axis=1).max(axis=-1) * np.abs(inv).sum(axis=1).max(axis=-1)
    if not np.all(cond < _MAX_COND):
        bad = d2[np.argmax(~(cond < _MAX_COND))]
        raise ValueError(f"ill-posed LFT: I - M11 Delta is singular for deltas = {bad.tolist()}")
    return m[n:, n:] + m[n:, :n] @ (dv[:, :, None] * (inv @ m[:n, n:]))


def _check_deltas(deltas: ArrayLike, n_blocks: int) -> NDArray[np.float64]:
    d = np.asarray(deltas, dtype=float)
    if d.ndim not in (1, 2) or d.shape[-1] != n_blocks:
        raise ValueError(f"deltas: need shape ({n_blocks},) or (N, {n_blocks}) (one value per block), got {d.shape}")
    if not np.all(np.abs(d) <= 1.0):
        raise ValueError("deltas: values must be finite and in [-1, 1]")
    return d


def lft_upper(m: ArrayLike, blocks: Sequence, deltas: ArrayLike) -> NDArray[np.complex128]:
    """Upper LFT ``F_u(M, Delta) = M22 + M21 Delta (I - M11 Delta)^-1 M12``.

    Parameters
    ----------
    m : array_like, shape (n + n_e, n + n_p)
        Complex matrix ``M(jw)``, Delta channels first.
    blocks : sequence of int or (name, int)
        Repetitions ``k_i`` of the real scalar blocks (``n = sum k_i``).
    deltas : array_like, shape (n_blocks,) or (N, n_blocks)
        One value in ``[-1, 1]`` per block (or N such vectors).

    Returns
    -------
    ndarray, shape (n_e, n_p) or (N, n_e, n_p)

    Raises
    ------
    ValueError
        On a bad block structure, shape or value, or if ``I - M11 Delta`` is singular (ill-posed).
    """
    sizes = _block_sizes(blocks)
    ms, scale = _balanced(m, sizes)
    d = _check_deltas(deltas, len(sizes))
    f = scale * _fu(ms, sizes, np.atleast_2d(d))
    return f[0] if d.ndim == 1 else f


def _realify(h: NDArray) -> NDArray[np.float64]:
    """Real symmetric form ``[[Re H, -Im H], [Im H, Re H]]`` of (a stack of) Hermitian ``H``."""
    return np.concatenate([np.concatenate([h.real, -h.imag], -1), np.concatenate([h.imag, h.real], -1)], -2)


@functools.lru_cache(maxsize=32)
def _hermitian_basis(sizes: tuple[int, ...]) -> NDArray[np.complex128]:
    """Real basis of ``blkdiag`` of Hermitian ``k_i x k_i`` blocks: array ``(sum k_i^2, n, n)``, block by block."""
    n, mats, off = sum(sizes), [], 0
    for k in sizes:
        for a in range(k):
            for b in range(a, k):
                for val in ((1.0,) if a == b else (1.0, 1j)):
                    h = np.zeros((n, n), complex)
                    h[off + a, off + b], h[off + b, off + a] = val, np.conj(val)
                    mats.append(h)
        off += k
    return np.array(mats)


@functools.lru_cache(maxsize=16)
def _sdp(sizes: tuple[int, ...], n_p: int) -> tuple[cp.Problem, cp.Parameter, cp.Parameter, cp.Variable]:
    """DPP problem ``min t`` s.t. ``B [y_D; y_G] + q0 - t vec(P^H P) << 0``, ``D_i >> 0``; data ``B``, ``q0``."""
    n, basis = sum(sizes), _hermitian_basis(sizes)
    nc, nb = n + n_p, len(basis)
    y, t = cp.Variable(2 * nb), cp.Variable()
    b, q0 = cp.Parameter((4 * nc * nc, 2 * nb)), cp.Parameter(4 * nc * nc)
    pp = _realify(np.diag(np.r_[np.zeros(n), np.ones(n_p)]).astype(complex)).ravel()
    cons = [cp.reshape(b @ y + q0 - t * pp, (2 * nc, 2 * nc), order="F") << 0]
    start, off = 0, 0
    for k in sizes:  # D_i >> 0, from the basis coefficients of block i
        loc = _realify(basis[start:start + k * k, off:off + k, off:off + k]).reshape(k * k, -1).T
        cons.append(cp.reshape(loc @ y[start:start + k * k], (2 * k, 2 * k), order="F") >> 0)
        start, off = start + k * k, off + k
    return cp.Problem(cp.Minimize(t), cons), b, q0, y


def _balance(m: NDArray, n: int, sweeps: int = 20) -> tuple[NDArray, NDArray, float, float]:
    """Diagonal similarity ``T`` on the Delta channels, scalars ``c_e``, ``c_p`` on ``e``, ``p`` (Osborne-like):
    returns ``(diag(T, c_e) M diag(T^-1, c_p), T, c_e, c_p)``; ``F_u`` of the result is ``c_e c_p F_u(M)``."""
    s = np.abs(m)
    s[np.arange(n), np.arange(n)] = 0.0
    tv, ce, cpv = np.ones(n), 1.0, 1.0
    for _ in range(sweeps):
        worst = 0.0
        for i in range(n):
            c, r = np.linalg.norm(s[:, i]), np.linalg.norm(s[i, :])
            if c > 0 and r > 0:
                f = np.sqrt(c / r)
                s[i, :], s[:, i], tv[i], worst = s[i, :] * f, s[:, i] / f, tv[i] * f, max(worst, float(abs(np.log(f))))
        for rows, is_e in ((np.s_[n:, :], True), (np.s_[:, n:], False)):
            nrm = np.float64(np.linalg.norm(s[rows]))  # numpy arithmetic: inf, not an exception, at extreme scales
            if nrm > 0:
                s[rows] /= nrm
                worst = max(worst, float(abs(np.log(nrm))))
                ce, cpv = (ce / nrm, cpv) if is_e else (ce, cpv / nrm)
        if worst < 1e-3:
            break
    left, right = np.r_[tv, np.full(m.shape[0] - n, ce)], np.r_[1.0 / tv, np.full(m.shape[1] - n, cpv)]
    return left[:, None] * m * right[None, :], tv, ce, cpv


def _lmi_forms(ms: NDArray, n: int, dmat: NDArray, gmat: NDArray) -> NDArray:
    """``Z^H Pi Z`` for (a stack of) ``D``, ``G`` (``G`` may be a zero array)."""
    nh, jm = ms[:n, :].conj().T, np.eye(n, ms.shape[1])
    ngj = nh @ gmat @ jm
    return nh @ dmat @ nh.conj().T - jm.T @ dmat @ jm + 1j * (ngj - np.swapaxes(ngj.conj(), -1, -2))


def _certify(ms: NDArray, sizes: tuple[int, ...], dmat: NDArray, gmat: NDArray) -> tuple[float, float, NDArray]:
    """Smallest ``t`` (and margin) for which the LMI holds with the given scalings, after projecting ``D >= 0``."""
    n, off = sum(sizes), 0
    dmat = 0.5 * (dmat + dmat.conj().T)
    for k in sizes:
        lam, vec = np.linalg.eigh(dmat[off:off + k, off:off + k])
        dmat[off:off + k, off:off + k] = (vec * np.maximum(lam, 0.0)) @ vec.conj().T
        off += k
    e = ms[n:, :]
    a = _lmi_forms(ms, n, dmat, 0.5 * (gmat + gmat.conj().T)) + e.conj().T @ e
    a = 0.5 * (a + a.conj().T)
    margin = -np.linalg.eigvalsh(a[:n, :n])[-1]
    if not margin > 1e-12 * (1.0 + np.linalg.norm(a)):
        return np.inf, margin, dmat
    schur = a[n:, n:] - a[n:, :n] @ np.linalg.solve(a[:n, :n], a[:n, n:])
    return max(np.linalg.eigvalsh(0.5 * (schur + schur.conj().T))[-1], 0.0), margin, dmat


_RETRIES: tuple[tuple[str, dict[str, float]], ...] = (("CLARABEL", {"static_regularization_constant": 1e-7}), ("SCS", {}))  # after a failed first solve


def wc_gain_upper(m: ArrayLike, blocks: Sequence, solver: str = "CLARABEL", retry: bool = True, **solver_opts) -> UpperBound:
    """Certified upper bound on ``max_Delta sigma_max(F_u(M, Delta))`` at one frequency (D-G scaling LMI).

    Parameters
    ----------
    m : array_like, shape (n + n_e, n + n_p)
        Complex matrix ``M(jw)``, Delta channels first.
    blocks : sequence of int or (name, int)
        Repetitions of the real scalar blocks.
    solver : str
        cvxpy SDP solver (``"CLARABEL"`` or ``"SCS"``).
    retry : bool
        If the solve fails or its certificate does not hold, solve again with Clarabel's static regularisation
        raised to 1e-7, then with SCS (Clarabel fails now and then on these near-singular data while the bound is
        finite and tight), then with the performance channels divided by the largest gain at the nominal point and
        the corners (when above 10: a gain of 5e3 makes ``t`` 2.5e7 against data of order 1, which the solvers
        declared infeasible). Every solve starts from scratch: the bound of an ``m`` does not depend on earlier calls.
    **solver_opts
        Passed to the solver; for Clarabel the tolerances default to 1e-7 (the bound is re-certified anyway).

    Returns
    -------
    UpperBound
        ``beta = inf`` if every solve fails or robust well-posedness cannot be certified.
    """
    if not isinstance(solver, str) or solver.upper() not in cp.installed_solvers():
        raise ValueError(f"solver must be one of the installed cvxpy solvers {cp.installed_solvers()}, got {solver!r}")
    first = _wc_gain_upper(m, blocks, solver, **solver_opts)
    if np.isfinite(first.beta) or not retry:
        return first
    for name, opts in _RETRIES:
        again = _wc_gain_upper(m, blocks, name, **opts)
        if np.isfinite(again.beta):
            return UpperBound(again.beta, again.d, again.g, f"{again.status} ({name} {opts} after {first.status})",
                              again.well_posed_margin)
    gamma = _gain_estimate(m, blocks)
    if gamma > 10.0:
        again = _wc_gain_upper(m, blocks, solver, gain_scale=gamma, **solver_opts)
        if np.isfinite(again.beta):
            return UpperBound(again.beta, again.d, again.g, f"{again.status} (performance channels / {gamma:.3g} after "
                              f"{first.status})", again.well_posed_margin)
    return first


def _box_corners(nbk: int) -> NDArray[np.float64]:
    """The ``2^nbk`` corners of the normalised box, one per row."""
    return np.array(np.meshgrid(*[[-1.0, 1.0]] * nbk, indexing="ij")).reshape(nbk, -1).T


def _gain_estimate(m: ArrayLike, blocks: Sequence) -> float:
    """Largest ``sigma_max(F_u)`` at the nominal point and the corners of the box (at most 1024 of them) where the LFT
    is well posed (0 if it is nowhere)."""
    nbk = len(_block_sizes(blocks))
    pts = _box_corners(nbk) if nbk <= 10 else np.zeros((0, nbk))
    best = 0.0
    for d in np.vstack([np.zeros(nbk), pts]):
        try:
            best = max(best, float(np.linalg.norm(lft_upper(m, blocks, d), 2)))
        except (ValueError, np.linalg.LinAlgError):
            continue
    return best


def _wc_gain_upper(m: ArrayLike, blocks: Sequence, solver: str = "CLARABEL", gain_scale: float | None = None, **solver_opts) -> UpperBound:
    """One solve of the D-G LMI (see :func:`wc_gain_upper`), with the performance channels (and the LMI's strictness)
    divided by ``gain_scale`` (an estimate of the gain of ``m``; None: not scaled) in the solve: ``(D, G, t)`` solve the scaled LMI iff
    ``gain_scale^2 (D, G, t)`` solve the original one. The certificate is computed on the original data."""
    sizes = _block_sizes(blocks)
    m = _check_m(m, sizes)
    n = sum(sizes)
    ms, tv, ce, cpv = _balance(m, n)
    basis = _hermitian_basis(sizes)
    qd = _lmi_forms(ms, n, basis, np.zeros_like(basis))
    qg = _lmi_forms(ms, n, np.zeros_like(basis), basis)
    prob, b, q0, y = _sdp(sizes, ms.shape[1] - n)
    b.value = _realify(np.concatenate([qd, qg])).reshape(2 * len(basis), -1).T
    gs = 1.0 if gain_scale is None else gain_scale * ce * cpv  # the gain estimate in the balanced coordinates
    e = ms[n:, :] / gs
    q0.value = _realify(e.conj().T @ e + _EPS_LMI / gs**2 * np.eye(ms.shape[1])).ravel()
    nan = np.full((n, n), np.nan + 0j)
    try:
        opts = {"tol_gap_abs": 1e-7, "tol_gap_rel": 1e-7, "tol_feas": 1e-7} if solver.upper() == "CLARABEL" else {}
        with warnings.catch_warnings():  # "Solution may be inaccurate": reported in the status
            warnings.filterwarnings("ignore", message="Solution may be inaccurate")
            # warm_start=False: the problem is cached (_sdp) and cvxpy would otherwise re-solve it from the previous
            # solve, so that a bound would depend on what was solved before it in the process (measured: 1.4e-5
            # relative between a fresh Dask worker and a used process, and Clarabel failing after some predecessors)
            prob.solve(solver=solver, **({"warm_start": False} | opts | solver_opts))
    except cp.error.SolverError as exc:
        return UpperBound(np.inf, nan, nan, f"solver_error: {exc}", np.nan)
    if prob.status not in ("optimal", "optimal_inaccurate") or y.value is None:
        return UpperBound(np.inf, nan, nan, str(prob.status), np.nan)
    coef = np.asarray(y.value) * gs**2
    if not np.all(np.isfinite(coef)):
        return UpperBound(np.inf, nan, nan, f"{prob.status}: non-finite scalings", np.nan)
    dmat = np.einsum("k,kij->ij", coef[:len(basis)], basis)
    gmat = np.einsum("k,kij->ij", coef[len(basis):], basis)
    t, margin, dmat = _certify(ms, sizes, dmat, gmat)
    if not np.isfinite(t):
        return UpperBound(np.inf, nan, nan, f"{prob.status}: certificate failed (well-posedness)", float(margin))
    scale = tv[:, None] * tv[None, :] / ce**2  # back to the coordinates of m
    return UpperBound(float(np.sqrt(t) / (ce * cpv)), dmat * scale, gmat * scale, str(prob.status), float(margin))


def recentre(m: ArrayLike, blocks: Sequence, centre: ArrayLike, radius: ArrayLike) -> NDArray[np.complex128]:
    """``M'`` with ``F_u(M', Delta') = F_u(M, Delta_c + Delta_r Delta')``: the sub-box ``centre +- radius`` of the
    parameters mapped to the unit box.

    With ``N = (I - M11 Delta_c)^-1``: ``M'11 = N M11 Delta_r``, ``M'12 = N M12``,
    ``M'21 = M21 (I - Delta_c M11)^-1 Delta_r``, ``M'22 = M22 + M21 Delta_c N M12``.

    Parameters
    ----------
    m : array_like, shape (n + n_e, n + n_p)
    blocks : sequence of int or (name, int)
    centre, radius : array_like, shape (n_blocks,)
        Centre in ``[-1, 1]`` and half-width ``> 0`` of the sub-box, per block (normalised units).
    """
    sizes = _block_sizes(blocks)
    m = _check_m(m, sizes)
    c, r = np.asarray(centre, dtype=float), np.asarray(radius, dtype=float)
    if c.shape != (len(sizes),) or r.shape != (len(sizes),) or not np.all(r > 0) or not np.all(np.abs(c) + r <= 1 + 1e-12):
        raise ValueError(f"centre, radius: need {len(sizes)} values each with radius > 0 and |centre| + radius <= 1, "
                         f"got {c.tolist()}, {r.tolist()}")
    n = sum(sizes)
    dc, dr = np.repeat(c, sizes), np.repeat(r, sizes)
    m11, m12, m21, m22 = m[:n, :n], m[:n, n:], m[n:, :n], m[n:, n:]
    nm = np.linalg.solve(np.eye(n) - m11 * dc[None, :], np.c_[m11 * dr[None, :], m12])
    left = np.linalg.solve((np.eye(n) - dc[:, None] * m11).T, m21.T).T
    return np.block([[nm[:, :n], nm[:, n:]], [left * dr[None, :], m22 + (m21 * dc[None, :]) @ nm[:, n:]]])


@dataclass(frozen=True)
class BranchBound:
    """Branch-and-bound upper bound over the parameter box at one frequency.

    ``beta`` bounds ``max_Delta sigma_max(F_u)`` (the largest leaf bound), ``lower`` is the largest gain achieved
    at a leaf centre, ``boxes`` the number of leaves, ``solves`` the LMIs solved, ``status`` why it stopped.
    """

    beta: float
    lower: float
    boxes: int
    solves: int
    status: str


def wc_gain_upper_bb(m: ArrayLike, blocks: Sequence, target: float | None = None, rtol: float = 0.02, max_solves: int = 200,
                     min_radius: float = 1.0 / 64, solver: str = "CLARABEL") -> BranchBound:
    """Upper bound on ``max_Delta sigma_max(F_u(M, Delta))`` tightened by branch and bound over the box.

    The leaf with the largest bound is split in two along the parameter with the widest interval, and both halves are
    bounded by :func:`wc_gain_upper` on their re-centred LFT (:func:`recentre`), until the largest leaf bound is below
    ``target`` (default: ``(1 + rtol)`` times the best gain achieved at a leaf centre), or ``max_solves`` LMIs were
    solved, or the leaf to split is already narrower than ``min_radius`` (normalised) in every parameter.

    Parameters
    ----------
    m : array_like, shape (n + n_e, n + n_p)
        Complex matrix ``M(jw)``, Delta channels first.
    blocks : sequence of int or (name, int)
        Repetitions of the real scalar blocks.
    target : float, optional
        Stop once the bound is below this value (e.g. ``(1 + rtol)`` times a lower bound over all frequencies).
    rtol : float
        Relative gap to the achieved gain at which to stop (used when ``target`` is None).
    max_solves, min_radius : int, float
        Work limits; the bound returned is valid whenever it stops.
    solver : str
        cvxpy SDP solver.
    """
    sizes = _block_sizes(blocks)
    m = _check_m(m, sizes)
    if max_solves < 1 or not 0 < min_radius <= 1:
        raise ValueError(f"max_solves must be >= 1 and min_radius in (0, 1], got {max_solves}, {min_radius}")
    nb = len(sizes)

    def bound(c: NDArray, r: NDArray) -> tuple[float, float]:
        try:
            mr = recentre(m, sizes, c, r)
        except np.linalg.LinAlgError:  # ill-posed at the sub-box's centre: no finite bound over it (and no gain achieved)
            return np.inf, 0.0
        centre_gain = float(np.linalg.norm(mr[sum(sizes):, sum(sizes):], 2))  # F_u at the centre: Delta' = 0
        return wc_gain_upper(mr, sizes, solver).beta, centre_gain

    leaves = [(np.zeros(nb), np.ones(nb), *bound(np.zeros(nb), np.ones(nb)))]
    solves, lower = 1, leaves[0][3]
    status = "max_solves"
    while True:
        k = int(np.argmax([leaf[2] for leaf in leaves]))
        c, r, beta, _ = leaves[k]
        goal = target if target is not None else (1 + rtol) * lower
        if beta <= goal:
            status = "converged"
            break
        if solves + 2 > max_solves:
            break
        if r.max() <= min_radius:
            status = "min_radius"
            break
        i = int(np.argmax(r))
        half = r.copy()
        half[i] /= 2
        leaves.pop(k)
        for sign in (-1.0, 1.0):
            cc = c.copy()
            cc[i] += sign * half[i]
            b, g = bound(cc, half)
            leaves.append((cc, half, b, g))
            lower = max(lower, g)
        solves += 2
    return BranchBound(float(max(leaf[2] for leaf in leaves)), float(lower), len(leaves), solves, status)


def _m_at(m_of_w: MOfW, omegas: NDArray) -> Callable[[int | None, float], NDArray]:
    """``get(i, w)``: ``M`` at grid index ``i`` (array input) or at any ``w`` (callable input)."""
    if callable(m_of_w):
        return lambda i, w: np.asarray(m_of_w(float(w)))
    arr = np.asarray(m_of_w)
    if arr.ndim != 3 or arr.shape[0] != len(omegas):
        raise ValueError(f"m_of_w: need a callable or an array (n_w={len(omegas)}, rows, cols), got shape {arr.shape}")
    return lambda i, w: arr[i]


def _check_omegas(omegas: ArrayLike) -> NDArray[np.float64]:
    w = np.atleast_1d(np.asarray(omegas, dtype=float))
    if w.ndim != 1 or not w.size or not np.all(np.isfinite(w) & (w > 0)) or np.any(np.diff(w) <= 0):
        raise ValueError("omegas: need a non-empty, strictly increasing 1-D array of positive finite rad/s")
    return w


def wc_gain_upper_sweep(m_of_w: MOfW, omegas: ArrayLike, blocks: Sequence, solver: str = "CLARABEL") -> UpperSweep:
    """:func:`wc_gain_upper` at each frequency of ``omegas`` [rad/s]; ``m_of_w`` is ``w -> M(jw)`` or an array
    of shape ``(n_w, rows, cols)``. The maximum is over the grid only."""
    w = _check_omegas(omegas)
    get = _m_at(m_of_w, w)
    res = [wc_gain_upper(_check_m(get(i, wi), _block_sizes(blocks), f"m_of_w({wi:g})"), blocks, solver)
           for i, wi in enumerate(w)]
    betas = np.array([r.beta for r in res])
    i_max = int(np.argmax(betas))
    return UpperSweep(w, betas, tuple(r.status for r in res), float(betas[i_max]), float(w[i_max]))


def _gain_grad(m: NDArray, sizes: tuple[int, ...], d: NDArray) -> tuple[float, NDArray]:
    """``sigma_max(F_u)`` and its gradient in the block deltas (``Re u^H dF v``, ``dF = M21 L^-1 E_i R^-1 M12``)."""
    n = sum(sizes)
    dv = np.repeat(d, sizes)
    r = np.eye(n) - m[:n, :n] * dv[None, :]
    if not np.linalg.cond(r) < _MAX_COND:
        raise ValueError(f"ill-posed LFT: I - M11 Delta is singular for deltas = {d.tolist()}")
    x = np.linalg.solve(r, m[:n, n:])
    u, s, vh = np.linalg.svd(m[n:, n:] + m[n:, :n] @ (dv[:, None] * x))
    left = np.linalg.solve((np.eye(n) - dv[:, None] * m[:n, :n]).T, m[n:, :n].T @ u[:, 0].conj())
    per_channel = np.real(left * (x @ vh[0].conj()))
    return float(s[0]), np.add.reduceat(per_channel, np.r_[0, np.cumsum(sizes)[:-1]])


def wc_gain_lower(m_of_w: MOfW, blocks: Sequence, omegas: ArrayLike, n_starts: int = 6, n_random: int = 64,
                  rng: np.random.Generator | int | None = None, maxiter: int = 200) -> LowerBound:
    """Achieved worst-case gain (a lower bound on the worst-case H-infinity norm).

    Parameters
    ----------
    m_of_w : callable or array_like
        ``w -> M(jw)`` (w in rad/s), or an array ``(n_w, rows, cols)`` on ``omegas`` (no frequency refinement).
    blocks : sequence of int or (name, int)
        Repetitions of the real scalar blocks.
    omegas : array_like
        Increasing frequency grid [rad/s] (make it peak-aware).
    n_starts : int
        Number of local searches, from the best grid points (at most half of them at one frequency).
    n_random : int
        Random delta vectors per frequency, besides the box corners (all of them if ``2**m <= 1024``) and 0.
    rng : Generator, int or None
        Random generator or seed.
    maxiter : int
        L-BFGS-B iterations per local search (over the deltas and ``log w`` between the neighbouring grid points).

    Returns
    -------
    LowerBound
        The best evaluated point: ``gain`` is attained at (``omega``, ``deltas``).

    Raises
    ------
    ValueError
        On bad arguments, or if the LFT is found ill-posed (``I - M11 Delta`` singular) at a point of the box.
    """
    sizes = _block_sizes(blocks)
    w = _check_omegas(omegas)
    for name, value in (("n_starts", n_starts), ("maxiter", maxiter)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    if isinstance(n_random, bool) or not isinstance(n_random, (int, np.integer)) or n_random < 0:
        raise ValueError(f"n_random must be a non-negative integer, got {n_random!r}")
    get, rng, nbk = _m_at(m_of_w, w), np.random.default_rng(rng), len(sizes)
    corners = _box_corners(nbk) if nbk <= 10 \
        else rng.choice([-1.0, 1.0], size=(1024, nbk))
    best: dict[str, Any] = {"gain": -1.0, "omega": np.nan, "deltas": np.zeros(nbk), "n": 0}
    mats: dict[float, tuple[NDArray, float]] = {}

    def gain_grad(i: int | None, wi: float, d: NDArray) -> tuple[float, NDArray]:
        if wi not in mats:
            mats[wi] = _balanced(get(i, wi), sizes, f"m_of_w({wi:g})")
        gain, grad = _gain_grad(mats[wi][0], sizes, d)
        return gain * mats[wi][1], grad * mats[wi][1]

    def record(gain: float, wi: float, d: NDArray) -> None:
        best["n"] += 1
        if gain > best["gain"]:
            best.update(gain=gain, omega=wi, deltas=d.copy())

    per_freq, corner_gains = [], np.zeros(len(w))
    for i, wi in enumerate(w):
        cand = np.vstack([np.zeros(nbk), corners, rng.uniform(-1.0, 1.0, (n_random, nbk))])
        ms, scale = mats[wi] = _balanced(get(i, wi), sizes, f"m_of_w({wi:g})")
        gains = scale * np.linalg.norm(_fu(ms, sizes, cand), 2, axis=(1, 2))
        corner_gains[i] = gains[:1 + len(corners)].max()
        top = np.argsort(-gains)[:n_starts]
        best["n"] += len(cand) - 1
        record(float(gains[top[0]]), wi, cand[top[0]])
        per_freq += [(gains[j], i, cand[j]) for j in top]
    starts: list[tuple[float, int, NDArray]] = []
    count = np.zeros(len(w), int)
    cap = n_starts if len(w) == 1 else -(-n_starts // 2)  # starts per frequency
    for c in sorted(per_freq, key=lambda c: -c[0]):
        if len(starts) < n_starts and count[c[1]] < cap:
            starts.append(c)
            count[c[1]] += 1
    refine_w = callable(m_of_w) and len(w) > 1
    h = 1e-7  # step in log w for the central difference
    for g0, i, d0 in starts:
        scale = max(g0, 1e-300)

        def fun(v: NDArray, i: int = i, scale: float = scale) -> tuple[float, NDArray]:
            d, wi = np.clip(v[:nbk], -1.0, 1.0), (float(np.exp(v[nbk])) if refine_w else w[i])
            gain, grad = gain_grad(i, wi, d)
            record(gain, wi, d)
            if not refine_w:
                return -gain / scale, -grad / scale
            gp, gm = (gain_grad(None, wi * np.exp(s), d)[0] for s in (h, -h))
            best["n"] += 2  # counted, not recorded: they may lie just outside the bracket
            return -gain / scale, -np.r_[grad, (gp - gm) / (2 * h)] / scale

        bounds = [(-1.0, 1.0)] * nbk
        v0 = d0
        if refine_w:
            bounds.append((np.log(w[max(i - 1, 0)]), np.log(w[min(i + 1, len(w) - 1)])))
            v0 = np.r_[d0, np.log(w[i])]
        minimize(fun, v0, jac=True, method="L-BFGS-B", bounds=bounds, options={"maxiter": maxiter})
    return LowerBound(float(best["gain"]), float(best["omega"]), np.asarray(best["deltas"]), int(best["n"]), corner_gains)
