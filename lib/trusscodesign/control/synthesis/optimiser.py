"""The robust synthesis itself: the scenario set, its evaluation, the stabilisation and the trust-region sequential LP,
rounds of optimisation and worst-case search (:func:`synthesize`).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...model.lft import LFT
from ..closedloop import GeneralizedPlant, LoopSettings
from ..modalloop import ModalLoop
from .options import (
    _BAND,
    _COVER_TOL,
    _MARGIN,
    _MAX_UNSTABLE,
    _MIN_DECAY,
    _RADIUS0,
    _SEARCH_DAMPING,
    _STALL_STEPS,
    SynthesisOptions,
)
from .peaks import GROUPS, LoopPeaks, _Eigen, _eigen, loop_peaks, peak_gradient
from .scenarios import Scenario, default_scenarios, plant_at
from .search import WorstCase, _merge, worst_case
from .steps import _least_change, _lp
from .threads import _n_workers, _workers

__all__ = ['NOT_STABILISED', 'SynthesisResult', 'synthesize']


# progress: a line per round (INFO) and per accepted step (DEBUG); enable with logging.getLogger("trusscodesign").setLevel(...)
logger = logging.getLogger(__name__)


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
