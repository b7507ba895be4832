"""Benchmark: the mu upper bound certified over all frequencies (lib.mu_interval) at the worst panel angles of notebook 08.

Notebook 08 certifies the upper bound over every frequency at the critical angle of each transfer (section 4b). This
script does it at the ``--top`` angles with the largest upper bound of each transfer in the stored sweep
(``data/results/box/08_worst_case_mu.json``), on ``--workers`` Dask workers (one job per angle and transfer): at each, the
grid bounds of :func:`lib.robustness.bounds_at_angle` (as the sweep computes them), then
:func:`lib.robustness.certify_at_angle` from the grid's frequencies. It records the certified level, whether the whole
frequency axis is covered, the points it took and the largest pointwise bound found among them: above the grid's upper
bound, the grid had missed a worse frequency at that angle.

Prints and saves benchmarks/results/mu_certify.json.
Run: python benchmarks/mu_certify.py [--top 3] [--slack 0.02] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from lib import codesign, design, robustness  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402

ROOT = Path(__file__).parents[1]


def _job(args: tuple, models: design.DesignModels) -> dict:
    """Grid bounds and the certified bound of one transfer at one angle [deg]."""
    gain, theta_deg, group, slack, opts = args
    settings = LoopSettings.from_parameters()
    t0 = time.perf_counter()
    grid = robustness.bounds_at_angle(models.g_r_low, np.deg2rad(theta_deg), gain, models.inertia, settings, groups=(group,),
                                      **opts)[group]
    t1 = time.perf_counter()
    cert = robustness.certify_at_angle(models.g_r_low, np.deg2rad(theta_deg), gain, models.inertia, settings, group,
                                       grid.omegas, slack=slack)
    return dict(group=group, theta_deg=theta_deg, grid_upper=grid.upper, lower=grid.lower, certified_upper=cert.gamma,
                covered=cert.covered, points=len(cert.omegas), largest_point_bound=float(cert.betas.max()),
                missed_by_grid=float(cert.betas.max() / grid.upper - 1), grid_s=t1 - t0, certify_s=time.perf_counter() - t1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--top", type=int, default=3, help="angles per transfer, those with the largest upper bound")
    parser.add_argument("--slack", type=float, default=0.02)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    stored = json.loads((ROOT / "data" / "results" / "box" / "08_worst_case_mu.json").read_text())
    res, params = stored["results"], stored["parameters"]
    models = design.models_at(res["h"])
    gain = np.array(res["gain"])
    opts = dict(n_log=params["n_log"], focus=params["focus"], seed=params["seed"])
    jobs = []
    for group in ("rpe", "effort"):
        rows = sorted((r for r in res["sweep"] if r["group"] == group), key=lambda r: -r["upper"])[:args.top]
        jobs += [(gain, float(r["theta_deg"]), group, args.slack, opts) for r in rows]
    t0 = time.perf_counter()
    client = codesign.local_client(args.workers)
    try:
        # the models sent once per worker, not once per job (as lib.robustness.sweep does)
        out = client.gather(client.map(_job, jobs, models=client.scatter(models, broadcast=True), pure=False))
    finally:
        codesign.close_client(client)
    wall = time.perf_counter() - t0
    for r in out:
        print(f"{r['group']:6s} {r['theta_deg']:6.1f} deg: grid upper {r['grid_upper']:.6f}, lower {r['lower']:.6f}, certified "
              f"{r['certified_upper']:.6f} ({'covered' if r['covered'] else 'NOT covered'}, {r['points']} points, {r['certify_s']:.0f} s); "
              f"largest pointwise bound {r['largest_point_bound']:.6f} ({100 * r['missed_by_grid']:+.4f} % of the grid's)")
    print(f"{len(out)} certifications in {wall:.0f} s on {args.workers} workers; all covered: {all(r['covered'] for r in out)}; "
          f"largest excess of a pointwise bound over the grid's: {100 * max(r['missed_by_grid'] for r in out):+.4f} %")
    path = Path(__file__).parent / "results" / "mu_certify.json"
    path.write_text(json.dumps(dict(machine=machine_info(), design_h=res["h"], slack=args.slack, top=args.top, wall_s=wall,
                                    jobs=out), indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
