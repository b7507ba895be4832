"""Benchmark: where the time of a warm-started co-design evaluation goes, and what a free worst-case search would leave.

Reruns particles of a stored fast-path swarm (``benchmarks/results/codesign_fast_checkpoint.json`` by default) exactly
as the swarm evaluated them: same h, warm-started from the best valid particle of the previous iteration (its gain and
scenario set), by ``lib.codesign.evaluate_particle`` with the fast path, one BLAS thread, under the standard-library
profiler. For each it reports the synthesis time, the part spent in worst-case searches (``lib.synthesis.worst_case``,
cumulative), the model build, and how far J_c is from the stored one (round-off across machines). It then projects the
paper-setting swarm (20 iterations of 24 particles, the first cold) on 2 workers with the searches at no cost: the
floor that a faster search alone can reach, from the sample's mean times and from the swarm's own stored mean times
with the sample's search share.

Prints a line per particle and saves benchmarks/results/codesign_split.json (profiler overhead included).
Run: python benchmarks/codesign_split.py [--iterations 5 10 15 19] [--particles 3 11 17] [--checkpoint PATH]
"""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import pstats
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from lib import codesign, synthesis  # noqa: E402

ROOT = Path(__file__).parents[1]


def _cumulative(stats: pstats.Stats, name: str) -> float:
    """Cumulative time [s] of the functions called ``name`` (outermost calls: worst_case does not call itself)."""
    return sum(v[3] for k, v in stats.stats.items() if k[2] == name)  # type: ignore[attr-defined]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--iterations", type=int, nargs="*", default=[5, 10, 15, 19])
    parser.add_argument("--particles", type=int, nargs="*", default=[3, 11, 17])
    parser.add_argument("--checkpoint", default=str(ROOT / "benchmarks" / "results" / "codesign_fast_checkpoint.json"))
    args = parser.parse_args()
    state = json.loads(Path(args.checkpoint).read_text())
    history = state["history"]
    options = {**codesign.SYNTHESIS_OPTIONS, **(state["extra"].get("options") or {"fast": True})}
    rows = []
    for k in args.iterations:
        previous = [r for r in history if r["iteration"] == k - 1 and r["gain"] is not None and not str(r["status"]).startswith("failed")]
        if not previous:
            raise ValueError(f"iteration {k}: no valid particle in iteration {k - 1} to warm-start from (iterations must be >= 1)")
        best = min(previous, key=lambda r: r["f"])
        for p in args.particles:
            stored = next(r for r in history if r["iteration"] == k and r["particle"] == p)
            prof = cProfile.Profile()
            prof.enable()
            out = codesign.evaluate_particle(stored["h"], gain0=best["gain"], scenarios0=best["scenarios"], synthesis_options=options)
            prof.disable()
            search = _cumulative(pstats.Stats(prof), "worst_case")
            row = {"iteration": k, "particle": p, "h": stored["h"], "t_model_s": out["t_model"], "t_synthesis_s": out["t_synthesis"],
                   "t_search_s": search, "J_c": out["J_c"], "J_c_stored": stored["J_c"], "status": out["status"]}
            rows.append(row)
            print(f"iteration {k} particle {p}: h = {100 * stored['h']:.4f} cm, synthesis {out['t_synthesis']:.1f} s of which searches "
                  f"{search:.1f} s, models {out['t_model']:.1f} s; J_c {out['J_c']:.6f} (stored {stored['J_c']:.6f})", flush=True)
    syn, search = np.mean([r["t_synthesis_s"] for r in rows]), np.mean([r["t_search_s"] for r in rows])
    model = np.mean([r["t_model_s"] for r in rows])
    distinct = float(np.mean([len({r["h"] for r in history if r["iteration"] == k}) for k in range(1, 20)]))
    cold_s = state["extra"]["iteration_wall_s"][0]
    no_search_min = (19 * distinct * (syn - search + model) / 2 + cold_s) / 60
    # the sample's search share applied to the swarm's own mean times (its distinct warm evaluations, as stored)
    own = [r for r in history if r["iteration"] >= 1 and "shared_with" not in r]
    swarm_syn, swarm_model = float(np.mean([r["t_synthesis"] for r in own])), float(np.mean([r["t_model"] for r in own]))
    swarm_min = (19 * distinct * (swarm_syn * (1 - search / syn) + swarm_model) / 2 + cold_s) / 60
    out_json = {"machine": machine_info(), "synthesis_algorithm": synthesis.ALGORITHM, "options": options, "checkpoint": Path(args.checkpoint).name,
                "rows": rows, "mean_synthesis_s": syn, "mean_search_s": search, "search_share": search / syn, "mean_model_s": model,
                "distinct_per_warm_iteration": distinct, "cold_iteration_s": cold_s, "projected_min_with_free_search": no_search_min,
                "swarm_mean_synthesis_s": swarm_syn, "swarm_mean_model_s": swarm_model, "swarm_warm_evaluations": len(own),
                "projected_min_with_free_search_swarm_mean": swarm_min,
                "largest_rel_diff_J_c": max(abs(r["J_c"] / r["J_c_stored"] - 1) for r in rows)}
    path = ROOT / "benchmarks" / "results" / "codesign_split.json"
    path.write_text(json.dumps(out_json, indent=1) + "\n")
    print(f"mean synthesis {syn:.1f} s, searches {search:.1f} s ({100 * search / syn:.0f} %), models {model:.1f} s; with free searches "
          f"the 24 x 20 swarm would take about {no_search_min:.0f} min on 2 workers ({distinct:.1f} distinct particles per warm "
          f"iteration, the stored cold iteration {cold_s / 60:.1f} min); with the swarm's own mean synthesis ({swarm_syn:.1f} s over "
          f"{len(own)} warm evaluations) and the sample's search share: about {swarm_min:.0f} min; saved {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
