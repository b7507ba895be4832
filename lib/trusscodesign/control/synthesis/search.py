"""The worst-case search over the uncertainty box: a grid of corners and panel angles, then Nelder-Mead refinements.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import minimize

from ...infra.checks import check_option as _check_option
from ...model.lft import LFT
from ..closedloop import LoopSettings
from .peaks import GROUPS, LoopPeaks, loop_peaks
from .scenarios import Scenario, plant_at, search_candidates
from .threads import _workers

__all__ = ['WorstCase', 'worst_case']


# ----------------------------------------------------------------------------- worst case over the box
@dataclass
class WorstCase:
    """Worst case over the uncertainty box found by a search: value, scenario and peak frequency per group."""

    value: dict[str, float]
    scenario: dict[str, Scenario]
    omega: dict[str, float]
    evaluations: int
    unstable: list[Scenario] = field(default_factory=list)


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
