"""Worst-case pointing analysis of a design: mu upper and lower bounds over the panel angle (the ``wcgain`` step).

Paper: section "Worst-case pointing analysis". For each of ``N_tau`` panel angles ``theta_i = 4 atan(tau_i)``
the closed loop ``P_i = F_l(F_u(G_r_low(h, tau_i), Delta_p), K_PMA)`` (all flexible modes kept) keeps its
``Delta_p = diag(delta_M I_3, delta_Iyy, delta_w1 I_4)`` channels open, and the worst-case gain of
``p~ -> RPE`` and ``p~ -> W~u`` over the unit box of ``Delta_p`` is bracketed by

* an **upper bound**: the D-G scaling LMI of :func:`trusscodesign.control.mu.wc_gain_upper` at each frequency of a grid that
  follows the peaks (the log points and the lightly damped closed-loop poles at nominal and at every corner of the
  box, restricted to where the sampled worst-case gain is within ``focus`` of its maximum, plus the lower bound's
  critical frequency),
  tightened by branch and bound over the parameter box (:func:`trusscodesign.control.mu.wc_gain_upper_bb`) where it is not within
  ``bb_rtol`` of the lower bound, as ``wcgain`` does;
* a **lower bound**: an achieved gain at a worst-case parameter set and frequency, in three passes: a search over the
  parameters and the frequency on the grid (:func:`trusscodesign.control.mu.wc_gain_lower`), the same around the upper bound's
  critical frequency, then a search over the parameters along the resonance ridge from the best point so far, the
  frequency following the closed-loop pole the parameters move (:func:`_ridge_lower`: interior worst cases, e.g. a
  parameter value inside the box that minimises a damping).

Nothing is certified between the frequencies evaluated: an interior worst case that none of the passes reaches is
missed by both bounds. Known cases: a parameter that brings one lightly damped mode onto another, within a sliver of
the box (``tests/study/test_robustness.py``: both stop 12 % below it, the certified bound below does not); a damping
minimised inside the box on a mode other than the best point's (:func:`_ridge_lower`). :func:`certify_at_angle` closes
that gap for the upper bound at one angle: it covers every frequency by intervals, each certified by one set of scalings
(:mod:`trusscodesign.control.mu_interval`), at a cost of about two minutes per transfer and angle on the spacecraft, so notebook
08 applies it at the critical angles (:func:`certify_critical`): at the other angles of its sweep the upper bound holds
at the evaluated frequencies, and between angles nothing is bounded.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from contextlib import nullcontext
from dataclasses import asdict, dataclass, field
from inspect import signature
from typing import Any
from pathlib import Path
import time

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import minimize, minimize_scalar
from threadpoolctl import threadpool_limits

from ..infra.checks import check_panel_angles
from ..control.closedloop import LoopSettings
from ..model.lft import LFT, block_runs
from ..control.mu import _MAX_COND, LowerBound, _box_corners, lft_upper, wc_gain_lower, wc_gain_upper, wc_gain_upper_bb
from ..control.mu_interval import CertifiedUpper, wc_gain_upper_certified
from ..infra.results import read_keyed, run_lock, write_json
from ..model.spacecraft import MODEL
from ..control.synthesis import Scenario, plant_at

__all__ = ["KEEP", "METHOD", "ModalResponse", "AngleBounds", "Analysed", "bounds_at_angle", "certify_at_angle", "certify_critical", "physical_deltas", "sweep"]

KEEP = ("Iyy_SC", "M_SC", "omega1_SP")  # the parameters of Delta_p, in the grouped channel order
# how bounds_at_angle computes its bounds; part of the key of a sweep's partial file, so that a sweep never resumes from
# angles bounded by an earlier method (change it with the method)
METHOD = "grid with corner poles; lower bound in three passes (grid, around the upper bound's frequency, ridge)"


class ModalResponse:
    """``w -> C (jwI - A)^-1 B + D`` through one eigen-decomposition, checked against a direct solve.

    The check tolerance ``rtol`` (relative to the largest entry, default 1e-5) is far below what the bounds are used
    for (upper and lower bounds compared at 5 %, every worst case confirmed by a rebuilt model and a Hamiltonian
    norm); it was 1e-7 until a design with closely spaced closed-loop poles (synthesis v4 at 2.139 cm) gave 6.3e-7.

    Raises
    ------
    ValueError
        If the modal and direct responses differ by more than ``rtol`` at the check frequencies
        (defective or ill-conditioned eigenvectors).
    """

    def __init__(self, a: NDArray, b: NDArray, c: NDArray, d: NDArray, check: Sequence[float] = (1.0, 97.0), rtol: float = 1e-5):
        self.lam, vec = np.linalg.eig(a)
        self.cv, self.vb, self.d = c @ vec, np.linalg.solve(vec, b), d
        for w in check:
            ref = d + c @ np.linalg.solve(1j * w * np.eye(a.shape[0]) - a, b)
            err = np.abs(self(w) - ref).max() / max(np.abs(ref).max(), 1e-300)
            if err > rtol:
                raise ValueError(f"modal response differs from a direct solve by {err:.1e} at {w} rad/s")

    def __call__(self, w: float) -> NDArray[np.complex128]:
        return self.at(1j * w)

    def at(self, s: complex) -> NDArray[np.complex128]:
        """The transfer at a complex frequency ``s`` [rad/s] (not an eigenvalue of ``A``)."""
        return (self.cv / (s - self.lam)) @ self.vb + self.d

    def slope(self, s: complex) -> NDArray[np.complex128]:
        """Its derivative with respect to ``s``."""
        return -(self.cv / (s - self.lam) ** 2) @ self.vb


@dataclass
class AngleBounds:
    """Bounds on the worst-case gain at one panel angle, for one transfer.

    Attributes
    ----------
    theta_deg : float
        Panel angle [deg].
    upper, lower : float
        Upper bound (max over the evaluated frequencies) and achieved lower bound.
    omega_upper, omega_lower : float
        Frequencies of the two [rad/s].
    deltas : dict
        Normalised worst-case parameters of the lower bound (``Iyy_SC``, ``M_SC``, ``omega1_SP``).
    n_upper : int
        Frequencies at which the LMI was solved.
    statuses : list of str
        Solver statuses (``optimal`` or the reason a bound is infinite).
    omegas, betas : ndarray
        The evaluated frequencies [rad/s] and upper bounds.
    """

    theta_deg: float
    upper: float
    lower: float
    omega_upper: float
    omega_lower: float
    deltas: dict[str, float]
    n_upper: int
    statuses: list[str] = field(default_factory=list)
    omegas: NDArray = field(default_factory=lambda: np.zeros(0))
    betas: NDArray = field(default_factory=lambda: np.zeros(0))

    @property
    def gap(self) -> float:
        """Relative gap ``upper / lower - 1``."""
        return self.upper / self.lower - 1.0


def physical_deltas(model: LFT, deltas: dict[str, float]) -> dict[str, float]:
    """Physical values of normalised worst-case parameters (hub mass [kg], Iyy [kg m^2], omega1 [rad/s])."""
    return {name: model.params[name].from_delta(v) for name, v in deltas.items()}


def _grid(lam: NDArray, omega_range: tuple[float, float], n_log: int) -> NDArray:
    wn = np.abs(lam)
    zeta = -lam.real / np.maximum(wn, 1e-300)
    wd = np.abs(lam.imag)
    lo, hi = omega_range
    sel = (zeta < 0.3) & (wd > lo) & (wd < hi)
    return np.unique(np.r_[np.geomspace(lo, hi, n_log), wd[sel], (wd * (1 - zeta))[sel], (wd * (1 + zeta))[sel]])


def _corner_poles(a: NDArray, b: NDArray, c: NDArray, d: NDArray, structure: Sequence[tuple[str, int]],
                  grid: NDArray, tol: float = 0.1) -> NDArray[np.complex128]:
    """Poles of ``F_u(M, Delta)`` at the corners of the normalised box that the frequency ``grid`` does not already
    resolve (``M`` the closed loop ``(a, b, c, d)`` whose first inputs and outputs are the Delta channels, in the runs
    of ``structure``).

    The worst case often sits at a corner that moves a lightly damped mode away from its nominal frequency (by up to
    10 % for a +-20 % stiffness), between the points of a grid built on the nominal poles: a resonance of damping 1e-3
    is then read at a small fraction of its peak by the samples and by the upper bound. A corner pole (upper half plane)
    is returned unless a grid point lies within ``tol |Re lambda|`` of its damped frequency (read there at 0.995 of
    its peak or more; most truss modes hardly move and sit on the nominal grid's points).

    Raises
    ------
    ValueError
        If the loop is ill-posed at a corner (``I - D_ww Delta`` singular).
    """
    sizes = [n for _, n in structure]
    nd = sum(sizes)
    if nd == 0:
        return np.zeros(0, complex)
    points = np.r_[-np.inf, np.sort(grid), np.inf]  # padded: every pole has a grid neighbour on each side
    out = []
    for signs in _box_corners(len(sizes)):
        delta = np.diag(np.repeat(signs, sizes))
        ret = np.eye(nd) - d[:nd, :nd] @ delta
        if np.linalg.cond(ret) > _MAX_COND:  # trusscodesign.control.mu's threshold of ill-posedness
            raise ValueError(f"the Delta loop is ill-posed at the corner {signs.tolist()} (I - D_ww Delta singular)")
        # x' = (a + b_w Delta (I - d_ww Delta)^-1 c_z) x: the Delta channels closed (w = Delta z)
        lam = np.linalg.eigvals(a + b[:, :nd] @ delta @ np.linalg.solve(ret, c[:nd]))
        lam = lam[lam.imag > 0]
        i = np.searchsorted(points, lam.imag)
        near = np.minimum(lam.imag - points[i - 1], points[i] - lam.imag)
        out.append(lam[near > tol * np.abs(lam.real)])
    return np.concatenate(out)


def _upper(m: NDArray, structure, target: float, max_solves: int) -> tuple[float, str]:
    """Upper bound at one frequency: the D-G LMI on the whole box (:func:`trusscodesign.control.mu.wc_gain_upper`, with its solver
    retries), then, if above ``target``, branch and bound over the box (:func:`trusscodesign.control.mu.wc_gain_upper_bb`).
    Returns ``(beta, status)``."""
    whole = wc_gain_upper(m, structure)
    if whole.beta <= target:
        return whole.beta, whole.status
    bb = wc_gain_upper_bb(m, structure, target=target, max_solves=max_solves)
    if bb.beta < whole.beta:
        return bb.beta, f"branch and bound: {bb.boxes} boxes, {bb.solves} LMIs ({bb.status})"
    return whole.beta, whole.status


def _pole_near(resp: ModalResponse, sizes: Sequence[int], deltas: NDArray, s0: complex, max_iter: int = 50) -> complex | None:
    """A pole of ``F_u(M, Delta)`` (the Delta channels of ``resp`` closed at the block values ``deltas``) by Newton's
    method from ``s0`` [rad/s]; None if it does not converge.

    The poles are the zeros of ``det(sI - A) det(I - M11(s) Delta)`` (``M11``: the Delta-to-Delta block, from the modal
    form; ``O(n k^2)`` per step for ``k`` channels, against ``O(n^3)`` for the eigenvalues of the closed state matrix).
    Newton's step is ``-1 / (sum_i 1 / (s - lambda_i) - tr((I - M11 Delta)^-1 M11' Delta))`` (the logarithmic derivative
    of that product; ``lambda_i`` the poles of ``M``).
    """
    nd = sum(sizes)
    dv = np.repeat(deltas, sizes)[None, :]
    s = complex(s0)
    if np.abs(resp.lam - s).min() < 1e-9 * abs(s):  # a start on a pole of M (e.g. a nominal pole): start beside it
        s += 1e-6 * abs(s)
    for _ in range(max_iter):
        if np.any(s == resp.lam):  # Newton's last step landed on a pole of M that Delta does not move
            return s
        try:
            with np.errstate(all="ignore"):  # M11 infinite, or I - M11 Delta singular: not a finite step
                t = np.trace(np.linalg.solve(np.eye(nd) - resp.at(s)[:nd, :nd] * dv, resp.slope(s)[:nd, :nd] * dv))
                step = -1.0 / (np.sum(1.0 / (s - resp.lam)) - t)
        except np.linalg.LinAlgError:
            return None
        if not np.isfinite(step):
            return None
        s += step
        if abs(step) <= 1e-12 * abs(s):
            return s
    return None


def _peak_near(resp: ModalResponse, sizes: Sequence[int], deltas: NDArray, pole: complex) -> tuple[float, float, int]:
    """Largest ``sigma_max(F_u(M(jw), Delta))`` for ``w`` within ``3 |Re pole|`` of the pole's damped frequency (a
    13-point scan, then Brent's method between the neighbours of its best point): ``(gain, w, evaluations)``."""
    wd = abs(pole.imag)
    half = 3.0 * max(abs(pole.real), 1e-9 * abs(pole))
    ws = np.linspace(max(wd - half, 0.5 * wd), wd + half, 13)

    def gain(w: float) -> float:
        return float(np.linalg.norm(lft_upper(resp(w), sizes, deltas), 2))

    scan = np.array([gain(w) for w in ws])
    i = int(np.argmax(scan))
    res = minimize_scalar(lambda w: -gain(w), bounds=(ws[max(i - 1, 0)], ws[min(i + 1, 12)]), method="bounded",
                          options={"xatol": 1e-12 * max(wd, half)})
    if -res.fun > scan[i]:
        return float(-res.fun), float(res.x), 13 + int(res.nfev)
    return float(scan[i]), float(ws[i]), 13 + int(res.nfev)


def _ridge_lower(resp: ModalResponse, sizes: Sequence[int], start: LowerBound, max_evals: int = 60) -> LowerBound:
    """The lower bound improved along its resonance ridge.

    The worst case of a lightly damped loop is a resonance that the parameters move: in ``(delta, w)`` a ridge as narrow as
    the damping, which a search over both (:func:`trusscodesign.control.mu.wc_gain_lower`, each frequency held between two grid points) leaves
    as soon as the parameters move the resonance off that bracket, e.g. where a parameter brings one mode onto another or
    minimises a damping inside the box. Here the frequency follows the parameters: the objective of a Nelder-Mead search
    over the box is, at each ``delta``, the peak near the closed-loop pole that continues the start's critical one
    (:func:`_pole_near`, :func:`_peak_near`). Every point evaluated is an achieved gain, so the result is a lower bound
    whatever the search does; it is the start if nothing better is found. A point where the loop is ill-posed on the
    axis (a pole on it: the box is not robustly stable there) counts as a gain of 0, not an error.

    It follows the start's resonance only: an interior worst case on another mode, whose corners read low, is missed (a
    review's random problems with a damping minimised inside the box: 3 of 25 with both bounds below a brute force, by
    up to 41 %; starts at the next largest sampled resonances did not reach them, and a start per lightly damped pole
    costs too much on the spacecraft's 784 states).
    """
    d0 = np.asarray(start.deltas, float)
    pole0 = _pole_near(resp, sizes, d0, 1j * start.omega)
    if pole0 is None:  # no convergence from the peak's frequency: the pole of M nearest it
        pole0 = complex(resp.lam[np.argmin(np.abs(resp.lam - 1j * start.omega))])
    best: dict[str, Any] = {"gain": start.gain, "omega": start.omega, "deltas": d0.copy(), "n": 0}

    def ridge(x: NDArray) -> float:
        d = np.clip(x, -1.0, 1.0)
        pole = _pole_near(resp, sizes, d, pole0)
        try:
            gain, w, n = _peak_near(resp, sizes, d, pole0 if pole is None else pole)
        except ValueError:  # I - M11(jw) Delta singular: a pole on the axis at d (the box is not robustly stable there)
            return 0.0
        best["n"] += n
        if gain > best["gain"]:
            best.update(gain=gain, omega=w, deltas=d.copy())
        return -gain / max(start.gain, 1e-300)

    steps = np.where(d0 > 0.75, -0.25, 0.25)  # a simplex inside the box
    simplex = np.vstack([d0, d0 + np.diag(steps)])
    minimize(ridge, d0, method="Nelder-Mead", bounds=[(-1.0, 1.0)] * len(d0),
             options={"maxfev": max_evals, "initial_simplex": simplex, "xatol": 1e-7, "fatol": 1e-10})
    return LowerBound(float(best["gain"]), float(best["omega"]), np.asarray(best["deltas"]), start.evaluations + best["n"],
                      start.corner_gains)


def _with_upper_at(omega: float, freqs: NDArray, ups: list[tuple[float, str]], resp: ModalResponse, structure,
                   target: float, max_solves: int) -> tuple[NDArray, list[tuple[float, str]]]:
    """The frequencies of the upper bound and their bounds (:func:`_upper`), with ``omega`` [rad/s] added in order unless
    it is already there."""
    if np.any(np.isclose(freqs, omega, rtol=1e-12, atol=0)):
        return freqs, ups
    freqs, ups = np.r_[freqs, omega], ups + [_upper(resp(omega), structure, target, max_solves)]
    order = np.argsort(freqs)
    return freqs[order], [ups[i] for i in order]


def _loop_at_angle(model_low: LFT, theta: float, gain: ArrayLike, inertia_p1: ArrayLike, settings: LoopSettings,
                   groups: Sequence[str]) -> tuple[NDArray, NDArray, NDArray, NDArray, dict[str, list[int]], list[tuple[str, int]]]:
    """The closed loop at one panel angle with the ``Delta_p`` channels open: ``(a, b, c, d)``, the output rows of each
    group (the Delta rows first) and the block structure ``[(name, repetitions)]``; a ValueError if it is unstable."""
    plant = plant_at(model_low, Scenario(theta=float(theta)), inertia_p1, settings, keep=KEEP)
    kept = [b for b in model_low.blocks if b in KEEP]  # the plant's open channels, in their order
    structure = block_runs(kept)
    if len({name for name, _ in structure}) != len(structure):
        raise ValueError(f"the Delta channels of model_low must be grouped by parameter (LFT.grouped()), got {kept}")
    a, b, c, d = plant.closed_loop_matrices(gain)
    if np.linalg.eigvals(a).real.max() >= 0:
        raise ValueError(f"the closed loop is unstable at nominal parameters and theta = {np.rad2deg(theta):.2f} deg")
    sl = plant.slices()
    rows = {group: list(range(plant.n_delta)) + list(range(plant.n_reg))[sl[group]] for group in groups}  # Delta, then the group
    return a, b, c, d, rows, structure


# the points a certification may spend: each lightly damped mode of the loop needs one to three of its own (measured on
# the calibrated designs, truss damping 1.5e-4: 150-190 points at order 802, about 10 min on one thread)
CERTIFY_MAX_POINTS = 400


def certify_at_angle(model_low: LFT, theta: float, gain: ArrayLike, inertia_p1: ArrayLike, settings: LoopSettings,
                     group: str, omegas: ArrayLike, slack: float = 0.02) -> CertifiedUpper:
    """Upper bound of the worst-case gain of ``group`` at one panel angle ``theta`` [rad], certified over every
    frequency (:func:`trusscodesign.control.mu_interval.wc_gain_upper_certified`), not only at the frequencies of a grid as
    :func:`bounds_at_angle`'s. ``omegas`` [rad/s]: starting points (e.g. that grid's, ``AngleBounds.omegas``).
    Each point costs an LMI and an eigenvalue problem of twice the loop's order (about 4 s at order 802 on one thread);
    at most :data:`CERTIFY_MAX_POINTS` points."""
    if group not in ("rpe", "effort"):
        raise ValueError(f"group must be 'rpe' or 'effort', got {group!r}")
    a, b, c, d, rows, structure = _loop_at_angle(model_low, theta, gain, inertia_p1, settings, (group,))
    with threadpool_limits(1):
        return wc_gain_upper_certified(a, b, c[rows[group]], d[rows[group]], structure, omegas, slack=slack,
                                       max_points=CERTIFY_MAX_POINTS)


@dataclass(frozen=True)
class Analysed:
    """One design as :func:`sweep` analysed it: its ``model_low``, the sweep's ``bounds``, its ``gain``, ``inertia_p1`` and
    loop ``settings`` (as :func:`bounds_at_angle`)."""

    model_low: LFT
    bounds: Sequence[dict[str, AngleBounds]]
    gain: NDArray
    inertia_p1: NDArray
    settings: LoopSettings


def _certify_one(d: Analysed, group: str, slack: float) -> dict:
    """:func:`certify_critical`'s record of one design and transfer."""
    b = max((out[group] for out in d.bounds), key=lambda x: x.upper)
    t0 = time.perf_counter()
    cert = certify_at_angle(d.model_low, np.deg2rad(b.theta_deg), d.gain, d.inertia_p1, d.settings, group, b.omegas, slack=slack)
    return {"theta_deg": b.theta_deg, "grid_upper": b.upper, "lower": b.lower, "certified_upper": cert.gamma,
            "covered": bool(cert.covered), "points": int(len(cert.omegas)), "largest_point_bound": float(cert.betas.max()),
            "gaps": cert.gaps.tolist(), "time_s": time.perf_counter() - t0}


def certify_critical(designs: dict[str, Analysed], groups: Sequence[str], slack: float = 0.02, client=None) -> dict[str, dict[str, dict]]:
    """For each design and each of ``groups``, the upper bound certified over every frequency (:func:`certify_at_angle`)
    at the panel angle of the design's sweep with the largest upper bound, from that angle's frequencies; on a Dask
    ``client`` if given (one task per design and transfer, all submitted at once), else in this process.

    Returns ``{label: {group: record}}``, each record with the angle ``theta_deg``, ``grid_upper`` (the sweep's bound
    there), ``lower``, ``certified_upper``, ``covered`` (every frequency covered: then ``certified_upper`` bounds the
    worst case at that angle over all frequencies), ``gaps`` [rad/s] (left uncovered), ``points``,
    ``largest_point_bound`` and ``time_s`` (the task's own time). A bound is certified at that angle only: at the
    sweep's other angles the upper bound holds at the frequencies it evaluated, and between angles nothing is bounded."""
    for group in groups:
        if group not in ("rpe", "effort"):
            raise ValueError(f"groups must hold 'rpe' and/or 'effort', got {group!r}")
    if client is None:
        return {label: {g: _certify_one(d, g, slack) for g in groups} for label, d in designs.items()}
    futures = {label: {g: client.submit(_certify_one, d, g, slack, pure=False) for g in groups} for label, d in designs.items()}
    return {label: {g: f.result() for g, f in fs.items()} for label, fs in futures.items()}


def bounds_at_angle(model_low: LFT, theta: float, gain: ArrayLike, inertia_p1: ArrayLike, settings: LoopSettings,
                    groups: Sequence[str] = ("rpe", "effort"), omega_range: tuple[float, float] = (1e-2, 2e3), n_log: int = 150,
                    focus: float = 0.7, max_upper: int = 40, seed: int = 0, bb_rtol: float = 0.02,
                    bb_max_solves: int = 100) -> dict[str, AngleBounds]:
    """Upper and lower bounds of the worst-case gain over ``Delta_p`` at one panel angle ``theta`` [rad].

    Parameters
    ----------
    model_low : trusscodesign.model.lft.LFT
        Uncertain open loop without spurious slow poles (``G_r_low``: :func:`trusscodesign.model.spacecraft.reduced_uncertain_model`
        with ``omega_max=None``).
    theta : float
        Panel angle [rad].
    gain : array_like (4, 8)
        The PMA gain.
    inertia_p1 : array_like (3, 3)
        ACS inertia [kg m^2].
    settings : LoopSettings
    groups : sequence of str
        Transfers analysed: ``"rpe"`` (p~ -> RPE) and/or ``"effort"`` (p~ -> W~u).
    omega_range, n_log : tuple, int
        Frequency range [rad/s] and log points of the grid (plus the lightly damped poles).
    focus : float
        The upper bound is evaluated where the sampled worst-case gain exceeds ``focus`` times its maximum
        (at most ``max_upper`` frequencies, the largest first), and at the lower bound's frequency.
    seed : int
        Seed of the random candidates of the lower bound.
    bb_rtol, bb_max_solves : float, int
        Where the whole-box bound exceeds ``(1 + bb_rtol)`` times the lower bound (or is infinite), it is tightened
        by branch and bound over the parameter box, with at most ``bb_max_solves`` LMIs per frequency.
    """
    a, b, c, d, rows, structure = _loop_at_angle(model_low, theta, gain, inertia_p1, settings, groups)
    names = [name for name, _ in structure]
    sizes = [size for _, size in structure]
    out = {}
    with threadpool_limits(1):
        resps = {group: ModalResponse(a, b, c[rows[group]], d[rows[group]]) for group in groups}
        nominal_grid = _grid(resps[groups[0]].lam, omega_range, n_log)  # the same closed loop (a) for every group
        # and the corner poles that grid does not resolve, with their half-power points
        grid = np.unique(np.r_[nominal_grid, _grid(_corner_poles(a, b, c, d, structure, nominal_grid), omega_range, 0)])
        for group in groups:
            resp = resps[group]
            lower = wc_gain_lower(resp, structure, grid, rng=seed)
            sampled = lower.corner_gains  # worst case per frequency over the nominal and the corners: where to bound
            order = np.argsort(-sampled)
            pick = [i for i in order[:max_upper] if sampled[i] >= focus * sampled[order[0]]]
            freqs = np.unique(np.r_[grid[pick], lower.omega])
            target = (1 + bb_rtol) * lower.gain
            ups = [_upper(resp(w), structure, target, bb_max_solves) for w in freqs]
            betas = np.array([u[0] for u in ups])
            k = int(np.argmax(betas))
            # second pass of the lower bound around the upper bound's frequency: the worst Delta moves a lightly damped
            # mode onto that frequency, a narrow ridge in (delta, w) that the first pass may have missed
            near = wc_gain_lower(resp, structure, freqs[k] * np.linspace(1 - 1e-3, 1 + 1e-3, 21), n_starts=12, n_random=512,
                                 rng=seed + 1)
            if near.gain > lower.gain:
                lower = near
                freqs, ups = _with_upper_at(lower.omega, freqs, ups, resp, structure, (1 + bb_rtol) * lower.gain, bb_max_solves)
            # third pass: along the resonance ridge, the frequency following the parameters (interior worst cases)
            ridge = _ridge_lower(resp, sizes, lower)
            if ridge.gain > lower.gain:
                lower = ridge
                freqs, ups = _with_upper_at(lower.omega, freqs, ups, resp, structure, (1 + bb_rtol) * lower.gain, bb_max_solves)
            betas = np.array([u[0] for u in ups])
            k = int(np.argmax(betas))
            out[group] = AngleBounds(float(np.rad2deg(theta)), float(betas[k]), lower.gain, float(freqs[k]), lower.omega,
                                     dict(zip(names, map(float, lower.deltas))), len(freqs), [u[1] for u in ups], freqs, betas)
    return out


def _record(bounds: dict[str, AngleBounds]) -> dict:
    """JSON-ready form of the bounds at one angle (see :func:`_from_record`)."""
    return {group: asdict(b) for group, b in bounds.items()}


def _from_record(rec: dict) -> dict[str, AngleBounds]:
    return {group: AngleBounds(**{**b, "omegas": np.asarray(b["omegas"], dtype=float), "betas": np.asarray(b["betas"], dtype=float)})
            for group, b in rec.items()}


def sweep(model_low: LFT, thetas: ArrayLike, gain: ArrayLike, inertia_p1: ArrayLike, settings: LoopSettings, client=None,
          progress: Callable[[Iterable], Iterable] = iter, partial: str | Path | None = None, partial_key: dict | None = None,
          **options) -> list[dict[str, AngleBounds]]:
    """:func:`bounds_at_angle` at each panel angle of ``thetas`` [rad], in parallel on a Dask client if given.

    The angles are independent and each is computed in one thread (one BLAS thread) from its own seed, so the
    results come in the order of ``thetas`` and do not depend on the number of workers (or none: this process): both
    bounds are the same to the last bit (each SDP is solved from scratch, :func:`trusscodesign.control.mu.wc_gain_upper`). A worker that
    dies is retried by Dask (twice).

    Parameters
    ----------
    model_low, gain, inertia_p1, settings
        As :func:`bounds_at_angle`.
    thetas : array_like
        Panel angles [rad].
    client : dask.distributed.Client, optional
        E.g. :func:`trusscodesign.study.cluster.local_client` (one single-threaded worker per core); default: this process.
    progress : callable
        Wraps the iterable of finished angles (e.g. a tqdm progress bar with ``total=len(thetas)``).
    partial : path, optional
        JSON file where each finished angle is saved at once, so that an interrupted sweep loses only the angles under
        way: a sweep with the same gain, inertia, settings, options (defaults included), :data:`METHOD` and
        ``partial_key`` takes the angles it holds from it. Removed once every angle is done. The key follows the method
        by :data:`METHOD` only, not every change of the library's code: after an update that changes the bounds without
        changing it, delete a partial file left by an interrupted sweep before rerunning.
    partial_key : dict
        What identifies ``model_low`` (e.g. h and the spacecraft parameters); required with ``partial``.
    **options
        Keyword options of :func:`bounds_at_angle` (``n_log``, ``focus``, ``seed``, ...).

    Raises
    ------
    ValueError
        If ``thetas`` is empty or not finite, or as :func:`bounds_at_angle` (an unstable nominal loop at an angle).
    """
    angles = np.atleast_1d(np.asarray(thetas, dtype=float))
    if angles.ndim != 1 or not angles.size or not np.all(np.isfinite(angles)):
        raise ValueError(f"thetas must be a non-empty 1-D array of finite panel angles [rad], got {thetas!r}")
    check_panel_angles("thetas", angles)
    if partial is not None and not partial_key:
        raise ValueError("partial_key is required with partial: give what identifies model_low (e.g. {'h': h, 'parameters': ...}), "
                         "or angles of another model could be reused")
    gain = np.asarray(gain, dtype=float)
    bound = signature(bounds_at_angle).bind_partial(**options)
    bound.apply_defaults()
    key = dict(model=partial_key, gain=gain.tolist(), inertia=np.asarray(inertia_p1, dtype=float).tolist(), settings=settings.__dict__,
               options=dict(bound.arguments), method=METHOD, model_version=MODEL)  # the options given and the defaults of the others
    # one sweep at a time on a partial file: another live run holding it stops this one at once, naming it
    with run_lock(partial) if partial is not None else nullcontext():
        return _sweep(model_low, angles, gain, inertia_p1, settings, client, progress, partial, key, options)


def _sweep(model_low: LFT, angles: NDArray, gain: NDArray, inertia_p1: ArrayLike, settings: LoopSettings, client,
           progress: Callable[[Iterable], Iterable], partial: str | Path | None, key: dict,
           options: dict) -> list[dict[str, AngleBounds]]:
    """:func:`sweep` once its inputs are checked and its partial file (if any) is locked."""
    stored, key = read_keyed(partial, key)
    records = stored["records"] if stored else {}
    tags = [repr(float(th)) for th in angles]
    out: list[dict[str, AngleBounds] | None] = [_from_record(records[t]) if t in records else None for t in tags]
    todo = [i for i, b in enumerate(out) if b is None]

    def finished():  # (index, bounds) of the angles as they finish, those read from ``partial`` first
        yield from ((i, b) for i, b in enumerate(out) if b is not None)
        if client is None:
            for i in todo:
                yield i, bounds_at_angle(model_low, float(angles[i]), gain, inertia_p1, settings, **options)
            return
        from dask.distributed import as_completed

        model = client.scatter(model_low, broadcast=True)  # sent once per worker, not once per angle
        futures = {client.submit(bounds_at_angle, model, float(angles[i]), gain, inertia_p1, settings, pure=False, retries=2,
                                 **options): i for i in todo}
        for fut in as_completed(futures):
            yield futures[fut], fut.result()

    with threadpool_limits(1):  # in this process, one BLAS thread as on a worker: the same arithmetic
        for i, bounds in progress(finished()):
            if out[i] is None and partial is not None:
                records[tags[i]] = _record(bounds)
                write_json(partial, {"key": key, "records": records})
            out[i] = bounds
    if partial is not None and Path(partial).exists() and all(b is not None for b in out):
        Path(partial).unlink()
    return out  # type: ignore[return-value]
