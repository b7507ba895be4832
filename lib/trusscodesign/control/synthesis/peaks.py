"""Peaks of the closed loop with a static gain: a peak-aware frequency grid refined by nested grids, checked by a
direct solve; their gradients in the gain; the closed-loop poles and their margins.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..closedloop import GeneralizedPlant
from ..modalloop import ModalLoop, sigma_max

__all__ = ['LoopPeaks', 'loop_peaks', 'peak_gradient']


GROUPS = ("rpe", "effort")


# ----------------------------------------------------------------------------- peaks of the closed loop
@dataclass
class LoopPeaks:
    """Peaks of the closed loop with a static gain at one scenario.

    ``peaks[group]`` is a list of ``(value, omega)`` local maxima of the largest singular value of the
    group's transfer from p~ (``"rpe"`` or ``"effort"``), largest first; ``abscissa`` is the largest
    ``Re lambda + min_damping |lambda|`` over the closed-loop poles [1/s] (the largest real part when
    ``min_damping = 0``) and ``stable`` whether it is below ``-min_decay``: every pole stable and damped at
    least ``min_damping``.
    """

    peaks: dict[str, list[tuple[float, float]]]
    abscissa: float
    stable: bool
    checked: float = 0.0  # relative difference of the top peak between modal and direct evaluation
    eigen: "_Eigen | None" = None  # the closed-loop eigen-decomposition (margins and their gradients)

    def norm(self, group: str) -> float:
        """Largest peak of a group (inf if unstable)."""
        return self.peaks[group][0][0] if self.stable else np.inf

    def omega(self, group: str) -> float:
        """Frequency of the largest peak [rad/s]."""
        return self.peaks[group][0][1]

    def decomposition(self) -> "_Eigen":
        """``eigen``, which :func:`loop_peaks` sets; a ValueError if these peaks carry none."""
        if self.eigen is None:
            raise ValueError("these peaks carry no eigen-decomposition (eigen is None): compute them with loop_peaks")
        return self.eigen

    def poles(self) -> NDArray[np.complex128]:
        """The closed-loop poles [rad/s]."""
        return self.decomposition().lam


def _zoom_max(fun: Callable[[NDArray], NDArray], lo: NDArray, hi: NDArray, n: int = 17,
              zooms: int = 5) -> tuple[NDArray, NDArray]:
    """Maximise ``fun(log w)`` on each bracket ``[lo_i, hi_i]`` by nested grids: ``n`` points, then ``n`` points on the two
    intervals around the best, ``zooms`` times (the bracket shrinks ``(n - 1) / 2`` times per zoom: 8^5 = 3e4 here,
    so a peak bracketed by its half-power points is located to 3e-5 of its bandwidth and its value to 1e-9).

    ``fun`` maps a ``(brackets, n)`` array of log frequencies to the values there: all the peaks of a loop are refined
    together, ``zooms`` vectorised calls in all instead of ``zooms`` per peak (or the ~50 scalar calls per peak of a
    golden-section search). Each bracket's grids are exactly those it would get alone. Returns ``(values, log w)``.
    """
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    best_v, best_x = np.full(lo.shape, -np.inf), lo.copy()
    rows = np.arange(lo.size)
    for _ in range(zooms):
        x = np.linspace(lo, hi, n, axis=1)
        v = fun(x)
        i = np.argmax(v, axis=1)
        better = v[rows, i] > best_v
        best_v[better], best_x[better] = v[rows, i][better], x[rows, i][better]
        step = x[:, 1] - x[:, 0]
        lo, hi = np.maximum(lo, best_x - step), np.minimum(hi, best_x + step)
    return best_v, best_x


def _per_group(groups: Sequence[str], group_of: NDArray, values: Callable[[str, NDArray], NDArray]) -> NDArray:
    """Values at points each of one group (``groups[group_of[i]]``): ``values(group, mask)`` gives those of a group's
    points (``mask`` selects them)."""
    out = np.empty(group_of.shape)
    for j, group in enumerate(groups):
        at = group_of == j
        if at.any():
            out[at] = values(group, at)
    return out


def _sv_max(cv: NDArray, lam: NDArray, vb: NDArray, d: NDArray, w: NDArray) -> NDArray:
    """Largest singular value of ``CV diag(1/(jw - lam)) VB + D`` at each w."""
    h = (cv[None, :, :] * (1.0 / (1j * w[:, None] - lam[None, :]))[:, None, :]) @ vb + d
    if h.shape[2] == 1:
        return np.sqrt(np.sum(np.abs(h[:, :, 0]) ** 2, axis=1))
    return np.linalg.svd(h, compute_uv=False)[:, 0]


def loop_peaks(plant: GeneralizedPlant, gain: ArrayLike, omega_range: tuple[float, float] = (1e-2, 3e3), n_log: int = 120,
               n_peaks: int = 4, min_decay: float = 1e-7, groups: Sequence[str] = GROUPS, min_damping: float = 0.0,
               lazy_cap: bool = False, modal: ModalLoop | None = None, passive_near: complex | None = None) -> LoopPeaks:
    """Peaks of ``sigma_max(T_{p~ -> group}(jw))`` of the closed loop, on a peak-aware grid, refined.

    Parameters
    ----------
    plant : GeneralizedPlant
        Without open Delta channels.
    gain : array_like (4, 8)
        Static PMA gain.
    omega_range : tuple of float
        Frequency range searched [rad/s], widened (to half the lowest and twice the highest) when a closed-loop pole
        with damping below 0.3 lies outside it; the limit at infinite frequency (``sigma_max(D)``) is not searched
        (0 on the spacecraft, whose transfers are strictly proper).
    n_log : int
        Log-spaced points, to which every closed-loop pole frequency with damping below 0.3 is added
        (with points at ``w_d (1 +- zeta)``), so that no lightly damped peak is missed.
    n_peaks : int
        Local maxima kept per group (each refined by nested grids in log frequency).
    min_decay : float
        Stability margin: all poles must have real part below ``-min_decay`` [1/s].
    min_damping : float
        Smallest damping ratio accepted for every closed-loop pole (0: stability only), capped at half the
        scenario's own passive (K = 0) smallest damping, so that the requirement never exceeds what the
        structure itself has.
    lazy_cap : bool
        Compute that cap (one more eigenvalue computation, a third of the cost of a call) only when the uncapped
        requirement fails. ``stable`` is the same either way (the cap only lowers the requirement); ``abscissa`` and
        the margins of ``eigen`` then hold the uncapped requirement whenever it is met. For callers that use only
        ``stable`` and the peaks (the worst-case search, whose plants are new at every call).
    passive_near : complex, optional
        With ``lazy_cap``: a pole near the plant's least damped passive pole [rad/s] (e.g. another scenario's
        :meth:`trusscodesign.control.closedloop.GeneralizedPlant.passive_pole`). The cap is then first bounded from above by the damping
        of the passive pole nearest it (:meth:`~trusscodesign.control.closedloop.GeneralizedPlant.passive_damping_bound`, a tenth of the
        cost of the cap); the cap itself is computed only if the requirement fails with that bound. ``stable`` is the
        same (the bound only raises the requirement), the cheaper check is conclusive at most scenarios.
    modal : trusscodesign.control.modalloop.ModalLoop, optional
        The plant's open-loop modal form: poles by the Aberth iteration and responses from the open-loop modal
        form, ``O(n^2)`` per gain instead of a dense eigen-decomposition (``O(n^3)``); the top peaks are then not
        re-checked by a direct solve (the tests compare both paths on the spacecraft plants). Its error grows as the
        closed loop nears instability (a review measured up to 1e-5 relative at a smallest damping of 1e-8 and 1e-4
        below it, against 4e-7 and 4e-6 for the dense path): the optimiser uses it far from there (damping floor
        about 1.6e-4), and the reported J_c and Z_c come from the dense path.
    """
    if plant.n_delta:
        raise ValueError("loop_peaks needs a plant without open Delta channels (substitute the uncertain parameters)")
    k = plant._check_gain(gain)
    sl = plant.slices()
    ne, nr = plant.n_exo, plant.n_reg
    if modal is None:
        a, b, c, d = plant.closed_loop_matrices(k)
        b, d = b[:, sl["p"]], d[:, sl["p"]]
        lam, vec = np.linalg.eig(a)
        cv_all, vb = c @ vec, np.linalg.solve(vec, b)

        def sigma(group: str, w: NDArray) -> NDArray:
            return _sv_max(cv_all[sl[group]], lam, vb, d[sl[group]], w)

        def sigmas(w: NDArray, group_of: NDArray) -> NDArray:
            return _per_group(groups, group_of, lambda group, at: sigma(group, w[at]))
    else:
        lam = modal.poles(k)
        response = modal.responder(k)
        rows = {g: slice(sl[g].start - plant.n_delta, sl[g].stop - plant.n_delta) for g in GROUPS}
        on_grid: dict[str, NDArray] = {}  # both groups from one evaluation on the grid

        def sigma(group: str, w: NDArray) -> NDArray:
            if w is grid and group in on_grid:
                return on_grid[group]
            t = response(w)
            if w is grid:
                on_grid.update({g: sigma_max(t[:, rows[g]]) for g in GROUPS})
                return on_grid[group]
            return sigma_max(t[:, rows[group]])

        def sigmas(w: NDArray, group_of: NDArray) -> NDArray:
            t = response(w)  # one response for all the groups
            return _per_group(groups, group_of, lambda group, at: sigma_max(t[at][:, rows[group]]))
    def meets(zeta_req: float) -> bool:
        return bool(lam.size) and np.max(lam.real + zeta_req * np.abs(lam)) < -min_decay

    if min_damping > 0 and not (lazy_cap and meets(min_damping)):
        bound = min(min_damping, 0.5 * plant.passive_damping_bound(passive_near)) if lazy_cap and passive_near is not None else -1.0
        # a passive plant with a negative damping must not lower the requirement below stability
        min_damping = bound if bound >= 0 and meets(bound) else min(min_damping, 0.5 * max(plant.passive_damping(), 0.0))
    value = lam.real + min_damping * np.abs(lam)
    if modal is None:
        eigen = _Eigen.dense(lam, vec, value, plant.b[:, ne:], plant.c[nr:, :])
    else:
        eigen = _Eigen.modal(modal, k, lam, value)
    abscissa = eigen.margin if lam.size else -np.inf
    wn = np.abs(lam)
    zeta = -lam.real / np.maximum(wn, 1e-300)
    wd = np.abs(lam.imag)
    lo, hi = omega_range
    light = (zeta < 0.3) & (wd > 0)
    if light.any():  # no lightly damped peak outside the range searched
        lo, hi = min(lo, 0.5 * wd[light].min()), max(hi, 2.0 * wd[light].max())
    sel = light & (wd > lo) & (wd < hi)
    grid = np.unique(np.r_[np.geomspace(lo, hi, n_log), wd[sel], (wd * (1 - zeta))[sel], (wd * (1 + zeta))[sel]])
    out: dict[str, list[tuple[float, float]]] = {}
    checked = 0.0
    found, brackets = {}, []  # per group: grid values and candidate indices; the peaks to refine: (group, index)
    for j, group in enumerate(groups):
        s = sigma(group, grid)
        interior = np.flatnonzero((s[1:-1] >= s[:-2]) & (s[1:-1] >= s[2:])) + 1
        cand = np.r_[interior, [0, grid.size - 1]]
        cand = cand[np.argsort(s[cand])[::-1]][:n_peaks]
        found[group] = (s, cand)
        brackets += [(j, i) for i in cand if 0 < i < grid.size - 1 and s[i] >= 0.5 * s[cand[0]]]  # the peaks that can matter
    refined = {}
    if brackets:
        group_of, at = np.array([b[0] for b in brackets]), np.array([b[1] for b in brackets])

        def fun(x: NDArray) -> NDArray:  # log w (brackets x points) -> sigma_max of each bracket's group
            return sigmas(np.exp(x).ravel(), np.repeat(group_of, x.shape[1])).reshape(x.shape)

        values, logw = _zoom_max(fun, np.log(grid[at - 1]), np.log(grid[at + 1]))
        refined = {b: (float(v), float(x)) for b, v, x in zip(brackets, values, logw)}
    for j, group in enumerate(groups):
        s, cand = found[group]
        peaks = []
        for i in cand:
            if (j, i) in refined:
                val, lw = refined[(j, i)]
                peaks.append((max(val, float(s[i])), float(np.exp(lw)) if val >= s[i] else float(grid[i])))
            else:
                peaks.append((float(s[i]), float(grid[i])))
        peaks.sort(reverse=True)
        if modal is None:  # check the top peak against a direct solve (modal form can lose accuracy for close poles)
            w0 = peaks[0][1]
            ref = d[sl[group]] + c[sl[group]] @ np.linalg.solve(1j * w0 * np.eye(a.shape[0]) - a, b)
            direct = float(np.linalg.svd(ref, compute_uv=False)[0])
            checked = max(checked, abs(direct - peaks[0][0]) / max(direct, 1e-300))
            if checked > 1e-6:
                peaks[0] = (direct, w0)
        out[group] = peaks
    return LoopPeaks(out, abscissa, abscissa < -min_decay, checked, eigen)


def peak_gradient(plant: GeneralizedPlant, gain: ArrayLike, group: str, omega: float,
                  modal: ModalLoop | None = None) -> tuple[float, NDArray[np.float64]]:
    """``sigma_max(T(jw))`` and its gradient with respect to the static gain K (4x8) at frequency ``omega``.

    With ``T = P_zp + P_zv K (I - P_yv K)^-1 P_yp``: ``dT = P_zv (I - K P_yv)^-1 dK (I - P_yv K)^-1 P_yp``,
    so ``d sigma = Re(u^H dT v)`` for the top singular pair ``(u, v)`` (a subgradient if sigma_max is multiple).
    With ``modal`` (the plant's open-loop modal form, no Delta channels) ``P(j omega)`` comes from it.
    """
    k = np.asarray(gain, dtype=float)
    sl = plant.slices()
    nr, ne = plant.n_reg, plant.n_exo
    p = plant.freqresp([omega])[:, :, 0] if modal is None else modal.open_loop(omega)
    p_zp, p_zv = p[sl[group], sl["p"]], p[sl[group], ne:]
    p_yp, p_yv = p[nr:, sl["p"]], p[nr:, ne:]
    left = p_zv @ np.linalg.inv(np.eye(k.shape[0]) - k @ p_yv)
    right = np.linalg.solve(np.eye(p_yv.shape[0]) - p_yv @ k, p_yp)
    t = p_zp + p_zv @ k @ right
    u, s, vh = np.linalg.svd(t)
    grad = np.real(np.outer(u[:, 0].conj() @ left, right @ vh[0].conj()))
    return float(s[0]), grad


@dataclass
class _Eigen:
    """Closed-loop poles of one plant, with their margins ``value = Re lambda + zeta_req |lambda|`` and, computed on
    demand (only the optimiser's linearisations need them) and kept (a rejected step linearises the same state again),
    ``vectors() = (w_i^H B_v rows (n x 4), C_y v_i columns (8 x n))`` for right/left eigenvectors with ``w_i^H v_i = 1``.
    ``form``: the plant's modal form, for poles from the fast path (None: dense)."""

    lam: NDArray
    value: NDArray
    compute: Callable[[], tuple[NDArray, NDArray]]
    form: ModalLoop | None = None
    known: tuple[NDArray, NDArray] | None = None  # vectors(), once computed (or computed elsewhere: _prefetch_vectors)

    @classmethod
    def dense(cls, lam: NDArray, vr: NDArray, value: NDArray, b_v: NDArray, c_y: NDArray) -> "_Eigen":
        """From a dense eigen-decomposition (right eigenvectors ``vr``) and the loop's ``B_v``, ``C_y``."""
        return cls(lam, value, lambda: (np.linalg.solve(vr, b_v), c_y @ vr))

    @classmethod
    def modal(cls, loop: ModalLoop, gain: NDArray, lam: NDArray, value: NDArray) -> "_Eigen":
        """From the poles ``lam`` of :meth:`trusscodesign.control.modalloop.ModalLoop.poles` at ``gain``."""
        return cls(lam, value, lambda: loop.pole_data(gain, lam), loop)

    def vectors(self) -> tuple[NDArray, NDArray]:
        if self.known is None:
            self.known = self.compute()
        return self.known

    @property
    def margin(self) -> float:
        return float(self.value.max())

    def rows(self, n: int, radius: NDArray | None = None) -> list[tuple[float, NDArray, float]]:
        """Margins of ``n`` poles with their gradients in K and ``zeta_req |lambda|``: ``d lambda = w^H B_v dK C_y v``
        for right/left eigenvectors ``v``, ``w`` with ``w^H v = 1``, and ``d margin = Re d lambda + zeta_req
        Re(conj(lambda) d lambda) / |lambda|`` (the ``|lambda|`` term matters for the high-frequency modes: at 4e3 rad/s
        and zeta_req 5e-4 it is as large as the real-part change).

        The ``n`` poles closest to violating their margin relative to ``|lambda|``; with ``radius`` (the trust region
        on K, 4x8 or flat) also the ``n`` whose margin could rise highest within it, ``margin + sum |dmargin/dK|
        radius``: a well-damped pole that is very sensitive to K can be the one a step destabilises (measured: a
        spillover mode at 1182 rad/s, not among the 8 least damped, went unstable at 1 % of |K|)."""
        mag = np.maximum(np.abs(self.lam), 1e-300)
        left_b, right_c = self.vectors()  # rows w_i^H B_v, columns C_y v_i, for every pole
        zeta_req = (self.value - self.lam.real) / mag
        order = np.argsort(-self.value / mag)[:n]
        if radius is not None:
            r = np.asarray(radius, dtype=float).reshape(left_b.shape[1], right_c.shape[0])
            reach = np.einsum("ij,jk,ki->i", np.abs(left_b), r, np.abs(right_c)) * (1.0 + zeta_req)
            order = np.r_[order, [i for i in np.argsort(-(self.value + reach))[:n] if i not in order]].astype(int)
        out = []
        for i in order:
            d_lam = np.outer(left_b[i], right_c[:, i])
            out.append((float(self.value[i]), np.real(d_lam) + zeta_req[i] * np.real(np.conj(self.lam[i]) / mag[i] * d_lam),
                        float(zeta_req[i] * mag[i])))
        return out


def _eigen(plant: GeneralizedPlant, gain: NDArray, min_damping: float = 0.0, omega_check: float = 0.0,
           modal: ModalLoop | None = None) -> _Eigen:
    """Eigen-decomposition of the closed loop; ``value = Re lambda + zeta_req |lambda|`` with ``zeta_req = min_damping``
    above ``omega_check`` [rad/s], else 0 (every value < 0: stable, and damped as required). With ``modal`` (the
    plant's open-loop modal form) the poles come from :meth:`trusscodesign.control.modalloop.ModalLoop.poles`."""
    def margins(lam: NDArray) -> NDArray:
        return lam.real + np.where(np.abs(lam) > omega_check, min_damping, 0.0) * np.abs(lam)

    if modal is not None:
        lam = modal.poles(gain)
        return _Eigen.modal(modal, gain, lam, margins(lam))
    nr, ne = plant.n_reg, plant.n_exo
    b_v, c_y = plant.b[:, ne:], plant.c[nr:, :]
    lam, vr = np.linalg.eig(plant.a + b_v @ gain @ c_y)
    return _Eigen.dense(lam, vr, margins(lam), b_v, c_y)
