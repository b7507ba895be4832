"""Benchmark: where the time of one robust synthesis goes, at several section sides h.

For each h: the model build (G_r, G_r_low and the spillover model), then one synthesis from all gains at -1 with the
co-design's stopping tolerance (``codesign.SYNTHESIS_OPTIONS``), on one thread (as a Dask worker of notebook 07 runs
it), under the standard-library profiler. The synthesis time is split into:

* ``optimiser_peaks``: peaks of the scenario plants inside the optimiser;
* ``g_r_eig`` (part of the two items above and below): closed-loop eigen-decompositions of the G_r plants, in the
  optimiser and in the search;
* ``spillover_eig``: eigen-decompositions of the nominal spillover model (G_r_low up to 1e4 rad/s, a stability
  constraint of every accepted step);
* ``gradients``: peak gradients (one frequency response of the plant per peak);
* ``lp``: the trust-region linear programs (HiGHS);
* ``stability_rows``: linearised pole margins;
* ``search``: the worst-case searches over the uncertainty box (plants built anew at every point);

with the orders of the models, the iterations and the plant evaluations. The split says which part a faster method
would have to shrink: the cost of the closed-loop eigen-decomposition grows as the cube of the order of G_r, which
is largest at the low end of the design range (more truss modes below the 500 rad/s cut), where the co-design's
optimum lies.

With ``--fast`` the synthesis evaluates the optimiser's plants by the fast path (:mod:`lib.modalloop`, as the
co-design's fast runs do; ``modal_poles`` is then the Aberth iteration of the closed-loop poles, part of
``optimiser_peaks``); with ``--warm`` it starts, as a co-design particle does, from the gain and scenario set of the
stored co-design grid's design nearest below h (``data/results/box/07_grid.json``) instead of all gains at -1.

Prints a table and saves benchmarks/results/synthesis_profile.json (``--out`` elsewhere).
Run: python benchmarks/synthesis_profile.py [--h 0.015 0.02139 0.03] [--fast] [--warm] [--out PATH]
"""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import pstats
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from threadpoolctl import threadpool_limits  # noqa: E402

from _machine import machine_info  # noqa: E402
from lib import codesign, design, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402

# (label, function name in lib/synthesis.py or numpy, restricted to calls from this caller or None)
PARTS = (
    ("optimiser_peaks", "peaks_of", None),
    ("g_r_eig", "eig", "loop_peaks"),
    ("spillover_eig", "_eigen", None),
    ("gradients", "peak_gradient", None),
    ("lp", "_lp", None),
    ("stability_rows", "stability_rows", None),
    ("search", "worst_case", None),
    ("modal_poles", "aberth_poles", None),
)


def _cumulative(stats: pstats.Stats, name: str, caller: str | None) -> float:
    """Cumulative time [s] of the functions called ``name`` (only the calls made from ``caller``, if given)."""
    total = 0.0
    for (_, _, func), (_, _, _, ct, callers) in stats.stats.items():  # type: ignore[attr-defined]  # undocumented table of pstats
        if func != name:
            continue
        if caller is None:
            total += ct
        else:
            total += sum(c[3] for (_, _, f), c in callers.items() if f == caller)
    return total


def _warm_start(h: float) -> tuple[float, dict]:
    """The stored co-design grid's design nearest below ``h`` [m]: its h and the warm-start arguments (gain, scenarios)."""
    grid = json.loads((Path(__file__).parents[1] / "data" / "results" / "box" / "07_grid.json").read_text())
    below = [r for r in grid["records"] if r["h"] < h - 1e-9 and r["status"] == "ok"]
    if not below:
        raise SystemExit(f"--warm: the stored grid has no valid design below h = {h} m")
    rec = max(below, key=lambda r: r["h"])
    return rec["h"], dict(gain0=rec["gain"], scenarios=[synthesis.Scenario.from_vector(v) for v in rec["scenarios"]])


def profile_at(h: float, settings: LoopSettings, fast: bool = False, warm: bool = False) -> dict:
    """Build the models at ``h`` [m] and profile one synthesis (co-design tolerance, one thread): cold, or with
    ``warm`` from the grid's design nearest below h; by the fast path with ``fast``."""
    start: dict = {}
    h_start = None
    if warm:
        h_start, start = _warm_start(h)
    with threadpool_limits(1):
        t0 = time.perf_counter()
        models = design.models_at(h)
        t_model = time.perf_counter() - t0
        prof = cProfile.Profile()
        t0 = time.perf_counter()
        prof.enable()
        res = design.robust_design(models, settings, workers=1, fast=fast, **start, **codesign.SYNTHESIS_OPTIONS)
        prof.disable()
        t_syn = time.perf_counter() - t0
    stats = pstats.Stats(prof)
    parts = {label: _cumulative(stats, name, caller) for label, name, caller in PARTS}
    return {"h": h, "fast": fast, "warm_from_h": h_start, "order_g_r": int(models.g_r.a.shape[0]), "order_spillover": int(models.g_check.a.shape[0]),
            "t_model_s": t_model, "t_synthesis_s": t_syn, "parts_s": parts,
            "other_s": t_syn - sum(v for k, v in parts.items() if k not in ("g_r_eig", "modal_poles")),
            "iterations": res.iterations, "evaluations": res.evaluations, "scenarios": len(res.scenarios),
            "j_c": res.j_c, "z_c": res.z_c, "success": res.success, "message": res.message}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h", type=float, nargs="+", default=[0.015, 0.02139, 0.03], help="section sides [m]")
    ap.add_argument("--fast", action="store_true", help="the fast path (lib.modalloop) in the optimiser")
    ap.add_argument("--warm", action="store_true", help="warm start from the stored grid's design nearest below h")
    ap.add_argument("--out", default=str(Path(__file__).parent / "results" / "synthesis_profile.json"))
    args = ap.parse_args()
    settings = LoopSettings.from_parameters()
    rows = []
    for h in args.h:
        r = profile_at(h, settings, args.fast, args.warm)
        rows.append(r)
        p = r["parts_s"]
        start = "cold" if r["warm_from_h"] is None else f"warm from the {100 * r['warm_from_h']:.2f} cm grid design"
        print(f"[{start}, {'fast' if args.fast else 'dense'} path] h = {100 * h:.3f} cm: G_r order {r['order_g_r']}, spillover model {r['order_spillover']}; model {r['t_model_s']:.1f} s, "
              f"synthesis {r['t_synthesis_s']:.1f} s ({r['iterations']} iterations, {r['evaluations']} plant evaluations, "
              f"{r['scenarios']} scenarios; J_c {r['j_c']:.4f}, Z_c {r['z_c']:.3f}, {'valid' if r['success'] else 'FAILED'})")
        for label, _, _ in PARTS:
            print(f"    {label:16s} {p[label]:7.1f} s  {100 * p[label] / r['t_synthesis_s']:5.1f} %")
        print(f"    {'other':16s} {r['other_s']:7.1f} s")
    out = {"machine": machine_info(),
           "synthesis": synthesis.ALGORITHM, "options": {**codesign.SYNTHESIS_OPTIONS, "fast": args.fast}, "runs": rows,
           "note": "standard-library profiler (cProfile); times include its overhead"}
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(out, indent=1))
    print(f"saved {args.out}")


if __name__ == "__main__":
    main()
