"""Benchmark: how the synthesis model's cut frequency changes the closed-loop norms it reports (is G_r conservative?).

The synthesis works on ``G_r`` (``lib.design.models_at``): ``G_r_low`` with its modes above ``omega_max = 500 rad/s``
residualised (static part kept). Notebook 08 found that at the stored co-design's mu worst case (h = 1.5 cm) ``G_r``
gives an RPE gain of 0.019895 where ``G_r_low`` (all 784 states) gives 0.021912: 10 % *below*, because the residualised
modes move the lightly damped closed-loop mode at 325 rad/s. This script measures, for the stored designs of
notebook 07 (the optimum, 1.5 cm) and notebook 06 (2.139 cm), the same gain closed on ``G_r_low`` residualised at
several cut frequencies, at the worst-case search's 90 grid scenarios and at notebook 08's mu worst cases (07's design):

* per cut: the order, the largest RPE and effort gains over those scenarios (dense peak-aware grid,
  ``lib.synthesis.loop_peaks``, within 1e-6 of the Hamiltonian method on these loops), their largest relative errors
  against ``G_r_low`` scenario by scenario (signed: negative means the cut model reports less), scenarios whose
  stability verdict differs, and the time of one evaluation (one thread);
* at notebook 08's mu worst cases, the certified norms (``lib.synthesis.exact_norms``) on each model.

Prints a table per design and saves benchmarks/results/model_cut.json.
Run: python benchmarks/model_cut.py [--cuts 500 750 1000 1500 2000 3000 10000] [--processes 2]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from lib import design, reduction, results, synthesis  # noqa: E402
from lib.closedloop import LoopSettings  # noqa: E402
from lib.lft import LFT  # noqa: E402

ROOT = Path(__file__).parents[1]
CUTS = (500.0, 750.0, 1000.0, 1500.0, 2000.0, 3000.0, 10000.0)


def _mu_worst_cases() -> dict[str, tuple[float, float, float, float]]:
    """Notebook 08's mu worst cases (its stored design is notebook 07's optimum), per transfer: hub mass [kg], hub Iyy
    [kg m^2], omega1 [rad/s], theta [deg]."""
    table = results.load_results("08_worst_case_mu", str(ROOT / "data" / "results"))["results"]["table"]
    out = {}
    for group, key in (("rpe", "p~ -> RPE"), ("effort", "p~ -> W~u")):
        row = table[key]
        out[group] = (row["critical M_SC [kg]"], row["critical Iyy [kg m^2]"], row["critical omega1_SP [rad/s]"],
                      row["critical theta [deg]"])
    return out


def _scenario(model: LFT, physical: tuple[float, float, float, float]) -> synthesis.Scenario:
    """The scenario of physical values (hub mass [kg], hub Iyy [kg m^2], omega1 [rad/s], theta [deg])."""
    mass, iyy, omega1, theta = physical
    p = model.params
    return synthesis.Scenario(p["M_SC"].to_delta(mass), p["Iyy_SC"].to_delta(iyy), p["omega1_SP"].to_delta(omega1),
                              float(np.deg2rad(theta)))


def _design(job: tuple[str, tuple[float, ...]]) -> dict:
    """All cuts (rad/s) of one stored design: norms at the grid scenarios (and the mu worst cases), errors against G_r_low."""
    from threadpoolctl import threadpool_limits

    source, cuts = job
    with threadpool_limits(1):
        name, h, gain = design.stored_design(source, str(ROOT / "data" / "results"))
        m = design.models_at(h)
        settings = LoopSettings.from_parameters()
        low = m.g_r_low
        models = {f"{cut:g}": LFT(*reduction.residualize_above(low.a, low.b, low.c, low.d, cut)[0], low.blocks, low.params)
                  for cut in cuts}
        models["G_r_low"] = low
        scenarios = synthesis.search_candidates()
        mu = {g: _scenario(low, v) for g, v in _mu_worst_cases().items()} if name == "07" else {}
        values: dict[str, np.ndarray] = {}
        rows: dict[str, dict] = {}
        for key, model in models.items():
            t0 = time.perf_counter()
            peaks = [synthesis.loop_peaks(synthesis.plant_at(model, sc, m.inertia, settings), gain, n_peaks=1) for sc in scenarios]
            per_eval = (time.perf_counter() - t0) / len(scenarios)
            values[key] = np.array([[lp.norm("rpe"), lp.norm("effort")] for lp in peaks])
            rows[key] = {"order": model.nstates, "s_per_evaluation": per_eval,
                         "largest_rpe": float(values[key][:, 0].max()), "largest_effort": float(values[key][:, 1].max())}
            for group, sc in mu.items():
                norms = synthesis.exact_norms(synthesis.plant_at(model, sc, m.inertia, settings), gain)
                rows[key][f"mu_worst_{group}"] = {"norm": norms[group][0], "omega": norms[group][1], "certified": norms[group][2]}
        ref = values["G_r_low"]
        for key in models:
            finite = np.isfinite(ref) & np.isfinite(values[key])
            rel = np.where(finite, values[key] / np.where(finite, ref, 1.0) - 1.0, 0.0)
            worst = [int(np.argmax(np.abs(rel[:, i]))) for i in range(2)]
            rows[key].update({"rpe_rel_err_largest": float(rel[worst[0], 0]), "effort_rel_err_largest": float(rel[worst[1], 1]),
                              "stability_verdicts_differ": int(np.sum(np.isfinite(ref[:, 0]) != np.isfinite(values[key][:, 0])))})
            for group in mu:
                rows[key][f"mu_worst_{group}"]["rel_err"] = (rows[key][f"mu_worst_{group}"]["norm"]
                                                            / rows["G_r_low"][f"mu_worst_{group}"]["norm"] - 1.0)
    return {"design": name, "h": h, "scenarios": len(scenarios), "cuts": rows}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cuts", type=float, nargs="+", default=list(CUTS))
    parser.add_argument("--processes", type=int, default=2)
    args = parser.parse_args()
    with ProcessPoolExecutor(args.processes) as pool:
        out = list(pool.map(_design, [("07", tuple(args.cuts)), ("06", tuple(args.cuts))]))
    for d in out:
        print(f"design {d['design']}, h = {100 * d['h']:.3f} cm ({d['scenarios']} grid scenarios):")
        for key, r in d["cuts"].items():
            mu = "".join(f", mu worst {g} {r[f'mu_worst_{g}']['norm']:.6g} ({100 * r[f'mu_worst_{g}']['rel_err']:+.2f} %)"
                         for g in ("rpe", "effort") if f"mu_worst_{g}" in r)
            print(f"  cut {key:>8}: order {r['order']:4d}, {1e3 * r['s_per_evaluation']:6.1f} ms/eval, largest RPE "
                  f"{r['largest_rpe']:.6g} effort {r['largest_effort']:.5g}; largest error RPE {100 * r['rpe_rel_err_largest']:+.2f} % "
                  f"effort {100 * r['effort_rel_err_largest']:+.2f} %, verdicts differ {r['stability_verdicts_differ']}{mu}")
    path = ROOT / "benchmarks" / "results" / "model_cut.json"
    path.write_text(json.dumps({"machine": machine_info(), "cuts_rad_s": list(args.cuts), "designs": out}, indent=1))
    print(f"saved {path}")


if __name__ == "__main__":
    main()
