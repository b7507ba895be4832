"""Benchmark: notebook 07b's search of the mass / pointing front over k = 3 sides, on 2 cores and on 1 and 2 Dask workers.

Two measurements, each saved in ``benchmarks/results/front_search.json``:

- ``--report``: the stored search of notebook 07b (its evaluations file ``data/results/07b_evaluations.json`` and results),
  on this machine's local cluster of 2 workers: its wall time (the evaluations' calls, summed over the sessions that
  ran them: the file's ``time_s``), its distinct evaluations and their time, the workers' waiting time, and the time the
  search itself took to propose its designs (the Gaussian processes and the expected improvement), measured by
  replaying the search on that file (every evaluation found there: only the proposals cost).
- ``--scaling``: a short search from scratch (seed 0, ``--initial`` designs then one generation of ``--population``),
  run on a local cluster of 1 worker and then of 2, each with its own new evaluations file: the same designs (the search
  does not depend on the workers), so the ratio of the two wall times is the speed-up, and the waiting is what batches
  of unequal evaluations cost. The extrapolation to N workers: a generation offers ``seeds x population`` designs at
  once, so N workers shorten it until N reaches that number; the time is ``t_propose + ceil(n / N) x t_eval / e`` per
  generation of n designs, with e the efficiency measured on 2 workers.

Run on an otherwise idle machine: python benchmarks/front_search.py --report --scaling [--initial 2] [--population 2]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from _machine import machine_info  # noqa: E402
from trusscodesign.control.closedloop import LoopSettings  # noqa: E402
from trusscodesign.infra import results  # noqa: E402
from trusscodesign.model import spacecraft  # noqa: E402
from trusscodesign.study import cluster, codesign, frontsearch, objective, sizing  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
OUT = Path(__file__).parent / "results" / "front_search.json"


def setup(stored: dict) -> dict:
    """The arguments of notebook 07b's search, from its stored parameters."""
    p = stored["parameters"]
    params = spacecraft.study_parameters(stored["results"]["preset"])
    settings = LoopSettings.from_parameters(params)
    options = objective.synthesis_options(p["fast_synthesis"], p["trust_region"], p["restoration"])
    key = codesign.evaluation_key(settings, params, objective.M0_PAPER, options, p["truss_tolerance"])
    prior_file = ROOT / p["prior_dir"] / f"07_pso_checkpoint_{stored['results']['preset']}.evaluations.json"
    prior = list(results.read_json(prior_file)["records"].values())
    return dict(grouping=sizing.Grouping.of(p["groups"]), prior=prior, settings=settings, params=params,
                synthesis_options=options, truss_tolerance=p["truss_tolerance"], resolution=p["resolution"], key=key)


def report(stored: dict, kw: dict) -> dict:
    """The stored search's figures, and its proposals' time replayed on its evaluations file."""
    p = stored["parameters"]
    store = ROOT / "data" / "results" / "07b_evaluations.json"
    evaluations = results.read_json(store)
    t0 = time.perf_counter()
    replay = frontsearch.run_front_search(kw["grouping"], p["seeds"], p["n_initial"], p["population"], p["generations"],
                                          kw["prior"], None, store, kw["settings"], kw["params"],
                                          synthesis_options=kw["synthesis_options"], truss_tolerance=kw["truss_tolerance"],
                                          resolution=kw["resolution"], progress=False, log=lambda _: None)
    propose_s = time.perf_counter() - t0
    if replay.evaluated:
        raise RuntimeError(f"the replay ran {replay.evaluated} evaluations: the stored file does not hold the whole search")
    own = [r for r in replay.records() if "seed" in r]
    distinct = {repr(r["h"]): r for r in own}
    busy = float(sum(r["t_total"] for r in distinct.values()))
    wall = float(evaluations["time_s"])
    return {"seeds": p["seeds"], "n_initial": p["n_initial"], "population": p["population"], "generations": p["generations"],
            "evaluations": len(own), "distinct_evaluations": len(distinct), "evaluations_wall_s": wall,
            "wall_time_min": (wall + propose_s) / 60, "propose_s": propose_s,
            "per_evaluation_s": {k: float(np.mean([r[f"t_{k}"] for r in distinct.values()])) for k in ("model", "synthesis", "total")},
            "worker_waiting_s": 2 * wall - busy, "workers": 2}


def scaling(kw: dict, n_initial: int, population: int) -> dict:
    """The same short search on 1 and on 2 local workers, each from an empty evaluations file."""
    out: dict[int, dict] = {}
    walls: dict[int, float] = {}
    for workers in (1, 2):
        client = cluster.local_client(workers)
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.perf_counter()
            run = frontsearch.run_front_search(kw["grouping"], (0,), n_initial, population, 1, kw["prior"], client,
                                               Path(tmp) / "evaluations.json", kw["settings"], kw["params"],
                                               synthesis_options=kw["synthesis_options"], truss_tolerance=kw["truss_tolerance"],
                                               resolution=kw["resolution"], progress=False)
            wall = walls[workers] = time.perf_counter() - t0
        cluster.close_client(client)
        busy = float(sum(r["t_total"] for r in run.runs[0]))
        out[workers] = {"wall_s": wall, "evaluations": run.evaluated, "busy_s": busy, "waiting_s": workers * wall - busy,
                        "designs": [r["theta"] for r in run.runs[0]]}
        print(f"{workers} worker(s): {wall:.0f} s for {run.evaluated} evaluations ({busy:.0f} s of evaluation)", flush=True)
    if out[1]["designs"] != out[2]["designs"]:
        raise RuntimeError("the search proposed other designs on 2 workers than on 1: it must not depend on the workers")
    speedup = walls[1] / walls[2]
    return {"n_initial": n_initial, "population": population, "runs": out, "speedup_2": speedup, "efficiency_2": speedup / 2}


def extrapolate(rep: dict, scale: dict, workers=(1, 2, 4, 6, 12, 24)) -> list[dict]:
    """Wall time of the stored search's generations on N workers (see the module docstring), from the measured
    evaluation time, proposal time and efficiency on 2 workers."""
    n_seeds, n_gen = len(rep["seeds"]), rep["generations"]
    t_eval, eff = rep["per_evaluation_s"]["total"], min(1.0, scale["efficiency_2"])
    sizes = [n_seeds * rep["n_initial"]] + [n_seeds * rep["population"]] * n_gen
    out = []
    for n in workers:
        rounds = sum(math.ceil(size / n) for size in sizes)
        wall = rep["propose_s"] + rounds * t_eval / (eff if n > 1 else 1.0)
        out.append({"workers": n, "wall_min": wall / 60, "useful_workers": min(n, max(sizes))})
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--report", action="store_true", help="the stored search's figures (data/results/07b_*)")
    parser.add_argument("--scaling", action="store_true", help="a short search on 1 and on 2 workers")
    parser.add_argument("--initial", type=int, default=2)
    parser.add_argument("--population", type=int, default=2)
    args = parser.parse_args()
    stored = results.load_results("07b_multiparameter_pareto", ROOT / "data" / "results")
    kw = setup(stored)
    out = json.loads(OUT.read_text()) if OUT.exists() else {}
    out["machine"] = machine_info()
    if args.report:
        out["report"] = report(stored, kw)
        print(json.dumps(out["report"], indent=2))
    if args.scaling:
        out["scaling"] = scaling(kw, args.initial, args.population)
    if "report" in out and "scaling" in out:
        out["extrapolation"] = extrapolate(out["report"], out["scaling"])
        for row in out["extrapolation"]:
            print(f"{row['workers']:3d} workers: about {row['wall_min']:.0f} min")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(out, indent=2) + "\n")
    print(f"saved {OUT}")


if __name__ == "__main__":
    main()
