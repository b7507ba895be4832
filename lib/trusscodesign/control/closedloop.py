"""The closed loop of the pointing study: ACS, PMA filters, RPE weight, effort bound, static PMA gain.

Paper: sections "Closed-Loop System" (control system architecture, fine pointing performance)
and "Co-design optimization architecture" (``J_c``, ``Z_c``). From the open-loop spacecraft
model ``G(s)`` (accelerations out) the generalized plant ``P`` of the synthesis is built:

* exogenous inputs ``[w_Delta (n_delta); p~ (2)]``: Delta channels kept open (if any) and the
  SADM torques normalised by ``p_max`` (``p = p_max p~``);
* regulated outputs ``[z_Delta (n_delta); RPE (2); W~u (4)]``: ``RPE = F_RPE(s) LOS`` (LOS
  angles, rad) and the PMA effort divided by ``u_max``;
* control ``v (4)`` and measurement ``y (8)``: the PMA forces are ``u = F_PMA(s) v`` and the
  gain closes ``v = K_PMA y`` on the 8 accelerations at N17 and N20;
* the ACS ``K_ACS(s) = -(k_p + k_v s)/s^2`` on the rotational acceleration of P1 is closed inside.

**Well-posed at s = 0.** ``K_ACS`` and the LOS angle both integrate accelerations twice. Done
naively (integrators on the outputs) this leaves poles at 0 that cancel only in exact
arithmetic. Here the position-level outputs are realised from the acceleration model ``(A, B, C, D)``
(no poles at 0 once the spurious slow poles are removed) as

``pos(s) = G_0 / s^2 + C A^-2 (sI - A)^-1 B``,   ``G_0 = D - C A^-1 B`` (the rigid part),

with ``G_0`` realised minimally by ``r = rank G_0`` double integrators (``r = 3``: the rigid
rotation) and the velocity as ``s pos(s)``. ``acc / s^2`` also contains ``G_1 / s`` with
``G_1 = -C A^-2 B``, which is zero for a mechanical model (each mode contributes
``s^2 / (s^2 + 2 xi w s + w^2)`` to an acceleration); its size after reduction is measured
and reported (:attr:`GeneralizedPlant.dropped`). The ACS then acts on the attitude and rate
of P1 through static gains, and every transfer is finite at s = 0.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, fields, replace
from functools import lru_cache
from typing import cast

import control as ct
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

from ..infra.checks import check_option
from ..model.statespace import close_static, frequency_response

__all__ = ["LoopSettings", "GeneralizedPlant", "generalized_plant", "rpe_weight", "pma_filter", "acs_gains",
           "MEASUREMENTS", "EFFORTS"]

ROT = ("Rx", "Ry", "Rz")
MEASUREMENTS = [f"a_{n}_{c}" for n in ("N17", "N20") for c in ("Tx", "Ty", "Rx", "Ry")]
EFFORTS = [f"u_PMA{i}" for i in range(1, 5)]
_EFFORT_KINDS = ("command", "transmitted")
# relative margin added to the damping ratio of a pole found by inverse iteration (GeneralizedPlant.passive_damping_bound):
# a residual of 1e-9 |lambda| moves a pole of condition number kappa by up to 1e-9 kappa |lambda|, i.e. its damping ratio
# (about 2e-4 on this spacecraft) by 1e-9 kappa; 1e-3 of 2e-4 covers kappa up to 200 (measured on the spacecraft
# plants at 1.5, 2.139 and 3 cm: the damping ratio found agrees with LAPACK's to 2e-6 relative or better, see the tests)
PASSIVE_BOUND_MARGIN = 1e-3


@dataclass(frozen=True)
class LoopSettings:
    """Closed-loop settings (paper values by default; ``xi_pma`` and ``effort`` are choices).

    Attributes
    ----------
    omega_acs, xi_acs : float
        ACS pole frequency [rad/s] and damping for the rigid spacecraft (0.1, 0.7), placed axis by axis from the
        diagonal of the inertia at P1 as the paper does; the centre of mass is not at P1 and the inertia has products,
        so the rigid closed-loop poles are near, not at, these values (0.0985-0.104 rad/s, damping 0.69-0.73 at
        2.139 cm).
    omega_pma, xi_pma : float
        PMA filter ``s / (s^2 + 2 xi w s + w^2)``: frequency [rad/s] (0.5) and damping (the
        paper omits it; 0.7 by default).
    eps_max, t_delta : float
        RPE weight: largest RPE [rad] (50e-6) and averaging window [s] (3e-3).
    p_max, u_max : float
        Normalisation of the SADM torques [N m] (0.382) and of the PMA effort [N] (15).
    gamma_u : float
        Bound of the hard effort constraint ``Z_c < gamma_u`` (1).
    effort : str
        ``"command"``: the effort is the PMA force command u; ``"transmitted"``: the force
        the actuator transmits to the structure, ``u - k x - d x'`` (x the proof-mass stroke).
    """

    omega_acs: float = 0.1
    xi_acs: float = 0.7
    omega_pma: float = 0.5
    xi_pma: float = 0.7
    eps_max: float = 50e-6
    t_delta: float = 3e-3
    p_max: float = 0.382
    u_max: float = 15.0
    gamma_u: float = 1.0
    effort: str = "command"

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name == "effort":
                continue
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) or not np.isfinite(value) or value <= 0:
                raise ValueError(f"LoopSettings.{f.name} must be a finite positive number, got {value!r}")
        if self.eps_max >= np.pi:  # an angle in rad: 50 (the paper's 50 urad in urad) would scale J_c by 1e-6, silently
            raise ValueError(f"LoopSettings.eps_max is the largest RPE in rad and must be below pi, got {self.eps_max!r}: "
                             "in microradians? (the paper's 50 urad is 50e-6)")
        if self.effort not in _EFFORT_KINDS:
            raise ValueError(f"LoopSettings.effort must be one of {_EFFORT_KINDS}, got {self.effort!r}")

    @classmethod
    def from_parameters(cls, params: dict | None = None, **overrides) -> "LoopSettings":
        """Settings from ``lib/trusscodesign/data/spacecraft/parameters.json`` (``closed_loop`` and ``choices``), then ``overrides``."""
        from ..model.spacecraft import load_parameters

        p = load_parameters() if params is None else params
        cl, ch = p["closed_loop"], p["choices"]
        base = {f.name: cl[f.name] for f in fields(cls) if f.name in cl}
        base.update(xi_pma=ch.get("xi_pma", cls.xi_pma), effort=ch.get("effort", cls.effort))
        unknown = sorted(set(overrides) - {f.name for f in fields(cls)})
        if unknown:
            raise ValueError(f"unknown LoopSettings fields {unknown}; allowed: {[f.name for f in fields(cls)]}")
        return cls(**{**base, **overrides})

    def replace(self, **changes) -> "LoopSettings":
        """A copy with some fields changed."""
        return replace(self, **changes)


def rpe_weight(settings: LoopSettings) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """State-space of ``F_RPE(s) = eps^-1 T s (T s + sqrt 12) / ((T s)^2 + 6 T s + 12)`` (SISO, 2 states).

    High-pass RPE filter of the paper (``T = t_delta``): 0 at DC, ``1 / eps_max`` at high frequency.
    """
    t, e = settings.t_delta, settings.eps_max
    a1, b1, b0 = np.sqrt(12.0) / t, 6.0 / t, 12.0 / t**2
    # (s^2 + a1 s) / (s^2 + b1 s + b0) = 1 + ((a1 - b1) s - b0) / (s^2 + b1 s + b0)
    return (np.array([[0.0, 1.0], [-b0, -b1]]), np.array([[0.0], [1.0]]), np.array([[-b0, a1 - b1]]) / e, np.array([[1.0 / e]]))


def pma_filter(settings: LoopSettings) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """State-space of ``F_PMA(s) = s / (s^2 + 2 xi_pma w_pma s + w_pma^2)`` (SISO, 2 states)."""
    w, xi = settings.omega_pma, settings.xi_pma
    return np.array([[0.0, 1.0], [-(w**2), -2 * xi * w]]), np.array([[0.0], [1.0]]), np.array([[0.0, 1.0]]), np.zeros((1, 1))


def acs_gains(inertia: ArrayLike, settings: LoopSettings) -> tuple[NDArray, NDArray]:
    """ACS gains ``k_p = w^2 diag(J)``, ``k_v = 2 xi w diag(J)`` [N m/rad, N m s/rad] from the 3x3 inertia J at P1."""
    j = np.asarray(inertia, dtype=float)
    if j.shape != (3, 3) or not np.all(np.isfinite(j)) or np.any(np.diag(j) <= 0):
        raise ValueError(f"inertia must be a finite 3x3 matrix with a positive diagonal [kg m^2], got {j!r}")
    w, xi = settings.omega_acs, settings.xi_acs
    return w**2 * np.diag(j).copy(), 2 * xi * w * np.diag(j).copy()


def _blkdiag_siso(mats: tuple[NDArray, NDArray, NDArray, NDArray], k: int) -> tuple[NDArray, ...]:
    return tuple(linalg.block_diag(*([m] * k)) for m in mats)


@lru_cache(maxsize=32)
def _filter_blocks(omega_pma: float, xi_pma: float, t_delta: float, eps_max: float) -> tuple[tuple[NDArray, ...], tuple[NDArray, ...]]:
    """``F_PMA`` on the 4 commands and ``F_RPE`` on the 2 LOS angles, block-diagonal state-space (read-only, cached: the
    same for every plant of a study, and a third of the cost of :func:`generalized_plant` to rebuild each time)."""
    settings = LoopSettings(omega_pma=omega_pma, xi_pma=xi_pma, t_delta=t_delta, eps_max=eps_max)
    blocks = (_blkdiag_siso(pma_filter(settings), 4), _blkdiag_siso(rpe_weight(settings), 2))
    for mats in blocks:
        for m in mats:
            m.setflags(write=False)
    return blocks


@dataclass
class GeneralizedPlant:
    """Generalized plant ``P`` of the synthesis at one parameter value (Delta channels optional).

    Inputs ``[w (n_delta); p~ (2); v (4)]``, outputs ``[z (n_delta); RPE (2); W~u (4); y (8)]``.

    Attributes
    ----------
    a, b, c, d : ndarray
        Real state-space matrices. States: the flexible states of the open-loop model, the
        ``rigid_rank`` rigid attitudes and rates, 8 PMA-filter and 4 RPE-weight states.
    n_delta : int
        Number of open Delta channels.
    rigid_rank : int
        Rank of the rigid part ``G_0`` of the position-level outputs (3 for a free spacecraft).
    dropped : dict
        Relative sizes of what the realisation leaves out: ``"rank"`` (the singular values of
        ``G_0`` below the rank threshold over the largest), ``"g1"`` (``||G_1|| / ||G_0||`` [s]; measured at 1.5, 2.139 and
        3 cm: about 1e-10 s on ``G_r_low`` and a residualisation residue of 1.1e-4 to 2.9e-4 s on ``G_r``, which shifts
        ``G_r``'s transfers by 1e-5 to 2e-4 relative from a naive build with integrators) and, for the transmitted
        effort, ``"stroke_feedthrough"``.
    settings : LoopSettings
    """

    a: NDArray
    b: NDArray
    c: NDArray
    d: NDArray
    n_delta: int
    rigid_rank: int
    dropped: dict = field(default_factory=dict)
    settings: LoopSettings = field(default_factory=LoopSettings)
    _passive_damping: float | None = field(default=None, repr=False, compare=False)  # cache of passive_damping()
    _passive_pole: complex | None = field(default=None, repr=False, compare=False)  # cache of passive_pole()

    N_P, N_V, N_RPE, N_U, N_Y = 2, 4, 2, 4, 8

    @property
    def n_exo(self) -> int:
        """Exogenous inputs ``[w; p~]``."""
        return self.n_delta + self.N_P

    @property
    def n_reg(self) -> int:
        """Regulated outputs ``[z; RPE; W~u]``."""
        return self.n_delta + self.N_RPE + self.N_U

    def slices(self) -> dict[str, slice]:
        """Row slices of the regulated outputs and column slices of the exogenous inputs."""
        nd = self.n_delta
        return {"z": slice(0, nd), "rpe": slice(nd, nd + 2), "effort": slice(nd + 2, nd + 6), "w": slice(0, nd), "p": slice(nd, nd + 2)}

    def _check_gain(self, gain: ArrayLike) -> NDArray:
        k = np.asarray(gain, dtype=float)
        if k.shape != (self.N_V, self.N_Y) or not np.all(np.isfinite(k)):
            raise ValueError(f"gain must be a finite {self.N_V}x{self.N_Y} matrix (PMA commands x accelerations), got shape {k.shape}")
        return k

    def input_names(self) -> list[str]:
        """Signal names of the inputs ``[w; p~; v]``.

        ``w_delta<i>``: the open Delta channels (normalised, in the order of the model's ``blocks``); ``pn_SP1``,
        ``pn_SP2``: the SADM torques over ``p_max`` (dimensionless); ``v_PMA1`` to ``v_PMA4``: the PMA commands [N]
        before the PMA filters.
        """
        return [f"w_delta{i}" for i in range(self.n_delta)] + ["pn_SP1", "pn_SP2"] + [f"v_PMA{i}" for i in range(1, 5)]

    def output_names(self) -> list[str]:
        """Signal names of the outputs ``[z; RPE; W~u; y]``.

        ``z_delta<i>``: the Delta channels; ``RPE_el``, ``RPE_az``: the LOS angles through the RPE weight and divided
        by ``eps_max`` (dimensionless: 1 is the requirement); ``Wu_PMA1`` to ``Wu_PMA4``: the PMA effort over
        ``u_max`` (dimensionless); the 8 measured accelerations of :data:`MEASUREMENTS` [m/s^2, rad/s^2].
        """
        return ([f"z_delta{i}" for i in range(self.n_delta)] + ["RPE_el", "RPE_az"] + [f"Wu_PMA{i}" for i in range(1, 5)]
                + MEASUREMENTS)

    def to_ss(self) -> ct.StateSpace:
        """``P`` as a ``control.StateSpace`` named ``"P"``, with the signal names of :meth:`input_names` and
        :meth:`output_names`.

        The realisation is this object's ``(a, b, c, d)``. For frequency responses prefer :meth:`freqresp` (a direct
        solve): python-control's own, through slycot, was measured 4e-4 of the largest entry off on a 180-state loop.
        """
        return ct.ss(self.a, self.b, self.c, self.d, inputs=self.input_names(), outputs=self.output_names(), name="P")

    def closed_loop(self, gain: ArrayLike) -> ct.StateSpace:
        """``F_l(P, K)`` for the static gain ``v = K y``, as a ``control.StateSpace``.

        Parameters
        ----------
        gain : array_like (4, 8)
            ``K_PMA``: PMA commands [N] per measured acceleration [m/s^2 or rad/s^2].

        Returns
        -------
        control.StateSpace
            Named ``"closed_loop"``, from ``[w; p~]`` to ``[z; RPE; W~u]`` with the names of :meth:`to_ss`; its
            matrices are :meth:`closed_loop_matrices` (frequency responses: see :meth:`to_ss`).
        """
        ne, nr = self.n_exo, self.n_reg
        return ct.ss(*self.closed_loop_matrices(gain), inputs=self.input_names()[:ne], outputs=self.output_names()[:nr],
                     name="closed_loop")

    def closed_loop_matrices(self, gain: ArrayLike) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """``(A, B, C, D)`` of ``F_l(P, K)`` (:meth:`closed_loop`), for the numerical loops that need no object."""
        k = self._check_gain(gain)
        ne, nr = self.n_exo, self.n_reg
        kk = np.zeros((self.b.shape[1], self.c.shape[0]))
        kk[ne:, nr:] = k
        e = np.vstack([np.eye(ne), np.zeros((self.N_V, ne))])
        f = np.hstack([np.eye(nr), np.zeros((nr, self.N_Y))])
        return close_static(self.a, self.b, self.c, self.d, kk, e, f, np.zeros((nr, ne)))

    def closed_loop_poles(self, gain: ArrayLike) -> NDArray[np.complex128]:
        """Poles of the closed loop with the static gain [rad/s]."""
        k = self._check_gain(gain)
        ne, nr = self.n_exo, self.n_reg
        d_yv = self.d[nr:, ne:]
        if np.any(d_yv):
            return np.linalg.eigvals(self.closed_loop_matrices(k)[0])
        return np.linalg.eigvals(self.a + self.b[:, ne:] @ k @ self.c[nr:, :])

    def passive_damping(self) -> float:
        """Smallest damping ratio of the closed-loop poles with the PMAs passive (K = 0), cached."""
        if self._passive_damping is None:
            self.passive_pole()
        return cast(float, self._passive_damping)  # set by passive_pole()

    def passive_pole(self) -> complex:
        """The least damped closed-loop pole with the PMAs passive (K = 0) [rad/s], cached (sets
        :meth:`passive_damping`)."""
        if self._passive_pole is None:
            lam = self.closed_loop_poles(np.zeros((self.N_V, self.N_Y)))
            zeta = -lam.real / np.abs(lam)
            self._passive_pole = complex(lam[np.argmin(zeta)])
            self._passive_damping = float(zeta.min())
        return self._passive_pole

    def passive_damping_bound(self, near: complex, iterations: int = 8) -> float:
        """An upper bound on :meth:`passive_damping`, much cheaper to compute when the plant is new.

        The damping ratio of the passive pole nearest ``near`` [rad/s] (e.g. another scenario's
        :meth:`passive_pole`), found by shifted inverse iteration (one complex LU of ``A - near I``, about a tenth of
        the cost of all the poles), raised by the relative margin ``PASSIVE_BOUND_MARGIN`` that covers the error of
        the converged eigenvalue. Every pole's damping bounds the smallest one from above. Returns the exact value if
        it is cached, and ``inf`` (no bound) if the iteration does not converge to a residual
        ``|A x - lambda x| <= 1e-9 |lambda|`` within ``iterations``.
        """
        if self._passive_damping is not None:
            return self._passive_damping
        if np.any(self.d[self.n_reg:, self.n_exo:]):
            return np.inf  # the passive poles are those of the loop closed through D_yv, not of A: no shortcut
        a = self.a
        x = np.random.default_rng(0).standard_normal((a.shape[0],)).astype(complex)
        with np.errstate(all="ignore"):
            lu = linalg.lu_factor(a - complex(near) * np.eye(a.shape[0]), check_finite=False)
            for _ in range(iterations):
                y = linalg.lu_solve(lu, x, check_finite=False)
                if not np.all(np.isfinite(y)) or not np.any(y):
                    return np.inf
                x = y / np.linalg.norm(y)
                ax = a @ x
                lam = np.vdot(x, ax)
                if lam != 0 and np.linalg.norm(ax - lam * x) <= 1e-9 * abs(lam):
                    return float(-lam.real / abs(lam)) * (1.0 + PASSIVE_BOUND_MARGIN)
        return np.inf

    def freqresp(self, omega: ArrayLike) -> NDArray[np.complex128]:
        """Frequency response of P, shape ``(outputs, inputs, len(omega))`` (direct solve per frequency)."""
        return frequency_response(self.a, self.b, self.c, self.d, omega)


def generalized_plant(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike, inertia_p1: ArrayLike,
                      settings: LoopSettings | None = None, n_delta: int = 0, pma_stiffness: float | None = None,
                      pma_damping: float | None = None, rank_rtol: float = 1e-8, min_pole: float = 1e-3) -> GeneralizedPlant:
    """Build the generalized plant ``P`` from the open-loop acceleration model.

    Parameters
    ----------
    a, b, c, d : array_like
        Open-loop model with inputs ``[w (n_delta); spacecraft.INPUTS]`` and outputs
        ``[z (n_delta); spacecraft.OUTPUTS]``, without poles at s = 0 (spurious slow poles removed,
        e.g. ``G_r_low`` or ``G_r``).
    inertia_p1 : array_like (3, 3)
        Rigid inertia of the whole spacecraft at P1 [kg m^2] used for the ACS gains (nominal).
    settings : LoopSettings, optional
        Defaults: :meth:`LoopSettings.from_parameters`.
    n_delta : int
        Number of Delta channels first in the model's inputs and outputs (kept open in P).
    pma_stiffness, pma_damping : float, optional
        PMA spring k [N/m] and damper d [N s/m], for ``settings.effort = "transmitted"`` (default: the ``pma``
        entry of ``lib/trusscodesign/data/spacecraft/parameters.json``, 10 and 1.4).
    rank_rtol : float
        Singular values of ``G_0`` below ``rank_rtol`` times the largest are treated as zero (in (0, 1)).
    min_pole : float
        Smallest accepted pole modulus of A [rad/s]; 0 skips the check (an eigenvalue computation), for callers
        that build many plants from one checked model.

    Raises
    ------
    ValueError
        If A has a pole at s = 0 (remove the spurious slow poles first), the model does not
        have the spacecraft's inputs and outputs, or it has no rigid part (``G_0 = 0``).
    """
    from ..model.spacecraft import INPUTS, OUTPUTS, load_parameters

    settings = settings or LoopSettings.from_parameters()
    a, b, c, d = (np.asarray(m, dtype=float) for m in (a, b, c, d))
    if isinstance(n_delta, bool) or not isinstance(n_delta, (int, np.integer)) or n_delta < 0:
        raise ValueError(f"n_delta must be a non-negative integer (the open Delta channels), got {n_delta!r}")
    if not 0.0 < rank_rtol < 1.0:
        raise ValueError(f"rank_rtol must be in (0, 1), got {rank_rtol!r}")
    check_option("min_pole", min_pole, 0.0, np.inf, open_high=True)
    if not all(np.all(np.isfinite(m)) for m in (a, b, c, d)):
        raise ValueError("A, B, C and D must be finite (no NaN or inf)")
    nd = int(n_delta)
    n = a.shape[0] if a.ndim == 2 else -1
    if d.shape != (nd + len(OUTPUTS), nd + len(INPUTS)) or a.shape != (n, n) or b.shape != (n, d.shape[1]) or c.shape != (d.shape[0], n):
        raise ValueError(f"the open-loop model must have {nd} + {len(INPUTS)} inputs and {nd} + {len(OUTPUTS)} outputs and "
                         f"consistent A, B, C, D; got A {a.shape}, B {b.shape}, C {c.shape}, D {d.shape}")
    transmitted = settings.effort == "transmitted"
    if transmitted:
        pma = load_parameters()["pma"] if pma_stiffness is None or pma_damping is None else {}
        k_pma = float(pma["stiffness"] if pma_stiffness is None else pma_stiffness)
        d_pma = float(pma["damping"] if pma_damping is None else pma_damping)
        for name, value in (("pma_stiffness", k_pma), ("pma_damping", d_pma)):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a finite positive number [N/m, N s/m], got {value!r}")
    lam = np.linalg.eigvals(a) if n and min_pole > 0 else np.zeros(0)
    if lam.size and np.min(np.abs(lam)) < min_pole:
        raise ValueError(f"A has a pole at |s| = {np.min(np.abs(lam)):.1e} rad/s < min_pole = {min_pole:g}: remove the spurious "
                         "slow poles first (trusscodesign.model.reduction.modal_reduction)")
    ins = list(range(nd)) + [nd + INPUTS.index(s) for s in ("p_SP1", "p_SP2", *(f"W_P1_{r}" for r in ROT), *EFFORTS)]
    rows = lambda names: [nd + OUTPUTS.index(s) for s in names]  # noqa: E731
    acc = list(range(nd)) + rows(MEASUREMENTS)
    pos = rows(["LOS_el", "LOS_az", *(f"a_P1_{r}" for r in ROT)])
    stroke = rows([f"x_PMA{i}" for i in range(1, 5)])
    b_s = b[:, ins]
    # Rigid part of the position-level outputs and its minimal realisation (double integrators).
    # one LU of A for A^-1 B, C A^-1 and C A^-2 (the worst-case search builds a plant per evaluation)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", linalg.LinAlgWarning)  # an exact zero pivot: the ValueError below says it
        lu = linalg.lu_factor(a, check_finite=False)
    if np.any(np.diag(lu[0]) == 0):
        raise ValueError("A is singular (a pole at s = 0): remove the spurious slow poles first (trusscodesign.model.reduction.modal_reduction)")
    a_inv_b = linalg.lu_solve(lu, b_s, check_finite=False)
    c_pos1 = linalg.lu_solve(lu, c[pos].T, trans=1, check_finite=False).T  # C A^-1
    c_pos2 = linalg.lu_solve(lu, c_pos1.T, trans=1, check_finite=False).T  # C A^-2
    g0 = d[np.ix_(pos, ins)] - c[pos] @ a_inv_b
    g1 = -c_pos2 @ b_s
    u_, sv, vt = np.linalg.svd(g0)
    if not sv[0] > 0:
        raise ValueError("the model has no rigid part (G_0 = D - C A^-1 B is zero on the LOS and P1 rotations): the ACS "
                         "needs a free spacecraft model")
    r = int(np.sum(sv > rank_rtol * sv[0]))
    dropped = {"rank": float(sv[r] / sv[0]) if r < sv.size else 0.0, "g1": float(np.linalg.norm(g1, 2) / sv[0])}
    p1 = slice(2, 5)
    n_rows = len(acc) + 5 + 3 + (8 if transmitted else 0)
    # Structure block S: states [x; q; v], inputs [w, p, W_rot, u], outputs [z, y, theta_LOS, theta_P1, omega_P1 (, x, x')].
    a_s = linalg.block_diag(a, np.block([[np.zeros((r, r)), np.eye(r)], [np.zeros((r, 2 * r))]]))
    bb = np.vstack([b_s, np.zeros((r, len(ins))), sv[:r, None] * vt[:r]])
    cc = np.zeros((n_rows, n + 2 * r))
    dd = np.zeros((n_rows, len(ins)))
    na = len(acc)
    cc[:na, :n], dd[:na] = c[acc], d[np.ix_(acc, ins)]
    cc[na : na + 5, :n], cc[na : na + 5, n : n + r] = c_pos2, u_[:, :r]
    cc[na + 5 : na + 8, :n], cc[na + 5 : na + 8, n + r :] = c_pos1[p1], u_[p1, :r]
    dd[na + 5 : na + 8] = c_pos2[p1] @ b_s
    if transmitted:
        # stroke x = C_x x + D_x u and its rate x' = C_x (A x + B u): the stroke has no feedthrough in a mechanical
        # model (a residualised model can leave a small D_x, kept in x; its rate D_x u' is dropped: measured)
        d_x = d[np.ix_(stroke, ins)]
        dc_x = d_x - c[stroke] @ a_inv_b
        dropped["stroke_feedthrough"] = float(np.linalg.norm(d_x, 2) / np.linalg.norm(dc_x, 2))
        if dropped["stroke_feedthrough"] > 1e-3:
            raise ValueError(f"the PMA stroke has a direct feedthrough ({dropped['stroke_feedthrough']:.1e} of its DC gain): the "
                             "transmitted force needs a model without it (reduce with a larger omega_max)")
        cc[na + 8 : na + 12, :n], dd[na + 8 : na + 12] = c[stroke], d_x
        cc[na + 12 : na + 16, :n] = c[stroke] @ a
        dd[na + 12 : na + 16] = c[stroke] @ b_s
    # Filters: F_PMA on the 4 commands, F_RPE on the 2 LOS angles.
    (fa, fb, fc, fd), (wa, wb, wc, wd) = _filter_blocks(settings.omega_pma, settings.xi_pma, settings.t_delta, settings.eps_max)
    big_a = linalg.block_diag(a_s, fa, wa)
    big_b = linalg.block_diag(bb, fb, wb)
    big_c = linalg.block_diag(cc, fc, wc)
    big_d = linalg.block_diag(dd, fd, wd)
    # Stacked inputs: [w (nd), p (2), W_rot (3), u (4) | v (4) | theta_LOS in (2)]
    # Stacked outputs: [z (nd), y (8), th_L (2), th_P1 (3), om_P1 (3) (, x, x') | u_F (4) | rpe (2)]
    n_in, n_out = big_b.shape[1], big_c.shape[0]
    i_p, i_w, i_u, i_v, i_th = nd, nd + 2, nd + 5, nd + 9, nd + 13
    o_y, o_thl, o_thp, o_om, o_x = nd, nd + 8, nd + 10, nd + 13, nd + 16
    o_uf, o_rpe = n_rows, n_rows + 4
    kp, kv = acs_gains(inertia_p1, settings)
    kk = np.zeros((n_in, n_out))
    kk[i_w : i_w + 3, o_thp : o_thp + 3] = -np.diag(kp)
    kk[i_w : i_w + 3, o_om : o_om + 3] = -np.diag(kv)
    kk[i_u : i_u + 4, o_uf : o_uf + 4] = np.eye(4)
    kk[i_th : i_th + 2, o_thl : o_thl + 2] = np.eye(2)
    n_exo, n_reg = nd + 2 + 4, nd + 2 + 4 + 8
    e = np.zeros((n_in, n_exo))
    e[:nd, :nd] = np.eye(nd)
    e[i_p : i_p + 2, nd : nd + 2] = settings.p_max * np.eye(2)
    e[i_v : i_v + 4, nd + 2 :] = np.eye(4)
    f = np.zeros((n_reg, n_out))
    f[:nd, :nd] = np.eye(nd)
    f[nd : nd + 2, o_rpe : o_rpe + 2] = np.eye(2)
    f[nd + 2 : nd + 6, o_uf : o_uf + 4] = np.eye(4) / settings.u_max
    if transmitted:
        # W~u = (u - k x - d x') / u_max
        f[nd + 2 : nd + 6, o_x : o_x + 4] = -k_pma * np.eye(4) / settings.u_max
        f[nd + 2 : nd + 6, o_x + 4 : o_x + 8] = -d_pma * np.eye(4) / settings.u_max
    f[nd + 6 :, o_y : o_y + 8] = np.eye(8)
    pa, pb, pc, pd = close_static(big_a, big_b, big_c, big_d, kk, e, f, np.zeros((n_reg, n_exo)))
    return GeneralizedPlant(pa, pb, pc, pd, nd, r, dropped, settings)
