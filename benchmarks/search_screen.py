"""Benchmark: can a smaller model screen the candidates of the worst-case search? (Measured: no, not safely.)

The worst-case search (``lib.synthesis.worst_case``) is the floor of the co-design's time (README, co-design section):
each of its ~200 evaluations is a dense eigen-decomposition of the closed loop on ``G_r`` (order 294 at 1.5 cm). A
screen would rank the 90 grid candidates (and drive the Nelder-Mead refinement) on a cheaper model, ``G_r`` with its
modes above ``omega_s`` residualised (static part kept, as ``lib.reduction.residualize_above``), and evaluate only the
best few on ``G_r``. This script measures, at the grid candidates of stored designs (the swarm particles and grid points
of ``benchmarks/search_refinement.py``), how far each screen's peaks are from ``G_r``'s (largest relative difference per
group), whether ``G_r``'s worst candidate is among the screen's 3 best, and the time per evaluation.

Prints a line per design and screen and saves benchmarks/results/search_screen.json.
Run: python benchmarks/search_screen.py [--swarm-designs 6] [--seed 0] [--omegas 200 300 400]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

from _machine import machine_info  # noqa: E402
from search_refinement import SEARCH_DAMPING, _designs  # noqa: E402
from lib import design, reduction, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402
from lib.lft import LFT  # noqa: E402

ROOT = Path(__file__).parents[1]
GRID = synthesis.search_candidates()  # the worst-case search's 90 candidates


def _peaks(model: LFT, gain: np.ndarray, inertia: np.ndarray, settings: LoopSettings) -> tuple[np.ndarray, np.ndarray, float]:
    """(rpe, effort) peaks at the 90 candidates (inf where unstable) and their frequencies [rad/s], as the search evaluates
    them (lazy damping cap bounded near the nominal passive pole), and the time per evaluation [s]."""
    t0 = time.perf_counter()
    near = synthesis.plant_at(model, synthesis.Scenario(), inertia, settings).passive_pole()
    out, omega = [], []
    for sc in GRID:
        lp = synthesis.loop_peaks(synthesis.plant_at(model, sc, inertia, settings), gain, n_peaks=1, min_damping=SEARCH_DAMPING,
                                  lazy_cap=True, passive_near=near)
        out.append([lp.norm(g) for g in synthesis.GROUPS])
        omega.append([lp.omega(g) for g in synthesis.GROUPS])
    return np.array(out), np.array(omega), (time.perf_counter() - t0) / len(GRID)


def _damping_near(model: LFT, sc: synthesis.Scenario, gain: np.ndarray, inertia: np.ndarray, settings: LoopSettings,
                  omega: float) -> float:
    """Damping ratio of the closed-loop pole of ``model`` nearest the frequency ``omega`` [rad/s] at scenario ``sc``."""
    lam = synthesis.plant_at(model, sc, inertia, settings).closed_loop_poles(gain)
    pole = lam[np.argmin(np.abs(np.abs(lam.imag) - omega))]
    return float(-pole.real / abs(pole))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--swarm-designs", type=int, default=6)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--omegas", type=float, nargs="*", default=[200.0, 300.0, 400.0])
    args = parser.parse_args()
    settings = LoopSettings.from_parameters()
    rows = []
    with threadpool_limits(1):
        for rec in _designs(args.swarm_designs, args.seed):
            models = design.models_at(rec["h"])
            gain = np.array(rec["gain"])
            ref, w_ref, t_ref = _peaks(models.g_r, gain, models.inertia, settings)
            row = {"h": rec["h"], "source": rec["source"], "order": models.g_r.a.shape[0], "s_per_evaluation": t_ref, "screens": {}}
            for omega in args.omegas:
                red, _ = reduction.residualize_above(models.g_r.a, models.g_r.b, models.g_r.c, models.g_r.d, omega)
                val, _, t_s = _peaks(LFT(*red, models.g_r.blocks, models.g_r.params), gain, models.inertia, settings)
                both = np.isfinite(ref) & np.isfinite(val)
                rel = np.where(both, np.abs(val - ref) / np.where(both, ref, 1.0), 0.0)
                diff = rel.max(axis=0)
                i = int(np.argmax(rel[:, 1]))  # the candidate of the largest effort difference: its G_r peak and pole
                found = [bool(np.argmax(ref[:, j]) in np.argsort(-val[:, j])[:3]) for j in range(2)]
                row["screens"][str(omega)] = {"order": red[0].shape[0], "s_per_evaluation": t_s,
                                              "stability_verdicts_differ": int((np.isfinite(ref) != np.isfinite(val)).any(axis=1).sum()),
                                              **{f"{g}_largest_rel_diff": float(diff[j]) for j, g in enumerate(synthesis.GROUPS)},
                                              **{f"{g}_worst_in_screen_top3": found[j] for j, g in enumerate(synthesis.GROUPS)},
                                              "largest_effort_diff_at": {"scenario": GRID[i].vector().tolist(), "omega": float(w_ref[i, 1]),
                                                                         "damping_of_nearest_pole": _damping_near(models.g_r, GRID[i], gain,
                                                                                                                  models.inertia, settings,
                                                                                                                  float(w_ref[i, 1]))}}
                s = row["screens"][str(omega)]
                print(f"h = {100 * rec['h']:.4f} cm ({rec['source']}), order {row['order']} ({1e3 * t_ref:.1f} ms/eval); screen "
                      f"{omega:.0f} rad/s: order {s['order']} ({1e3 * t_s:.1f} ms/eval), largest difference RPE "
                      f"{100 * s['rpe_largest_rel_diff']:.2f} %, effort {100 * s['effort_largest_rel_diff']:.2f} %, worst in top 3: "
                      f"{found}, stability verdicts differing: {s['stability_verdicts_differ']}; largest effort difference at "
                      f"{s['largest_effort_diff_at']['omega']:.1f} rad/s (G_r pole damping {s['largest_effort_diff_at']['damping_of_nearest_pole']:.1e})",
                      flush=True)
            rows.append(row)
    summary = {str(o): {f"{g}_largest_rel_diff": max(r["screens"][str(o)][f"{g}_largest_rel_diff"] for r in rows) for g in synthesis.GROUPS}
               for o in args.omegas}
    out = {"machine": machine_info(), "synthesis_algorithm": synthesis.ALGORITHM, "threads": 1, "candidates": len(GRID),
           "search_damping": SEARCH_DAMPING, "summary": summary, "designs": rows}
    path = ROOT / "benchmarks" / "results" / "search_screen.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"largest differences over the designs: {summary}; saved {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
