"""Benchmark: where the time of a warm-started synthesis goes, and what bounds it (the synthesis issue's "under 10 s").

The two warm starts of ``benchmarks/trust_region.py --warm-only`` (from the co-design grid's 2.1 cm design, gain and
scenario set, to 2.139 and 2.2 cm; co-design tolerance, fast path, ball trust region: notebook 07's options), each run
with 1 and 2 threads (``workers``) alone on the machine. For each run it records:

* the wall time and its split: stabilisation and the evaluations of the scenario set at the start of each round, the
  optimiser (per round: iterations and time), the worst-case searches (per search), the final dense evaluation;
* every step of the optimiser (2-thread runs): the relative decrease of J its linear model predicts, the one the trial
  gave (none if the trial was rejected before all its plants were evaluated), whether the step lies on the ball's
  boundary, and how many pole-damping rows and J peaks are active at it;

and, at the 2.139 cm design, one worst-case search's grid of 90 candidates: the time per evaluation on one thread and
the share of the closed-loop ``eig`` in it, then the grid on 2 threads (as the search runs it) and on 2 forked
processes (what processes would gain).

With ``--restoration least_change`` the syntheses take least-change restoration steps (``benchmarks/restoration.py``)
and the results go to ``warm_start_least_change.json``.

``warm_start_8730c38.json`` holds the run at commit 8730c38, before the plant build of
``lib.closedloop.generalized_plant`` changed at round-off and a round began to evaluate only its new scenarios (the
same algorithm; the paths differ, README).

Prints a summary and saves benchmarks/results/warm_start.json.
Run: python benchmarks/warm_start.py [--restoration {minmax,least_change}]
"""

from __future__ import annotations

import argparse
import inspect
import json
import multiprocessing
import os
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path
from typing import Any

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

from _machine import machine_info  # noqa: E402
from robust_synthesis import grid_design  # noqa: E402
from lib import codesign, design, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402

ROOT = Path(__file__).parents[1]
CASES = (("warm 2.1 -> 2.139 cm", 0.02139), ("warm 2.1 -> 2.2 cm", 0.022))
OPTIONS = dict(codesign.synthesis_options(True, "ball") or {})


class _Recorder:
    """Wraps the synthesis's parts (module functions and ``_Problem`` methods) for one run, and undoes it."""

    def __init__(self, steps: bool) -> None:
        self.parts: dict[str, list[float]] = {"round_start": [], "optimise": [], "search": [], "final_dense": []}
        self.rounds: list[dict] = []
        self.steps: list[dict] = []
        self._pending: dict | None = None
        self._saved: list[tuple[Any, str, Any]] = []
        self._patch(synthesis, "_optimise", self._optimise)
        self._patch(synthesis, "worst_case", self._timed("search"))
        self._patch(synthesis._Problem, "evaluate_all", self._evaluate_all)
        if steps:
            self._patch(synthesis, "_lp", self._lp)
            self._patch(synthesis._Problem, "evaluate", self._evaluate)

    def _patch(self, owner: Any, name: str, make: Callable[[Callable], Callable]) -> None:
        original = getattr(owner, name)
        self._saved.append((owner, name, original))
        setattr(owner, name, make(original))

    def restore(self) -> None:
        for owner, name, original in reversed(self._saved):
            setattr(owner, name, original)

    def _timed(self, part: str) -> Callable[[Callable], Callable]:
        def make(f: Callable) -> Callable:
            def run(*args, **kwargs):
                t0 = time.perf_counter()
                try:
                    return f(*args, **kwargs)
                finally:
                    self.parts[part].append(time.perf_counter() - t0)
            return run
        return make

    def _optimise(self, f: Callable) -> Callable:
        def run(prob, state):
            t0, it0 = time.perf_counter(), prob.iterations
            out = f(prob, state)
            self.parts["optimise"].append(time.perf_counter() - t0)
            self.rounds.append({"plants": len(prob.plants), "iterations": prob.iterations - it0, "J": out[0].value("rpe"),
                                "Z": out[0].value("effort"), "time_s": self.parts["optimise"][-1]})
            return out
        return run

    def _evaluate_all(self, f: Callable) -> Callable:
        def run(prob, gain, dense=False):
            t0 = time.perf_counter()
            out = f(prob, gain, dense)
            self.parts["final_dense" if dense else "round_start"].append(time.perf_counter() - t0)
            return out
        return run

    def _lp(self, f: Callable) -> Callable:
        def run(objective, constraints, radius, soft=(), penalty=0.0, shape="box"):
            out = f(objective, constraints, radius, soft, penalty, shape)
            self._pending = None
            if out is not None and penalty > 0:  # a step of the optimisation phase (J normalised by its current value)
                d, t, s = out
                hard = [bound - c - h.ravel() @ d for c, h, bound in constraints]
                self._pending = {"predicted_decrease": 1.0 - t, "slack_s": s,
                                 "on_ball": bool(np.linalg.norm(d / radius) >= 0.999 * 0.5 * np.sqrt(d.size)),
                                 "damping_rows_active": int(sum(x <= 1e-7 for x in hard)), "damping_rows": len(hard),
                                 "j_peaks_active": int(sum(fj + g @ d >= t - 1e-7 for fj, g in objective)), "j_peaks": len(objective)}
            return out
        return run

    def _evaluate(self, f: Callable) -> Callable:
        def run(prob, gain, reject=None, current=None, dense=False):
            out = f(prob, gain, reject, current, dense)
            if self._pending is not None and reject is not None and current is not None:
                step, self._pending = self._pending, None
                step["actual_decrease"] = None if out is None else 1.0 - out.value("rpe") / current.value("rpe")
                step["Z_after"] = None if out is None else out.value("effort")
                self.steps.append(step)
            return out
        return run


def _run(h: float, workers: int, steps: bool) -> dict:
    """One warm start from the grid's 2.1 cm design to ``h`` [m] on ``workers`` threads; its record."""
    settings = LoopSettings.from_parameters()
    rec, scen = grid_design(0.021)
    models = design.models_at(h)
    recorder = _Recorder(steps)
    try:
        t0 = time.perf_counter()
        res = design.robust_design(models, settings, gain0=rec["gain"], scenarios=scen, workers=workers, **OPTIONS)
        wall = time.perf_counter() - t0
    finally:
        recorder.restore()
    parts = {k: float(np.sum(v)) for k, v in recorder.parts.items()}
    out = {"h": h, "workers": workers, "time_s": wall, "parts_s": parts, "other_s": wall - sum(parts.values()),
           "searches_s": recorder.parts["search"], "rounds": recorder.rounds, "iterations": res.iterations,
           "J_c": res.j_c, "Z_c": res.z_c, "success": res.success, "message": res.message, "gain": res.gain.tolist()}
    if steps:
        out["steps"] = recorder.steps
    return out


_JOB: dict[str, Any] = {}


def _set_job(model, gain, inertia, settings, near) -> None:
    _JOB.update(model=model, gain=gain, inertia=inertia, settings=settings, near=near)


def _option(name: str) -> float:
    """A synthesis option of :data:`OPTIONS`, else :func:`lib.synthesis.synthesize`'s default."""
    return float(OPTIONS.get(name, inspect.signature(synthesis.synthesize).parameters[name].default))


def _candidate(v: np.ndarray) -> tuple[float, float]:
    """One candidate of the search's grid, evaluated as :func:`lib.synthesis.worst_case` does."""
    plant = synthesis.plant_at(_JOB["model"], synthesis.Scenario.from_vector(v), _JOB["inertia"], _JOB["settings"])
    lp = synthesis.loop_peaks(plant, _JOB["gain"], min_decay=_option("min_decay"), n_peaks=1,
                              min_damping=_option("search_damping") * _option("min_damping_all"), lazy_cap=True, passive_near=_JOB["near"])
    return lp.norm("rpe"), lp.norm("effort")


def _search_grid(h: float, gain: np.ndarray) -> dict:
    """The search grid's evaluations at ``gain``: one thread (with the eig share), 2 threads, 2 processes."""
    settings = LoopSettings.from_parameters()
    models = design.models_at(h)
    cands = [sc.vector() for sc in synthesis.search_candidates()]
    near = synthesis.plant_at(models.g_r, synthesis.Scenario(), models.inertia, settings).passive_pole()
    _set_job(models.g_r, gain, models.inertia, settings, near)
    t0 = time.perf_counter()
    serial = [_candidate(v) for v in cands]
    t_serial = time.perf_counter() - t0
    loops = [synthesis.plant_at(models.g_r, synthesis.Scenario.from_vector(v), models.inertia, settings).closed_loop(gain)[0]
             for v in cands]
    t0 = time.perf_counter()
    for a in loops:
        np.linalg.eig(a)
    t_eig = time.perf_counter() - t0
    t0 = time.perf_counter()
    with ThreadPoolExecutor(2) as pool:
        threads = list(pool.map(_candidate, cands))
    t_threads = time.perf_counter() - t0
    t0 = time.perf_counter()
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("fork"), initializer=_set_job,
                             initargs=(models.g_r, gain, models.inertia, settings, near)) as pool:
        procs = list(pool.map(_candidate, cands, chunksize=5))
    t_procs = time.perf_counter() - t0
    if not (np.array_equal(serial, threads) and np.array_equal(serial, procs)):
        raise RuntimeError("the grid's values differ between one thread, two threads and two processes")
    return {"h": h, "candidates": len(cands), "order": int(loops[0].shape[0]), "ms_per_evaluation": 1e3 * t_serial / len(cands),
            "eig_ms": 1e3 * t_eig / len(cands), "eig_share": t_eig / t_serial, "one_thread_s": t_serial,
            "two_threads_s": t_threads, "two_processes_s": t_procs}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--restoration", choices=("minmax", "least_change"), default="minmax")
    args = parser.parse_args()
    OPTIONS["restoration"] = args.restoration
    rows = []
    with threadpool_limits(1):
        for name, h in CASES:
            for workers in (1, 2):
                row = _run(h, workers, steps=workers == 2)
                row["case"] = name
                rows.append(row)
                p = row["parts_s"]
                print(f"{name}, {workers} thread(s): {row['time_s']:.1f} s = optimiser {p['optimise']:.1f} ({row['iterations']} it.) "
                      f"+ searches {p['search']:.1f} ({len(row['searches_s'])}) + round starts {p['round_start']:.1f} "
                      f"+ final dense {p['final_dense']:.1f} + other {row['other_s']:.1f}; J_c {row['J_c']:.5f}, Z_c {row['Z_c']:.4f}")
        grid = _search_grid(CASES[0][1], np.array(rows[1]["gain"]))
    steps = [s for r in rows if "steps" in r for s in r["steps"]]
    accepted = [s for s in steps if s["actual_decrease"] is not None and s["actual_decrease"] > 0.1 * s["predicted_decrease"]]
    summary = {"steps": len(steps), "on_ball": sum(s["on_ball"] for s in steps),
               "accepted_median_ratio": float(np.median([s["actual_decrease"] / s["predicted_decrease"] for s in accepted])) if accepted else None,
               "median_predicted_decrease": float(np.median([s["predicted_decrease"] for s in steps])) if steps else None}
    print(f"steps (2 threads): {summary['steps']}, on the ball's boundary {summary['on_ball']}; accepted: median actual/predicted "
          f"decrease of J {summary['accepted_median_ratio']:.2f}; median predicted decrease {summary['median_predicted_decrease']:.4f}")
    print(f"search grid at {grid['h']} m (order {grid['order']}): {grid['ms_per_evaluation']:.1f} ms per evaluation on one thread, "
          f"eig {grid['eig_ms']:.1f} ms ({100 * grid['eig_share']:.0f} %); 90 candidates: 1 thread {grid['one_thread_s']:.2f} s, "
          f"2 threads {grid['two_threads_s']:.2f} s, 2 processes {grid['two_processes_s']:.2f} s")
    out = {"machine": machine_info(), "synthesis_algorithm": synthesis.ALGORITHM, "options": OPTIONS, "rows": rows,
           "step_summary": summary, "search_grid": grid}
    path = ROOT / "benchmarks" / "results" / ("warm_start.json" if args.restoration == "minmax" else "warm_start_least_change.json")
    path.write_text(json.dumps(out, indent=1, default=float) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
