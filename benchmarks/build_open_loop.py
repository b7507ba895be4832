"""Benchmark: time to build the open-loop spacecraft model G at one h (order 1324), to reduce it
(G_r_low, G_r) and to build its uncertain/tunable LFT form; and the models of one design point
(``trusscodesign.study.design.models_at``: G_r, G_r_low and the spillover model of the uncertain model) against the naive path it
is tested against (scipy's ``solve_sylvester``, which recomputes the Schur forms it is given, and ``modal_reduction``
of G_r_low, which splits its slow part again before each cut).

Prints the timings and saves them to benchmarks/results/build_open_loop.json.
Run: python benchmarks/build_open_loop.py [--repeat N]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from _machine import machine_info
from trusscodesign.study import design
from trusscodesign.model import reduction, spacecraft, truss, titop


def timed(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, float(np.median(times)), float(np.min(times))


def naive_models(h: float) -> tuple:
    """The reference path of ``models_at``'s reductions (see the module docstring)."""
    fast = reduction.sylvester_schur
    reduction.sylvester_schur = reduction.sylvester_general
    try:
        lft = spacecraft.open_loop(h, uncertain=True).uncertain().grouped()
        low = reduction.modal_reduction(lft.a, lft.b, lft.c, lft.d)
        return (low, reduction.modal_reduction(*low.reduced, omega_max=500.0),
                reduction.modal_reduction(*low.reduced, omega_max=1e4))
    finally:
        reduction.sylvester_schur = fast


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    spacecraft.open_loop(0.03)  # warm caches (root finding, parameter file)
    rows = {}
    _, med, best = timed(lambda: titop.clamped_free(1.0, titop.Section.square(0.03)), args.repeat)
    rows["beam (order 20)"] = (med, best)
    _, med, best = timed(lambda: truss.t_truss(titop.Section.square(0.03)), args.repeat)
    rows["T-truss (order 1300)"] = (med, best)
    ol, med, best = timed(lambda: spacecraft.open_loop(0.02139), args.repeat)
    rows["open-loop G (order 1324)"] = (med, best)
    g = ol.G
    _, med, best = timed(lambda: reduction.modal_reduction(g.A, g.B, g.C, g.D), max(1, args.repeat // 2))
    rows["G_r_low: removal of the 540 slow poles"] = (med, best)
    _, med, best = timed(lambda: reduction.modal_reduction(g.A, g.B, g.C, g.D, omega_max=500.0), max(1, args.repeat // 2))
    rows["G_r: slow poles + modes above 500 rad/s"] = (med, best)
    for h in (0.015, 0.02139):
        _, med, best = timed(lambda h=h: naive_models(h), max(1, args.repeat // 2))
        rows[f"design models at {100 * h:.3g} cm, naive reference"] = (med, best)
        _, med, best = timed(lambda h=h: design.models_at(h), max(1, args.repeat // 2))
        rows[f"design models at {100 * h:.3g} cm (models_at)"] = (med, best)
    unc, med, best = timed(lambda: spacecraft.open_loop(uncertain=True, tunable=True), max(1, args.repeat // 2))
    rows["uncertain + tunable G(h, Delta) (LFT)"] = (med, best)
    _, med, best = timed(lambda: unc.lft.substitute({"h": 0.02139}), max(1, args.repeat // 2))
    rows["substitute h in the LFT"] = (med, best)
    print(f"{'step':42s} {'median [s]':>11s} {'best [s]':>9s}")
    for name, (med, best) in rows.items():
        print(f"{name:42s} {med:11.3f} {best:9.3f}")
    out = Path(__file__).resolve().parent / "results"
    out.mkdir(exist_ok=True)
    payload = {"machine": machine_info(),
               "repeat": args.repeat, "seconds": {k: {"median": v[0], "best": v[1]} for k, v in rows.items()}}
    (out / "build_open_loop.json").write_text(json.dumps(payload, indent=2) + "\n")
    print(f"saved {out / 'build_open_loop.json'}")


if __name__ == "__main__":
    main()
