"""Benchmark: notebook 08's mu sweep (both transfers at 50 panel angles) in this process and on a local Dask cluster.

The angles of the sweep are independent (:func:`trusscodesign.study.robustness.sweep`), so on the 2-core reference machine they can
run on two single-threaded workers. This script times the sweep of notebook 08's settings (``n_tau`` angles with
tau = tan(theta/4) evenly spaced in [0, 1], ``n_log`` = 150, ``focus`` = 0.7, seed 2026) on one design:

* in this process (one thread, as notebook 08 ran it before) and on ``--workers`` Dask workers, one after the other;
* the largest relative difference between the two runs' bounds, and the largest gap upper/lower - 1.

The design is the one notebook 08 analyses by default: notebook 07's optimum if stored, else notebook 06's design at
2.139 cm (``--design 06`` to force it). Prints and saves benchmarks/results/mu_sweep.json.
Run: python benchmarks/mu_sweep.py [--design auto|06|07] [--n-tau 50] [--workers 2]
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
from trusscodesign.study import cluster, design, robustness
from trusscodesign.model import spacecraft  # noqa: E402
from trusscodesign.control.closedloop import LoopSettings  # noqa: E402


def _flat(sweep: list[dict]) -> dict[str, np.ndarray]:
    """Upper and lower bounds of a sweep as arrays (angle x transfer)."""
    return {key: np.array([[getattr(b, key) for b in out.values()] for out in sweep]) for key in ("upper", "lower")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--design", choices=["auto", "06", "07"], default="auto")
    parser.add_argument("--n-tau", type=int, default=50)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    source, h, gain = design.stored_design(args.design)
    params = spacecraft.study_parameters(design.stored_preset(args.design))  # those the design was made for
    settings = LoopSettings.from_parameters(params)
    models = design.models_at(h, params)
    thetas = 4 * np.arctan(np.linspace(0.0, 1.0, args.n_tau))
    opts: dict = dict(n_log=150, focus=0.7, seed=2026)

    t0 = time.perf_counter()
    seq = robustness.sweep(models.g_r_low, thetas, gain, models.inertia, settings, **opts)
    t_seq = time.perf_counter() - t0
    print(f"design {source} (h = {100 * h:.3f} cm): {args.n_tau} angles in this process: {t_seq:.1f} s", flush=True)

    t0 = time.perf_counter()
    client = cluster.local_client(args.workers)
    t_start = time.perf_counter() - t0
    try:
        par = robustness.sweep(models.g_r_low, thetas, gain, models.inertia, settings, client=client, **opts)
    finally:
        cluster.close_client(client)
    t_par = time.perf_counter() - t0
    a, b = _flat(seq), _flat(par)
    diff = {key: float(np.max(np.abs(b[key] / a[key] - 1))) for key in a}
    gap = float(np.max(a["upper"] / a["lower"] - 1))
    print(f"{args.workers} workers: {t_par:.1f} s (of which {t_start:.1f} s to start the cluster): x{t_seq / t_par:.2f}; "
          f"largest relative difference upper {diff['upper']:.1e}, lower {diff['lower']:.1e}; largest gap {100 * gap:.3f} %")
    out = dict(machine=machine_info(), design=dict(source=source, h=h, preset=design.stored_preset(args.design)), n_tau=args.n_tau, options=opts,
               in_process_s=t_seq, workers=args.workers, dask_s=t_par, dask_cluster_start_s=t_start, speed_up=t_seq / t_par,
               largest_relative_difference=diff, largest_gap=gap)
    path = Path(__file__).parent / "results" / "mu_sweep.json"
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
