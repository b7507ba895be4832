"""The trust-region step sub-problems: a linear program in the box (HiGHS), a second-order cone program in the box cut
by a ball (Clarabel), and the least-change restoration step.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linprog

__all__ = []


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
