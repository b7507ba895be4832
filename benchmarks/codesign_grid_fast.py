"""Benchmark: notebook 07's dense grid of the co-design objective by the fast path, against the stored dense-path grid.

Evaluates f^n(h) at the 31 points of ``data/results/box/07_grid.json`` (cold syntheses, the co-design's tolerance) with
``synthesis_options = {"tol": 1e-2, "fast": True}`` (:mod:`lib.modalloop`) on a local Dask cluster, and compares
point by point with the stored grid (computed by the dense path, synthesis v4): wall time, synthesis time per point,
J_c, Z_c, validity. The two paths evaluate the same quantities (to 1e-8 in the tests); where the optimiser's path
branches on those differences the syntheses end at different local optima, which this shows.

With ``--tol`` another stopping tolerance of the synthesis (e.g. its default 2e-3 instead of the co-design's 1e-2: the
objective with syntheses run further, ``benchmarks/thin_end_plateau.py``); the files then carry the suffix ``_tol<tol>``.
With ``--trust-region ball`` the synthesis's steps are taken in the box cut by a ball (``benchmarks/trust_region.py``);
suffix ``_ball``.

Prints the comparison and saves benchmarks/results/codesign_grid_fast.json (the records in
benchmarks/results/codesign_grid_fast_records.json, resumable).
Run: python benchmarks/codesign_grid_fast.py [--workers 2] [--tol 0.01] [--trust-region box]
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from lib import codesign, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402

ROOT = Path(__file__).parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--workers", type=int, default=2, help="Dask workers (default 2, one per core)")
    parser.add_argument("--tol", type=float, default=codesign.SYNTHESIS_OPTIONS["tol"],
                        help="stopping tolerance of the synthesis (default the co-design's)")
    parser.add_argument("--trust-region", default="box", choices=["box", "ball"], help="shape of the synthesis's steps")
    args = parser.parse_args()
    suffix = ("" if args.tol == codesign.SYNTHESIS_OPTIONS["tol"] else f"_tol{args.tol:g}") + ("_ball" if args.trust_region == "ball" else "")
    dense = json.loads((ROOT / "data" / "results" / "box" / "07_grid.json").read_text())
    hs = [r["h"] for r in dense["records"]]
    settings = LoopSettings.from_parameters()
    options = {**codesign.SYNTHESIS_OPTIONS, "tol": args.tol, "fast": True,
               **({"trust_region": "ball"} if args.trust_region == "ball" else {})}
    key = {"h": hs, "settings": settings.__dict__, "synthesis": options, "algorithm": synthesis.ALGORITHM}
    client = codesign.local_client(args.workers)
    try:
        records, time_s = codesign.evaluate_grid(hs, client, settings, cache=Path(__file__).parent / "results" / f"codesign_grid_fast{suffix}_records.json",
                                                 key=key, chunk=2 * args.workers, synthesis_options=options)
    finally:
        client.close()
    rows = []
    for d, f in zip(dense["records"], records):  # non-finite values are stored as strings in the JSON files
        d = {**d, **{k: float(d[k]) for k in ("J_c", "Z_c", "f")}}
        f = {**f, **{k: float(f[k]) for k in ("J_c", "Z_c", "f")}}
        rows.append(dict(h=d["h"], dense_J_c=d["J_c"], fast_J_c=f["J_c"], dense_Z_c=d["Z_c"], fast_Z_c=f["Z_c"],
                         dense_status=d["status"], fast_status=f["status"], dense_t_synthesis=d["t_synthesis"],
                         fast_t_synthesis=f["t_synthesis"], dense_f=d["f"], fast_f=f["f"]))
        print(f"h {100 * d['h']:.2f} cm: J_c dense {d['J_c']:.5f} fast {f['J_c']:.5f}; synthesis {d['t_synthesis']:.0f} s -> "
              f"{f['t_synthesis']:.0f} s; {d['status'][:20]} / {f['status'][:20]}")
    same = [r for r in rows if np.isfinite(r["dense_J_c"]) and np.isfinite(r["fast_J_c"])
            and abs(r["fast_J_c"] - r["dense_J_c"]) <= 1e-4 * r["dense_J_c"]]
    i_d, i_f = int(np.argmin([r["dense_f"] for r in rows])), int(np.argmin([r["fast_f"] for r in rows]))
    out = dict(machine=machine_info(),
               synthesis=synthesis.ALGORITHM, options=options, workers=args.workers, points=len(hs),
               wall_s=dict(dense=dense.get("time_s"), fast=time_s),
               synthesis_s_total=dict(dense=float(sum(r["dense_t_synthesis"] for r in rows)),
                                      fast=float(sum(r["fast_t_synthesis"] for r in rows))),
               same_J_c_to_1e4=len(same),
               valid=dict(dense=sum(r["dense_status"] == "ok" for r in rows), fast=sum(r["fast_status"] == "ok" for r in rows)),
               minimum=dict(dense=dict(h=rows[i_d]["h"], f=rows[i_d]["dense_f"]), fast=dict(h=rows[i_f]["h"], f=rows[i_f]["fast_f"])),
               rows=rows)
    print(f"wall time: dense {out['wall_s']['dense'] / 60:.1f} min (stored run), fast {time_s / 60:.1f} min; synthesis time summed "
          f"{out['synthesis_s_total']['dense'] / 60:.1f} -> {out['synthesis_s_total']['fast'] / 60:.1f} min; J_c equal to 1e-4 at "
          f"{len(same)} of {len(rows)} points; valid {out['valid']['dense']} / {out['valid']['fast']}; minimum f^n dense "
          f"{rows[i_d]['dense_f']:.5f} at {100 * rows[i_d]['h']:.2f} cm, fast {rows[i_f]['fast_f']:.5f} at {100 * rows[i_f]['h']:.2f} cm")
    path = Path(__file__).parent / "results" / f"codesign_grid_fast{suffix}.json"
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
