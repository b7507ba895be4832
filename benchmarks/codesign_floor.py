"""Benchmark: the lowest time the paper-setting co-design (24 x 20) can take with the current synthesis, from its parts.

The swarm spends nearly all its time in warm-started robust syntheses at the low end of H, where its particles
gather. This script measures, on one thread (as a Dask worker of notebook 07 runs a particle):

* the cost of one plant evaluation (closed-loop poles and peaks of one scenario, ``lib.synthesis.loop_peaks``) and
  the order of the closed loop, at h = 1.5, 2.139 and 3 cm, and of one spillover check (the nominal ``G_r_low`` loop
  up to 1e4 rad/s);
* one warm-started synthesis at 1.5 cm from the gain and scenario set a next swarm iteration would start from (the
  stored swarm's last best particle, at 1.529 cm), with the co-design's
  tolerance (its iterations, accepted steps, plant evaluations and time), then one worst-case search over the
  uncertainty box with its final gain (plant evaluations and time);

and, from the stored swarm (``data/results/box/07_pso_checkpoint.json``), the mean number of distinct particles per
iteration. With ``--fast`` the same plant evaluations and warm synthesis are also measured by the fast path
(``fast=True``, :mod:`lib.modalloop`), with its projection. Two projections of the 24 x 20 run, ``20 x distinct particles x (model + synthesis) / workers`` with the
workers never idle: with the measured warm synthesis, and with a synthesis that only verifies its start (evaluates
its scenario set twice and searches the box once, no optimisation step): a floor for any synthesis that keeps this
scenario set, this search and these plants.

Prints the figures and saves benchmarks/results/codesign_floor.json.
Run: python benchmarks/codesign_floor.py [--workers 2] [--repeat 20] [--fast]
"""

from __future__ import annotations

import argparse
import inspect
import json
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from lib import codesign, design, pso, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402

from build_open_loop import timed  # noqa: E402  (benchmarks/ is on the path when a benchmark runs as a script)

ROOT = Path(__file__).parents[1]
# the synthesis's own pole-damping requirements, so that the timed evaluations do what the synthesis does
_DEFAULTS = {k: v.default for k, v in inspect.signature(synthesis.synthesize).parameters.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--workers", type=int, default=2, help="Dask workers of the co-design (default 2, one per core)")
    parser.add_argument("--repeat", type=int, default=20, help="repetitions of each timed plant evaluation")
    parser.add_argument("--fast", action="store_true", help="also measure the fast path (lib.modalloop)")
    args = parser.parse_args()
    settings = LoopSettings.from_parameters()
    state = pso.load_state(ROOT / "data" / "results" / "box" / "07_pso_checkpoint.json")
    gain = np.array(state.extra["best_gain"])
    scen = [synthesis.Scenario.from_vector(v) for v in state.extra["best_scenarios"]]
    from lib.modalloop import ModalLoop

    out: dict = {"machine": machine_info(),
                 "synthesis": synthesis.ALGORITHM, "gain": "warm-start gain of the stored swarm (best particle of its last iteration)", "per_h": []}
    models = {}
    for h in (0.015, 0.02139, 0.03):
        t0 = time.perf_counter()
        m = models[h] = design.models_at(h)
        t_model = time.perf_counter() - t0
        plant = synthesis.plant_at(m.g_r, synthesis.Scenario(), m.inertia, settings)
        check = synthesis.plant_at(m.g_check, synthesis.Scenario(), m.inertia, settings)
        row = dict(h=h, t_model_s=t_model, order_plant=int(plant.a.shape[0]), order_spillover=int(check.a.shape[0]),
                   plant_evaluation_s=timed(lambda: synthesis.loop_peaks(plant, gain, min_damping=_DEFAULTS["min_damping_all"]),
                                            args.repeat)[1],
                   spillover_check_s=timed(lambda: synthesis._eigen(check, gain, _DEFAULTS["min_damping"], m.omega_max),
                                           max(3, args.repeat // 4))[1])
        if args.fast:  # the optimiser's evaluations: the modal form is built once per plant, then reused at every gain
            ml, mc = ModalLoop.of(plant), ModalLoop.of(check)
            steps = iter(gain * (1 + 1e-3 * np.random.default_rng(i).normal(size=gain.shape)) for i in range(10 ** 6))
            row.update(modal_form_s=timed(lambda: ModalLoop.of(plant), 3)[1],
                       plant_evaluation_fast_s=timed(lambda: synthesis.loop_peaks(
                           plant, next(steps), min_damping=_DEFAULTS["min_damping_all"], modal=ml), args.repeat)[1],
                       spillover_check_fast_s=timed(lambda: synthesis._eigen(
                           check, next(steps), _DEFAULTS["min_damping"], m.omega_max, mc), max(3, args.repeat // 4))[1])
            print(f"  fast path: modal form {1e3 * row['modal_form_s']:.0f} ms once per plant, then one evaluation "
                  f"{1e3 * row['plant_evaluation_fast_s']:.1f} ms, spillover check {1e3 * row['spillover_check_fast_s']:.0f} ms "
                  f"(successive gains 0.1 % apart, as trust-region steps)")
        out["per_h"].append(row)
        print(f"h {100 * h:.3f} cm: model {t_model:.1f} s; plant order {row['order_plant']}, one evaluation "
              f"{1e3 * row['plant_evaluation_s']:.1f} ms; spillover check ({row['order_spillover']} states) "
              f"{1e3 * row['spillover_check_s']:.0f} ms")
    m = models[0.015]
    r = design.robust_design(m, settings, gain0=gain, scenarios=scen, workers=1, **codesign.SYNTHESIS_OPTIONS)
    accepted = sum(1 for e in r.history if e.get("phase") in ("optimise", "feasibility"))
    out["warm_1.5cm"] = dict(time_s=r.time_s, iterations=r.iterations, accepted_steps=accepted, evaluations=r.evaluations,
                             scenarios_start=len(scen), scenarios_end=len(r.scenarios), J_c=r.j_c, Z_c=r.z_c, success=r.success,
                             message=r.message)
    print(f"warm synthesis at 1.5 cm: {r.time_s:.1f} s, {r.iterations} iterations ({accepted} accepted steps), "
          f"{r.evaluations} plant evaluations, {len(scen)} -> {len(r.scenarios)} scenarios, J_c {r.j_c:.4f}, Z_c {r.z_c:.3f}, "
          f"{'valid' if r.success else 'NOT valid: ' + r.message}")
    if args.fast:
        f = design.robust_design(m, settings, gain0=gain, scenarios=scen, workers=1, fast=True, **codesign.SYNTHESIS_OPTIONS)
        out["warm_1.5cm_fast"] = dict(time_s=f.time_s, iterations=f.iterations, evaluations=f.evaluations, J_c=f.j_c, Z_c=f.z_c,
                                      success=f.success, fallbacks=f.fallbacks, message=f.message)
        print(f"the same by the fast path: {f.time_s:.1f} s, {f.iterations} iterations, {f.evaluations} plant evaluations, "
              f"J_c {f.j_c:.4f}, Z_c {f.z_c:.3f}, {'valid' if f.success else 'NOT valid: ' + f.message}, {f.fallbacks} fallbacks")
    t0 = time.perf_counter()  # the search as the synthesis ends it: on its final gain (stable on the whole box)
    wc = synthesis.worst_case(m.g_r, r.gain, m.inertia, settings, workers=1, min_damping=_DEFAULTS["search_damping"] * _DEFAULTS["min_damping_all"])
    out["search_1.5cm"] = dict(evaluations=wc.evaluations, time_s=time.perf_counter() - t0)
    print(f"worst-case search at 1.5 cm on the final gain: {wc.evaluations} plant evaluations, "
          f"{out['search_1.5cm']['time_s']:.1f} s")
    per_iter: dict[int, set] = {}
    for rec in state.history:
        per_iter.setdefault(rec["iteration"], set()).add(round(rec["h"], 12))
    distinct = float(np.mean([len(v) for v in per_iter.values()]))
    low = out["per_h"][0]
    # a synthesis that takes no optimisation step at all still evaluates its scenario set (with the spillover check),
    # searches the box once and checks the final gain on the set
    verify_s = 2 * (len(scen) * low["plant_evaluation_s"] + low["spillover_check_s"]) + out["search_1.5cm"]["time_s"]

    def minutes(particle_s: float) -> float:
        return 20 * distinct * (particle_s + low["t_model_s"]) / args.workers / 60

    out["projection"] = dict(iterations=20, distinct_particles_per_iteration=distinct, workers=args.workers,
                             measured_warm_min=minutes(r.time_s), verification_only_s=verify_s,
                             verification_only_min=minutes(verify_s))
    if args.fast:
        fast_verify_s = (2 * (len(scen) * low["plant_evaluation_fast_s"] + low["spillover_check_fast_s"])
                         + (len(scen) + 1) * low["modal_form_s"] + out["search_1.5cm"]["time_s"])
        out["projection"].update(measured_warm_fast_min=minutes(out["warm_1.5cm_fast"]["time_s"]),
                                 verification_only_fast_s=fast_verify_s, verification_only_fast_min=minutes(fast_verify_s))
        print(f"fast path: {minutes(out['warm_1.5cm_fast']['time_s']):.0f} min at its measured warm synthesis; "
              f"{minutes(fast_verify_s):.0f} min if each synthesis only verified its start ({fast_verify_s:.1f} s, the search "
              "being dense)")
    print(f"20 iterations x {distinct:.1f} distinct particles / {args.workers} workers, model {low['t_model_s']:.1f} s each: "
          f"{minutes(r.time_s):.0f} min at the measured warm synthesis; {minutes(verify_s):.0f} min if each synthesis "
          f"only verified its start ({verify_s:.1f} s: the set twice and one search, no optimisation step)")
    path = Path(__file__).parent / "results" / "codesign_floor.json"
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {path}")


if __name__ == "__main__":
    main()
