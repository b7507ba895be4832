"""Benchmark: the warm-started synthesis (a co-design particle's), with notebook 07's options and with seven options added.

A warm start from a neighbouring design takes 1-6 rounds, each ending with a dense worst-case search over the
uncertainty box (90 grid candidates, then four Nelder-Mead refinements of up to 31 evaluations): 35-50 % of its time.
Three options of :func:`trusscodesign.control.synthesis.synthesize` make the search cheaper or the rounds fewer:

* ``fast_search``: the grid by the fast path, each grid plant's modal form kept from one search to the next; the best
  candidates and those found unstable evaluated again densely (the search's results stay the dense path's);
* ``search_max_evals = 10``: shorter refinements (worst cases within 0.11 % (RPE) and 0.91 % (effort) of 30's at 10
  stored designs; ``docs/experiments.md``);
* ``max_unstable = 4``: a round adds up to four distinct unstable scenarios its search found, not one.

and two make each evaluation cheaper (the same steps, to 1e-8 of the values or to the last bit):

* ``peak_refine = "parabolic"``: each peak refined by 8 parabolic steps instead of 85 nested-grid points;
* ``processes = True``: the optimiser's fast-path evaluations on a worker process and this one instead of two threads
  (:mod:`trusscodesign.control.modalpool`), the same values to the last bit;

and two stop the optimiser of a round sooner (fewer steps, a J_c a little higher):

* ``carry_history = True``: a round after the first whose added scenarios leave J within ``tol`` goes on with the last
  round's stopping test instead of starting it afresh;
* ``stall_steps = 3``: the stopping test over the last 3 accepted steps instead of 5.

This script runs notebook 07's options (co-design tolerance, fast path, ball, least-change restoration) alone and
with those options added in turn on 14 warm starts (the stored co-design grid's designs, ``data/results/07_grid.json``,
at 1.6, 1.9, 2.1, 2.4 and 2.8 cm, gain and scenario set, to h + 0.39 mm, + 1 mm and + 3 mm; steps past 3 cm left out)
and the cold start at 2.139 cm, each synthesis alone on the machine with two threads (the setting of the targets: a warm
start under 10 s, a cold one under 60 s), the variants of a case one after the other. It records J_c, Z_c, validity, iterations, searches, the time
and the time spent in the searches, and how much two threads, or a worker process and this one, speed up the
optimiser's fast-path evaluations; prints a line per run and a summary, and saves benchmarks/results/warm_search.json.
Run: python benchmarks/warm_search.py [--steps 0.00039 0.001 0.003] [--no-cold]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from _machine import machine_info  # noqa: E402
from robust_synthesis import grid_design  # noqa: E402
from trusscodesign.study import codesign, design
from trusscodesign.control import synthesis  # noqa: E402
from trusscodesign.control.closedloop import LoopSettings  # noqa: E402
from trusscodesign.control.modalpool import shared_pool  # noqa: E402

ROOT = Path(__file__).parents[1]
WARM_FROM = (0.016, 0.019, 0.021, 0.024, 0.028)
STEPS = (0.00039, 0.001, 0.003)
CHEAPER = {"fast_search": True, "search_max_evals": 10, "max_unstable": 4}
VARIANTS: dict[str, dict] = {"reference": {},
                             "cheaper search": CHEAPER,
                             "+ parabolic peaks": {**CHEAPER, "peak_refine": "parabolic"},
                             "+ parabolic peaks, processes": {**CHEAPER, "peak_refine": "parabolic", "processes": True},
                             "+ carried history": {**CHEAPER, "peak_refine": "parabolic", "processes": True, "carry_history": True},
                             "+ carried history, stall 3": {**CHEAPER, "peak_refine": "parabolic", "processes": True,
                                                            "carry_history": True, "stall_steps": 3}}
COLD = (0.02139,)


def cases(steps: Sequence[float] = STEPS) -> list[tuple[str, float, float]]:
    """The warm starts: (name, h [m], grid point h0 [m] it starts from); steps past the design range (3 cm) left out."""
    return [(f"warm {100 * h0:.1f} -> {100 * (h0 + dh):.3f} cm", h0 + dh, h0) for h0 in WARM_FROM for dh in steps
            if h0 + dh <= 0.03 + 1e-12]


def run_case(name: str, h: float, h0: float | None, options: dict, workers: int, **key) -> dict:
    """One synthesis of a case (``h`` [m], warm-started from the stored grid's design at ``h0`` [m], its gain and
    scenario set, or cold if None) with ``options`` for :func:`trusscodesign.study.design.robust_design` and ``workers``
    threads, BLAS on one thread; its record: ``key`` (e.g. ``variant=...``), J_c, Z_c, validity, iterations, searches
    and the synthesis's wall time [s] (the model's build left out)."""
    from threadpoolctl import threadpool_limits

    kw = dict(options)
    if h0 is not None:
        rec, scen = grid_design(h0)
        kw.update(gain0=rec["gain"], scenarios=scen)
    with threadpool_limits(1):
        models = design.models_at(h)
        t0 = time.perf_counter()
        res = design.robust_design(models, LoopSettings.from_parameters(), workers=workers, **kw)
        wall = time.perf_counter() - t0
    return {"case": name, "h": h, "warm_from": h0, **key, "J_c": res.j_c, "Z_c": res.z_c, "success": res.success,
            "message": res.message, "iterations": res.iterations, "searches": res.searches, "scenarios": len(res.scenarios),
            "time_s": wall}


def summary(rows: list[dict], key: str, variants: Sequence[str], warm: bool, iterations: bool = False) -> dict:
    """Per variant (``row[key]``) over the warm (or cold) runs: valid runs, median and largest time, runs under 10 s,
    median J_c of the valid ones, (with ``iterations``) median iterations, and median searches."""
    out = {}
    for variant in variants:
        mine = [r for r in rows if r[key] == variant and (r["warm_from"] is not None) == warm]
        if not mine:
            continue
        out[variant] = {"runs": len(mine), "valid": sum(r["success"] for r in mine),
                        "median_time_s": float(np.median([r["time_s"] for r in mine])),
                        "max_time_s": max(r["time_s"] for r in mine), "under_10_s": sum(r["time_s"] < 10.0 for r in mine),
                        "median_J_c": float(np.median([r["J_c"] for r in mine if r["success"]] or [np.inf])),
                        **({"median_iterations": float(np.median([r["iterations"] for r in mine]))} if iterations else {}),
                        "median_searches": float(np.median([r["searches"] for r in mine]))}
    return out



def _run(name: str, h: float, h0: float | None, variant: str) -> dict:
    """One synthesis of a case with a variant's options, two threads; its record, with the time spent searching."""
    searching = [0.0]
    search = synthesis.worst_case

    def timed(*args, **kwargs):
        t = time.perf_counter()
        try:
            return search(*args, **kwargs)
        finally:
            searching[0] += time.perf_counter() - t

    synthesis.worst_case = timed  # synthesize looks it up in its module at every round
    try:
        options = dict(codesign.synthesis_options(True, "ball", "least_change") or {}, **VARIANTS[variant])
        row = run_case(name, h, h0, options, 2, variant=variant)
    finally:
        synthesis.worst_case = search
    return {**row, "search_time_s": searching[0]}


def _thread_scaling(h: float = 0.02139, h0: float = 0.021, repeats: int = 10) -> dict:
    """Time of one fast-path evaluation of the optimiser (:func:`trusscodesign.control.synthesis.loop_peaks` with a modal form) of each plant
    of a warm start's scenario set (the grid's design at ``h0`` [m], evaluated at ``h``), on one and on two threads, and
    (parabolic peaks) on one thread, two threads and a worker process with this one, at gains 0.1 % apart as trust-region
    steps [ms per plant]."""
    from concurrent.futures import ThreadPoolExecutor

    from threadpoolctl import threadpool_limits

    from trusscodesign.control.modalloop import ModalLoop

    settings = LoopSettings.from_parameters()
    rec, scen = grid_design(h0)
    models = design.models_at(h)
    plants = [synthesis.plant_at(models.g_r, sc, models.inertia, settings) for sc in scen]
    forms = [ModalLoop.of(p) for p in plants]
    gain = np.array(rec["gain"])
    rng = np.random.default_rng(0)

    def one(i: int, k: np.ndarray, refine: str = "zoom") -> None:
        synthesis.loop_peaks(plants[i], k, min_damping=2e-4, modal=forms[i], peak_refine=refine)

    for i in range(len(plants)):  # the first call of a form starts its poles from the open loop's
        one(i, gain)
    out = {}
    processes = shared_pool(1)
    try:
        with threadpool_limits(1), ThreadPoolExecutor(2) as pool:
            synthesis._pool_peaks(processes, plants, forms, gain, min_damping=2e-4)  # the worker builds its forms
            for name, refine, how in (("1", "zoom", "thread"), ("2", "zoom", "threads"), ("1 parabolic", "parabolic", "thread"),
                                      ("2 parabolic", "parabolic", "threads"), ("process parabolic", "parabolic", "process")):
                t0 = time.perf_counter()
                for _ in range(repeats):
                    k = gain * (1 + 1e-3 * rng.standard_normal(gain.shape))
                    if how == "process":
                        synthesis._pool_peaks(processes, plants, forms, k, min_damping=2e-4, peak_refine=refine)
                    else:
                        list((map if how == "thread" else pool.map)(lambda i: one(i, k, refine), range(len(plants))))
                out[name] = 1e3 * (time.perf_counter() - t0) / (repeats * len(plants))
    finally:
        processes.forget()
    return {"h": h, "plants": len(plants), "ms_per_plant": out}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--steps", type=float, nargs="+", default=list(STEPS))
    parser.add_argument("--cold", action=argparse.BooleanOptionalAction, default=True)
    args = parser.parse_args()
    todo: list[tuple[str, float, float | None]] = [*cases(args.steps)]
    todo += [(f"cold {100 * h:.3f} cm", h, None) for h in COLD] if args.cold else []
    rows = []
    for name, h, h0 in todo:
        for variant in VARIANTS:
            row = _run(name, h, h0, variant)
            rows.append(row)
            print(f"{name}, {variant}: J_c {row['J_c']:.5f}, Z_c {row['Z_c']:.4f}, valid {row['success']}, "
                  f"{row['iterations']} iterations, {row['searches']} searches, {row['time_s']:.1f} s "
                  f"(searching {row['search_time_s']:.1f} s)", flush=True)
    result = {kind: summary(rows, "variant", list(VARIANTS), kind == "warm", iterations=True) for kind in ("warm", "cold")}
    for kind, per in result.items():
        for variant, s in per.items():
            mine = [r for r in rows if r["variant"] == variant and (r["warm_from"] is not None) == (kind == "warm")]
            s["total_time_s"] = sum(r["time_s"] for r in mine)
            s["total_search_time_s"] = sum(r["search_time_s"] for r in mine)
            print(f"{kind}, {variant}: {s['valid']}/{s['runs']} valid, time median {s['median_time_s']:.1f} s "
                  f"(max {s['max_time_s']:.1f} s, total {s['total_time_s']:.0f} s of which searching "
                  f"{s['total_search_time_s']:.0f} s, {s['under_10_s']} under 10 s), median J_c {s['median_J_c']:.5f}, "
                  f"median iterations {s['median_iterations']:.0f}, median searches {s['median_searches']:.0f}")
    names = list(VARIANTS)
    for against, key in ((lambda i: names[0], "warm_case_by_case"), (lambda i: names[i - 1], "warm_case_by_case_previous")):
        result[key] = {}
        for i, variant in enumerate(names[1:], start=1):
            ref = {r["case"]: r for r in rows if r["variant"] == against(i)}
            ratios = [(r["time_s"] / ref[r["case"]]["time_s"], r["J_c"] / ref[r["case"]]["J_c"] - 1.0)
                      for r in rows if r["variant"] == variant and r["warm_from"] is not None and r["case"] in ref]
            if ratios:
                c = result[key][variant] = {
                    "against": against(i), "median_time_ratio": float(np.median([t for t, _ in ratios])),
                    "J_c_change_min": min(j for _, j in ratios), "J_c_change_median": float(np.median([j for _, j in ratios])),
                    "J_c_change_max": max(j for _, j in ratios)}
                print(f"warm, case by case, {variant} against {against(i)}: median time ratio {c['median_time_ratio']:.2f}, "
                      f"J_c change {100 * c['J_c_change_min']:+.1f} to {100 * c['J_c_change_max']:+.1f} % "
                      f"(median {100 * c['J_c_change_median']:+.1f} %)")
    scaling = _thread_scaling()
    print(f"the optimiser's evaluations (fast path, {scaling['plants']} scenario plants at {100 * scaling['h']:.3f} cm), "
          "ms per plant: " + ", ".join(f"{k} {v:.2f}" for k, v in scaling["ms_per_plant"].items()))
    out = {"machine": machine_info(), "synthesis_algorithm": synthesis.ALGORITHM, "threads_per_synthesis": 2,
           "variants": VARIANTS, "steps": args.steps, "rows": rows, "summary": result, "thread_scaling": scaling}
    path = ROOT / "benchmarks" / "results" / "warm_search.json"
    path.write_text(json.dumps(out, indent=1))
    print(f"saved {path}")


if __name__ == "__main__":
    main()
