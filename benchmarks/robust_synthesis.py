"""Benchmark: robust structured synthesis of the PMA gain (cold and warm-started) and the mu sweep per panel angle.

Measures, on this machine (2 cores; one BLAS thread per synthesis worker):

* model build at one h: G_r and G_r_low from one assembly;
* one robust synthesis from all gains at -1 (the paper's cold start) at h = 2.139 cm;
* one synthesis warm-started from the gain of a nearby h (2.0 cm -> 2.139 cm), and one warm-started from its gain and
  its final scenario set, with the co-design's stopping tolerance (as notebook 07 does);
* warm starts from the stored co-design grid's design at 2.1 cm (``data/results/07_grid.json``, gain and scenario set)
  to 2.11, 2.139 and 2.2 cm: how the gain fares at the new h before any iteration, and the synthesis time;
* a warm start to 2.139 cm from a truss-tolerant design at 2.1 cm (synthesised with its truss moved by -2, -1, +1 and
  +2 %, which covers 2.139 cm = +1.86 %; notebook 06, section 8), against the grid design's warm start above, by the
  dense path and by the fast one, from its gain alone and from its gain and final scenario set (as a co-design does),
  with the source design synthesised by each path (two local optima; restarted once from its final gain if it fails);
* cold syntheses at h = 2.5 cm with the default stopping tolerance and the co-design's (notebook 07 quotes both);
* the same syntheses by the dense path and by the fast one (``fast=True``, :mod:`trusscodesign.control.modalloop`): cold at 2.139 cm,
  warm from a 2.0 cm design's gain, warm from the grid's 2.1 cm design (co-design tolerance);
* the mu analysis (both transfers) at ``--n-tau`` panel angles, per angle (notebook 08 runs 50).

Prints the timings and saves them to benchmarks/results/robust_synthesis.json.
Run: python benchmarks/robust_synthesis.py [--n-tau N] [--only tolerant|fast]  (``--only``: that case alone, merged into
the saved JSON)
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
from trusscodesign.study import design, robustness  # noqa: E402
from trusscodesign.control.closedloop import LoopSettings  # noqa: E402
from trusscodesign.control.synthesis import SynthesisOptions  # noqa: E402


# the stored co-design grid (notebook 07: ball trust region, least-change restoration, fast path)
GRID = Path("data") / "results" / "07_grid.json"


def grid_design(h0: float) -> tuple[dict, list]:
    """The stored co-design grid's design at ``h0`` [m] (``data/results/07_grid.json``): its record (gain, J_c, ...)
    and its final scenario set, the warm start a co-design makes (notebook 07's Step 3)."""
    from trusscodesign.control import synthesis

    grid = json.loads((Path(__file__).parents[1] / GRID).read_text())
    rec = next((r for r in grid["records"] if abs(r["h"] - h0) < 1e-9), None)
    if rec is None:
        raise ValueError(f"h0 = {h0} m is not a point of the stored co-design grid ({GRID})")
    return rec, [synthesis.Scenario.from_vector(v) for v in rec["scenarios"]]


def _warm_from_grid(h0: float, steps: tuple[float, ...], settings: LoopSettings) -> dict:
    """Warm starts from the co-design grid's design at ``h0`` [m] (its gain and final scenario set, the co-design's
    tolerance) to ``h0 + step``: first how the gain itself fares at the new h (largest real part and smallest
    damping ratio of the closed-loop poles over the scenario set), then the synthesis time."""
    from trusscodesign.study import objective
    from trusscodesign.control import synthesis

    rec, scen = grid_design(h0)
    out = {}
    for step in steps:
        m = design.models_at(h0 + step)
        poles = [synthesis.loop_peaks(synthesis.plant_at(m.g_r, sc, m.inertia, settings), rec["gain"]).poles() for sc in scen]
        zeta = min(float(np.min(-lam.real / np.abs(lam))) for lam in poles)
        r = design.robust_design(m, settings, objective.CODESIGN_OPTIONS, gain0=rec["gain"], scenarios=scen)
        optimiser_steps = [e for e in r.history if e.get("phase") != "stabilise"]
        out[f"+{1e3 * step:g}mm"] = dict(start_max_real=max(float(lam.real.max()) for lam in poles), start_min_damping=zeta,
                                         time_s=r.time_s, iterations=r.iterations, J_c=r.j_c, Z_c=r.z_c, success=r.success,
                                         grid_J_c=rec["J_c"],
                                         # what restoring stability cost: accepted restoration steps, then J and Z after the
                                         # first accepted optimiser step that follows them
                                         stabilise_steps=sum(1 for e in r.history if e.get("phase") == "stabilise"),
                                         first_step_after_restoration=(dict(J=optimiser_steps[0]["J"], Z=optimiser_steps[0]["Z"])
                                                                       if optimiser_steps else None))
    return out


def _row(r) -> dict:
    """The figures of a synthesis result that the benchmark records."""
    return dict(time_s=r.time_s, iterations=r.iterations, evaluations=r.evaluations, J_c=r.j_c, Z_c=r.z_c,
                success=r.success, fallbacks=r.fallbacks, searches=r.searches)


def _warm_from_tolerant(settings: LoopSettings, h0: float = 0.021, h: float = 0.02139,
                        shifts: tuple[float, ...] = (-0.02, -0.01, 0.01, 0.02), fast_source: bool = False) -> dict:
    """Warm start at ``h`` [m] from a design at ``h0`` synthesised to serve its truss moved by ``shifts`` (relative), by
    the dense path or (``fast_source``) the fast one: how the gain fares at the new h before any iteration (default
    scenario set), then the synthesis (co-design tolerance)."""
    from trusscodesign.study import objective
    from trusscodesign.control import synthesis

    m0 = design.models_at(h0)
    # one restart if the source fails (measured on an Intel machine: the fast-path source stopped after 6 rounds, Z_c 1.23)
    src = design.robust_design(m0, settings, SynthesisOptions(fast=fast_source, restarts=1),
                               variants=design.truss_variants(m0, shifts))
    m = design.models_at(h)
    peaks = [synthesis.loop_peaks(synthesis.plant_at(m.g_r, sc, m.inertia, settings), src.gain) for sc in synthesis.default_scenarios()]
    r = design.robust_design(m, settings, objective.CODESIGN_OPTIONS, gain0=src.gain)
    fast = design.robust_design(m, settings, objective.CODESIGN_OPTIONS.replace(fast=True), gain0=src.gain)
    print(f"warm start from the truss-tolerant design: dense {r.time_s:.1f} s ({r.iterations} it, J_c {r.j_c:.5f}), "
          f"fast {fast.time_s:.1f} s ({fast.iterations} it, J_c {fast.j_c:.5f}, {fast.fallbacks} fallbacks)")
    # the warm start a co-design makes: the source's gain and its final scenario set (notebook 07's Step 3)
    with_set = {path: _row(design.robust_design(m, settings, objective.CODESIGN_OPTIONS.replace(fast=path == "fast"),
                                                gain0=src.gain, scenarios=src.scenarios)) for path in ("dense", "fast")}
    print("with the source's scenario set: " + ", ".join(f"{path} {row['time_s']:.1f} s ({row['iterations']} it, "
                                                           f"{row['searches']} searches, J_c {row['J_c']:.5f})"
                                                           for path, row in with_set.items()))
    return dict(source=dict(h=h0, shifts=list(shifts), fast=fast_source, time_s=src.time_s, iterations=src.iterations, J_c=src.j_c,
                            Z_c=src.z_c, success=src.success, restarts=src.restarts, message=src.message),
                start_max_real=max(float(p.poles().real.max()) for p in peaks), start_J=max(p.norm("rpe") for p in peaks),
                start_Z=max(p.norm("effort") for p in peaks), time_s=r.time_s, iterations=r.iterations, evaluations=r.evaluations,
                J_c=r.j_c, Z_c=r.z_c, success=r.success, scenarios=len(r.scenarios),
                fast=_row(fast), with_source_scenarios=dict(scenarios=len(src.scenarios), **with_set))


def _fast_against_dense(settings: LoopSettings) -> dict:
    """The same syntheses by the dense path and by the fast one (``fast=True``, :mod:`trusscodesign.control.modalloop`): cold at
    2.139 cm, warm-started there from the gain of a design at 2.0 cm, and from the co-design grid's 2.1 cm design
    (gain and scenario set, co-design tolerance)."""
    from trusscodesign.study import objective

    m = design.models_at(0.02139)
    near = design.robust_design(design.models_at(0.020), settings, SynthesisOptions(fast=True))
    rec, scen = grid_design(0.021)
    cases = {"cold_2.139cm": (SynthesisOptions(), {}),
             "warm_from_h_2.0cm": (SynthesisOptions(), dict(gain0=near.gain)),
             "warm_from_grid_2.1cm_codesign_tol": (objective.CODESIGN_OPTIONS, dict(gain0=rec["gain"], scenarios=scen))}
    out = {}
    for name, (opts, kw) in cases.items():
        out[name] = {path: _row(design.robust_design(m, settings, opts.replace(fast=path == "fast"), **kw))
                     for path in ("dense", "fast")}
        d, f = out[name]["dense"], out[name]["fast"]
        print(f"{name}: dense {d['time_s']:.1f} s ({d['iterations']} it, J_c {d['J_c']:.5f}), fast {f['time_s']:.1f} s "
              f"({f['iterations']} it, J_c {f['J_c']:.5f}, {f['fallbacks']} fallbacks): x{d['time_s'] / f['time_s']:.2f}")
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n-tau", type=int, default=6)
    parser.add_argument("--only", choices=["tolerant", "fast"], help="run this case alone and merge it into the saved JSON")
    args = parser.parse_args()
    settings = LoopSettings.from_parameters()
    path = Path(__file__).parent / "results" / "robust_synthesis.json"
    if args.only:
        out: dict = json.loads(path.read_text()) if path.exists() else {}
        if args.only == "tolerant":
            for name, fast_source in (("warm_from_truss_tolerant_2.1cm", False), ("warm_from_truss_tolerant_2.1cm_fast_source", True)):
                out[name] = case = _warm_from_tolerant(settings, fast_source=fast_source)
                print(f"{name}: {case}")
        else:
            out["fast_against_dense"] = _fast_against_dense(settings)
        out.setdefault("machine_of_only_runs", {})[args.only] = machine_info()  # "machine" is the full run's
        path.write_text(json.dumps(out, indent=2) + "\n")
        print(f"saved {path}")
        return
    out = {"machine": machine_info()}
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
    from trusscodesign.study import objective

    co = design.robust_design(m, settings, objective.CODESIGN_OPTIONS, gain0=near.gain, scenarios=near.scenarios)
    out["warm_from_h_2.0cm_with_scenarios_codesign_tol"] = dict(time_s=co.time_s, iterations=co.iterations,
                                                                evaluations=co.evaluations, J_c=co.j_c, Z_c=co.z_c,
                                                                success=co.success, scenarios=len(co.scenarios))
    out["warm_from_grid_2.1cm"] = _warm_from_grid(0.021, (0.0001, 0.00039, 0.001), settings)
    out["warm_from_truss_tolerant_2.1cm"] = _warm_from_tolerant(settings)
    out["warm_from_truss_tolerant_2.1cm_fast_source"] = _warm_from_tolerant(settings, fast_source=True)
    out["fast_against_dense"] = _fast_against_dense(settings)
    m25 = design.models_at(0.025)
    for name, opts in (("cold_2.5cm_default_tol", SynthesisOptions()), ("cold_2.5cm_codesign_tol", objective.CODESIGN_OPTIONS)):
        r = design.robust_design(m25, settings, opts)
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
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
