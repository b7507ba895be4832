"""Robust structured H-infinity synthesis of the static PMA gain (the ``systune`` step of the paper).

Paper: section "Co-design optimization architecture", Step 3: find the 4x8 gain ``K_PMA`` that minimises
``J_c = max_Delta ||T_{p~ -> RPE}||_inf`` subject to the hard constraint ``Z_c = max_Delta ||T_{p~ -> W~u}||_inf
< gamma_u`` and closed-loop stability, for the uncertain closed loop of :mod:`trusscodesign.control.closedloop`.

Method (in the spirit of Apkarian and Noll's ``systune``, written here because no Python package does
multi-model structured H-infinity synthesis):

* **multi-model**: a finite set of uncertainty scenarios (nominal, box corners at several panel angles) is
  grown by a worst-case search over the whole parameter box (dynamic sampling);
* **peaks**: for each scenario the closed loop is put in modal form; its largest singular value is
  evaluated on a peak-aware grid (log points plus every lightly damped closed-loop pole frequency) and
  each local maximum is refined by nested grids in log frequency; the peak is checked by a direct solve;
* **nonsmooth step**: every peak within a band of the current maximum is linearised (gradient from the
  singular vectors at the peak frequency, exact for a static gain) and a trust-region linear program
  (HiGHS) minimises the largest linearised RPE peak; the effort peaks are elastic (an l1 merit) above a
  target halfway between the current ``Z`` and ``0.98 gamma_u``, and a feasibility phase first brings ``Z``
  under ``gamma_u``; the pole margins that could rise highest within the trust region are linearised with a
  1 % back-off; a step is accepted only if all scenarios stay stable, ``Z < gamma_u`` holds and the merit
  decreases by at least 10 % of the predicted decrease;
* **stabilisation**: from a destabilising start (e.g. a warm start from another h) the spectral abscissa
  is first pushed below ``-min_decay`` by the same trust-region LP on eigenvalue gradients.

A synthesis that does not reach a stable, feasible, converged point is returned with
``success = False`` and the reason; it is never reported as a result.
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linprog, minimize
from threadpoolctl import threadpool_limits

from ..infra.checks import check_option as _check_option
from ..infra.checks import check_panel_angles, check_real as _check_real
from .closedloop import GeneralizedPlant, LoopSettings, generalized_plant
from .hinf import hinf_norm
from ..model.lft import LFT
from .modalloop import ModalLoop, sigma_max
from ..infra.versions import ALGORITHM

__all__ = ["ALGORITHM", "NOT_STABILISED", "Scenario", "LoopPeaks", "loop_peaks", "peak_gradient", "SynthesisResult", "synthesize", "WorstCase", "worst_case",
           "search_candidates", "plant_at", "default_scenarios", "exact_norms", "sigma_curve", "SynthesisOptions"]

# progress: a line per round (INFO) and per accepted step (DEBUG); enable with logging.getLogger("trusscodesign").setLevel(...)
logger = logging.getLogger(__name__)

GROUPS = ("rpe", "effort")


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


def _n_workers(n: int | None) -> int:
    """Worker threads: ``n``, or up to 2 (the cores of the reference machine)."""
    if n is not None:
        _check_option("workers", n, 1, integer=True)
    return max(1, min(os.cpu_count() or 1, 2) if n is None else int(n))


@contextmanager
def _workers(n: int | None):
    """A thread pool (LAPACK releases the GIL) with one BLAS thread per worker: no oversubscription."""
    n = _n_workers(n)
    if n == 1:  # in this thread: no pool overhead, and profilers see the work
        with threadpool_limits(1):
            yield map
        return
    with threadpool_limits(1), ThreadPoolExecutor(n) as pool:
        yield pool.map


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


# ----------------------------------------------------------------------------- worst case over the box
@dataclass
class WorstCase:
    """Worst case over the uncertainty box found by a search: value, scenario and peak frequency per group."""

    value: dict[str, float]
    scenario: dict[str, Scenario]
    omega: dict[str, float]
    evaluations: int
    unstable: list[Scenario] = field(default_factory=list)


def search_candidates(thetas_deg: Sequence[float] | None = None) -> list[Scenario]:
    """The grid of :func:`worst_case`: the 8 corners of (M_SC, Iyy_SC, omega1_SP) and the nominal at each panel angle
    [deg] (default 10, every 20 deg from 0 to 180), angle by angle."""
    thetas = np.deg2rad(np.linspace(0.0, 180.0, 10) if thetas_deg is None else _thetas_deg(thetas_deg))
    corners = [np.array(c) for c in np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).T.reshape(-1, 3)] + [np.zeros(3)]
    return [Scenario(float(c[0]), float(c[1]), float(c[2]), float(th)) for th in thetas for c in corners]


def worst_case(model: LFT, gain: ArrayLike, inertia_p1: ArrayLike, settings: LoopSettings, thetas_deg: Sequence[float] | None = None,
               refine: int = 2, max_evals: int = 30, min_decay: float = 1e-7, workers: int | None = None,
               min_damping: float = 0.0) -> WorstCase:
    """Search the uncertainty box for the worst RPE and effort peaks with a given gain.

    Candidates: the 8 corners of (M_SC, Iyy_SC, omega1_SP) and the nominal, at each panel angle of
    ``thetas_deg`` (default 10 angles, every 20 deg from 0 to 180); then the ``refine`` best candidates of each
    group are improved by a bounded Nelder-Mead search over (d_mass, d_iyy, d_omega1, theta), ``max_evals``
    evaluations each.

    Unstable scenarios are listed in the grid's order, then in each refinement's; a refinement adds those it meets.
    """
    _check_option("refine", refine, 0, integer=True)
    _check_option("max_evals", max_evals, 1, integer=True)
    _check_option("min_decay", min_decay, 0.0)
    _check_option("min_damping", min_damping, 0.0, 1.0, open_high=True)
    cands = search_candidates(thetas_deg)
    evals = 0
    unstable: list[Scenario] = []

    # the least damped passive pole of the nominal plant: near it, each scenario's cap is bounded cheaply (loop_peaks)
    near = plant_at(model, Scenario(), inertia_p1, settings).passive_pole() if min_damping > 0 else None

    def evaluate(sc: Scenario, groups: Sequence[str] = GROUPS, met: list[Scenario] | None = None) -> LoopPeaks:
        lp = loop_peaks(plant_at(model, sc, inertia_p1, settings), gain, min_decay=min_decay, n_peaks=1,
                        min_damping=min_damping, lazy_cap=True, groups=groups, passive_near=near)
        if met is not None and not lp.stable:
            met.append(sc)
        return lp

    with _workers(workers) as pmap:
        table = list(zip(cands, pmap(evaluate, cands)))
        evals += len(cands)
        unstable += [sc for sc, lp in table if not lp.stable]
        value, worst, omega = {}, {}, {}
        for group in GROUPS:
            ranked = [table[i] for i in _ranked(table, group)]
            best = (ranked[0][1].norm(group), ranked[0][0], ranked[0][1].omega(group))
            if not np.isfinite(best[0]):
                value[group], worst[group], omega[group] = best
                continue

            def search(start: Scenario, group: str = group):
                # the peaks of this group only (the other group's, unused, cost about a tenth of an evaluation). Each
                # group's peaks are computed apart, so the values are the same, with one exception: in loop_peaks a
                # failed direct check of the RPE peak (> 1e-6) also replaces the effort peak by its direct value, a
                # change below 1e-6 that an effort-only evaluation does not make
                met: list[Scenario] = []

                def neg(x):
                    v = evaluate(Scenario.from_vector(x), (group,), met).norm(group)
                    return -v if np.isfinite(v) else -1e12

                res = minimize(neg, start.vector(), method="Nelder-Mead", bounds=[(-1, 1)] * 3 + [(0, np.pi)],
                               options=dict(maxfev=max_evals, initial_simplex=_simplex(start.vector()), xatol=1e-3, fatol=1e-6))
                sc = Scenario.from_vector(res.x)
                return sc, evaluate(sc, (group,), met), res.nfev + 1, met

            for sc, lp, n, met in pmap(search, [t[0] for t in ranked[:refine]]):
                evals += n
                unstable += met
                if lp.norm(group) > best[0]:
                    best = (lp.norm(group), sc, lp.omega(group))
            value[group], worst[group], omega[group] = best
    return WorstCase(value, worst, omega, evals, unstable)


def _ranked(table: Sequence[tuple[Scenario, LoopPeaks]], group: str) -> list[int]:
    """Indices of the table's candidates, the worst of ``group`` first (a stable sort: ties in the grid's order)."""
    return sorted(range(len(table)), key=lambda i: -table[i][1].norm(group))


def _simplex(x0: NDArray) -> NDArray:
    """Initial simplex inside the box around a start point (steps 0.3 normalised, 10 deg)."""
    steps = np.array([0.3, 0.3, 0.3, np.deg2rad(10.0)])
    simplex = [x0]
    for i in range(4):
        x = x0.copy()
        x[i] = x[i] - steps[i] if x[i] + steps[i] > (np.pi if i == 3 else 1.0) else x[i] + steps[i]
        simplex.append(x)
    return np.array(simplex)


# ----------------------------------------------------------------------------- the synthesis
def _merge(found: Sequence[WorstCase]) -> WorstCase:
    """One worst case from the searches of several open loops (the loop itself is not recorded: the scenario of each group
    is the one of the loop where it is worst)."""
    if len(found) == 1:
        return found[0]
    value, scenario, omega = {}, {}, {}
    for group in GROUPS:
        top = max(found, key=lambda w: w.value[group])
        value[group], scenario[group], omega[group] = top.value[group], top.scenario[group], top.omega[group]
    return WorstCase(value, scenario, omega, sum(w.evaluations for w in found), [sc for w in found for sc in w.unstable])


# message of a synthesis that could not stabilise its scenario set from its starting gain (the gain has not moved)
NOT_STABILISED = "could not stabilise every scenario from the starting gain"


@dataclass
class SynthesisResult:
    """Outcome of :func:`synthesize`.

    Attributes
    ----------
    gain : ndarray (4, 8)
        The PMA gain [N / (m/s^2) or N / (rad/s^2), through ``F_PMA``].
    j_c, z_c : float
        Worst-case ``||T_{p~->RPE}||_inf`` and ``||T_{p~->W~u}||_inf`` over the final scenario set and the
        last worst-case search (on the model and on every variant, if any).
    success : bool
        Stable at every scenario, ``z_c < gamma_u``, and the optimiser converged.
    message : str
        Why it stopped (and what failed, if it did).
    scenarios : list of Scenario
        The final scenario set (grown by the worst-case searches; each scenario is evaluated on every variant too).
    worst : WorstCase
        The last worst-case search.
    iterations, time_s, evaluations : int, float, int
    history : list of dict
        Per accepted iteration: J, Z, trust radius, phase.
    fallbacks : int
        With ``fast``: evaluations at which the fast path's pole checks failed and the dense eig was used.
    searches : int
        Rounds that ended with a worst-case search over the box (on the model and on every variant).
    restarts : int
        Attempts that failed and were started again from their final gain (:func:`trusscodesign.study.design.robust_design`,
        ``restarts``); the counters above add up every attempt.
    """

    gain: NDArray[np.float64]
    j_c: float
    z_c: float
    success: bool
    message: str
    scenarios: list[Scenario]
    worst: WorstCase | None
    iterations: int
    time_s: float
    evaluations: int
    history: list[dict] = field(default_factory=list)
    fallbacks: int = 0
    searches: int = 0
    restarts: int = 0


@dataclass
class _State:
    gain: NDArray
    peaks: list[LoopPeaks]
    extra: list[_Eigen | None] = field(default_factory=list)  # stability-only plants (None: not evaluated)
    min_decay: float = 1e-7

    def value(self, group: str) -> float:
        return max(p.norm(group) for p in self.peaks)

    def stable(self) -> bool:
        return all(p.stable for p in self.peaks) and all(x is not None and x.margin < -self.min_decay for x in self.extra)

    def abscissa(self) -> float:
        return max([p.abscissa for p in self.peaks] + [x.margin for x in self.extra if x is not None])


def _evaluate(plants: list[GeneralizedPlant], gain: NDArray, min_decay: float, pmap: Callable = map,
              checks: Sequence[GeneralizedPlant] = (), min_damping: float = 0.0, omega_check: float = 0.0,
              min_damping_all: float = 0.0, reject: Callable[[LoopPeaks], bool] | None = None,
              order: Sequence[int] | NDArray | None = None, chunk: int = 1,
              modal: Callable[[GeneralizedPlant], ModalLoop | None] = lambda p: None) -> tuple[_State | None, int]:
    """Peaks of the scenario plants, then, if they are all stable, the eigen-decomposition of the stability-only
    plants (skipped for a step that is rejected anyway). Returns the state and the number of plants evaluated.
    ``modal`` gives a plant's open-loop modal form (the fast path), or None (the dense path).

    With ``reject``, the plants are evaluated in ``order``, ``chunk`` at a time, and the evaluation stops (returns
    None) as soon as one plant's peaks show that the step is rejected whatever the others give: a trial step then
    costs one or two plants instead of all. The decision is the same as after a full evaluation.
    """

    def many(ps: list[GeneralizedPlant]) -> list[LoopPeaks]:
        return list(pmap(lambda p: loop_peaks(p, gain, min_decay=min_decay, min_damping=min_damping_all, modal=modal(p)), ps))

    if reject is None:
        peaks = many(plants)
    else:
        order = list(range(len(plants))) if order is None else list(order)
        found: dict[int, LoopPeaks] = {}
        for start in range(0, len(order), chunk):
            idx = order[start:start + chunk]
            found.update(zip(idx, many([plants[i] for i in idx])))
            if any(reject(found[i]) for i in idx):
                return None, len(found)
        peaks = [found[i] for i in range(len(plants))]
    state = _State(gain, peaks, [None] * len(checks), min_decay)
    if all(p.stable for p in peaks):
        state.extra = list(pmap(lambda p: _eigen(p, gain, min_damping, omega_check, modal(p)), checks))
    return state, len(peaks)


def _linearise(plants, state: _State, group: str, band: float,
               modal: Callable[[GeneralizedPlant], ModalLoop | None] = lambda p: None) -> list[tuple[float, NDArray]]:
    """Linearisations (value, gradient) of every peak of ``group`` above ``band`` times the current maximum."""
    top = state.value(group)
    rows = []
    for plant, lp in zip(plants, state.peaks):
        for val, w in lp.peaks[group]:
            if val >= band * top:
                v, g = peak_gradient(plant, state.gain, group, w, modal(plant))
                rows.append((v, g.ravel()))
    return rows


# radius of the ball of trust_region="ball", in units of the box's per-entry radii and of sqrt(n): halfway from the
# box's inscribed ball (1) to its corners (sqrt(n)). The first and only value tried (docs/experiments.md)
_BALL = 0.5
def _step_rows(objective: Sequence[tuple[float, NDArray]], constraints: Sequence[tuple[float, NDArray, float]],
               soft: Sequence[tuple[float, NDArray, float]]) -> tuple[list[NDArray], list[float]]:
    """Rows ``a x <= b`` of a step's program in ``x = (d, t, s)``: peaks ``f + g d - t <= 0``, hard ``c + h d <= bound``,
    elastic ``c + h d - s <= bound`` (the trust region's bounds on ``d`` and ``s`` apart)."""
    a = ([np.r_[g, -1.0, 0.0] for _, g in objective] + [np.r_[h.ravel(), 0.0, 0.0] for _, h, _ in constraints]
         + [np.r_[h.ravel(), 0.0, -1.0] for _, h, _ in soft])
    b = [-f for f, _ in objective] + [bound - c for c, _, bound in constraints] + [bound - c for c, _, bound in soft]
    return a, b


def _lp(objective: Sequence[tuple[float, NDArray]], constraints: Sequence[tuple[float, NDArray, float]], radius: NDArray,
        soft: Sequence[tuple[float, NDArray, float]] = (), penalty: float = 0.0,
        shape: str = "box") -> tuple[NDArray, float, float] | None:
    """Trust-region LP: ``min t + penalty s`` s.t. ``f_j + g_j d <= t``, ``c_k + h_k d <= bound_k`` (hard),
    ``c_l + h_l d <= bound_l + s`` (soft, elastic), ``s >= 0``, ``|d| <= radius``. Returns ``(d, t, s)``, or None
    if the LP has no solution (the hard constraints cannot be met in the trust region).

    ``shape="ball"`` adds ``||d / radius||_2 <= 0.5 sqrt(n)``: a second-order cone program (Clarabel), whose
    solution is not pushed into a corner of the box (see :func:`synthesize`, ``trust_region``)."""
    if shape == "ball":
        return _socp(objective, constraints, radius, soft, penalty)
    n = radius.size
    a_ub, b_ub = _step_rows(objective, constraints, soft)
    s_max = None if soft else 0.0
    res = linprog(np.r_[np.zeros(n), 1.0, penalty], A_ub=np.array(a_ub), b_ub=np.array(b_ub),
                  bounds=[(-r, r) for r in radius] + [(None, None), (0.0, s_max)], method="highs")
    return (res.x[:n], float(res.x[n]), float(res.x[n + 1])) if res.status == 0 else None


def _socp(objective: Sequence[tuple[float, NDArray]], constraints: Sequence[tuple[float, NDArray, float]], radius: NDArray,
          soft: Sequence[tuple[float, NDArray, float]], penalty: float) -> tuple[NDArray, float, float] | None:
    """:func:`_lp` in the box intersected with the ball ``||d / radius||_2 <= _BALL sqrt(n)``, a second-order cone
    program solved by Clarabel (scipy has no cone solver; Clarabel is cvxpy's, already the mu analysis's). It is given
    to Clarabel directly, in its form ``A x + z = b``, ``z`` in the cones: written in cvxpy, building and compiling the
    program took 80 ms per step, a third of a warm-started synthesis (``tests/control/test_synthesis.py`` keeps that
    formulation as the reference of this one)."""
    n = radius.size
    # x = (d, t, s): the step's rows, then -s <= 0 and |d| <= r (nonnegative cone)
    rows, rhs = _step_rows(objective, constraints, soft)
    eye = np.eye(n, n + 2)
    a_lin = np.vstack([*rows, np.r_[np.zeros(n + 1), -1.0], eye, -eye])
    b_lin = np.r_[rhs, 0.0, radius, radius]
    # the ball: z = (R, d_1 / r_1, ..., d_n / r_n) in the second-order cone
    a_soc = np.vstack([np.zeros(n + 2), -eye / radius[:, None]])
    b_soc = np.r_[_BALL * np.sqrt(n), np.zeros(n)]
    zero = [] if soft else [np.r_[np.zeros(n + 1), 1.0]]  # s = 0 without elastic rows (zero cone)
    cones = [("zero", len(zero)), ("nonneg", a_lin.shape[0]), ("soc", n + 1)]
    x = _clarabel(np.zeros(n + 2), np.r_[np.zeros(n), 1.0, penalty], np.vstack([*zero, a_lin, a_soc]),
                  np.r_[np.zeros(len(zero)), b_lin, b_soc], cones)
    if x is None:
        return None
    return x[:n], float(x[n]), float(x[n + 1])


def _clarabel(p_diag: NDArray, q: NDArray, a: NDArray, b: NDArray, cones: Sequence[tuple[str, int]]) -> NDArray | None:
    """``argmin 0.5 x^T diag(p_diag) x + q^T x`` s.t. ``b - a x`` in the cones, given in order as ``(kind, rows)`` with
    kind ``"zero"``, ``"nonneg"`` or ``"soc"``, by Clarabel; None unless it reports the problem solved."""
    import clarabel
    from scipy import sparse

    kinds = {"zero": clarabel.ZeroConeT, "nonneg": clarabel.NonnegativeConeT, "soc": clarabel.SecondOrderConeT}
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    p = sparse.diags(p_diag, format="csc")
    p.eliminate_zeros()  # a linear program's P without stored zeros
    solution = clarabel.DefaultSolver(p, q, sparse.csc_matrix(a), b, [kinds[kind](rows) for kind, rows in cones if rows],
                                      settings).solve()
    if solution.status != clarabel.SolverStatus.Solved:
        return None
    return np.asarray(solution.x, dtype=float)


def _least_change(constraints: Sequence[tuple[float, NDArray, float]], radius: NDArray, ball: bool = False) -> NDArray | None:
    """The smallest step ``d`` (in ``||d / radius||_2``) inside the box ``|d| <= radius`` (and, with ``ball``, the ball of
    ``trust_region="ball"``) with every linearised constraint ``c + h d <= bound`` met: a quadratic program (Clarabel),
    solved in the scaled step ``x = d / radius``. None if Clarabel does not solve it (no such step, or not to its
    tolerance): the caller then takes the min-max step.

    The restoration step of ``restoration="least_change"`` (see :func:`synthesize`): it moves the gain only as far as the
    linearised constraints ask, where the min-max step goes to the edge of the trust region."""
    n = radius.size
    eye = np.eye(n)
    a = np.vstack([*(h.ravel() * radius for _, h, _ in constraints), eye, -eye])
    b = np.r_[[bound - c for c, _, bound in constraints], np.ones(2 * n)]
    cones = [("nonneg", a.shape[0])]
    if ball:  # (_BALL sqrt(n), x) in the second-order cone
        a, b = np.vstack([a, np.zeros(n), -eye]), np.r_[b, _BALL * np.sqrt(n), np.zeros(n)]
        cones.append(("soc", n + 1))
    x = _clarabel(np.ones(n), np.zeros(n), a, b, cones)
    return None if x is None else x * radius


@dataclass(frozen=True)
class SynthesisOptions:
    """The options of a robust synthesis, checked when created (a ``TypeError`` or ``ValueError`` naming the option).

    One object travels from a notebook through the co-design, the design helpers and the sensitivity study to
    :func:`synthesize`; :meth:`key` is what stored results record of it.

    Attributes
    ----------
    min_damping, omega_check : float
        Damping ratio that every pole of the stability models above ``omega_check`` [rad/s] (the modes ``G_r``
        residualises) must keep (None: 5e-4 in :func:`synthesize`, half the truss damping in
        :func:`trusscodesign.study.design.robust_design`; they have at least 7e-4 with the PMAs
        passive; None: 500 rad/s, and the models' cut frequency in the design). A margin: left on the stability boundary, these modes would be pushed across by the uncertain
        parameters. Below ``omega_check`` the stability models need only be stable.
    min_damping_all : float
        Damping ratio every closed-loop pole of every scenario of the set must keep (default 2e-4; capped at half
        the scenario's passive least damping, 3.2e-4 on this spacecraft): without it the optimiser parks modes at a
        damping of 1e-4 or less, where the mu analysis can no longer certify robustness.
    max_iter : int
        Trust-region iterations per round.
    max_rounds : int
        Rounds of (optimise on the set, search the box, add the worst scenarios). A round whose optimisation
        stopped at ``max_iter`` is followed by another even when the search adds nothing; if the last one still
        does, the design is returned as valid (stable, feasible, covered by the search) with that message.
    search_thetas_deg : sequence of float, optional
        Panel angles of the worst-case search grid [deg] (default 10, every 20 deg from 0 to 180).
    tol : float
        Relative decrease of J over the last 5 accepted steps of a round's optimisation phase below which it stops
        (default 2e-3; the co-design's 1e-2, :data:`trusscodesign.study.codesign.CODESIGN_OPTIONS`).
    fast : bool
        Evaluate the scenario plants and stability-only plants during the optimisation through their open-loop
        modal form (:mod:`trusscodesign.control.modalloop`: ``O(n^2)`` per gain instead of a dense eigen-decomposition); the final
        evaluation of the scenario set and the worst-case searches stay dense, so ``j_c``, ``z_c`` and ``success``
        are always from the dense path. Default False (the reference path).
    trust_region : {"box", "ball"}
        Region of each step: the box ``|d_i| <= r_i`` on the gain entries (default: each step a linear program; every
        stored result) or that box intersected with the ball ``||d / r||_2 <= sqrt(32) / 2`` (a second-order cone program,
        Clarabel). (A third shape, the ball in a BFGS metric learnt over the accepted steps, gained nothing and was
        removed: ``docs/experiments.md``.) In the box, the steps of a cold start at the thin end of the h range sit in a corner of the box (27 to 32
        of the 32 entries on its faces) while 6-10 pole-damping rows are active, and the synthesis can crawl for dozens
        of steps and stop on that plateau (``docs/experiments.md``). Measured (``docs/experiments.md``,
        fast path, 8 cases): the ball takes the two such stalls (J_c 0.164 at 1.5 cm with ``tol = 0.01``, 0.181 at
        1.6 cm with 2e-3) and the 0.041 of 1.5 cm with 2e-3 to J_c 0.020-0.021; in the other cold starts its J_c is
        3.6 % lower to 5.2 % higher than the box's; warm starts take fewer iterations (25-31 against 44-51) and end 1.6
        and 14.5 % higher.
    restoration : {"minmax", "least_change"}
        The steps that restore stability (a start, or a scenario a search added, unstable at the current gain) and then
        ``Z < gamma_u``. ``"minmax"`` (default: every stored result): minimise the largest linearised pole margin (then
        the largest effort peak) in the trust region, which moves the gain to the edge of the region. ``"least_change"``:
        the smallest step (:func:`_least_change`, inside the trust region) whose linearised margins pass their targets by
        a quarter of their violation, then whose effort peaks reach ``gamma_u (1 - margin)`` (this phase lasting until
        ``Z < gamma_u (1 - margin / 2)``); the min-max step where no such step fits in the region, and for the rest of a
        stabilisation once a least-change trial has failed (``docs/experiments.md``). Measured
        (``docs/experiments.md``): one min-max step that stabilised a scenario the search added (abscissa 2.7e-3 to
        -5.0e-3 1/s, 5e4 times the required margin) took J from 0.018 to 0.071 and Z to 1.09, and the synthesis ended
        not converged with J_c 0.12 after 6 rounds.
    spillover : bool
        Used by :func:`trusscodesign.study.design.robust_design`: the nominal loops on the models' ``G_r_low`` as
        stability-only plants (default True).
    restarts : int
        Used by :func:`trusscodesign.study.design.robust_design`: how many times a failed synthesis is started again
        from its final gain (default 0).
    """

    min_damping: float | None = None
    omega_check: float | None = None
    min_damping_all: float = 2e-4
    max_iter: int = 60
    max_rounds: int = 6
    search_thetas_deg: tuple[float, ...] | None = None
    tol: float = 2e-3
    fast: bool = False
    trust_region: str = "box"
    restoration: str = "minmax"
    spillover: bool = True
    restarts: int = 0

    def __post_init__(self) -> None:
        if not (isinstance(self.trust_region, str) and self.trust_region in ("box", "ball")):
            raise ValueError(f"trust_region must be 'box' or 'ball', got {self.trust_region!r}")
        if not (isinstance(self.restoration, str) and self.restoration in ("minmax", "least_change")):
            raise ValueError(f"restoration must be 'minmax' or 'least_change', got {self.restoration!r}")
        for name in ("min_damping", "min_damping_all"):
            if getattr(self, name) is not None:
                _check_option(name, getattr(self, name), 0.0, 1.0, open_high=True)
        if self.omega_check is not None:
            _check_option("omega_check", self.omega_check, 0.0)
        _check_option("tol", self.tol, 0.0, 1.0, open_low=True, open_high=True)
        for name in ("max_iter", "max_rounds"):
            _check_option(name, getattr(self, name), 1, integer=True)
        _check_option("restarts", self.restarts, 0, integer=True)
        for name in ("fast", "spillover"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise TypeError(f"{name} must be True or False, got {getattr(self, name)!r}")
        if self.search_thetas_deg is not None:
            object.__setattr__(self, "search_thetas_deg", tuple(float(x) for x in _thetas_deg(self.search_thetas_deg, "search_thetas_deg")))

    def replace(self, **changes: Any) -> "SynthesisOptions":
        """A copy with ``changes``, checked."""
        return replace(self, **changes)

    def key(self) -> dict[str, Any]:
        """The options that differ from the defaults, by name, in JSON types: what stored results record (the co-design's
        ``{"tol": 0.01, "fast": true, "trust_region": "ball", "restoration": "least_change"}``)."""
        out: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if value != f.default:
                out[f.name] = list(value) if isinstance(value, tuple) else value
        return out

    @classmethod
    def from_key(cls, key: Mapping[str, Any] | None) -> "SynthesisOptions":
        """The options a stored :meth:`key` describes (None: the defaults); a ``TypeError`` names an option this version
        no longer has."""
        key = dict(key or {})
        unknown = sorted(set(key) - {f.name for f in fields(cls)})
        if unknown:
            raise TypeError(f"unknown synthesis option(s) {unknown}; SynthesisOptions has {[f.name for f in fields(cls)]}")
        return cls(**key)


# The optimiser's fixed parameters (options once, never set by any stored result, default or notebook)
_MIN_DECAY = 1e-7  # stability margin on the closed-loop poles [1/s]
_SEARCH_DAMPING = 0.75  # fraction of min_damping_all the worst-case search over the box requires (a margin, like _MARGIN)
_BAND = 0.7  # peaks within this fraction of the maximum enter the local model
_MARGIN = 0.02  # the linearised effort peaks are kept below gamma_u (1 - _MARGIN)
_COVER_TOL = 1e-2  # relative excess over the set's J (or Z) below which a searched worst case counts as covered
_RADIUS0 = 1.0  # initial trust radius on each gain entry (relative, at least 1)
_STALL_STEPS = 5  # the stopping test's window of accepted steps (see SynthesisOptions.tol)
_MAX_UNSTABLE = 1  # unstable scenarios a round adds from its search


def synthesize(model: LFT, inertia_p1: ArrayLike, settings: LoopSettings | None = None,
               options: SynthesisOptions | None = None, gain0: ArrayLike | None = None,
               scenarios: Sequence[Scenario] | None = None, stability_models: Sequence[GeneralizedPlant] = (),
               variants: Sequence[tuple[LFT, ArrayLike]] = (), workers: int | None = None) -> SynthesisResult:
    """Robust structured H-infinity synthesis of the 4x8 PMA gain (multi-model, hard effort constraint).

    Parameters
    ----------
    model : trusscodesign.model.lft.LFT
        Uncertain open loop at one h, e.g. :func:`trusscodesign.model.spacecraft.reduced_uncertain_model` (``G_r``).
    inertia_p1 : array_like (3, 3)
        Rigid inertia at P1 for the ACS [kg m^2] (:func:`trusscodesign.model.spacecraft.inertia_at_p1`).
    settings : LoopSettings, optional
    options : SynthesisOptions, optional
        What the optimiser does (default ``SynthesisOptions()``; ``spillover`` and ``restarts`` are the design's).
    gain0 : array_like (4, 8), optional
        Starting gain; default all entries -1 (as the paper).
    scenarios : sequence of Scenario, optional
        Initial scenario set (default :func:`default_scenarios`).
    stability_models : sequence of GeneralizedPlant
        Plants whose closed-loop stability is a hard constraint but whose norms are not optimised: e.g. the
        nominal ``G_r_low`` plant (all flexible modes), so that the gain does not destabilise the modes that
        ``G_r`` residualises (spillover). Their least damped poles enter the local model as linear constraints.
    variants : sequence of (LFT, array_like (3, 3)) pairs
        Further uncertain open loops, each with the rigid inertia at P1 its ACS is designed on [kg m^2], that the gain
        must serve as well as ``model``: e.g. the spacecraft with its truss frequencies shifted by a model error
        (:func:`trusscodesign.study.design.robust_design`, ``variants``). Every scenario of the set is evaluated on ``model`` and on every
        variant, and the worst-case search covers each of them. Default none: the paper's synthesis, unchanged.
    workers : int, optional
        Threads evaluating the scenarios (default: up to 2); BLAS is limited to one thread each.
    """
    t0 = time.perf_counter()
    opts = SynthesisOptions() if options is None else options
    if not isinstance(opts, SynthesisOptions):
        raise TypeError(f"options must be a SynthesisOptions, got {type(opts).__name__}")
    _n_workers(workers)
    min_damping = 5e-4 if opts.min_damping is None else opts.min_damping
    omega_check = 500.0 if opts.omega_check is None else opts.omega_check
    settings = settings or LoopSettings.from_parameters()
    gain = -np.ones((4, 8)) if gain0 is None else np.array(gain0, dtype=float)
    if gain.shape != (4, 8) or not np.all(np.isfinite(gain)):
        raise ValueError(f"gain0 must be a finite 4x8 matrix, got shape {gain.shape}")
    variants = list(variants)
    for i, variant in enumerate(variants):
        if not (isinstance(variant, tuple) and len(variant) == 2 and isinstance(variant[0], LFT)):
            raise TypeError(f"variants[{i}] must be a pair (LFT, inertia at P1), got {type(variant).__name__}")
        if np.shape(variant[1]) != (3, 3) or not np.all(np.isfinite(variant[1])):
            raise ValueError(f"variants[{i}]: the inertia at P1 must be a finite 3x3 matrix [kg m^2], got shape {np.shape(variant[1])}")
    scen = list(default_scenarios() if scenarios is None else scenarios)
    if not scen:
        raise ValueError("scenarios must hold at least one Scenario (None: default_scenarios()), got an empty set")
    for i, sc in enumerate(scen):
        if not isinstance(sc, Scenario):
            raise TypeError(f"scenarios[{i}] must be a Scenario, got {type(sc).__name__}")
    loops = [(model, inertia_p1)] + [(m, inertia) for m, inertia in variants]
    worst: WorstCase | None = None
    searches = 0
    message = f"stopped after {opts.max_rounds} rounds with the worst-case search still finding worse scenarios"
    with _workers(workers) as pmap:
        def plants_for(scs: Sequence[Scenario]) -> list[GeneralizedPlant]:
            return list(pmap(lambda job: plant_at(job[0][0], job[1], job[0][1], settings), [(loop, sc) for loop in loops for sc in scs]))

        prob = _Problem(plants_for(scen), list(stability_models), pmap, settings.gamma_u, opts, min_damping, omega_check,
                        chunk=_n_workers(workers))
        state = None
        for round_ in range(opts.max_rounds):
            # the first round evaluates the set at the starting gain; a later one starts from the last round's state, at
            # the same gain, with only the scenarios its search added still to evaluate
            state = _stabilise(prob, prob.evaluate_all(gain) if state is None else prob.extend(state))
            if not state.stable():
                message = (NOT_STABILISED if round_ == 0 else
                           f"could not stabilise the scenarios the worst-case search added in round {round_ - 1}")
                break
            state, at_limit = _optimise(prob, state)
            gain = state.gain
            worst = _merge([worst_case(m, gain, inertia, settings, opts.search_thetas_deg, min_decay=_MIN_DECAY, workers=workers,
                                       min_damping=_SEARCH_DAMPING * opts.min_damping_all) for m, inertia in loops])
            prob.evaluations += worst.evaluations
            searches += 1
            added = _uncovered(state, worst, settings.gamma_u)
            logger.info(f"round {round_}: {len(prob.plants)} scenario plants, J {state.value('rpe'):.5f} Z {state.value('effort'):.4f}; "
                        f"search J {worst.value['rpe']:.5f} Z {worst.value['effort']:.4f}; adding {len(added)} "
                        f"({time.perf_counter() - t0:.1f} s)")
            if not added and not at_limit:
                message = "converged: the worst-case search finds nothing worse than the scenario set"
                break
            if not added:  # the set covers the box but the optimiser was still improving: another round on the same set
                message = (f"iteration limit ({opts.max_rounds} x {opts.max_iter}): the worst-case search finds nothing worse "
                           "than the scenario set, but the optimiser had not converged")
                continue
            message = f"stopped after {opts.max_rounds} rounds with the worst-case search still finding worse scenarios"
            scen += added
            prob.plants += plants_for(added)
        final = prob.evaluate_all(gain, dense=True)
    j_c = max(final.value("rpe"), worst.value["rpe"] if worst else 0.0)
    z_c = max(final.value("effort"), worst.value["effort"] if worst else 0.0)
    stable = final.stable() and (worst is None or not worst.unstable)
    covered = message.startswith(("converged", "iteration limit"))
    success = covered and stable and z_c < settings.gamma_u
    if not success and covered:
        message = f"not a valid design: stable={stable}, Z_c={z_c:.4f} (bound {settings.gamma_u})"
    return SynthesisResult(gain, j_c, z_c, success, message, scen, worst, prob.iterations, time.perf_counter() - t0,
                           prob.evaluations, prob.history, prob.fallbacks(), searches)


@dataclass
class _Problem:
    """The data of one synthesis: scenario plants, stability-only plants, options and counters."""

    plants: list[GeneralizedPlant]
    checks: list[GeneralizedPlant]
    pmap: Callable
    gamma: float
    opts: SynthesisOptions
    min_damping: float
    omega_check: float
    chunk: int = 1
    iterations: int = 0
    evaluations: int = 0
    history: list[dict] = field(default_factory=list)
    _modal: dict[int, ModalLoop] = field(default_factory=dict, repr=False)

    def modal(self, plant: GeneralizedPlant) -> ModalLoop | None:
        """The plant's open-loop modal form (built at first use) if the fast path is on, else None."""
        if not self.opts.fast:
            return None
        if id(plant) not in self._modal:
            self._modal[id(plant)] = ModalLoop.of(plant)
        return self._modal[id(plant)]

    def fallbacks(self) -> int:
        """Gains at which the fast path's pole checks failed and a dense eig was used."""
        return sum(m.fallbacks for m in self._modal.values())

    def evaluate(self, gain: NDArray, reject: Callable[[LoopPeaks], bool] | None = None,
                 current: _State | None = None, dense: bool = False) -> _State | None:
        """All plants at ``gain``; with ``reject``, the most active plants of ``current`` first and None as soon as
        one of them rejects the step (see :func:`_evaluate`). ``dense``: by the dense path even if ``fast``."""
        order = None
        if reject is not None and current is not None:
            scale = {g: max(current.value(g), 1e-300) for g in GROUPS}
            order = np.argsort([-max(lp.norm(g) / scale[g] for g in GROUPS) for lp in current.peaks], kind="stable")
        state, n = _evaluate(self.plants, gain, _MIN_DECAY, self.pmap, self.checks, self.min_damping, self.omega_check,
                             self.opts.min_damping_all, reject, order, self.chunk, (lambda p: None) if dense else self.modal)
        self.evaluations += n
        return state

    def evaluate_all(self, gain: NDArray, dense: bool = False) -> _State:
        """All plants at ``gain`` (no reject test, so never stopped early); ``dense`` as in :meth:`evaluate`."""
        state = self.evaluate(gain, dense=dense)
        if state is None:  # only a reject test stops an evaluation
            raise RuntimeError("internal error: an evaluation without a reject test returned no state")
        return state

    def extend(self, state: _State) -> _State:
        """``state`` (an evaluation of the first plants of the set at ``state.gain``) with the plants added since evaluated
        at the same gain, by the same path as :meth:`evaluate_all`; its stability-only plants kept if they were evaluated."""
        new = self.plants[len(state.peaks):]
        if not new:
            return state
        part, n = _evaluate(new, state.gain, _MIN_DECAY, self.pmap, (), min_damping_all=self.opts.min_damping_all,
                            modal=self.modal)
        self.evaluations += n
        if part is None:  # only a reject test stops an evaluation
            raise RuntimeError("internal error: an evaluation without a reject test returned no state")
        return _State(state.gain, state.peaks + part.peaks, list(state.extra), _MIN_DECAY)

    def stability_rows(self, state: _State, all_plants: bool, radius: NDArray | None = None,
                       restore: bool = False) -> list[tuple[float, NDArray, float]]:
        """Linearised margins of the poles nearest their limit (stability plants; all plants if asked; with
        ``radius``, the trust region, those that could rise highest within it, see :meth:`_Eigen.rows`). Target
        ``T = -min_decay - 0.01 zeta_req |lambda|`` (a 1 % back-off): a pole below it may close half its distance
        to it per step; one inside the back-off may not rise (with ``restore``: must pass ``T`` by a quarter of its
        distance to it, the bound of a least-change restoration step). A constraint held exactly on its boundary (``value = -min_decay``) would be
        crossed at second order by every step along it."""
        def rows(eig: _Eigen, n: int) -> list[tuple[float, NDArray, float]]:
            out = []
            for v, g, req in eig.rows(n, radius):
                target = -_MIN_DECAY - 0.01 * req
                # restoring, a violated margin must pass its target by a quarter of its violation (a step aimed exactly at
                # the boundary ends on it, or above it at second order)
                out.append((v, g, 0.5 * (v + target) if v <= target else (target - 0.25 * (v - target) if restore else v)))
            return out

        found = [r for lp in state.peaks for r in rows(lp.decomposition(), 6 if all_plants else 2)]
        extra = [x if x is not None else _eigen(p, state.gain, self.min_damping, self.omega_check, self.modal(p))
                 for x, p in zip(state.extra, self.checks)]
        state.extra = [*extra]
        return found + [r for x in extra for r in rows(x, 12)]

    def radius(self, gain: NDArray) -> NDArray:
        return _RADIUS0 * np.maximum(1.0, np.abs(gain.ravel()))


def _uncovered(state: _State, worst: WorstCase, gamma: float) -> list[Scenario]:
    """Scenarios of the search that the set does not cover: unstable ones (at most :data:`_MAX_UNSTABLE`, no two
    within :data:`_NEAR` of each other), and the worst J or Z if more than :data:`_COVER_TOL` worse than the set's."""
    added = _distinct(worst.unstable, _NEAR)[:_MAX_UNSTABLE]
    if worst.value["rpe"] > state.value("rpe") * (1 + _COVER_TOL):
        added.append(worst.scenario["rpe"])
    if worst.value["effort"] > max(state.value("effort") * (1 + _COVER_TOL), gamma * (1 - _MARGIN)):
        added.append(worst.scenario["effort"])
    return _distinct(added)  # an unstable scenario is often also the worst J and Z (all inf): add it once


# two unstable scenarios closer than this in every coordinate (normalised mass, Iyy, omega1; theta [rad]) count as one
_NEAR = np.array([0.1, 0.1, 0.1, np.deg2rad(5.0)])


def _distinct(scenarios: Sequence[Scenario], near: NDArray | None = None) -> list[Scenario]:
    """The scenarios without repeats, in their order: no two equal, or with ``near``, no two closer than it in every
    coordinate."""
    unique: list[Scenario] = []
    for sc in scenarios:
        x = sc.vector()
        if not any(np.array_equal(x, u.vector()) if near is None else np.all(np.abs(x - u.vector()) < near) for u in unique):
            unique.append(sc)
    return unique


def _stabilise(prob: _Problem, state: _State) -> _State:
    """Push the spectral abscissa of every plant below ``-min_decay`` (trust-region LP on eigenvalue gradients)."""
    radius = prob.radius(state.gain)
    least = prob.opts.restoration == "least_change"  # until a least-change trial fails: then min-max steps
    for _ in range(prob.opts.max_iter):
        if state.stable() or np.all(radius < 1e-9):
            break
        prob.iterations += 1
        found = prob.stability_rows(state, all_plants=True, radius=radius, restore=least)
        step = _least_change(found, radius, prob.opts.trust_region != "box") if least else None
        if step is not None and not np.any(step):  # the linearised margins met already: the unstable pole is not among them
            step, least = None, False
        if step is None:  # the min-max step (restoration="minmax", or no least-change step fits in the region)
            sol = _lp([(v, g.ravel()) for v, g, _ in found], [], radius, shape=prob.opts.trust_region)
            if sol is None:
                radius = radius / 4
                continue
            step = sol[0]
        trial = prob.evaluate_all(state.gain + step.reshape(4, 8))
        if trial.abscissa() < state.abscissa():
            state = trial
            prob.history.append(dict(phase="stabilise", abscissa=trial.abscissa()))
        else:
            radius, least = radius / 4, False
    return state


_PENALTY = 10.0  # weight of the effort excess (relative to gamma) against the relative J in the merit


def _optimise(prob: _Problem, state: _State) -> tuple[_State, bool]:
    """Feasibility (Z < gamma), then min J s.t. Z < gamma and stability, by a trust-region sequential LP on the peaks.
    Returns the state and whether the iteration limit stopped it (rather than its own convergence tests)."""
    radius = prob.radius(state.gain)
    accepted: list[float] = []
    gamma = prob.gamma
    # the feasibility phase lasts until Z < gamma_u; with least-change steps, which aim at the margin bound
    # gamma_u (1 - margin), until Z < gamma_u (1 - margin / 2): left just under gamma_u, the optimiser, which rejects
    # every trial with Z >= gamma_u, is held to tiny steps (measured: J 0.168 with Z 0.99996 after a warm start
    # 2.8 -> 2.9 cm, where the others reach 0.02), and a phase that ended exactly at the bound aimed at would crawl to it
    restored = gamma * (1 - 0.5 * _MARGIN) if prob.opts.restoration == "least_change" else gamma
    restoring = state.value("effort") >= restored
    at_limit = False
    for _ in range(prob.opts.max_iter):
        prob.iterations += 1
        z_now = state.value("effort")
        restoring = restoring and z_now >= restored
        feasible = not restoring
        cons = _linearise(prob.plants, state, "effort", _BAND, prob.modal)
        # the stability rows of the poles that could rise highest within the step's reach
        stab = prob.stability_rows(state, all_plants=False, radius=radius)
        if feasible:
            # min J with the effort peaks elastic above a target halfway between Z and the margin bound (l1 penalty):
            # demanding them below the bound at once can leave no room to decrease J, and a pure feasibility step
            # throws J away; the merit J/J_now + penalty * max(0, Z - target)/gamma decides acceptance
            current = state.value("rpe")
            bound = gamma * (1 - _MARGIN)
            target = max(bound, 0.5 * (z_now + bound))
            rpe = _linearise(prob.plants, state, "rpe", _BAND, prob.modal)
            obj = [(f / current, g / current) for f, g in rpe]
            soft = [(c / gamma, h / gamma, target / gamma) for c, h in cons if c >= _BAND * gamma]

            def merit(j: float, z: float) -> float:
                return j / current + _PENALTY * max(0.0, z - target) / gamma

            sol = _lp(obj, stab, radius, soft, _PENALTY, prob.opts.trust_region)
            now, pred = merit(current, z_now), (None if sol is None else sol[1] + _PENALTY * sol[2])
        else:
            sol = None
            if prob.opts.restoration == "least_change":  # the smallest step to the margin bound, where one fits in the region
                bound = gamma * (1 - _MARGIN)
                step = _least_change([(c, h, bound) for c, h in cons] + stab, radius, prob.opts.trust_region != "box")
                sol = None if step is None else (step, max(c + h @ step for c, h in cons), 0.0)
            if sol is None:
                sol = _lp(cons, stab, radius, shape=prob.opts.trust_region)
            now, pred = z_now, (None if sol is None else sol[1])
        small = np.all(radius < 1e-7 * np.maximum(1.0, np.abs(state.gain.ravel())))
        if sol is None or pred is None or now - pred <= 1e-3 * prob.opts.tol * now:
            if small:
                break
            radius = radius / 4
            continue
        worst_new = now - 0.1 * (now - pred)  # a step whose merit ends above this is rejected (ratio <= 0.1)
        if feasible:
            def reject(lp: LoopPeaks) -> bool:  # one plant's peaks bound the merit from below
                return not lp.stable or lp.norm("effort") >= gamma or merit(lp.norm("rpe"), lp.norm("effort")) >= worst_new
        else:
            def reject(lp: LoopPeaks) -> bool:
                return not lp.stable or lp.norm("effort") >= worst_new
        trial = prob.evaluate(state.gain + sol[0].reshape(4, 8), reject, state)
        new = None  # the merit of an acceptable trial
        if trial is not None and trial.stable() and (trial.value("effort") < gamma if feasible else True):
            new = merit(trial.value("rpe"), trial.value("effort")) if feasible else trial.value("effort")
        ratio = (now - new) / (now - pred) if new is not None else -1.0
        if trial is not None and new is not None and ratio > 0.1:
            state = trial
            prob.history.append(dict(phase="optimise" if feasible else "feasibility", J=trial.value("rpe"), Z=trial.value("effort"),
                                     radius=float(radius.max())))
            logger.debug(f"it {prob.iterations}: J {trial.value('rpe'):.5f} Z {trial.value('effort'):.4f} radius {radius.max():.3g}")
            radius = radius * (2.0 if ratio > 0.75 else 1.0)
            accepted = accepted + [trial.value("rpe")] if feasible else []
            if len(accepted) > _STALL_STEPS and accepted[-_STALL_STEPS - 1] - accepted[-1] < prob.opts.tol * accepted[-1]:
                break  # less than tol relative decrease of J over the last _STALL_STEPS accepted steps
        else:
            if small:
                break
            radius = radius / 4
    else:
        at_limit = True
    return state, at_limit


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
    from .hinf import peak_grid, sigma_max

    a, b, c, d = plant.closed_loop_matrices(gain)
    sl = plant.slices()
    w = peak_grid(a, omega_range[0], omega_range[1], n_log=n_log)
    with threadpool_limits(1):
        return w, sigma_max(a, b[:, sl["p"]], c[sl[group]], d[sl[group], sl["p"]], w)
