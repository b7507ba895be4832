"""Benchmark: the whole co-design (24 particles x 20 iterations) from scratch on this machine, with notebook 07's options.

Each particle is a full robust multi-model synthesis (notebook 06); the particles of an iteration run on a local Dask
cluster (one worker per core, one BLAS thread each). Every synthesis takes notebook 07's options
(``objective.synthesis_options(True, "ball", "least_change")``: the co-design's tolerance, the fast path, the ball trust
region, least-change restoration) and the swarm MATLAB particleswarm's documented rules.

By default the run is notebook 07's headline co-design: the preset ``paper_calibrated``, every design truss-tolerant
(+-2 % of h), every synthesis started cold so that an evaluation is a function of h alone, h on a 0.1 mm resolution
(evaluations shared by every particle at an h already evaluated). ``--preset stated --truss-tolerance 0 --start
previous_best --h-resolution 0`` is the stated-values run (the paper's recipe, warm-started from the previous
iteration's best particle).

Reports the wall time, the distinct evaluations, the time per evaluation split into model assembly, reduction, the
shifted trusses' models (tolerance) and synthesis, and the workers' waiting time (wall time x workers - the
evaluations' time); saves benchmarks/results/codesign_<preset>.json. The paper: 11 h 16 min on 24 cores; the bar here:
under 2 h on 2 cores (goal: 30 min).

An interrupted run resumes from its checkpoint (default ``runs/benchmark_codesign_checkpoint.json``): the wall time
reported is the sum over its iterations, whatever the sessions they ran in.

Run: python benchmarks/codesign.py [--particles 24] [--iterations 20] [--workers N] [--checkpoint PATH] [--stop-after K]
                                   [--preset NAME] [--truss-tolerance T] [--start RULE] [--h-resolution M] [--json PATH]
     python benchmarks/codesign.py --preset stated --report data/results/07_pso_checkpoint.json   # a run already made
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from trusscodesign.study import cluster, codesign, objective
from trusscodesign.model import spacecraft  # noqa: E402
from trusscodesign.control.closedloop import LoopSettings  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--particles", type=int, default=24)
    parser.add_argument("--iterations", type=int, default=None, help="default 20 (with --report: the run's target, if known)")
    parser.add_argument("--workers", type=int, default=0)
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument("--preset", default="paper_calibrated", help="a preset name, or 'stated' for the stated values")
    parser.add_argument("--truss-tolerance", type=float, default=0.02, help="relative section-side error every design survives")
    parser.add_argument("--start", default="cold", choices=codesign.START_RULES)
    parser.add_argument("--h-resolution", type=float, default=1e-4, help="[m]; 0: none")
    parser.add_argument("--checkpoint", default="", help="default runs/benchmark_codesign_<preset>_checkpoint.json")
    parser.add_argument("--stop-after", type=int, default=None,
                        help="stop after this many iterations in all (resume later with the same checkpoint)")
    parser.add_argument("--report", default="", help="report the timing stored in this checkpoint instead of running")
    parser.add_argument("--json", default="", help="where to save the figures (default benchmarks/results/codesign_<preset>.json;"
                        " give another path for a rerun that must not replace the stored one)")
    args = parser.parse_args()
    params = spacecraft.study_parameters(args.preset)
    checkpoint = args.checkpoint or f"runs/benchmark_codesign_{args.preset}_checkpoint.json"
    if args.report:
        from trusscodesign.study import pso

        state = pso.load_state(args.report)
        n_workers = os.cpu_count() or 1
        particles, iterations = len(state.x), state.iteration
    else:
        client = cluster.local_client(args.workers or None)
        n_workers = len(client.scheduler_info()["workers"])
        options = objective.synthesis_options(True, "ball", "least_change")  # notebook 07's defaults
        state = codesign.run_codesign(args.particles, args.iterations or 20, (0.015, 0.03), args.seed, client, checkpoint,
                                      LoopSettings.from_parameters(params), params, synthesis_options=options,
                                      stop_after=args.stop_after, truss_tolerance=args.truss_tolerance, start=args.start,
                                      h_resolution=args.h_resolution or None)
        client.close()
        particles, iterations = args.particles, state.iteration
    wall = float(sum(state.extra.get("iteration_wall_s", [np.nan])))  # over all iterations, resumed runs included
    store = codesign.evaluations_path(args.report or checkpoint)
    if state.extra.get("start") == "cold" and store.exists():  # with the time of iterations interrupted before a resume
        wall = max(wall, float(json.loads(store.read_text())["time_s"]))
    hist = state.history
    start = state.extra.get("start", "previous_best")
    counts = codesign.evaluation_counts(hist, start)
    own = codesign.distinct_evaluations(hist, start)
    mean = lambda k: float(np.mean([r.get(k, 0.0) for r in own]))  # noqa: E731
    best = min(hist, key=lambda r: r["f"])
    out = {
        "machine": machine_info(),
        "particles": particles, "iterations": iterations, "workers": n_workers, "particle_records": len(hist),
        "evaluations": counts["distinct"], "wall_time_s": wall, "wall_time_min": wall / 60,
        "iteration_wall_s": state.extra.get("iteration_wall_s", []),
        "per_evaluation_s": {"assembly": mean("t_build"), "reduction": mean("t_reduction"),
                             "tolerance_models": mean("t_variants"), "synthesis": mean("t_synthesis"), "total": mean("t_total")},
        "worker_waiting_s": wall * n_workers - float(sum(r["t_total"] for r in own)),
        "preset": args.preset, "truss_tolerance": state.extra.get("objective", {}).get("truss_tolerance", 0.0),
        "start": state.extra.get("start", "previous_best"), "h_resolution_m": state.extra.get("h_resolution"),
        "failed_or_penalised": counts["failed"],
        "best": {k: best[k] for k in ("h", "f", "J_c", "Z_c", "mass")},
        "source": args.report or "this run",
        "synthesis_algorithm": state.extra.get("algorithm"), "synthesis_options": state.extra.get("options"), "pso_rule": state.rule,
        "complete": iterations >= (args.iterations or 20) if not args.report or args.iterations else None,  # a checkpoint has no target
    }
    print(json.dumps(out, indent=2))
    path = Path(args.json) if args.json else Path(__file__).parent / "results" / f"codesign_{args.preset}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
