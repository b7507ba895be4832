"""Benchmark: what the Nelder-Mead refinement of the worst-case search adds to its grid, and what it costs.

The worst-case search over the uncertainty box (``lib.synthesis.worst_case``) evaluates 90 candidates (the 8 corners
of (M_SC, Iyy_SC, omega1_SP) and the nominal at 10 panel angles), then refines the 2 best of each group by a bounded
Nelder-Mead search of up to 30 evaluations each. The searches are most of the time of a warm synthesis (README,
co-design section), so a cheaper search is the lever left for the speed targets; this script measures, for designs
stored by notebook 07 (valid particles of the swarm drawn with a fixed seed, and the grid's designs at 2.1-2.2 cm and
3 cm), the grid's worst case alone (``refine=0``) against the full search: value per group, relative increase, time
and plant evaluations, on one thread, at the search damping a synthesis uses.

With ``--budgets 10 15 20`` it also runs the search with those Nelder-Mead budgets (``max_evals``; the synthesis uses
30) and reports how far each falls below the full search per group, and what it saves: the data for a cheaper search.

Prints a line per design and saves benchmarks/results/search_refinement.json.
Run: python benchmarks/search_refinement.py [--swarm-designs 6] [--seed 0] [--budgets 10 15 20]
"""

from __future__ import annotations

import argparse
import inspect
import json
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

from _machine import machine_info  # noqa: E402
from lib import design, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402

ROOT = Path(__file__).parents[1]
_DEFAULTS = {k: v.default for k, v in inspect.signature(synthesis.synthesize).parameters.items()}
SEARCH_DAMPING = _DEFAULTS["search_damping"] * _DEFAULTS["min_damping_all"]  # what a synthesis's searches require


def _designs(n_swarm: int, seed: int) -> list[dict]:
    """Stored designs: ``n_swarm`` valid swarm particles (fixed seed), the grid's at 2.1, 2.15, 2.2 and 3 cm."""
    swarm = json.loads((ROOT / "data" / "results" / "box" / "07_pso_checkpoint.json").read_text())
    valid = [r for r in swarm["history"] if r["status"] == "ok" and r["gain"] is not None]
    picks = [dict(valid[i], source="swarm") for i in np.random.default_rng(seed).choice(len(valid), n_swarm, replace=False)]
    grid = json.loads((ROOT / "data" / "results" / "box" / "07_grid.json").read_text())["records"]
    picks += [dict(r, source="grid") for r in grid
              if r["gain"] is not None and any(abs(r["h"] - h) < 1e-9 for h in (0.021, 0.0215, 0.022, 0.03))]
    return picks


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--swarm-designs", type=int, default=6)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--budgets", type=int, nargs="*", default=[],
                        help="Nelder-Mead budgets (max_evals) to compare with the synthesis's 30")
    args = parser.parse_args()
    settings = LoopSettings.from_parameters()
    rows = []
    with threadpool_limits(1):
        for rec in _designs(args.swarm_designs, args.seed):
            m = design.models_at(rec["h"])
            t0 = time.perf_counter()
            grid = synthesis.worst_case(m.g_r, rec["gain"], m.inertia, settings, refine=0, workers=1, min_damping=SEARCH_DAMPING)
            t1 = time.perf_counter()
            full = synthesis.worst_case(m.g_r, rec["gain"], m.inertia, settings, workers=1, min_damping=SEARCH_DAMPING)
            t2 = time.perf_counter()
            row = dict(h=rec["h"], source=rec["source"], grid_s=t1 - t0, full_s=t2 - t1, grid_evaluations=grid.evaluations,
                       full_evaluations=full.evaluations)
            for group in synthesis.GROUPS:
                row[group] = dict(grid=grid.value[group], full=full.value[group],
                                  increase_pct=100 * (full.value[group] / grid.value[group] - 1),
                                  theta_deg=float(np.rad2deg(full.scenario[group].theta)), omega=full.omega[group])
            row["budgets"] = {}
            for b in args.budgets:
                t3 = time.perf_counter()
                cut = synthesis.worst_case(m.g_r, rec["gain"], m.inertia, settings, max_evals=b, workers=1, min_damping=SEARCH_DAMPING)
                row["budgets"][str(b)] = dict(s=time.perf_counter() - t3, evaluations=cut.evaluations,
                                              **{f"{g}_below_full_pct": 100 * (1 - cut.value[g] / full.value[g]) for g in synthesis.GROUPS})
            rows.append(row)
            print(f"h {100 * rec['h']:.3f} cm ({rec['source']}): grid {row['grid_s']:.1f} s, {grid.evaluations} evals; full "
                  f"{row['full_s']:.1f} s, {full.evaluations} evals; refinement adds J +{row['rpe']['increase_pct']:.2f} %, "
                  f"Z +{row['effort']['increase_pct']:.2f} %" + "".join(
                      f"; budget {b}: {r['s']:.1f} s, J -{r['rpe_below_full_pct']:.2f} %, Z -{r['effort_below_full_pct']:.2f} %"
                      for b, r in row["budgets"].items()), flush=True)
    share = sum(r["full_s"] - r["grid_s"] for r in rows) / sum(r["full_s"] for r in rows)
    print(f"refinement: {100 * share:.0f} % of the search time; largest increase J "
          f"{max(r['rpe']['increase_pct'] for r in rows):.2f} %, Z {max(r['effort']['increase_pct'] for r in rows):.2f} %")
    budgets = {}
    for b in map(str, args.budgets):
        budgets[b] = dict(time_vs_full=sum(r["budgets"][b]["s"] for r in rows) / sum(r["full_s"] for r in rows),
                          **{f"largest_{g}_below_full_pct": max(r["budgets"][b][f"{g}_below_full_pct"] for r in rows)
                             for g in synthesis.GROUPS},
                          designs_within_cover_tol=sum(all(r["budgets"][b][f"{g}_below_full_pct"] <= 100 * _DEFAULTS["cover_tol"]
                                                           for g in synthesis.GROUPS) for r in rows))
        print(f"budget {b}: {100 * budgets[b]['time_vs_full']:.0f} % of the full search's time; largest shortfall J "
              f"{budgets[b]['largest_rpe_below_full_pct']:.2f} %, Z {budgets[b]['largest_effort_below_full_pct']:.2f} %; "
              f"{budgets[b]['designs_within_cover_tol']} of {len(rows)} designs within the coverage tolerance of both groups")
    out = dict(machine=machine_info(), synthesis_algorithm=synthesis.ALGORITHM, threads=1, refinement_time_share=share,
               budgets=budgets, designs=rows)
    path = Path(__file__).parent / "results" / "search_refinement.json"
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
