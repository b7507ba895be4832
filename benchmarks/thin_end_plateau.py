"""Benchmark: are the co-design grid's thin-end designs (1.5 and 1.55 cm) local optima of the synthesis, or a plateau?

The stored dense grid of notebook 07 (``data/results/box/07_grid.json``, co-design tolerance ``tol = 0.01``) has J_c = 0.164
at 1.5 cm and 0.208 at 1.55 cm against 0.018-0.030 from 1.6 to 3 cm, and its f^n minimum (the co-design's optimum) sits
on these two points, because f^n = m/m0 + |0.9 - J_c| rewards a larger J_c. This script reruns the same cold syntheses
(all gains at -1, default scenario set, one thread), by the dense path and by the fast one (``fast=True``, whose final
evaluation and worst-case searches are dense), with the co-design's tolerance and with the synthesis default
(``tol = 2e-3``), and records for each:
J_c, Z_c, validity, iterations, rounds (worst-case searches), time, the J of every accepted step, how each round ended,
and f^n. A plateau shows as a slow decrease of J that the 5-step stopping test (less than ``tol`` relative decrease of
J over the last 5 accepted steps) ends at one tolerance and the other goes through.

With ``--active-set`` every trust-region LP of the runs is also recorded: how many J peaks, pole-damping (stability)
rows and gain entries of the trust box are active at its solution, the radius, and the relative decrease it predicts;
the results then go to ``thin_end_plateau_active_set.json``.

Prints a line per run and saves benchmarks/results/thin_end_plateau.json.
Run: python benchmarks/thin_end_plateau.py [--h 0.015 0.0155] [--tols 0.01 0.002] [--paths dense fast] [--processes 2]
     [--active-set]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from _machine import machine_info  # noqa: E402
from lib import codesign, design, spacecraft, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402

ROOT = Path(__file__).parents[1]


def _recording_lp(log: list[dict]) -> Callable[..., Any]:
    """``lib.synthesis._lp`` that also appends the active set of each solution to ``log`` (the synthesis calls its LP
    by module name, so replacing it in this process is how the benchmark sees every step; the library is unchanged)."""
    solve = synthesis._lp

    def lp(objective: Sequence[tuple[float, Any]], constraints: Sequence[tuple[float, Any, float]], radius: Any,
           soft: Sequence = (), penalty: float = 0.0) -> Any:
        sol = solve(objective, constraints, radius, soft, penalty)
        rec: dict = {"J_rows": len(objective), "stability_rows": len(constraints), "radius": float(radius.max())}
        if sol is not None:
            d, t, _ = sol
            rec.update(J_active=int(sum(f + g @ d >= t - 1e-9 for f, g in objective)),
                       stability_active=int(sum(c + h.ravel() @ d >= b - 1e-9 * max(1.0, abs(b)) for c, h, b in constraints)),
                       box_active=int(sum(abs(abs(d) - radius) <= 1e-9 * radius)),
                       predicted_rel_decrease=float(1.0 - t / max(f for f, _ in objective)) if objective else None)
        log.append(rec)
        return sol

    return lp


def _run(job: tuple[float, float, str, bool]) -> dict:
    """One cold synthesis at ``h`` [m] with the co-design's options, tolerance ``tol``, by ``path`` ("dense" or "fast");
    its record (with ``active_set``, the active set of every LP)."""
    from threadpoolctl import threadpool_limits

    h, tol, path, active_set = job
    log: list[dict] = []
    if active_set:
        synthesis._lp = _recording_lp(log)
    settings = LoopSettings.from_parameters()
    with threadpool_limits(1):
        models = design.models_at(h)
        t0 = time.perf_counter()
        res = design.robust_design(models, settings, workers=1, **dict(codesign.SYNTHESIS_OPTIONS, tol=tol, fast=path == "fast"))
        wall = time.perf_counter() - t0
    accepted = [round(float(r["J"]), 6) for r in res.history if r["phase"] == "optimise"]
    mass = spacecraft.truss_mass(h)
    return {"h": h, "tol": tol, "path": path, "J_c": res.j_c, "Z_c": res.z_c, "success": res.success, "message": res.message,
            "iterations": res.iterations, "searches": res.searches, "time_s": wall, "accepted_J": accepted,
            "f": codesign.objective_value(mass, res.j_c, codesign.M0_PAPER) if res.success else None,
            **({"lp_active_sets": log} if active_set else {})}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--h", type=float, nargs="*", default=[0.015, 0.0155], help="section sides [m]")
    parser.add_argument("--tols", type=float, nargs="*", default=[codesign.SYNTHESIS_OPTIONS["tol"], 2e-3],
                        help="stopping tolerances (default: the co-design's and the synthesis default)")
    parser.add_argument("--paths", nargs="*", default=["dense", "fast"], choices=["dense", "fast"])
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--active-set", action="store_true", help="record the active set of every LP")
    args = parser.parse_args()
    grid = json.loads((ROOT / "data" / "results" / "box" / "07_grid.json").read_text())
    stored = {round(r["h"], 7): r for r in grid["records"]}
    jobs = [(h, tol, path, args.active_set) for h in args.h for tol in args.tols for path in args.paths]
    with ProcessPoolExecutor(args.processes) as pool:
        rows = list(pool.map(_run, jobs))
    for row in rows:
        ref = stored.get(round(row["h"], 7))
        row["stored_grid"] = None if ref is None else {"J_c": ref["J_c"], "Z_c": ref["Z_c"], "f": ref["f"],
                                                       "iterations": ref.get("iterations"), "tol": grid["key"]["synthesis"].get("tol")}
        j = row["accepted_J"]
        print(f"h = {100 * row['h']:.2f} cm, tol {row['tol']:g}, {row['path']}: J_c {row['J_c']:.5f}, Z_c {row['Z_c']:.4f}, "
              f"valid {row['success']}, {row['iterations']} iterations, {row['searches']} searches, {row['time_s']:.1f} s, "
              f"f^n {row['f'] if row['f'] is None else round(row['f'], 5)}; J of accepted steps {j[:1]} ... {j[-3:]}"
              + ("" if ref is None else f"; stored dense grid J_c {ref['J_c']:.5f} ({ref.get('iterations')} iterations)"))
    out = {"machine": machine_info(), "synthesis_algorithm": synthesis.ALGORITHM, "options": codesign.SYNTHESIS_OPTIONS,
           "rows": rows}
    path = ROOT / "benchmarks" / "results" / f"thin_end_plateau{'_active_set' if args.active_set else ''}.json"
    path.write_text(json.dumps(out, indent=1, default=float) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
