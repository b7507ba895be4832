"""Benchmark: the synthesis's trust region, the box (each step a linear program) against the box cut by a ball.

``lib.synthesis.synthesize(trust_region=...)``: in the box ``|d_i| <= r_i`` the step of each iteration sits in a corner
(``benchmarks/thin_end_plateau.py --active-set``), and cold starts at the thin end of the h range crawl for dozens of
steps and stop on that plateau (J_c 0.16-0.21 where other runs reach 0.02-0.04). ``"ball"`` adds
``||d / r||_2 <= sqrt(32) / 2``. This script runs the same syntheses with both shapes, by the fast path (final
evaluation and searches dense), one thread each, and records J_c, Z_c, validity, iterations, searches and time:

* cold starts (all gains at -1) at 1.5 and 1.55 cm with the co-design's tolerance (1 %), where the stored grid stalls;
  at 1.5 and 1.6 cm with the synthesis default (0.2 %), where the 0.2 % grid stalls at 1.6 cm; at 2.139 and 3 cm with
  the default (notebook 06's designs);
* warm starts from the co-design grid's 2.1 cm design (gain and scenario set, co-design tolerance) to 2.139 and 2.2 cm
  (the warm start of the synthesis benchmark).

Prints a line per run and saves benchmarks/results/trust_region.json. With ``--warm-only`` only the warm starts run, one
after the other in one process (``--processes 1``) with ``--workers`` threads for the synthesis's scenario evaluations
(default 1; 0: one per core), to time them alone on the machine (the synthesis issue's "under 10 s" point); saved to
``trust_region_warm_w<workers>.json``.
Run: python benchmarks/trust_region.py [--processes 2] [--warm-only [--workers N]]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from _machine import machine_info  # noqa: E402
from robust_synthesis import grid_design  # noqa: E402
from lib import codesign, design, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402

ROOT = Path(__file__).parents[1]
CO_TOL = codesign.SYNTHESIS_OPTIONS["tol"]
# (name, h [m], tol, warm start from the grid's 2.1 cm design)
CASES = [("cold 1.5 cm, co-design tol", 0.015, CO_TOL, False), ("cold 1.55 cm, co-design tol", 0.0155, CO_TOL, False),
         ("cold 1.5 cm, default tol", 0.015, 2e-3, False), ("cold 1.6 cm, default tol", 0.016, 2e-3, False),
         ("cold 2.139 cm, default tol", 0.02139, 2e-3, False), ("cold 3 cm, default tol", 0.03, 2e-3, False),
         ("warm 2.1 -> 2.139 cm, co-design tol", 0.02139, CO_TOL, True), ("warm 2.1 -> 2.2 cm, co-design tol", 0.022, CO_TOL, True)]


def _run(job: tuple[str, float, float, bool, str, int | None]) -> dict:
    """One synthesis (a case of :data:`CASES` with a trust-region shape and the synthesis's ``workers``); its record."""
    from threadpoolctl import threadpool_limits

    name, h, tol, warm, shape, workers = job
    settings = LoopSettings.from_parameters()
    kw: dict = dict(codesign.SYNTHESIS_OPTIONS, tol=tol, fast=True, trust_region=shape)
    if warm:
        rec, scen = grid_design(0.021)
        kw.update(gain0=rec["gain"], scenarios=scen)
    with threadpool_limits(1):
        models = design.models_at(h)
        t0 = time.perf_counter()
        res = design.robust_design(models, settings, workers=workers, **kw)
        wall = time.perf_counter() - t0
    return {"case": name, "h": h, "tol": tol, "warm": warm, "trust_region": shape, "workers": workers, "J_c": res.j_c, "Z_c": res.z_c,
            "success": res.success, "message": res.message, "iterations": res.iterations, "searches": res.searches,
            "time_s": wall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--warm-only", action="store_true", help="only the warm starts (time them alone: --processes 1)")
    parser.add_argument("--workers", type=int, default=1, help="threads of each synthesis (0: one per core)")
    args = parser.parse_args()
    workers = args.workers or None
    jobs = [(*case, shape, workers) for case in CASES for shape in ("box", "ball") if case[3] or not args.warm_only]
    with ProcessPoolExecutor(args.processes) as pool:
        rows = list(pool.map(_run, jobs))
    for row in rows:
        print(f"{row['case']}, {row['trust_region']}: J_c {row['J_c']:.5f}, Z_c {row['Z_c']:.4f}, valid {row['success']}, "
              f"{row['iterations']} iterations, {row['searches']} searches, {row['time_s']:.1f} s")
    out = {"machine": machine_info(), "synthesis_algorithm": synthesis.ALGORITHM, "path": "fast", "rows": rows}
    out["processes"] = args.processes
    path = ROOT / "benchmarks" / "results" / (f"trust_region_warm_w{args.workers}.json" if args.warm_only else "trust_region.json")
    path.write_text(json.dumps(out, indent=1, default=float) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
