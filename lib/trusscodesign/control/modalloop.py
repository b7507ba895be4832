"""Closed-loop poles and responses of a static-gain loop from the open-loop modal form, without a dense eig per gain.

The synthesis evaluates each scenario plant at hundreds of gains ``K``; the dense path
(:func:`trusscodesign.control.synthesis.loop_peaks`) computes the closed-loop eigen-decomposition at each, ``O(n^3)`` (LAPACK
``dgeev``, 37 ms at order 314 on one thread). Only the 4x8 gain changes, so the open-loop modal form
``A = V diag(mu) V^-1`` is computed once per plant and everything at a gain follows from the 8x4 transfer
``P_yv(s) = C_y (s - A)^-1 B_v`` (written here because no library solves this rank-4 eigenvalue update):

* **poles**: the closed-loop poles are the roots of ``det(s - A_cl) = det(s - A) det(I - K P_yv(s))``; all of them
  are found at once by the Aberth-Ehrlich iteration, whose Newton correction needs
  ``d/ds log det = sum 1/(s - mu_i) - tr((I - K P_yv)^-1 K P_yv')``; the transfers at all ``n`` poles are two
  complex matrix products ``(n x n) (n x 32)``, so one sweep costs ``O(32 n^2)``, and a start from the poles
  at a nearby gain converges in 3-4 sweeps. The result is checked by the power sums ``sum lambda`` and
  ``sum lambda^2`` against ``tr A_cl`` and ``tr A_cl^2`` (in the modal coordinates, ``O(32 n)``) and by the distance
  between poles (a root found twice); a failed check falls back to the dense ``eig``;
* **eigenvector data**: for the pole ``lambda`` with ``(I - K P_yv(lambda)) y = 0`` and
  ``x^H (I - K P_yv(lambda)) = 0``, the right eigenvector is ``v = (lambda - A)^-1 B_v y`` and the left one
  ``w^H = x^H K C_y (lambda - A)^-1``, so ``C_y v = P_yv y``, ``w^H B_v = x^H`` and ``w^H v = -x^H K P_yv' y``: the
  pole's gradient in K (``d lambda = w^H B_v dK C_y v / w^H v``) needs no n-vector;
* **responses**: ``T = P_zp + P_zv K (I - P_yv K)^-1 P_yp`` from the open-loop response in modal form, real matrix
  products over the conjugate pairs ``(2 n_omega x n) (n x 60)`` for both groups (the gain folded into the outputs).

The accuracy is that of the open-loop modal form (its eigenvector basis can be ill-conditioned where modes are close:
the two solar panels). The dense path stays the reference: ``tests/control/test_modalloop.py`` compares both.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .closedloop import GeneralizedPlant

__all__ = ["ModalLoop", "aberth_poles", "sigma_max"]

# A mode whose residue in P_yv over |mu| is below this fraction of the largest is not moved by the gain (measured on
# the spacecraft plants, residue / |mu| in their units: the RPE-weight states at 1e-25 - 1e-27, the next mode at
# 1e-10, the largest about 1e-2: a gap of 1e15 no gain bridges)
_UNCOUPLED = 1e-18


def _transfer_and_slope(r: NDArray, m_yv: NDArray, shape: tuple[int, int]) -> tuple[NDArray, NDArray]:
    """``P(s) = sum_i m_i r_i`` and ``P'(s) = -sum_i m_i r_i^2`` at each point, from ``r = 1 / (s - mu)`` (points x
    modes): two stacks of ``shape`` (ny x nv) matrices."""
    return (r @ m_yv).reshape(-1, *shape), -((r * r) @ m_yv).reshape(-1, *shape)


def _conjugate_pairs(mu: NDArray) -> tuple[NDArray, NDArray]:
    """Indices of the first pole of each conjugate pair (its partner next, as LAPACK orders them) and of the real
    poles; raises if the poles are not in that order."""
    real = np.flatnonzero(mu.imag == 0)
    first = np.flatnonzero(mu.imag > 0)
    if (first.size and (first[-1] + 1 >= mu.size or np.any(mu[np.minimum(first + 1, mu.size - 1)] != np.conj(mu[first])))
            or 2 * first.size + real.size != mu.size):
        raise ValueError("the open-loop poles are not in conjugate pairs ordered as LAPACK's eig gives them")
    return first, real


def _pair_residues(mu: NDArray, m: NDArray, pairs: NDArray, real: NDArray) -> NDArray:
    """The real right-hand factor of :func:`_imaginary_axis_transfer` for residues ``m`` (rows: modes): per pair
    ``-2 Re(m conj mu)`` and ``2 Re m``, then the real poles' ``m``; formed once per gain, not per frequency call."""
    mp = mu[pairs]
    return np.vstack([-2.0 * np.real(m[pairs] * np.conj(mp)[:, None]), 2.0 * m[pairs].real, m[real].real])


def _imaginary_axis_transfer(mu: NDArray, right: NDArray, pairs: NDArray, real: NDArray, omega: NDArray) -> NDArray:
    """``sum_i m_i / (j omega - mu_i)`` for a real system (``m`` of a conjugate pair conjugate), by one real matrix
    product with ``right = _pair_residues(mu, m, pairs, real)``: a pair contributes
    ``(j omega 2 Re m - 2 Re(m conj mu)) / (|mu|^2 - omega^2 - 2 j omega Re mu)``, half the arithmetic of a complex
    matrix product."""
    k, npair = omega.size, pairs.size
    w = omega[:, None]
    mp, mr = mu[pairs], mu[real].real
    q = 1.0 / ((np.abs(mp) ** 2)[None, :] - w ** 2 - 2j * w * mp.real[None, :])
    den = 1.0 / (w ** 2 + mr[None, :] ** 2)
    left = np.empty((2 * k, right.shape[0]))  # [[Re q, -w Im q, -mu_r den], [Im q, w Re q, -w den]]
    left[:k, :npair], left[k:, :npair] = q.real, q.imag
    np.multiply(-w, q.imag, out=left[:k, npair:2 * npair])
    np.multiply(w, q.real, out=left[k:, npair:2 * npair])
    np.multiply(-mr[None, :], den, out=left[:k, 2 * npair:])
    np.multiply(-w, den, out=left[k:, 2 * npair:])
    out = left @ right
    return out[:k] + 1j * out[k:]


def _symmetrise(lam: NDArray) -> NDArray:
    """The roots of a real polynomial made exactly conjugate-symmetric (as LAPACK's eig returns them): each pair
    replaced by its mean, roots within 1e-10 of the real axis made real. Unchanged if the pairing is ambiguous.

    Without it, a pair's two frequencies differ by rounding and the peak-aware grid of
    :func:`trusscodesign.control.synthesis.loop_peaks` gets two points 1e-12 apart, between which rounding can make a spurious
    local maximum whose bracket misses the true peak (measured: a peak read 3.7e-5 low).
    """
    mag = np.abs(lam)
    real = np.abs(lam.imag) <= 1e-10 * mag
    up, lo = np.flatnonzero(~real & (lam.imag > 0)), np.flatnonzero(~real & (lam.imag < 0))
    if up.size != lo.size:
        return lam
    if not up.size:  # every root real
        return np.where(real, lam.real, lam)
    dist = np.abs(lam[up][:, None] - np.conj(lam[lo])[None, :])
    partner = np.argmin(dist, axis=1)  # each upper pole's nearest conjugate, which must be nobody else's
    if (np.unique(partner).size != up.size or np.any(dist[np.arange(up.size), partner] > 1e-8 * mag[up])):
        return lam
    lo = lo[partner]
    out = lam.copy()
    out[up] = 0.5 * (lam[up] + np.conj(lam[lo]))
    out[lo] = np.conj(out[up])
    out[real] = lam[real].real
    return out


def sigma_max(t: NDArray) -> NDArray:
    """Largest singular value of each matrix of a stack ``(k, m, n)``; closed form for two columns (the largest
    eigenvalue of the 2x2 Gram matrix), else LAPACK's SVD."""
    if t.shape[2] != 2:
        return np.linalg.svd(t, compute_uv=False)[:, 0]
    scale = np.abs(t).max(axis=(1, 2))
    u = t / np.where(scale > 0, scale, 1.0)[:, None, None]  # no overflow or underflow in the squares
    a, c = np.sum(np.abs(u[:, :, 0]) ** 2, axis=1), np.sum(np.abs(u[:, :, 1]) ** 2, axis=1)
    b = np.sum(np.conj(u[:, :, 0]) * u[:, :, 1], axis=1)
    return scale * np.sqrt(0.5 * (a + c) + np.sqrt(0.25 * (a - c) ** 2 + np.abs(b) ** 2))


def _trace_solve(a: NDArray, b: NDArray) -> NDArray:
    """``tr(a_j^-1 b_j)`` for a stack; ``inf`` where ``a_j`` is exactly singular (LAPACK finds a zero pivot)."""
    try:
        return np.trace(np.linalg.solve(a, b), axis1=1, axis2=2)
    except np.linalg.LinAlgError:
        out = np.full(a.shape[0], np.inf, dtype=complex)
        for j in range(a.shape[0]):
            try:
                out[j] = np.trace(np.linalg.solve(a[j], b[j]))
            except np.linalg.LinAlgError:
                pass
        return out


# sweeps of the mirrored iteration (conjugate pairs kept symmetric) before the unconverged approximations are iterated
# independently; a warm start from the previous gain converges in 3-8
_MIRROR_SWEEPS = 12


def aberth_poles(mu: NDArray, m_yv: NDArray, gain: NDArray, start: NDArray, tol: float = 1e-13,
                 max_sweeps: int = 60) -> tuple[NDArray, int, bool]:
    """Roots of ``det(s - diag(mu)) det(I - K P(s))`` with ``P(s) = sum_i m_i / (s - mu_i)`` (Aberth-Ehrlich).

    Parameters
    ----------
    mu : ndarray (n,)
        Open-loop poles [rad/s].
    m_yv : ndarray (n, ny * nv)
        Residues of ``P_yv``: row ``i`` is ``(C_y v_i) (w_i^H B_v)`` flattened (row-major, ``ny x nv``).
    gain : ndarray (nv, ny)
        Static gain ``K``.
    start : ndarray (n,)
        Starting approximations (distinct, none equal to an open-loop pole). If they are exactly conjugate-symmetric
        (as the poles of the previous gain are), only the upper half-plane and real ones are iterated and the others
        mirrored: for a real system the Aberth step of ``conj z`` is the conjugate of that of ``z``, so this is the same
        iteration at half the cost. A real approximation stays real and a pair stays a pair, so a pair of roots that
        has become two real ones (or the reverse) cannot converge that way: after 12 sweeps the unconverged
        approximations and their partners are rotated by 1e-7 rad and iterated independently. (Mirroring takes the
        residues of a pair as exact conjugates; computed by a complex solve they are so to rounding: the two
        iterations differ by about 1e-11 at convergence, the accuracy of the roots.)
    tol : float
        An approximation is converged once its correction is below ``tol`` relative to its modulus (or below 1e-11
        and no longer decreasing: the accuracy of an ill-conditioned modal form).
    max_sweeps : int
        Largest number of sweeps.

    Returns
    -------
    poles : ndarray (n,), complex
    sweeps : int
    converged : bool
    """
    n = mu.size
    nv, ny = gain.shape
    lam = np.array(start, dtype=complex)
    pairing = _conjugate_partners(lam)
    mirror = pairing is not None
    partner = np.arange(n) if pairing is None else pairing  # (used only while mirroring)
    real: NDArray[np.bool_] = np.equal(partner, np.arange(n))
    # mirroring: iterate the upper half-plane and real ones, mirror the others; else iterate every approximation
    active = (lam.imag > 0) | real if mirror else np.ones(n, dtype=bool)
    last_change = np.full(n, np.inf)
    eye = np.eye(nv)
    sweeps = 0
    while active.any() and sweeps < max_sweeps:
        if mirror and sweeps == _MIRROR_SWEEPS:
            # not converged: a pair that must split into two real roots (or two real approximations that must become
            # a pair) cannot while the approximations are kept symmetric. Go on with all of them, symmetry broken by
            # a rotation of 1e-7 rad of the unconverged ones (their mirrored partners join).
            idx = np.flatnonzero(active)
            idx = np.union1d(idx, partner[idx])
            lam[idx] = lam[idx] * (1.0 + 1e-7j)
            active[idx], last_change[idx] = True, np.inf
            mirror = False
        sweeps += 1
        idx = np.flatnonzero(active)
        old = lam[idx]
        s = old.copy()
        # on an open-loop pole (or within rounding of one), where P is singular: step off it
        hit = np.any(np.abs(s[:, None] - mu[None, :]) <= 1e-12 * np.abs(mu[None, :]), axis=1)
        s[hit] = s[hit] * (1.0 + 1e-10) + 1e-10j * np.abs(s[hit])
        r = 1.0 / (s[:, None] - mu[None, :])
        p, dp = _transfer_and_slope(r, m_yv, (ny, nv))
        log_det = r.sum(axis=1) - _trace_solve(eye - gain @ p, gain @ dp)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = 1.0 / log_det  # 0 where I - K P is exactly singular: the approximation is a root
        diff = s[:, None] - lam[None, :]
        diff[np.arange(idx.size), idx] = np.inf
        step = newton / (1.0 - newton * (1.0 / diff).sum(axis=1))
        if not np.all(np.isfinite(step)):
            return lam, sweeps, False
        new = s - step
        if mirror:
            new[real[idx]] = new[real[idx]].real
        lam[idx] = new
        if mirror:
            lam[partner[idx]] = np.conj(new)  # a real approximation is its own partner
        # converged: the approximation moved by less than tol (measured from before any step off an open-loop pole,
        # which a root on it undoes), or it stagnates at the accuracy the modal form allows (1e-11)
        change, size = np.abs(lam[idx] - old), np.maximum(np.abs(old), 1e-300)
        done = (change <= tol * size) | ((change <= 1e-11 * size) & (change >= 0.5 * last_change[idx]))
        last_change[idx] = change
        active[idx[done]] = False
    return lam, sweeps, not active.any()


def _conjugate_partners(z: NDArray) -> NDArray | None:
    """``partner[i]``, the index of ``conj(z[i])`` in ``z`` (a real entry is its own partner), if ``z`` is exactly
    conjugate-symmetric with distinct entries; else None."""
    values = z.tolist()
    index = {v: i for i, v in enumerate(values)}
    if len(index) != len(values):
        return None
    partner = [index.get(v.conjugate(), -1) for v in values]
    return None if min(partner, default=0) < 0 else np.array(partner)


def _null_vectors(mats: NDArray) -> NDArray:
    """Unit vectors nearest the null space of each (numerically singular) matrix of a stack, by inverse iteration."""
    n = mats.shape[-1]
    e = np.linspace(1.0, 2.0, n) * np.exp(1j * np.arange(n))  # generic: not orthogonal to a null vector in practice
    scale = np.abs(mats).max(axis=(1, 2))[:, None, None]
    eps = np.finfo(float).eps
    try:
        x = np.linalg.solve(mats + eps * scale * np.eye(n), np.broadcast_to(e, mats.shape[:2])[..., None])[..., 0]
    except np.linalg.LinAlgError:  # an exact zero pivot: the SVD's last right singular vectors
        return np.conj(np.linalg.svd(mats)[2][:, -1, :])
    return x / np.linalg.norm(x, axis=1, keepdims=True)


@dataclass
class ModalLoop:
    """The open-loop modal form of a generalized plant, for many evaluations at different static gains.

    Build it with :meth:`of`. ``fallbacks`` counts the gains at which the iteration's checks failed and the dense
    ``eig`` was used instead.
    """

    plant: GeneralizedPlant
    mu: NDArray
    c_t: NDArray  # (regulated + measured outputs) x n: C V
    b_t: NDArray  # n x (p~ + v inputs): V^-1 B
    d: NDArray  # the matching feedthrough
    m_yv: NDArray  # residues of P_yv, n x (8 * 4)
    trace_cb: NDArray  # C_y B_v in modal coordinates (8 x 4): tr(A_cl) = sum mu + tr(K C_y B_v)
    trace_cab: NDArray  # C_y A B_v (8 x 4)
    coupled: NDArray  # modes the gain moves (the others, with residues 1e-18 below the largest, stay where they are)
    pairs: NDArray  # indices of the first pole of each complex-conjugate pair (LAPACK gives the partner next)
    real: NDArray  # indices of the real poles
    _last: NDArray | None = field(default=None, repr=False)
    _open_right: NDArray | None = field(default=None, repr=False)  # the open loop's pair residues, formed on first use
    fallbacks: int = 0
    sweeps: int = 0

    @classmethod
    def of(cls, plant: GeneralizedPlant) -> "ModalLoop":
        """Open-loop eigen-decomposition of ``plant`` (without open Delta channels, no feedthrough from v to y)."""
        if plant.n_delta:
            raise ValueError("ModalLoop needs a plant without open Delta channels (substitute the uncertain parameters)")
        ne, nr = plant.n_exo, plant.n_reg
        if np.any(plant.d[nr:, ne:]):
            raise ValueError("ModalLoop needs a plant without feedthrough from the PMA commands to the measurements")
        mu, vec = np.linalg.eig(plant.a)
        if plant._passive_damping is None:  # the open-loop poles are the closed-loop ones at K = 0
            plant._passive_damping = float(np.min(-mu.real / np.abs(mu)))
        b_t = np.linalg.solve(vec, plant.b[:, plant.slices()["p"].start:])
        c_t = plant.c[plant.slices()["rpe"].start:, :] @ vec
        d = plant.d[plant.slices()["rpe"].start:, plant.slices()["p"].start:]
        nz = plant.N_RPE + plant.N_U
        c_y, b_v = c_t[nz:], b_t[:, plant.N_P:]
        m_yv = (c_y.T[:, :, None] * b_v[:, None, :]).reshape(mu.size, -1)
        ratio = np.linalg.norm(m_yv, axis=1) / np.maximum(np.abs(mu), 1e-300)  # residue over |mu| [y / v]
        coupled = ratio > _UNCOUPLED * ratio.max()
        pairs, real = _conjugate_pairs(mu)
        return cls(plant, mu, c_t, b_t, d, m_yv, c_y @ b_v, (c_y * mu) @ b_v, coupled, pairs, real)

    # ------------------------------------------------------------------ poles
    def _checks_pass(self, gain: NDArray, lam: NDArray) -> bool:
        """Power sums of the poles against the traces of ``A_cl`` and ``A_cl^2`` in the modal coordinates (1e-9 of
        ``sum |lambda|`` and ``sum |lambda|^2``); no two moved poles within 1e-10 of each other."""
        kcb = gain @ self.trace_cb
        tr1 = self.mu.sum() + np.trace(kcb)
        tr2 = (self.mu ** 2).sum() + 2.0 * np.trace(gain @ self.trace_cab) + np.trace(kcb @ kcb)
        scale1, scale2 = np.abs(lam).sum(), (np.abs(lam) ** 2).sum()
        if abs(lam.sum() - tr1) > 1e-9 * scale1 or abs((lam ** 2).sum() - tr2) > 1e-9 * scale2:
            return False
        # a root found twice (the power sums miss it if the missed one is close): every pair of moved poles is compared
        # (0.2 ms for 160 poles). Near neighbours in a sort by imaginary part are not enough: real roots carry rounding
        # imaginary parts of either sign, and other real roots can sort between two copies of one.
        moved = lam[self.coupled]
        dist = np.abs(moved[:, None] - moved[None, :])
        np.fill_diagonal(dist, np.inf)
        return bool(np.all(dist.min(axis=1, initial=np.inf) > 1e-10 * np.maximum(np.abs(moved), 1e-300)))

    def poles(self, gain: ArrayLike) -> NDArray[np.complex128]:
        """Closed-loop poles with the static gain [rad/s] (started from the poles of the previous call)."""
        k = self.plant._check_gain(gain)
        mu, cp = self.mu[self.coupled], self.coupled
        if self._last is None:  # off the open-loop poles (where P_yv is singular), in a fixed pattern
            jitter = 1e-3 * np.exp(2j * np.pi * np.arange(mu.size) / max(mu.size, 1))
            start = mu + jitter * np.maximum(np.abs(mu), 1e-3)
        else:
            start = self._last[cp]
        lam = self.mu.astype(complex)
        lam[cp], sweeps, ok = aberth_poles(mu, self.m_yv[cp], k, start)
        self.sweeps += sweeps
        if ok and self._checks_pass(k, lam):
            lam[cp] = _symmetrise(lam[cp])
        else:
            self.fallbacks += 1
            lam = self._in_mode_order(self.plant.closed_loop_poles(k))
        self._last = lam.copy()
        return lam

    def _in_mode_order(self, dense: NDArray) -> NDArray:
        """Dense poles ordered as :meth:`poles` orders them: the pole nearest each unmoved mode at that mode's place
        (:meth:`pole_data` gives those places the open-loop vectors), the others at the moved modes' places."""
        out = np.empty_like(self.mu, dtype=complex)
        free = np.ones(dense.size, dtype=bool)
        for i in np.flatnonzero(~self.coupled):
            j = int(np.argmin(np.where(free, np.abs(dense - self.mu[i]), np.inf)))
            out[i], free[j] = dense[j], False
        out[self.coupled] = dense[free]
        return out

    def pole_data(self, gain: ArrayLike, lam: NDArray) -> tuple[NDArray, NDArray]:
        """For each pole, ``w^H B_v`` (rows, n x 4) and ``C_y v`` (columns, 8 x n) with ``w^H v = 1``.

        ``lam`` must be the poles returned by :meth:`poles` (same order): a mode the gain does not move keeps its
        open-loop vectors. A pole exactly on an open-loop pole ``mu_j`` (a mode the gain sees through a zero column
        of K, say) has ``v = v_j`` and ``w^H B_v = (w_j^H B_v) (I - K P_rest(mu_j))^-1``, ``P_rest`` without mode j.
        """
        k = self.plant._check_gain(gain)
        nv, ny = k.shape
        cp = self.coupled
        with np.errstate(divide="ignore", invalid="ignore"):  # a pole on an open-loop pole: handled at the end
            r = 1.0 / (lam[:, None] - self.mu[None, cp])
        finite = np.all(np.isfinite(r), axis=1) & cp
        on_mode = np.flatnonzero(~finite & cp)
        r[~finite] = 0.0
        p, dp = _transfer_and_slope(r, self.m_yv[cp], (ny, nv))
        ret = np.eye(nv) - k @ p
        # null vectors by one step of inverse iteration from a fixed generic vector (ret is singular to the
        # accuracy of the pole; a batched 4x4 solve is several times cheaper than a batched SVD)
        y = _null_vectors(ret)
        x = _null_vectors(np.conj(np.swapaxes(ret, 1, 2)))  # left null vectors (x^H (I - K P) = 0)
        c_v = (p @ y[:, :, None])[:, :, 0]
        w_v = -np.sum(x.conj() * (k @ (dp @ y[:, :, None]))[:, :, 0], axis=1)
        ok = finite & (np.abs(w_v) > 0)
        left = np.where(ok[:, None], x.conj() / np.where(ok, w_v, 1.0)[:, None], 0.0)
        right = np.where(ok[:, None], c_v, 0.0).T
        nz = self.plant.N_RPE + self.plant.N_U
        left[~cp], right[:, ~cp] = self.b_t[~cp, self.plant.N_P:], self.c_t[nz:, ~cp]
        modes = np.flatnonzero(cp)
        for i in on_mode:
            with np.errstate(divide="ignore", invalid="ignore"):
                rest = 1.0 / (lam[i] - self.mu[modes])
            j = modes[~np.isfinite(rest)][0]
            rest[~np.isfinite(rest)] = 0.0
            p_rest = (rest @ self.m_yv[modes]).reshape(ny, nv)
            left[i] = np.linalg.solve((np.eye(nv) - k @ p_rest).T, self.b_t[j, self.plant.N_P:])
            right[:, i] = self.c_t[nz:, j]
        return left, right

    # ------------------------------------------------------------------ responses
    def responder(self, gain: ArrayLike) -> Callable[[ArrayLike], NDArray[np.complex128]]:
        """``omega -> T(j omega)`` (omega [rad/s]), the closed loop from p~ to ``[RPE; W~u]`` with the static gain,
        shape ``(len(omega), 6, 2)`` (the gain's residues are formed once for all frequencies)."""
        k = self.plant._check_gain(gain)
        nz, npp = self.plant.N_RPE + self.plant.N_U, self.plant.N_P
        c = np.vstack([self.c_t[:nz], k @ self.c_t[nz:]])  # outputs [z; K y]
        d = np.vstack([self.d[:nz], k @ self.d[nz:]])
        m = (c.T[:, :, None] * self.b_t[:, None, :]).reshape(self.mu.size, -1)
        right = _pair_residues(self.mu, m, self.pairs, self.real)
        eye = np.eye(k.shape[0])

        def response(omega: ArrayLike) -> NDArray[np.complex128]:
            w = np.atleast_1d(np.asarray(omega, dtype=float))
            p = _imaginary_axis_transfer(self.mu, right, self.pairs, self.real, w).reshape(-1, *d.shape) + d
            return p[:, :nz, :npp] + p[:, :nz, npp:] @ np.linalg.solve(eye - p[:, nz:, npp:], p[:, nz:, :npp])
        return response

    def open_loop(self, omega: float) -> NDArray[np.complex128]:
        """Open-loop ``P(j omega)`` (omega [rad/s]) from ``[p~; v]`` to ``[RPE; W~u; y]`` (14 x 6)."""
        if self._open_right is None:
            m = (self.c_t.T[:, :, None] * self.b_t[:, None, :]).reshape(self.mu.size, -1)
            self._open_right = _pair_residues(self.mu, m, self.pairs, self.real)
        return (_imaginary_axis_transfer(self.mu, self._open_right, self.pairs, self.real, np.array([float(omega)]))[0]
                .reshape(self.d.shape) + self.d)
