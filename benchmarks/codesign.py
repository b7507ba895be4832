"""Benchmark: the whole paper-setting co-design (24 particles x 20 iterations) on this machine, with notebook 07's options.

Each particle is a full robust multi-model synthesis (notebook 06), warm-started from the previous iteration's
best particle; the particles of an iteration run on a local Dask cluster (one worker per core, one BLAS thread
each). Every synthesis takes notebook 07's default options (``codesign.synthesis_options(True, "ball", "least_change")``:
the co-design's tolerance, the fast path, the ball trust region, least-change restoration) and the swarm MATLAB
particleswarm's documented rules. Reports the wall time, the time per objective evaluation split into model assembly,
reduction and synthesis, and the result; saves benchmarks/results/codesign.json. The paper: 11 h 16 min on 24 cores;
the target here: under 60 min on 2 cores.

An interrupted run resumes from its checkpoint (default ``runs/benchmark_codesign_checkpoint.json``): the wall time
reported is the sum over its iterations, whatever the sessions they ran in.

Run: python benchmarks/codesign.py [--particles 24] [--iterations 20] [--workers N] [--checkpoint PATH] [--stop-after K]
                                   [--json PATH]
     python benchmarks/codesign.py --report data/results/07_pso_checkpoint.json   # the timing of a run already made
                                                                                  # (notebook 07's main job)
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from trusscodesign import codesign  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--particles", type=int, default=24)
    parser.add_argument("--iterations", type=int, default=None, help="default 20 (with --report: the run's target, if known)")
    parser.add_argument("--workers", type=int, default=0)
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument("--checkpoint", default="runs/benchmark_codesign_checkpoint.json")
    parser.add_argument("--stop-after", type=int, default=None,
                        help="stop after this many iterations in all (resume later with the same checkpoint)")
    parser.add_argument("--report", default="", help="report the timing stored in this checkpoint instead of running")
    parser.add_argument("--json", default="", help="where to save the figures (default benchmarks/results/codesign.json;"
                        " give another path for a rerun that must not replace the stored one)")
    args = parser.parse_args()
    if args.report:
        from trusscodesign import pso

        state = pso.load_state(args.report)
        n_workers = os.cpu_count()
        particles, iterations = len(state.x), state.iteration
    else:
        client = codesign.local_client(args.workers or None)
        n_workers = len(client.scheduler_info()["workers"])
        options = codesign.synthesis_options(True, "ball", "least_change")  # notebook 07's defaults
        state = codesign.run_codesign(args.particles, args.iterations or 20, (0.015, 0.03), args.seed, client, args.checkpoint,
                                      synthesis_options=options, stop_after=args.stop_after)
        client.close()
        particles, iterations = args.particles, state.iteration
    wall = float(sum(state.extra.get("iteration_wall_s", [np.nan])))  # over all iterations, resumed runs included
    hist = state.history
    own = [r for r in hist if "shared_with" not in r]  # particles at the same h share one evaluation
    mean = lambda k: float(np.mean([r[k] for r in own]))  # noqa: E731
    best = min(hist, key=lambda r: r["f"])
    out = {
        "machine": machine_info(),
        "particles": particles, "iterations": iterations, "workers": n_workers, "particle_records": len(hist),
        "evaluations": len(own), "wall_time_s": wall, "wall_time_min": wall / 60,
        "iteration_wall_s": state.extra.get("iteration_wall_s", []),
        "per_evaluation_s": {"assembly": mean("t_build"), "reduction": mean("t_reduction"), "synthesis": mean("t_synthesis"),
                             "total": mean("t_total")},
        "failed_or_penalised": sum(not str(r["status"]).startswith("ok") for r in own),
        "best": {k: best[k] for k in ("h", "f", "J_c", "Z_c", "mass")},
        "source": args.report or "this run",
        "synthesis_algorithm": state.extra.get("algorithm"), "synthesis_options": state.extra.get("options"), "pso_rule": state.rule,
        "complete": iterations >= (args.iterations or 20) if not args.report or args.iterations else None,  # a checkpoint has no target
    }
    print(json.dumps(out, indent=2))
    path = Path(args.json) if args.json else Path(__file__).parent / "results" / "codesign.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
