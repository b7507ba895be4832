"""Benchmark: robust structured synthesis of the PMA gain (cold and warm-started) and the mu sweep per panel angle.

Measures, on this machine (2 cores; one BLAS thread per synthesis worker):

* model build at one h: G_r and G_r_low from one assembly;
* one robust synthesis from all gains at -1 (the paper's cold start) at h = 2.139 cm;
* one synthesis warm-started from the gain of a nearby h (2.0 cm -> 2.139 cm), and one warm-started from its gain and
  its final scenario set, with the co-design's stopping tolerance (as notebook 07 does);
* cold syntheses at h = 2.5 cm with the default stopping tolerance and the co-design's (notebook 07 quotes both);
* the mu analysis (both transfers) at ``--n-tau`` panel angles, per angle (notebook 08 runs 50).

Prints the timings and saves them to benchmarks/results/robust_synthesis.json.
Run: python benchmarks/robust_synthesis.py [--n-tau N]
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

from lib import design, robustness  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n-tau", type=int, default=6)
    args = parser.parse_args()
    settings = LoopSettings.from_parameters()
    out: dict = {"machine": {"python": platform.python_version(), "machine": platform.machine(), "cpus": os.cpu_count()}}
    t0 = time.perf_counter()
    m = design.models_at(0.02139)
    out["models_at_s"] = time.perf_counter() - t0
    cold = design.robust_design(m, settings)
    out["cold"] = dict(time_s=cold.time_s, iterations=cold.iterations, evaluations=cold.evaluations, J_c=cold.j_c, Z_c=cold.z_c,
                       success=cold.success, scenarios=len(cold.scenarios))
    near = design.robust_design(design.models_at(0.020), settings)
    warm = design.robust_design(m, settings, gain0=near.gain)
    out["warm_from_h_2.0cm"] = dict(time_s=warm.time_s, iterations=warm.iterations, evaluations=warm.evaluations, J_c=warm.j_c,
                                    Z_c=warm.z_c, success=warm.success, scenarios=len(warm.scenarios))
    from lib import codesign

    co = design.robust_design(m, settings, gain0=near.gain, scenarios=near.scenarios, **codesign.SYNTHESIS_OPTIONS)
    out["warm_from_h_2.0cm_with_scenarios_codesign_tol"] = dict(time_s=co.time_s, iterations=co.iterations,
                                                                evaluations=co.evaluations, J_c=co.j_c, Z_c=co.z_c,
                                                                success=co.success, scenarios=len(co.scenarios))
    m25 = design.models_at(0.025)
    for name, opts in (("cold_2.5cm_default_tol", {}), ("cold_2.5cm_codesign_tol", codesign.SYNTHESIS_OPTIONS)):
        r = design.robust_design(m25, settings, **opts)
        out[name] = dict(time_s=r.time_s, iterations=r.iterations, evaluations=r.evaluations, J_c=r.j_c, Z_c=r.z_c,
                         success=r.success, scenarios=len(r.scenarios))
    taus = np.linspace(0.0, 1.0, args.n_tau)
    t0 = time.perf_counter()
    gaps = []
    for tau in taus:
        b = robustness.bounds_at_angle(m.g_r_low, 4 * np.arctan(tau), cold.gain, m.inertia, settings)
        gaps += [v.gap for v in b.values()]
    per_angle = (time.perf_counter() - t0) / len(taus)
    out["mu_per_angle_s"] = per_angle
    out["mu_50_angles_estimate_s"] = 50 * per_angle
    out["mu_largest_gap"] = float(max(gaps))
    for k, v in out.items():
        print(f"{k}: {v}")
    path = Path(__file__).parent / "results" / "robust_synthesis.json"
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
