"""Benchmark: the whole paper-setting co-design (24 particles x 20 iterations) on this machine.

Each particle is a full robust multi-model synthesis (notebook 06), warm-started from the previous iteration's
best particle; the particles of an iteration run on a local Dask cluster (one worker per core, one BLAS thread
each). Reports the wall time, the time per objective evaluation split into model assembly, reduction and synthesis,
and the result; saves benchmarks/results/codesign.json. The paper: 11 h 16 min on 24 cores.

Run: python benchmarks/codesign.py [--particles 24] [--iterations 20] [--workers N] [--checkpoint PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from lib import codesign  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--particles", type=int, default=24)
    parser.add_argument("--iterations", type=int, default=20)
    parser.add_argument("--workers", type=int, default=0)
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument("--checkpoint", default="runs/benchmark_codesign_checkpoint.json")
    args = parser.parse_args()
    client = codesign.local_client(args.workers or None)
    n_workers = len(client.scheduler_info()["workers"])
    t0 = time.perf_counter()
    state = codesign.run_codesign(args.particles, args.iterations, (0.015, 0.03), args.seed, client, args.checkpoint)
    wall = time.perf_counter() - t0
    client.close()
    hist = state.history
    mean = lambda k: float(np.mean([r[k] for r in hist]))  # noqa: E731
    best = min(hist, key=lambda r: r["f"])
    out = {
        "machine": {"python": platform.python_version(), "machine": platform.machine(), "cpus": os.cpu_count()},
        "particles": args.particles, "iterations": args.iterations, "workers": n_workers, "evaluations": len(hist),
        "wall_time_s": wall, "wall_time_min": wall / 60,
        "per_evaluation_s": {"assembly": mean("t_build"), "reduction": mean("t_reduction"), "synthesis": mean("t_synthesis"),
                             "total": mean("t_total")},
        "failed_or_penalised": sum(not str(r["status"]).startswith("ok") for r in hist),
        "best": {k: best[k] for k in ("h", "f", "J_c", "Z_c", "mass")},
        "note": "wall_time covers only the iterations run by this call (a resumed run counts the remaining ones)",
    }
    print(json.dumps(out, indent=2))
    path = Path(__file__).parent / "results" / "codesign.json"
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
