"""The mass / worst-case pointing Pareto front over k section sides: a surrogate search on the truss-tolerant co-design.

Beyond the paper, whose design variable is one side h. A design is ``theta``, one section side per group of members
(:class:`trusscodesign.study.sizing.Grouping`). Its truss mass is exact and cheap (``sum c theta^2``); its worst-case
J_c is the truss-tolerant robust synthesis of :func:`trusscodesign.study.objective.evaluate_particle` from a cold start
(minutes). So the search models the pointing only: a Gaussian process (scikit-learn; Matern 5/2 with one length per
side, plus a noise term, since the synthesis is a local optimiser whose J_c scatters by a few per cent) on log J_c over
theta scaled to [0, 1]^k. Each next design maximises the expected growth of the dominated (mass, log J_c) area
(:func:`trusscodesign.study.pareto.expected_improvement`, the mass exact) times the probability that its synthesis
succeeds (a second process on the effort Z_c, a failed synthesis counted at 1.5 gamma_u), over random candidates and
perturbations of the front.

A generation proposes ``population`` designs per seed (the later ones with the earlier counted at their predicted mean:
the "kriging believer"), and the designs of all seeds are evaluated together by
:func:`trusscodesign.study.codesign.evaluate_swarm` (on Dask given a client; every finished evaluation saved at once in a
store keyed on all it depends on). Each seed's processes see its own evaluations and the shared ``prior`` (e.g. the
k = 1 evaluations of notebook 07, all sides equal): a seed's run does not depend on the other seeds, the number of
workers or an interruption, and a rerun replays its proposals and finds them in the store.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ndtr

from ..control.closedloop import LoopSettings
from ..control.synthesis import SynthesisOptions
from ..infra.checks import check_option
from ..infra.results import run_lock
from ..model import spacecraft
from . import codesign, pareto
from .objective import JC_LIMIT, M0_PAPER
from .sizing import Grouping

__all__ = ["FrontSearch", "check_search", "front", "lightest_at", "run_front_search", "theta_of", "valid"]

FAILED_EFFORT = 1.5  # Z_c / gamma_u given to a failed synthesis in the feasibility model


@dataclass
class FrontSearch:
    """What :func:`run_front_search` returns.

    Attributes
    ----------
    grouping : Grouping
    ref : (float, float)
        Reference point (mass [kg], J_c) of the hypervolume: the truss with every side at the top of the range, and
        :data:`trusscodesign.study.objective.JC_LIMIT`.
    prior : list of dict
        The evaluations every seed started from, each with ``theta`` [m].
    runs : dict int -> list of dict
        Each seed's own evaluations in order, each record of :func:`evaluate_particle` with ``theta`` [m], ``seed`` and
        ``generation`` (0: the initial Latin hypercube).
    wall_s : float
        Wall time of this call [s] (a resumed run: only what it did).
    evaluated : int
        Distinct evaluations this call ran (the others were found in the store).
    """

    grouping: Grouping
    ref: tuple[float, float]
    prior: list[dict]
    runs: dict[int, list[dict]] = field(default_factory=dict)
    wall_s: float = 0.0
    evaluated: int = 0

    def records(self, seed: int | None = None) -> list[dict]:
        """The prior and the evaluations of ``seed`` (None: of every seed)."""
        own = self.runs[seed] if seed is not None else [r for recs in self.runs.values() for r in recs]
        return self.prior + own


def theta_of(record: Mapping[str, Any], grouping: Grouping) -> NDArray[np.float64]:
    """The design vector [m] of an evaluation record: its ``h`` for every group, or each group's side from its sides by
    key (a KeyError if a group's key is missing)."""
    h = record["h"]
    if isinstance(h, Mapping):
        return np.array([float(h[keys[0]]) for _, keys in grouping.groups])
    return np.full(len(grouping.groups), float(h))


def valid(record: Mapping[str, Any], gamma_u: float) -> bool:
    """Whether an evaluation is a design: its synthesis succeeded, ``J_c <= JC_LIMIT`` and ``Z_c < gamma_u``."""
    return str(record.get("status", "")).startswith("ok") and record["J_c"] <= JC_LIMIT and record["Z_c"] < gamma_u


def front(records: Sequence[Mapping[str, Any]], gamma_u: float) -> list[Mapping[str, Any]]:
    """The valid (:func:`valid`) non-dominated records in (mass, J_c), by increasing mass."""
    ok = [r for r in records if valid(r, gamma_u)]
    if not ok:
        return []
    idx = pareto.nondominated([r["mass"] for r in ok], [r["J_c"] for r in ok])
    return [ok[i] for i in idx]


def lightest_at(records: Sequence[Mapping[str, Any]], j_c: float, gamma_u: float) -> Mapping[str, Any] | None:
    """The lightest valid record with ``J_c <= j_c`` (None if there is none)."""
    ok = [r for r in records if valid(r, gamma_u) and r["J_c"] <= j_c]
    return min(ok, key=lambda r: r["mass"]) if ok else None


def check_search(grouping: Grouping, seeds: Sequence[int], n_initial: object, population: object, generations: object,
                 resolution: object) -> None:
    """Check a search's sizes before any model is built: ``seeds`` distinct non-negative integers, ``n_initial`` >= 1
    (the Latin hypercube of each seed), ``population`` >= 1 (designs per seed and generation), ``generations`` >= 0,
    ``resolution`` [m] in [1e-7, 1e-3] (sides are evaluated on its multiples)."""
    if not isinstance(grouping, Grouping):
        raise TypeError(f"grouping must be a trusscodesign.study.sizing.Grouping (Grouping.of(groups)), got {type(grouping).__name__}")
    if isinstance(seeds, (str, bytes)) or not len(seeds) or len(set(seeds)) != len(seeds):
        raise ValueError(f"seeds must be a non-empty list of distinct non-negative integers, got {seeds!r}")
    for i, s in enumerate(seeds):
        check_option(f"seeds[{i}]", s, 0, integer=True)
    check_option("n_initial", n_initial, 1, integer=True)
    check_option("population", population, 1, integer=True)
    check_option("generations", generations, 0, integer=True)
    check_option("resolution", resolution, 1e-7, 1e-3, unit="m")


class _Scale:
    """theta [m] <-> u in [0, 1]^k, and theta on multiples of the resolution."""

    def __init__(self, low: float, high: float, resolution: float):
        self.low, self.high, self.resolution = low, high, resolution

    def unit(self, theta: ArrayLike) -> NDArray[np.float64]:
        return (np.asarray(theta, dtype=float) - self.low) / (self.high - self.low)

    def theta(self, u: ArrayLike) -> NDArray[np.float64]:
        t = self.low + np.clip(np.asarray(u, dtype=float), 0.0, 1.0) * (self.high - self.low)
        return np.clip(np.round(np.round(t / self.resolution) * self.resolution, 12), self.low, self.high)


def _fit(x: NDArray, y: NDArray, seed: int, kernel=None):
    """A Gaussian process on (x, y) (normalised y); with ``kernel`` given, its hyperparameters are kept (not refitted)."""
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import ConstantKernel, Matern, WhiteKernel

    if kernel is None:
        k = x.shape[1]
        kernel = (ConstantKernel(1.0, (1e-2, 1e2)) * Matern(np.full(k, 0.5), (0.02, 50.0), nu=2.5)
                  + WhiteKernel(1e-2, (1e-6, 0.5)))
        gp = GaussianProcessRegressor(kernel, normalize_y=True, n_restarts_optimizer=4, random_state=seed)
    else:
        gp = GaussianProcessRegressor(kernel, normalize_y=True, optimizer=None)
    with warnings.catch_warnings():  # a length at its bound is a flat direction, not an error
        warnings.simplefilter("ignore")
        return gp.fit(x, y)


def _candidates(rng: np.random.Generator, k: int, front_u: NDArray, n_random: int = 2048, n_local: int = 64) -> NDArray:
    """Random designs in [0, 1]^k and Gaussian perturbations (0.05 of the range) of the front's."""
    local = [np.clip(u + 0.05 * rng.standard_normal((n_local, k)), 0, 1) for u in front_u]
    return np.vstack([rng.random((n_random, k)), *local])


def _propose(data: list[dict], coef: NDArray, scale: _Scale, ref: tuple[float, float], gamma_u: float, n: int,
             seed: int, generation: int) -> list[NDArray]:
    """The ``n`` next designs [m] of one seed from its evaluations ``data`` (expected hypervolume improvement times the
    probability of a successful synthesis; kriging believer within the generation)."""
    theta = np.array([r["theta"] for r in data])
    k = theta.shape[1]
    u = scale.unit(theta)
    fin = np.array([np.isfinite(r["J_c"]) for r in data])
    xs, ys = u[fin], np.log(np.array([r["J_c"] for r in data])[fin])
    gp = _fit(xs, ys, seed)
    z = np.array([min(r["Z_c"] / gamma_u, FAILED_EFFORT) if np.isfinite(r["Z_c"]) and not str(r["status"]).startswith("failed")
                  else FAILED_EFFORT for r in data])
    gp_z = _fit(u, z, seed) if np.any(z >= 1.0) else None
    ok = np.array([valid(r, gamma_u) for r in data])
    pts = theta[ok]  # the designs (and, within a generation, the believed ones) the front is made of
    fm, fy = np.array([r["mass"] for r in data])[ok], np.log(np.array([r["J_c"] for r in data])[ok])
    rng = np.random.default_rng([seed, generation])
    seen = {tuple(t) for t in theta}
    chosen: list[NDArray] = []
    for _ in range(n):
        on_front = pts[pareto.nondominated(fm, fy)] if fm.size else pts
        cand = np.unique(scale.theta(_candidates(rng, k, scale.unit(on_front))), axis=0)
        cand = cand[[tuple(t) not in seen for t in cand]]
        cu = scale.unit(cand)
        mu, sd = gp.predict(cu, return_std=True)
        sd = np.maximum(sd, 1e-9)
        score = pareto.expected_improvement(cand**2 @ coef, mu, sd, fm, fy, (ref[0], np.log(ref[1])))
        if gp_z is not None:
            mz, sz = gp_z.predict(cu, return_std=True)
            score = score * ndtr((1.0 - mz) / np.maximum(sz, 1e-9))
        best = int(np.argmax(score)) if np.max(score) > 0 else int(np.argmax(sd))  # nothing to gain: learn the most
        chosen.append(cand[best])
        seen.add(tuple(cand[best]))
        # kriging believer: the chosen design counts at its predicted mean for the next ones of this generation
        xs, ys = np.vstack([xs, cu[best]]), np.append(ys, mu[best])
        gp = _fit(xs, ys, seed, kernel=gp.kernel_)
        pts, fm, fy = np.vstack([pts, cand[best]]), np.append(fm, cand[best] ** 2 @ coef), np.append(fy, mu[best])
    return chosen


def _initial(seed: int, k: int, n: int, scale: _Scale) -> list[NDArray]:
    """A seed's first generation: a Latin hypercube of ``n`` designs [m] on the resolution."""
    from scipy.stats import qmc

    return list(scale.theta(qmc.LatinHypercube(d=k, seed=seed).random(n)))


def run_front_search(grouping: Grouping, seeds: Sequence[int] = (0, 1, 2), n_initial: int = 4, population: int = 2,
                     generations: int = 5, prior: Sequence[Mapping[str, Any]] = (), client=None,
                     store: str | Path | None = None, settings: LoopSettings | None = None, params: dict | None = None,
                     m0: float = M0_PAPER, synthesis_options: SynthesisOptions | None = None, truss_tolerance: float = 0.02,
                     resolution: float = 1e-4, progress: bool = True, log: Callable[[str], Any] = print) -> FrontSearch:
    """The (mass, worst-case J_c) front over the sides of ``grouping``, by one surrogate search per seed.

    Parameters
    ----------
    grouping : Grouping
        The k groups whose sides are the design variables.
    seeds : sequence of int
        One search per seed (their spread is the uncertainty of what the search finds).
    n_initial : int
        Designs of each seed's first generation (a Latin hypercube of the range).
    population, generations : int
        Designs each seed proposes per generation, and the generations after the first: each seed makes
        ``n_initial + population * generations`` evaluations.
    prior : sequence of dict
        Evaluation records every seed starts from (e.g. notebook 07's, at one side h), made with the same settings,
        parameters, synthesis options and truss tolerance.
    client : dask.distributed.Client, optional
        Where the evaluations run (default: in this process, one at a time).
    store : path, optional
        JSON file of every evaluation under :func:`trusscodesign.study.codesign.evaluation_key`, written as each one
        finishes; a rerun (after a kill, or with more generations) reuses them.
    settings, params, m0, synthesis_options, truss_tolerance
        Of every evaluation (:func:`trusscodesign.study.objective.evaluate_particle`); default truss tolerance +-2 %.
    resolution : float
        Sides are evaluated on its multiples [m] (0.1 mm by default).
    progress : bool
        Progress bar of each generation's evaluations.
    log : callable
        Receives one line per generation and seed.

    Returns
    -------
    FrontSearch

    Raises
    ------
    ValueError, TypeError
        For a bad size, seed or resolution (:func:`check_search`), before any evaluation.
    """
    check_search(grouping, seeds, n_initial, population, generations, resolution)
    params = params or spacecraft.load_parameters()
    settings = settings or LoopSettings.from_parameters(params)
    codesign._check_batch([grouping.sides(np.full(len(grouping.groups), params["truss"]["h_range"][0]), params)], m0,
                          synthesis_options, params, truss_tolerance)
    low, high = params["truss"]["h_range"]
    scale, coef = _Scale(low, high, float(resolution)), grouping.mass_coefficients(params)
    k = len(grouping.groups)
    ref = (float(np.full(k, high) ** 2 @ coef), JC_LIMIT)
    prior_recs = [{**r, "theta": theta_of(r, grouping).tolist()} for r in prior]
    out = FrontSearch(grouping, ref, prior_recs, {int(s): [] for s in seeds})
    key = codesign.evaluation_key(settings, params, m0, synthesis_options, truss_tolerance)
    t0 = time.perf_counter()
    with run_lock(store) if store is not None else nullcontext():
        for generation in range(int(generations) + 1):
            proposed = {s: (_initial(s, k, int(n_initial), scale) if generation == 0 else
                            _propose(out.records(s), coef, scale, ref, settings.gamma_u, int(population), s, generation))
                        for s in out.runs}
            batch = [(s, t) for s, thetas in proposed.items() for t in thetas]
            sides = [grouping.sides(t, params) for _, t in batch]
            stored = codesign._read_partial(store, key)["records"] if store is not None else {}
            out.evaluated += len({codesign._tag((codesign._point(h), False)) for h in sides} - set(stored))
            recs = codesign.evaluate_swarm(sides, None, client, settings, params, m0, progress=progress,
                                           synthesis_options=synthesis_options, partial=store, partial_key=key,
                                           truss_tolerance=truss_tolerance)
            for (s, t), rec in zip(batch, recs):
                rec = {k_: v for k_, v in rec.items() if k_ != "shared_with"}
                out.runs[s].append({**rec, "theta": [float(v) for v in t], "seed": s, "generation": generation})
            for s in out.runs:
                best = lightest_at(out.records(s), 0.9, settings.gamma_u)
                hv = _hypervolume(out.records(s), ref, settings.gamma_u)
                log(f"generation {generation}/{generations}, seed {s}: {len(out.runs[s])} evaluations, hypervolume "
                    f"{hv:.3f} kg (log J_c); lightest at J_c <= 0.9: "
                    + (f"{best['mass']:.2f} kg at sides {np.round(100 * np.array(best['theta']), 3).tolist()} cm" if best else "none"))
    out.wall_s = time.perf_counter() - t0
    return out


def _hypervolume(records: Sequence[Mapping[str, Any]], ref: tuple[float, float], gamma_u: float) -> float:
    """Area dominated by the valid records in (mass [kg], log J_c), below ``ref`` (mass, J_c)."""
    ok = [r for r in records if valid(r, gamma_u)]
    if not ok:
        return 0.0
    return pareto.hypervolume([r["mass"] for r in ok], np.log([r["J_c"] for r in ok]), (ref[0], np.log(ref[1])))
