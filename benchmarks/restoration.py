"""Benchmark: the synthesis's restoration steps, min-max (the default) against least-change.

``trusscodesign.synthesis.synthesize(restoration=...)``: when the gain must be made stable again (a warm start from another h,
or a scenario a worst-case search added, unstable at the current gain) and then feasible (``Z < gamma_u``), the min-max
step minimises the largest linearised pole margin (then the largest effort peak) in the trust region and so moves the
gain to the region's edge; the least-change step is the smallest step whose linearised margins (then effort peaks) reach
their targets. ``benchmarks/warm_start.py`` found one min-max stabilisation that took J from 0.018 to 0.071 and left the
synthesis unconverged after 6 rounds (J_c 0.12), where the same warm start, perturbed at round-off, converged in 2 rounds
(J_c 0.018).

This script runs, with notebook 07's options (co-design tolerance, fast path, ball), both restorations on:

* warm starts from designs of the stored co-design grid (``data/results/box/07_grid.json``, gain and scenario set) at
  1.6, 1.9, 2.1, 2.4 and 2.8 cm to h + 0.039 cm (the 2.1 -> 2.139 cm step of the synthesis benchmark) and h + 0.1 cm;
* cold starts (all gains at -1) at 1.5, 2.139 and 3 cm;

one thread per synthesis, two syntheses at a time, and records J_c, Z_c, validity, iterations, searches and time.
With ``--source ball_minmax`` the warm starts come from the ball grid computed with min-max restoration
(``data/results/ball_minmax/07_grid.json``, the stored co-design's until 2026-12-05), with ``--source ball`` from the
stored co-design's grid (``data/results/07_grid.json``, ball and least-change restoration since 2026-12-05);
``--steps`` sets the steps [m] and ``--no-cold`` leaves the cold starts out (they do not depend on the source); the
results then go to ``restoration_<source>.json``.
Prints a line per run and a summary and saves benchmarks/results/restoration.json.
Run: python benchmarks/restoration.py [--processes 2] [--source {box,ball_minmax,ball}] [--steps 0.00039 0.001] [--no-cold]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from robust_synthesis import grid_design  # noqa: E402
from trusscodesign import codesign, design, synthesis  # noqa: E402
from trusscodesign.closedloop import LoopSettings  # noqa: E402

ROOT = Path(__file__).parents[1]
WARM_FROM = (0.016, 0.019, 0.021, 0.024, 0.028)
STEPS = (0.00039, 0.001)
COLD = (0.015, 0.02139, 0.03)
MODES = ("minmax", "least_change")


def cases(steps: tuple[float, ...] = STEPS, cold: bool = True) -> list[tuple[str, float, float | None]]:
    """(name, h [m], warm-start grid point h0 [m] or None for a cold start); steps past the design range (3 cm) left out."""
    warm = [(f"warm {100 * h0:.1f} -> {100 * (h0 + dh):.3f} cm", h0 + dh, h0) for h0 in WARM_FROM for dh in steps
            if h0 + dh <= 0.03 + 1e-12]
    return warm + ([(f"cold {100 * h:.3f} cm", h, None) for h in COLD] if cold else [])


def run_case(name: str, h: float, h0: float | None, options: dict, workers: int, source: str = "ball", **key) -> dict:
    """One synthesis of a case (``h`` [m], warm-started from the grid ``source``'s design at ``h0`` [m], its gain and
    scenario set, or cold if None) with ``options`` for :func:`trusscodesign.design.robust_design` and ``workers`` threads, BLAS on
    one thread; its record: ``key`` (the variant, e.g. ``restoration="minmax"``), J_c, Z_c, validity, iterations,
    searches and the synthesis's wall time [s] (the model's build left out)."""
    from threadpoolctl import threadpool_limits

    kw = dict(options)
    if h0 is not None:
        rec, scen = grid_design(h0, source)
        kw.update(gain0=rec["gain"], scenarios=scen)
    with threadpool_limits(1):
        models = design.models_at(h)
        t0 = time.perf_counter()
        res = design.robust_design(models, LoopSettings.from_parameters(), workers=workers, **kw)
        wall = time.perf_counter() - t0
    return {"case": name, "h": h, "warm_from": h0, **key, "J_c": res.j_c, "Z_c": res.z_c, "success": res.success,
            "message": res.message, "iterations": res.iterations, "searches": res.searches, "scenarios": len(res.scenarios),
            "time_s": wall}


def _run(job: tuple[str, float, float | None, str, str]) -> dict:
    """One synthesis of a case with a restoration mode, warm starts from a grid ``source``; its record."""
    name, h, h0, mode, source = job
    return run_case(name, h, h0, codesign.synthesis_options(True, "ball", mode) or {}, 1, source, restoration=mode)


def summary(rows: list[dict], key: str, variants: Sequence[str], warm: bool, iterations: bool = False) -> dict:
    """Per variant (``row[key]``, e.g. the restoration) over the warm (or cold) runs: valid runs, median and largest
    time, runs under 10 s, median J_c of the valid ones, (with ``iterations``) median iterations, and median searches."""
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--source", choices=("box", "ball_minmax", "ball"), default="box")
    parser.add_argument("--steps", type=float, nargs="+", default=list(STEPS))
    parser.add_argument("--cold", action=argparse.BooleanOptionalAction, default=True)
    args = parser.parse_args()
    jobs = [(*case, mode, args.source) for case in cases(tuple(args.steps), args.cold) for mode in MODES]
    with ProcessPoolExecutor(args.processes) as pool:
        rows = list(pool.map(_run, jobs))
    for row in rows:
        print(f"{row['case']}, {row['restoration']}: J_c {row['J_c']:.5f}, Z_c {row['Z_c']:.4f}, valid {row['success']}, "
              f"{row['iterations']} iterations, {row['searches']} searches, {row['time_s']:.1f} s")
    result = {"warm": summary(rows, "restoration", MODES, True), "cold": summary(rows, "restoration", MODES, False) if args.cold else {}}
    for kind, per_mode in result.items():
        for mode, s in per_mode.items():
            print(f"{kind}, {mode}: {s['valid']}/{s['runs']} valid, time median {s['median_time_s']:.1f} s (max {s['max_time_s']:.1f} s, "
                  f"{s['under_10_s']} under 10 s), median searches {s['median_searches']:.0f}, median valid J_c {s['median_J_c']:.5f}")
    out = {"machine": machine_info(), "synthesis_algorithm": synthesis.ALGORITHM, "options": codesign.synthesis_options(True, "ball"),
           "processes": args.processes, "source": args.source, "steps": args.steps, "rows": rows, "summary": result}
    path = ROOT / "benchmarks" / "results" / ("restoration.json" if args.source == "box" else f"restoration_{args.source}.json")
    path.write_text(json.dumps(out, indent=1, default=float) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
