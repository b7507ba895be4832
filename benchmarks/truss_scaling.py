"""Benchmark: how the cost of a truss of cubes grows with its size, by two paths to the same beams' modes.

For booms of 1, 2, 5, 10, 20 and 50 cubes (1 m, clamped at their base, one free port at the tip) and a 3 x 3 plate
(clamped at its middle cube's base):

- the TITOP state-space path, the paper's (``cubetruss.truss_model``: member-by-member block diagram with channel
  inversions, dense): its build, the removal of its spurious slow poles (``reduction.split_slow``: ordered Schur form
  and Sylvester equation) and the reduction to the modes below ``--cutoff`` (``reduction.residualize_above``), each
  with its time and peak memory (tracemalloc);
- the sparse constrained path (``CubeTruss.modes``, two Ritz modes per field as notebook 04b's validation: the same beams with their tip constraints eliminated beam by beam,
  no spurious poles, sparse shift-invert for the lowest 20 modes);
- the OpenSeesPy frame model of the same truss (10 elements per member, its first 20 frequencies), the reference.

Each size reports the model order, the spurious poles, the times and memory, and the largest relative gap of the first
20 frequencies of each path to OpenSees. A dense stage whose extrapolated time (from the two largest sizes run) exceeds
``--budget`` seconds is not run, and says so. The fitted exponents (time ~ n^p over the booms run) and a log-log figure
are saved with the figures to benchmarks/results/truss_scaling.json and truss_scaling.png.
Run: python benchmarks/truss_scaling.py [--sizes 1 2 5 10 20 50] [--budget 300] [--cutoff 500]
"""

from __future__ import annotations

import argparse
import json
import time
import tracemalloc
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from trusscodesign.model import cubetruss, opensees_fe, reduction, titop  # noqa: E402

SECTION = titop.Section.square(0.02139)
K = 20
N_MODES = 2  # Ritz modes per field of every beam: notebook 04b's validation basis (one mode misses the first 20 of one cube by 1.2 %)


def measured(fn):
    """``fn()``, its wall time [s] and its peak traced memory [MB]."""
    tracemalloc.start()
    t0 = time.perf_counter()
    out = fn()
    seconds = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1] / 1e6
    tracemalloc.stop()
    return out, seconds, peak


def case(name: str, truss: cubetruss.CubeTruss, clamped: list[str], port: str, dense: bool, cutoff: float) -> dict:
    row: dict = {"case": name, "cubes": len(truss.cubes), "members": len(truss.members), "nodes": len(truss.nodes)}
    fe, row["opensees_s"], _ = measured(lambda: opensees_fe.frame_frequencies(truss.nodes, truss.pairs(), SECTION, clamped,
                                                                            10, "consistent", K))
    modes, row["sparse_s"], row["sparse_mb"] = measured(lambda: truss.modes(SECTION, clamped, K, N_MODES))
    row["sparse_gap"] = float(np.max(np.abs(modes.frequencies / fe - 1)))
    if dense:
        model, row["build_s"], row["build_mb"] = measured(
            lambda: cubetruss.truss_model(truss, SECTION, clamped, [port], N_MODES).select([port]))
        row["order"] = model.a.shape[0]
        split, row["remove_s"], row["remove_mb"] = measured(lambda: reduction.split_slow(model.a, model.b, model.c, model.d))
        row["spurious_poles"] = split.n_slow
        fa, fb, fc, fd = split.fast
        (red, _), row["reduce_s"], row["reduce_mb"] = measured(lambda: reduction.residualize_above(fa, fb, fc, fd, cutoff))
        p = np.linalg.eigvals(split.fast[0])
        f = np.sort(np.abs(p[p.imag > 0]))[:K]
        row["dense_gap"] = float(np.max(np.abs(f / fe - 1)))
        row["reduced_order"] = red[0].shape[0]
    print("  ".join(f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}" for k, v in row.items()), flush=True)
    return row


def exponent(rows: list[dict], key: str) -> float | None:
    """Slope of log(time) against log(cubes) over the booms where ``key`` was measured (the two smallest left out:
    fixed costs dominate there)."""
    pts = [(r["cubes"], r[key]) for r in rows if r["case"].startswith("boom") and key in r and r["cubes"] >= 5]
    if len(pts) < 2:
        return None
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 2, 5, 10, 20, 50])
    parser.add_argument("--budget", type=float, default=300.0, help="largest extrapolated time [s] of a dense stage run")
    parser.add_argument("--cutoff", type=float, default=500.0, help="reduction to the modes below this frequency [rad/s]")
    args = parser.parse_args()
    rows: list[dict] = []
    for n in args.sizes:
        done = [r for r in rows if "remove_s" in r]
        dense = True
        if len(done) >= 2:  # extrapolate the slowest dense stage with the exponent of the two largest sizes run
            (n1, t1), (n2, t2) = [(r["cubes"], r["build_s"] + r["remove_s"] + r["reduce_s"]) for r in done[-2:]]
            guess = t2 * (n / n2) ** (np.log(t2 / t1) / np.log(n2 / n1))
            dense = guess <= args.budget
            if not dense:
                print(f"boom of {n} cubes: the dense path not run (about {guess:.0f} s extrapolated > --budget {args.budget:.0f} s)")
        rows.append(case(f"boom {n}", cubetruss.boom(n), ["N1", "N2", "N3", "N4"], f"N{4 * n + 1}", dense, args.cutoff))
        if not dense:
            rows[-1]["dense_skipped_extrapolated_s"] = float(guess)
    plate = cubetruss.plate(3, 3)
    rows.append(case("plate 3 x 3", plate, [plate.cube_nodes["C2_2"][k] for k in ("N1", "N2", "N3", "N4")], "N1", True,
                     args.cutoff))
    exponents = {k: exponent(rows, k) for k in ("build_s", "remove_s", "reduce_s", "sparse_s", "opensees_s")}
    print("exponents (time ~ cubes^p, booms of 5 cubes and more):",
          ", ".join(f"{k} {v:.2f}" for k, v in exponents.items() if v is not None))
    out = Path(__file__).resolve().parent / "results"
    out.mkdir(exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    booms = [r for r in rows if r["case"].startswith("boom")]
    labels = {"build_s": "TITOP block diagram: build", "remove_s": "TITOP: removal of the spurious poles",
              "reduce_s": "TITOP: reduction below the cut-off", "sparse_s": "sparse constrained assembly: 20 modes",
              "opensees_s": "OpenSeesPy: 20 modes (10 elements per member)"}
    for key, label in labels.items():
        pts = [(r["cubes"], r[key]) for r in booms if key in r]
        p = exponents[key]
        ax.loglog(*zip(*pts), "o-", label=f"{label}" + (f" (slope {p:.2f})" if p is not None else ""))
    ax.set_xlabel("cubes in the boom")
    ax.set_ylabel("wall time [s]")
    ax.set_title("Cost of a boom of cubes, by path")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "truss_scaling.png", dpi=120)
    payload = {"machine": machine_info(), "cutoff_rad_s": args.cutoff, "budget_s": args.budget, "section_side_m": 0.02139,
               "rows": rows, "exponents": exponents}
    (out / "truss_scaling.json").write_text(json.dumps(payload, indent=2) + "\n")
    print(f"saved {out / 'truss_scaling.json'} and truss_scaling.png")


if __name__ == "__main__":
    main()
