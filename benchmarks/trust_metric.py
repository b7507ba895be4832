"""Benchmark: the synthesis's trust region in a learnt (BFGS) metric against the ball, notebook 07's other options kept.

``lib.synthesis.synthesize(trust_region="bfgs")``: the step's region is the ball of ``trust_region="ball"`` in the norm
of a BFGS estimate of J's curvature (:class:`lib.synthesis._Metric`), learnt from the change of J's subgradient over the
accepted steps. In the ball, the linear program's step is a steepest-descent step: on a warm start 2.4 -> 2.5 cm it
took 25 steps in a row on the ball, each predicting 0.42 % less J and giving 0.26 %.

This script runs, with notebook 07's options otherwise (co-design tolerance, fast path, least-change restoration), both
regions on:

* warm starts from the stored co-design grid's designs (``data/results/07_grid.json``, gain and scenario set) at 1.6,
  1.9, 2.1, 2.4 and 2.8 cm to h + 0.39 mm, + 1 mm and + 3 mm (steps past 3 cm left out);
* cold starts (all gains at -1) at 1.5, 2.139 and 3 cm;

one thread per synthesis, two syntheses at a time (``--processes``), or with ``--alone`` each synthesis alone on the
machine with two threads (the synthesis issue's setting for its "under 10 s"), and records J_c, Z_c, validity,
iterations, searches and time. Prints a line per run and a summary and saves benchmarks/results/trust_metric.json
(``trust_metric_alone.json`` with ``--alone``).
Run: python benchmarks/trust_metric.py [--processes 2] [--steps 0.00039 0.001 0.003] [--no-cold] [--regions ball bfgs]
     [--alone]
"""

from __future__ import annotations

import argparse
import json
import os
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from _machine import machine_info  # noqa: E402
from restoration import cases, run_case, summary  # noqa: E402
from lib import codesign, synthesis  # noqa: E402

ROOT = Path(__file__).parents[1]
STEPS = (0.00039, 0.001, 0.003)


def _run(job: tuple[str, float, float | None, str, int]) -> dict:
    """One synthesis of a case with a trust region and a number of threads (``workers``); its record."""
    name, h, h0, region, workers = job
    options = dict(codesign.synthesis_options(True, "ball", "least_change") or {}, trust_region=region)
    return run_case(name, h, h0, options, workers, trust_region=region)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--steps", type=float, nargs="+", default=list(STEPS))
    parser.add_argument("--cold", action=argparse.BooleanOptionalAction, default=True)
    parser.add_argument("--regions", nargs="+", default=["ball", "bfgs"], choices=("box", "ball", "bfgs"))
    parser.add_argument("--alone", action="store_true",
                        help="each synthesis alone on the machine with two threads (workers=2), one after the other; "
                             "results to trust_metric_alone.json")
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    if args.alone:
        args.processes = 1
    out_name = args.out or ("trust_metric_alone.json" if args.alone else "trust_metric.json")
    jobs = [(*case, region, 2 if args.alone else 1) for case in cases(tuple(args.steps), args.cold) for region in args.regions]
    # the longest first (cold starts), so that two processes finish together
    jobs.sort(key=lambda j: (j[2] is not None, -j[1] if j[2] is None else 0))
    with ProcessPoolExecutor(args.processes) as pool:
        rows = list(pool.map(_run, jobs))
    for row in rows:
        print(f"{row['case']}, {row['trust_region']}: J_c {row['J_c']:.5f}, Z_c {row['Z_c']:.4f}, valid {row['success']}, "
              f"{row['iterations']} iterations, {row['searches']} searches, {row['time_s']:.1f} s")
    result = {kind: summary(rows, "trust_region", args.regions, kind == "warm", iterations=True) for kind in ("warm", "cold")}
    for kind, per in result.items():
        for region, s in per.items():
            print(f"{kind}, {region}: {s['valid']}/{s['runs']} valid, time median {s['median_time_s']:.1f} s "
                  f"(max {s['max_time_s']:.1f} s, {s['under_10_s']} under 10 s), median J_c {s['median_J_c']:.5f}, "
                  f"median iterations {s['median_iterations']:.0f}, median searches {s['median_searches']:.0f}")
    out = {"machine": machine_info(), "synthesis_algorithm": synthesis.ALGORITHM, "processes": args.processes,
           "threads_per_synthesis": 2 if args.alone else 1,
           "steps": args.steps, "rows": rows, "summary": result}
    path = ROOT / "benchmarks" / "results" / out_name
    path.write_text(json.dumps(out, indent=1))
    print(f"saved {path}")


if __name__ == "__main__":
    main()
