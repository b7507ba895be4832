"""Benchmark: MATLAB particleswarm's adaptive rules as documented against as coded (``lib.pso``, ``rule=``).

The two differ in when the inertia W adapts (documented text: only after an iteration that improved the swarm's best;
MATLAB's code: after every iteration) and in the neighbourhood (the particle plus N others, or plus N - 1). This runs
the paper's swarm (24 particles, 20 iterations, h in [1.5, 3] cm) with each rule over many seeds on two cheap
objectives, so that the difference is measured, not argued:

* ``grid``: the co-design objective f^n(h) interpolated linearly between the 31 points of the stored dense grid
  (``data/results/box/07_grid.json``, cold syntheses). A surrogate only: the real f^n also depends on each particle's warm
  start (notebook 07, section 5), which no interpolation holds;
* ``multimodal``: ``1 + (x - 0.3)^2 + 0.1 sin^2(20 x)`` on the same range scaled to [0, 1] (local minima near 0.15 and
  0.45; the 1 puts it at the scale of f^n, so that the relative gap is comparable).

Per rule and objective: the share of seeds whose best is within 1 % of the objective's minimum (f^n is near 1, so the
gap is relative), the median and worst gap, the final inertia and the final spread of the swarm (max - min of the
positions, relative to the range).

Prints a table and saves benchmarks/results/pso_rules.json.
Run: python benchmarks/pso_rules.py [--seeds 200]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from _machine import machine_info
from lib import pso

ROOT = Path(__file__).parents[1]
H_RANGE = (0.015, 0.03)


def _grid_objective() -> tuple[np.ndarray, np.ndarray]:
    """The stored grid's (h, f^n), sorted by h."""
    records = json.loads((ROOT / "data" / "results" / "box" / "07_grid.json").read_text())["records"]
    h = np.array([r["h"] for r in records])
    f = np.array([r["f"] for r in records])
    order = np.argsort(h)
    return h[order], f[order]


def _multimodal(h: np.ndarray) -> np.ndarray:
    x = (h - H_RANGE[0]) / (H_RANGE[1] - H_RANGE[0])
    return 1.0 + (x - 0.3) ** 2 + 0.1 * np.sin(20 * x) ** 2


def _study(fun, f_min: float, rule: str, seeds: int, n: int, iterations: int) -> dict:
    gaps, inertia, spread = [], [], []
    for seed in range(seeds):
        state = pso.run(lambda x, st: [{"f": float(v)} for v in fun(x[:, 0])], n, [H_RANGE[0]], [H_RANGE[1]], iterations, seed,
                        rule=rule)
        gaps.append(state.g_f / f_min - 1)
        inertia.append(state.inertia)
        spread.append(float(np.ptp(state.x[:, 0]) / (H_RANGE[1] - H_RANGE[0])))
    gaps_a = np.array(gaps)
    return dict(within_1pct=float(np.mean(gaps_a <= 0.01)), median_gap=float(np.median(gaps_a)), worst_gap=float(gaps_a.max()),
                median_final_inertia=float(np.median(inertia)), median_final_spread=float(np.median(spread)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, default=200)
    parser.add_argument("--particles", type=int, default=24)
    parser.add_argument("--iterations", type=int, default=20)
    args = parser.parse_args()
    h_grid, f_grid = _grid_objective()
    fine = np.linspace(*H_RANGE, 200001)
    objectives = {
        "grid": (lambda h: np.interp(h, h_grid, f_grid), float(f_grid.min())),
        "multimodal": (_multimodal, float(_multimodal(fine).min())),
    }
    out: dict = {"machine": machine_info(), "seeds": args.seeds, "particles": args.particles, "iterations": args.iterations,
                 "objectives": {}}
    t0 = time.perf_counter()
    print(f"{'objective':<11} {'rule':<11} {'within 1 %':>10} {'median gap':>11} {'worst gap':>10} {'final W':>8} {'spread':>7}")
    for name, (fun, f_min) in objectives.items():
        out["objectives"][name] = {"minimum": f_min}
        for rule in pso.RULES:
            r = _study(fun, f_min, rule, args.seeds, args.particles, args.iterations)
            out["objectives"][name][rule] = r
            print(f"{name:<11} {rule:<11} {100 * r['within_1pct']:>9.1f}% {100 * r['median_gap']:>10.3f}% "
                  f"{100 * r['worst_gap']:>9.2f}% {r['median_final_inertia']:>8.3f} {r['median_final_spread']:>7.3f}")
    out["time_s"] = time.perf_counter() - t0
    path = ROOT / "benchmarks" / "results" / "pso_rules.json"
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path} ({out['time_s']:.1f} s)")


if __name__ == "__main__":
    main()
