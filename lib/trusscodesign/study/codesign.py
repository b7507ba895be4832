"""Structure/control co-design over the beam section side h: the particle swarm on the nested objective, in parallel.

Paper: "Co-design optimization architecture" and "Co-design optimization results". Each particle is one evaluation of
the objective ``f^n(h)`` (:func:`trusscodesign.study.objective.evaluate_particle`), its synthesis warm-started from the
previous iteration's best particle (the paper's Step 3) or cold. Particles of an iteration are evaluated in parallel
by Dask (:func:`evaluate_swarm`): a local cluster by default, or any scheduler (e.g. dask-jobqueue on Slurm); every
finished evaluation is saved at once, and a grid of the objective (:func:`evaluate_grid`) shares them.
"""

from __future__ import annotations

import json
import os
import time
import warnings
from collections.abc import Mapping, Sequence
from contextlib import nullcontext
from pathlib import Path
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..model import spacecraft
from ..control import synthesis
from ..infra.checks import check_option, check_real
from ..control.closedloop import LoopSettings
from ..infra.results import normalise_key, read_keyed, run_lock, write_json
from ..control.synthesis import SynthesisOptions
from .cluster import as_finished
from .objective import CODESIGN_OPTIONS, M0_PAPER, evaluate_particle, lost_evaluation, objective_value, tolerance_shifts

__all__ = ["check_study", "grid_key", "evaluate_swarm", "evaluate_grid", "partial_path", "evaluations_path", "evaluation_key",
           "on_resolution", "START_RULES", "distinct_evaluations", "evaluation_counts", "run_codesign"]


def _check_synthesis_options(options: object) -> None:
    """A TypeError unless ``options`` are None (:data:`CODESIGN_OPTIONS`) or a SynthesisOptions: checked once, before any
    particle."""
    if options is not None and not isinstance(options, SynthesisOptions):
        raise TypeError(f"synthesis_options must be a trusscodesign.control.synthesis.SynthesisOptions (or None: "
                        f"CODESIGN_OPTIONS), got {type(options).__name__}")


def _check_batch(hs: Sequence[float | Mapping[str, float]], m0: float, synthesis_options: object, params: dict | None,
                 truss_tolerance: float = 0.0) -> None:
    """Check what every particle of a batch would otherwise fail on, before any is evaluated: each h a section side in
    metres inside the design range (:func:`trusscodesign.study.design.models_at` refuses the others), or sides by key
    each inside it, ``m0``, the synthesis options and the truss tolerance."""
    from .design import in_design_range

    low, high = (params or spacecraft.load_parameters())["truss"]["h_range"]
    sides = [v for h in hs for v in (h.values() if isinstance(h, Mapping) else [h])] if len(hs) else []
    h = np.asarray(sides, dtype=float)
    if h.ndim != 1 or not h.size or not np.all(np.isfinite(h)) or not all(in_design_range(float(v), params) for v in h):
        raise ValueError(f"hs must be a non-empty list of section sides in metres (or of sides by key) in the design range "
                         f"[{low}, {high}], got {hs!r}")
    objective_value(1.0, 0.0, m0)  # m0: a ValueError now, not after every particle's synthesis
    _check_synthesis_options(synthesis_options)
    tolerance_shifts(truss_tolerance)


def evaluate_swarm(hs: Sequence[float | Mapping[str, float]], gain0: ArrayLike | None, client=None, settings: LoopSettings | None = None,
                   params: dict | None = None, m0: float = M0_PAPER, fail_particles: Sequence[int] = (), progress: bool = True,
                   synthesis_options: SynthesisOptions | None = None,
                   scenarios0: Sequence[Sequence[float]] | None = None, partial: str | Path | None = None,
                   partial_key: dict | None = None, truss_tolerance: float = 0.0) -> list[dict]:
    """Evaluate the particles ``hs`` [m] (in parallel on ``client`` if given), in the order of ``hs``; a particle is a
    section side, or sides by key (:func:`evaluate_particle`).

    A worker that dies is retried by Dask (up to its ``distributed.scheduler.allowed-failures``, 3 by default); a
    particle whose evaluation ends its worker every time, run again alone, is a failed particle (:func:`lost_evaluation`)
    and the run goes on. An evaluation that raises (a programming error, see :func:`evaluate_particle`) is not retried:
    it stops the batch with its traceback, after the finished evaluations are saved.
    The results do not depend on the number of workers (each evaluation is deterministic and single-threaded). Particles at the same h (e.g. several clamped to
    a bound of the range) share one evaluation: with the same warm start the result is the same.
    ``fail_particles`` injects failures (tests).

    With ``partial`` (a JSON file) every finished evaluation is saved at once with ``partial_key`` (what the
    evaluations depend on); a call with the same key reuses them, so an interrupted batch loses only the
    evaluations that were running. The file also accumulates the wall time spent (``time_s``).
    ``truss_tolerance``: see :func:`evaluate_particle`.
    """
    from tqdm.auto import tqdm

    _check_batch(hs, m0, synthesis_options, params, truss_tolerance)
    params = params or spacecraft.load_parameters()  # read here, once: the workers evaluate with these, not their own file's
    gain0 = None if gain0 is None else np.asarray(gain0, dtype=float)
    kw: dict[str, Any] = dict(settings=settings, params=params, m0=m0, synthesis_options=synthesis_options, scenarios0=scenarios0,
                              truss_tolerance=truss_tolerance)
    keys = [(_point(h), i in fail_particles) for i, h in enumerate(hs)]
    unique = list(dict.fromkeys(keys))
    saved = _read_partial(partial, partial_key)
    results = {k: saved["records"][_tag(k)] for k in unique if _tag(k) in saved["records"]}
    todo = [k for k in unique if k not in results]
    t0 = time.perf_counter()

    def finished(key: tuple[_Point, bool], rec: dict) -> None:
        results[key] = rec
        bar.update()
        if partial is not None:
            saved["records"][_tag(key)] = rec
            write_json(partial, {"key": saved["key"], "records": saved["records"],
                                 "time_s": saved["time_s"] + time.perf_counter() - t0})

    bar = tqdm(total=len(unique), initial=len(results), desc="particles", disable=not progress, leave=False)
    if client is None:
        for h, fail in todo:
            finished((h, fail), evaluate_particle(_side(h), gain0, fail=fail, **kw))
    else:
        from dask.distributed import KilledWorker

        futures = {client.submit(evaluate_particle, _side(h), gain0, fail=fail, pure=False, **kw): (h, fail)
                   for h, fail in todo}
        lost = []
        for fut in as_finished(client, futures):
            try:
                finished(futures[fut], fut.result())
            except KilledWorker:  # its workers died: this particle's doing, or another's
                lost.append(futures[fut])
        # Dask blames every task a dying worker held, so a particle that kills its worker takes the others queued there
        # with it: each lost particle runs again alone, and only one that still ends its worker is a failed particle
        for h, fail in lost:
            try:
                alone = client.submit(evaluate_particle, _side(h), gain0, fail=fail, pure=False, **kw)
                rec = next(as_finished(client, [alone])).result()
            except KilledWorker as exc:
                rec = lost_evaluation(_side(h), f"the evaluation ended its worker every time (KilledWorker: {exc})", params, m0)
            finished((h, fail), rec)  # saved in the partial file: a resume does not run it again
    bar.close()
    first = {k: i for i, k in reversed(list(enumerate(keys)))}
    return [dict(results[k], shared_with=first[k]) if first[k] != i else results[k] for i, k in enumerate(keys)]


_Point = float | tuple[tuple[str, float], ...]


def _point(h: float | Mapping[str, float]) -> _Point:
    """A particle as a hashable value: h [m], or its sides by key as sorted (key, side) pairs."""
    return tuple(sorted((str(k), float(v)) for k, v in h.items())) if isinstance(h, Mapping) else float(h)


def _side(point: _Point) -> float | dict[str, float]:
    """The particle of :func:`_point` as :func:`evaluate_particle` takes it."""
    return dict(point) if isinstance(point, tuple) else point


def _tag(key: tuple[_Point, bool]) -> str:
    """JSON key of an evaluation: h to 17 digits (or the sorted sides by key) and whether a failure is injected."""
    return f"{key[0]!r}|{key[1]}"


def _read_partial(path: str | Path | None, key: dict | None) -> dict:
    """The evaluations saved by an interrupted :func:`evaluate_swarm` with the same key (none if another key)."""
    try:
        stored, key = read_keyed(path, key)
    except ValueError as exc:  # (read_json: damaged) only a cache of finished particles: recompute them rather than stop
        warnings.warn(f"ignoring the unreadable partial file {path} ({exc}): its particles are evaluated again", stacklevel=2)
        stored, key = None, normalise_key(key)
    return stored or {"key": key, "records": {}, "time_s": 0.0}


def partial_path(checkpoint: str | Path) -> Path:
    """File of the finished evaluations of the iteration under way, next to a swarm checkpoint."""
    checkpoint = Path(checkpoint)
    return checkpoint.with_name(checkpoint.stem + ".partial.json")


def evaluations_path(checkpoint: str | Path) -> Path:
    """File of every evaluation of a swarm started cold (``start="cold"``), next to its checkpoint: kept after the run,
    so that the grid of the same objective and a rerun read it."""
    checkpoint = Path(checkpoint)
    return checkpoint.with_name(checkpoint.stem + ".evaluations.json")


#: How a particle's synthesis starts: "previous_best" (the paper's Step 3: from the gain and scenario set of the previous
#: iteration's best particle) or "cold" (from all gains at -1 and the default scenarios, so that the evaluation is a function
#: of h alone and a particle at an h evaluated before, by the swarm or by the grid, reuses it).
START_RULES = ("previous_best", "cold")


def evaluation_key(settings: LoopSettings | None, params: dict | None, m0: float = M0_PAPER,
                   synthesis_options: SynthesisOptions | None = None, truss_tolerance: float = 0.0) -> dict:
    """What a cold-started evaluation of h depends on besides h (the key of :func:`evaluations_path`'s file, as
    :func:`evaluate_swarm`'s ``partial_key``): the objective (loop settings, spacecraft parameters, model, m0, truss
    tolerance), the synthesis options and version. A grid evaluated under this key shares its evaluations with the swarm."""
    return {"start": "cold", "objective": _objective_key(settings, params, m0, truss_tolerance),
            "options": _options_key(synthesis_options), "algorithm": synthesis.ALGORITHM}


def on_resolution(h: float, resolution: float | None, h_range: Sequence[float]) -> float:
    """``h`` [m] rounded to the nearest multiple of ``resolution`` [m] (None: unchanged), kept in ``h_range``: where the
    swarm evaluates a position, and where a grid sharing its evaluations must put its points (the same float)."""
    if resolution is None:
        return float(h)
    return float(np.clip(round(round(h / resolution) * resolution, 12), h_range[0], h_range[1]))


def evaluate_grid(hs: Sequence[float], client=None, settings: LoopSettings | None = None, cache: str | Path | None = None,
                  key: dict | None = None, chunk: int = 4, progress: bool = True, **kwargs) -> tuple[list[dict], float]:
    """The nested objective at every h of a grid [m], each from a cold start (all gains at -1), resumable.

    Parameters
    ----------
    hs : sequence of float
        Section sides [m].
    client : dask.distributed.Client, optional
        Where the evaluations run (see :func:`evaluate_swarm`).
    settings : LoopSettings, optional
    cache : path, optional
        JSON file written after every ``chunk`` evaluations with ``key``; a rerun with the same ``key`` (and
        number of points) evaluates only the missing points, so an interrupted grid loses at most one chunk.
    key : dict, optional
        What the records depend on: a cache with another key is recomputed. Default: :func:`grid_key` (the grid, the
        settings, the synthesis options and version, the parameters' fingerprint, the model's version) and the other
        ``kwargs``. A cache whose records
        are at other h than ``hs`` is refused whatever the key.
    chunk : int
        Evaluations between two saves (a multiple of the number of workers keeps them busy).
    **kwargs
        Passed to :func:`evaluate_swarm`.

    Returns
    -------
    records : list of dict
        One per h, in the order of ``hs``.
    time_s : float
        Wall time spent evaluating, summed over the calls that did it [s].

    Raises
    ------
    ValueError
        If ``hs`` is empty or holds a section side outside the design range [m], or ``chunk`` < 1; also for a bad ``m0``
        or ``synthesis_options``, before any point is evaluated.
    """
    _check_batch(hs, kwargs.get("m0", M0_PAPER), kwargs.get("synthesis_options"), kwargs.get("params"), kwargs.get("truss_tolerance", 0.0))
    check_option("chunk", chunk, 1, integer=True)
    h = np.asarray(hs, dtype=float)
    kwargs["params"] = kwargs.get("params") or spacecraft.load_parameters()  # read once, here: every worker gets these
    if key is None:
        key = grid_key(hs, settings or LoopSettings.from_parameters(), kwargs.get("synthesis_options"), kwargs["params"])
        key["kwargs"] = {k: v for k, v in kwargs.items() if k != "params"}
    # one run at a time on a grid cache: another live run holding it stops this one at once, naming it
    with run_lock(cache) if cache is not None else nullcontext():
        stored, key = read_keyed(cache, key)
        records: list[dict | None] = [None] * len(hs)
        time_s = 0.0
        if stored is not None and len(stored.get("records", [])) == len(hs):  # resume
            records, time_s = stored["records"], float(stored.get("time_s", 0.0))
            other = [(i, r["h"]) for i, r in enumerate(records) if r is not None and float(r["h"]) != float(h[i])]
            if other:
                raise ValueError(f"the grid cache {cache} holds records at other h (e.g. {other[0][1]!r} m for "
                                 f"{float(h[other[0][0]])!r} m) under the same key: pass another cache path or a key that names the grid")
        todo = [i for i, r in enumerate(records) if r is None]
        for start in range(0, len(todo), chunk):
            idx = todo[start:start + chunk]
            t0 = time.perf_counter()
            done = evaluate_swarm([hs[i] for i in idx], None, client, settings, progress=progress, **kwargs)
            time_s += time.perf_counter() - t0
            for i, rec in zip(idx, done):  # (shared_with: evaluate_swarm's index within the chunk, made the grid's)
                records[i] = rec if "shared_with" not in rec else dict(rec, shared_with=idx[rec["shared_with"]])
            if cache is not None:
                write_json(cache, {"key": key, "records": records, "time_s": time_s})
        return cast(list[dict], records), time_s  # every record is filled by now


def grid_key(hs: Sequence[float], settings: LoopSettings, synthesis_options: SynthesisOptions | None = None,
             params: dict | None = None, truss_tolerance: float = 0.0) -> dict:
    """The key of a stored grid of the objective (notebook 07's ``07_grid*.json``, :func:`evaluate_grid`'s ``key``):
    the section sides [m], the loop settings, the synthesis options and version, the spacecraft parameters'
    fingerprint (:func:`trusscodesign.model.spacecraft.parameters_fingerprint`) and the model's version
    (:data:`trusscodesign.model.spacecraft.MODEL`), and the truss tolerance when there is one; a grid stored under another key
    is recomputed."""
    key = {"h": [float(h) for h in hs], "settings": settings.__dict__, "synthesis": _options_key(synthesis_options),
           "algorithm": synthesis.ALGORITHM, "parameters": spacecraft.parameters_fingerprint(params), "model": spacecraft.MODEL}
    return {**key, **_tolerance_entry(truss_tolerance)}


def _tolerance_entry(truss_tolerance: float) -> dict[str, float]:
    """The truss tolerance as a key entry: none for the paper's recipe (0), so that the keys of the runs stored before
    the tolerance existed still match."""
    tolerance_shifts(truss_tolerance)  # checked
    return {"truss_tolerance": float(truss_tolerance)} if truss_tolerance else {}


def _objective_key(settings: LoopSettings | None, params: dict | None, m0: float, truss_tolerance: float = 0.0) -> dict:
    """What f^n depends on besides h and the synthesis: the loop settings, the spacecraft parameters
    (:func:`trusscodesign.model.spacecraft.parameters_fingerprint`, of the package's parameters when ``params`` is None), the
    model's version (:data:`trusscodesign.model.spacecraft.MODEL`) and m0; stored in checkpoints and partial files, so that a run is never resumed with another objective."""
    digest = spacecraft.parameters_fingerprint(params)
    # settings=None is what trusscodesign.study.design.robust_design then takes, the data file's settings: stored resolved, so that a run
    # with None and one with those settings given are the same objective
    resolved = LoopSettings.from_parameters() if settings is None else settings
    key = {"settings": resolved.__dict__, "params_sha256": digest, "model": spacecraft.MODEL, "m0": float(m0),
           **_tolerance_entry(truss_tolerance)}
    return json.loads(json.dumps(key, default=str))  # as it reads back from a checkpoint


def _same_objective(stored: dict, objective: dict) -> bool:
    """Whether a checkpoint's objective key is ``objective`` (:func:`_objective_key`); checkpoints written before
    2026-12-05 stored ``settings=None`` unresolved."""
    if stored.get("settings") is None:
        stored = {**stored, "settings": _objective_key(None, None, 0.0)["settings"]}
    return stored == objective


def _changes(stored: dict, objective: dict) -> str:
    """What differs between a stored objective key and this run's, in words."""
    words = {"params_sha256": "the spacecraft parameters (their fingerprint)", "m0": "m0 [kg]", "truss_tolerance": "the truss tolerance"}
    out = []
    for k in sorted(set(stored) | set(objective)):
        old, new = stored.get(k), objective.get(k)
        if k == "settings" and isinstance(old, dict) and isinstance(new, dict):
            out += [f"settings.{n}: {old.get(n)!r} stored, {new.get(n)!r} now" for n in sorted(set(old) | set(new)) if old.get(n) != new.get(n)]
        elif old != new:
            out.append(f"{words.get(k, k)}: {old!r} stored, {new!r} now")
    return "; ".join(out) or "the same key"


def _options_key(options: SynthesisOptions | Mapping[str, Any] | None) -> dict[str, Any]:
    """Synthesis options as stored keys hold them (:meth:`SynthesisOptions.key`; None means :data:`CODESIGN_OPTIONS`);
    a stored key (a dict) as is."""
    if options is None:
        options = CODESIGN_OPTIONS
    return options.key() if isinstance(options, SynthesisOptions) else json.loads(json.dumps(dict(options), default=str))


def check_study(h_min: object, h_max: object, n_particles: object, n_iterations: object, n_grid: object,
                params: dict | None = None) -> None:
    """Check a co-design study's range and sizes before any model is built (notebook 07's first step).

    Parameters
    ----------
    h_min, h_max : float
        The design range of the section side h [m]; ``h_min < h_max``, both inside the spacecraft parameters'
        ``truss.h_range`` (the paper's [0.015, 0.03] m).
    n_particles, n_iterations : int
        Swarm size (at least 2) and iterations (at least 1).
    n_grid : int
        Points of the dense check of the objective over the range (at least 2).
    params : dict, optional
        Spacecraft parameters (default: the package's).

    Raises
    ------
    TypeError, ValueError
        Naming the parameter, its unit and the allowed range (and, for a value above 1 m, the likely centimetres).
    """
    low, high = (params or spacecraft.load_parameters())["truss"]["h_range"]
    for name, value in (("h_min", h_min), ("h_max", h_max)):
        check_real(name, value, "m")
        v = float(cast(float, value))
        if not (np.isfinite(v) and low - 1e-12 <= v <= high + 1e-12):
            hint = f" (in centimetres? {v:g} cm is {v / 100:g} m)" if 1.0 <= v <= 100.0 else ""
            raise ValueError(f"{name} = {value!r} m must lie in the design range [{low}, {high}] m of the spacecraft "
                             f"parameters (truss.h_range){hint}")
    if not float(cast(float, h_min)) < float(cast(float, h_max)):
        raise ValueError(f"h_min = {h_min!r} m must be below h_max = {h_max!r} m (an empty or reversed range)")
    check_option("n_particles", n_particles, 2, integer=True)
    check_option("n_iterations", n_iterations, 1, integer=True)
    check_option("n_grid", n_grid, 2, integer=True)


def _check_h_range(h_range: object, params: dict | None = None) -> None:
    """Raise a ValueError (TypeError for a non-sequence) unless ``h_range`` is ``(low, high)`` in metres with
    ``0 < low < high``, both finite, inside the design range of the spacecraft parameters (``truss.h_range``), where
    :func:`trusscodesign.study.design.models_at` builds models (outside it every particle would fail)."""
    if isinstance(h_range, (str, bytes)) or not isinstance(h_range, (Sequence, np.ndarray)):
        raise TypeError(f"h_range must be a pair (low, high) of section sides in metres, got {h_range!r}")
    pair = list(h_range)
    ok = len(pair) == 2 and all(isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) for v in pair)
    if not (ok and np.all(np.isfinite(pair)) and 0.0 < pair[0] < pair[1]):
        raise ValueError(f"h_range must be (low, high) in metres with 0 < low < high (the paper's (0.015, 0.03)), got {h_range!r}")
    low, high = (params or spacecraft.load_parameters())["truss"]["h_range"]
    if pair[0] < low - 1e-12 or pair[1] > high + 1e-12:
        raise ValueError(f"h_range {tuple(pair)} m leaves the design range [{low}, {high}] m of the spacecraft parameters: "
                         "widen truss.h_range in the parameters (lib/trusscodesign/data/spacecraft/parameters.json, or the params passed)")


def _checkpoint_mismatch(checkpoint: str | Path, n_particles: int, h_range: Sequence[float], seed: int, pso_rule: str,
                         synthesis_options: SynthesisOptions | None, objective: dict, start: str = "previous_best",
                         h_resolution: float | None = None) -> str | None:
    """Why the swarm checkpoint stored at ``checkpoint`` cannot be resumed by a run with these settings (None if it can):
    another synthesis version or options, another objective (:func:`_objective_key`: what changed is named), or
    another swarm (size, seed, range or rule), another start rule or h resolution."""
    from . import pso

    state = pso.load_state(checkpoint)
    found = state.extra.get("algorithm")
    if found != synthesis.ALGORITHM:
        return f"it was computed by the synthesis {found!r}, not the current {synthesis.ALGORITHM!r}"
    if _options_key(state.extra.get("options")) != _options_key(synthesis_options):
        return f"it was computed with synthesis options {state.extra.get('options')!r}, not {_options_key(synthesis_options)!r}"
    stored = state.extra.get("objective", {})
    if not _same_objective(stored, objective):
        return f"it was computed for another objective ({_changes(stored, objective)})"
    stored_start = (state.extra.get("start", "previous_best"), state.extra.get("h_resolution"))
    if stored_start != (start, h_resolution):
        return f"it was computed with start {stored_start[0]!r} and h_resolution {stored_start[1]!r}, not {start!r} and {h_resolution!r}"
    if not pso.same_run(state, n_particles, [h_range[0]], [h_range[1]], seed, pso_rule):
        return (f"it is from another swarm (n_particles={state.n}, seed={state.seed}, h range [{state.lower[0]}, "
                f"{state.upper[0]}] m, rule {state.rule!r})")
    return None


def distinct_evaluations(history: Sequence[Mapping[str, Any]], start: str = "previous_best") -> list[Mapping[str, Any]]:
    """The records of a swarm's distinct evaluations, one per evaluation however many particles shared it.

    With ``start="cold"`` an evaluation is a function of h: one per distinct h of the whole run (some may have been
    made by a grid of the same key). With ``"previous_best"`` particles share only within an iteration
    (:func:`evaluate_swarm`'s ``shared_with``).
    """
    if start not in START_RULES:
        raise ValueError(f"start must be one of {list(START_RULES)}, got {start!r}")
    return list({r["h"]: r for r in history}.values()) if start == "cold" else [r for r in history if "shared_with" not in r]


def evaluation_counts(history: Sequence[Mapping[str, Any]], start: str = "previous_best") -> dict[str, int]:
    """How a swarm's particles were evaluated: ``particles``, ``distinct`` evaluations (:func:`distinct_evaluations`),
    ``shared`` (particles that reused another's), ``failed`` (distinct evaluations failed or penalised) and
    ``failed_particles``."""
    own = distinct_evaluations(history, start)
    bad = lambda r: not str(r.get("status", "")).startswith("ok")  # noqa: E731
    return {"particles": len(history), "distinct": len(own), "shared": len(history) - len(own),
            "failed": sum(map(bad, own)), "failed_particles": sum(map(bad, history))}


def run_codesign(n_particles: int = 24, n_iterations: int = 20, h_range: tuple[float, float] = (0.015, 0.03), seed: int = 0,
                 client=None, checkpoint=None, settings: LoopSettings | None = None, params: dict | None = None,
                 m0: float = M0_PAPER, progress: bool = True, fail_particles: Sequence[tuple[int, int]] = (),
                 stop_after: int | None = None, log=print, synthesis_options: SynthesisOptions | None = None, pso_rule: str = "documented",
                 on_stale: str = "refuse", truss_tolerance: float = 0.0, start: str = "previous_best",
                 h_resolution: float | None = None):
    """The paper's particle-swarm co-design over h (Steps 1-4 per particle, the swarm in parallel).

    Parameters
    ----------
    n_particles, n_iterations : int
        Swarm size and iterations (paper: 24 and 20).
    h_range : tuple of float
        Design range of h [m] (paper: [0.015, 0.03]).
    seed : int
        Seed of the swarm (the run is reproducible, whatever the number of workers).
    client : dask.distributed.Client, optional
        Where the particles are evaluated (default: sequentially in this process).
    checkpoint : path, optional
        State file written after each iteration; an interrupted run resumes from it.
    fail_particles : sequence of (iteration, particle)
        Inject failures (tests): those evaluations raise inside the worker.
    stop_after : int, optional
        Stop after this many iterations (tests of the resume).
    log : callable
        Receives the one-line summary of each iteration.
    synthesis_options : SynthesisOptions, optional
        Of the synthesis of every particle (default :data:`CODESIGN_OPTIONS`).
    pso_rule : {"documented", "matlab"}
        MATLAB ``particleswarm``'s adaptive rules as documented (default; the stored swarms) or as its code applies
        them (:mod:`trusscodesign.study.pso`); a checkpoint is only resumed with the rule it was started with.
    on_stale : {"refuse", "restart"}
        What to do with a checkpoint that this run cannot resume (another synthesis, objective or swarm: edited
        spacecraft parameters, say): raise a ValueError naming what changed (default), or set it aside as
        ``<checkpoint>.stale.json``, log what changed and start afresh (notebook 07: a rerun after an edit recomputes).
    truss_tolerance : float
        Relative section-side error every particle's design must survive (:func:`evaluate_particle`; default 0, the
        paper's recipe).
    start : {"previous_best", "cold"}
        How each particle's synthesis starts (:data:`START_RULES`). With "cold" every evaluation is kept in
        :func:`evaluations_path` of the checkpoint under :func:`evaluation_key`, and reused by any later particle at
        the same h.
    h_resolution : float, optional
        Positions are evaluated at the nearest multiple of this [m] (a manufacturing resolution of the section side);
        default None: as they are.

    Returns
    -------
    trusscodesign.study.pso.SwarmState
        With ``history`` (every particle: h, f, J_c, Z_c, mass, status, gain, times; ``shared_with`` when it shared
        the evaluation of an earlier particle at the same h) and ``extra``: ``best_gain``, ``best_scenarios`` (the
        warm start of the next iteration) and ``iteration_wall_s`` (wall time of each iteration [s]).
    """
    from . import pso

    check_option("n_particles", n_particles, 2, integer=True)
    check_option("n_iterations", n_iterations, 1, integer=True)
    _check_h_range(h_range, params)
    objective_value(1.0, 0.0, m0)  # m0 checked now, not after the first particle's synthesis
    _check_synthesis_options(synthesis_options)  # likewise: a bad option would fail every particle of every iteration
    tolerance_shifts(truss_tolerance)
    if on_stale not in ("refuse", "restart"):
        raise ValueError(f"on_stale must be 'refuse' or 'restart', got {on_stale!r}")
    if start not in START_RULES:
        raise ValueError(f"start must be one of {list(START_RULES)}, got {start!r}")
    if h_resolution is not None:
        check_option("h_resolution", h_resolution, 1e-7, 1e-3, unit="m")
        if h_resolution > 0.1 * (h_range[1] - h_range[0]):
            raise ValueError(f"h_resolution = {h_resolution!r} m is more than a tenth of the h range {tuple(h_range)} m: the swarm "
                             "would see a few steps of the objective (0.0001 m is 0.1 mm)")
    params = params or spacecraft.load_parameters()  # read once: the key and every evaluation use these values
    # one run at a time on a checkpoint: another live run holding it stops this one at once, naming it
    with run_lock(checkpoint) if checkpoint is not None else nullcontext():
        objective = _objective_key(settings, params, m0, truss_tolerance)
        if checkpoint is not None and Path(checkpoint).exists():
            reason = _checkpoint_mismatch(checkpoint, n_particles, h_range, seed, pso_rule, synthesis_options, objective,
                                          start, h_resolution)
            if reason is not None and on_stale == "refuse":
                raise ValueError(f"checkpoint {checkpoint} cannot be resumed by this run: {reason}. Pass another checkpoint "
                                 "path (results_dir), delete it to recompute, or on_stale='restart' to set it aside and start afresh")
            if reason is not None:  # "restart": kept beside, never overwritten by the new run
                aside = Path(checkpoint).with_name(Path(checkpoint).stem + ".stale.json")
                os.replace(checkpoint, aside)
                partial_path(checkpoint).unlink(missing_ok=True)  # (the stale run's evaluations, keyed on it)
                log(f"checkpoint {checkpoint} set aside as {aside.name}, and the swarm starts afresh: {reason}")

        def evaluate(x: NDArray, state) -> list[dict]:
            t0 = time.perf_counter()
            state.extra["algorithm"], state.extra["options"], state.extra["objective"] = synthesis.ALGORITHM, _options_key(synthesis_options), objective
            if start != "previous_best" or h_resolution is not None:  # (absent: the runs stored before they existed)
                state.extra["start"], state.extra["h_resolution"] = start, h_resolution
            fails = [p for it, p in fail_particles if it == state.iteration]
            if start == "cold":  # one file of every evaluation, kept: a particle at an h evaluated before reuses it
                gain0, scen0 = None, None
                part = None if checkpoint is None else evaluations_path(checkpoint)
                key = evaluation_key(settings, params, m0, synthesis_options, truss_tolerance)
            else:  # the previous iteration's best particle (None: all gains at -1); a file of this iteration's evaluations
                gain0, scen0 = state.extra.get("best_gain"), state.extra.get("best_scenarios")
                part = None if checkpoint is None else partial_path(checkpoint)
                key = {"iteration": state.iteration, "x": x.tolist(), "algorithm": synthesis.ALGORITHM, "seed": seed,
                       "objective": objective, "options": _options_key(synthesis_options)}
            recs = evaluate_swarm([on_resolution(float(v[0]), h_resolution, h_range) for v in x], gain0, client, settings,
                                  params, m0, fails, progress, synthesis_options=synthesis_options, scenarios0=scen0,
                                  partial=part, partial_key=key, truss_tolerance=truss_tolerance)
            ok = [r for r in recs if r["gain"] is not None and not str(r.get("status", "")).startswith("failed")]
            if ok:  # (a failed synthesis's gain never becomes the warm start: the previous one is kept)
                best = min(ok, key=lambda r: r["f"])
                state.extra["best_gain"], state.extra["best_scenarios"] = best["gain"], best["scenarios"]
            wall = time.perf_counter() - t0
            if part is not None and start == "previous_best":  # with the time spent on this iteration before an interruption
                wall = max(wall, _read_partial(part, key)["time_s"])
            state.extra["iteration_wall_s"] = state.extra.get("iteration_wall_s", []) + [wall]
            return recs

        def summary(state) -> None:  # called once the iteration is in the checkpoint
            if checkpoint is not None and start == "previous_best":
                partial_path(checkpoint).unlink(missing_ok=True)
            it = [r for r in state.history if r["iteration"] == state.iteration - 1]
            best = min(it, key=lambda r: r["f"])
            failed = sum(not str(r.get("status", "")).startswith("ok") for r in it)
            log(f"iteration {state.iteration}/{n_iterations}: best of iteration h = {100 * best['h']:.4f} cm, J_c = {best['J_c']:.4f}, "
                f"f^n = {best['f']:.5f}; swarm best f^n = {state.g_f:.5f} at h = {100 * state.g[0]:.4f} cm; {failed} failed/penalised")

        return pso.run(evaluate, n_particles, [h_range[0]], [h_range[1]], n_iterations, seed, checkpoint, summary, stop_after, pso_rule)
