"""The table of benchmarks/README.md, generated from the stored results in benchmarks/results/.

Each row quotes its benchmark's latest figures and the machine they ran on, as the result file records them, so the
table cannot drift from the stored results.
Run: python benchmarks/table.py [--check | --write]  (print the table; check or rewrite the one in benchmarks/README.md)
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
START, END = "<!-- table:start -->", "<!-- table:end -->"


def _load(name: str, results: Path) -> dict:
    return json.loads((results / f"{name}.json").read_text())


def _machine(m: dict) -> str:
    """The machine as the result file records it (the older files record neither the CPU model nor, some, the cores)."""
    parts = [m.get("cpu") or m.get("processor") or "CPU model not recorded", m.get("machine", "")]
    parts.append(f"{m['cpus']} cores" if "cpus" in m else "cores not recorded")
    return ", ".join(p for p in parts if p)


def rows(results: Path = HERE / "results") -> list[tuple[str, str, str, str, str, str]]:
    """``(benchmark, what it measures, command, latest figures, machine, target)`` per kept benchmark."""
    b = _load("build_open_loop", results)
    s = b["seconds"]
    r = _load("robust_synthesis", results)
    m = _load("mu_sweep", results)
    c = _load("codesign_stated", results)
    e = c["per_evaluation_s"]
    return [
        ("`build_open_loop.py`", "model build and reduction at one h", "`python benchmarks/build_open_loop.py`",
         f"open loop G (order 1324) {s['open-loop G (order 1324)']['median']:.2f} s; G_r "
         f"{s['G_r: slow poles + modes above 500 rad/s']['median']:.2f} s; the models of one design point "
         f"(`design.models_at`, 2.14 cm) {s['design models at 2.14 cm (models_at)']['median']:.2f} s (medians of "
         f"{max(1, b['repeat'] // 2)}-{b['repeat']} runs)", _machine(b["machine"]), "-"),
        ("`robust_synthesis.py`", "one robust synthesis at 2.139 cm, cold and warm-started (library defaults); mu bounds "
         "per panel angle", "`python benchmarks/robust_synthesis.py`",
         f"cold {r['cold']['time_s']:.1f} s ({r['cold']['iterations']} iterations, J_c {r['cold']['J_c']:.4f}); warm from "
         f"the 2.0 cm gain {r['warm_from_h_2.0cm']['time_s']:.1f} s, with its scenario set and the co-design's tolerance "
         f"{r['warm_from_h_2.0cm_with_scenarios_codesign_tol']['time_s']:.1f} s; mu {r['mu_per_angle_s']:.1f} s per angle",
         _machine(r["machine"]), "cold under 60 s"),
        ("`mu_sweep.py`", "notebook 08's mu sweep (50 panel angles) in one process and on Dask workers",
         "`python benchmarks/mu_sweep.py`",
         f"{m['in_process_s']:.1f} s in one process, {m['dask_s']:.1f} s on {m['workers']} workers "
         f"(x{m['speed_up']:.2f}); largest gap between the bounds {100 * m['largest_gap']:.3f} % (design of notebook "
         f"{m['design']['source']} at h = {100 * m['design']['h']:.3f} cm)", _machine(m["machine"]), "under 10 min"),
        ("`codesign.py --preset stated ...`", "the stated-values co-design (24 particles x 20 iterations, the paper's recipe "
         "warm-started from the previous best) with notebook 07's synthesis options",
         "`python benchmarks/codesign.py --preset stated --truss-tolerance 0 --start previous_best --h-resolution 0` (or "
         "`--report data/results/07_pso_checkpoint.json` for a run already made)",
         f"{c['wall_time_min']:.1f} min on {c['workers']} workers; per evaluation: assembly {e['assembly']:.2f} s, "
         f"reduction {e['reduction']:.1f} s, synthesis {e['synthesis']:.1f} s; best h = {100 * c['best']['h']:.3f} cm, "
         f"J_c {c['best']['J_c']:.4f}", _machine(c["machine"]), "under 60 min (the paper: 11 h 16 min on 24 cores)"),
        _calibrated_row(results),
        _front_row(results),
        _truss_row(results),
    ]


def _front_row(results: Path) -> tuple[str, str, str, str, str, str]:
    """The row of notebook 07b's search of the mass / pointing front (``front_search.json``), or what is missing."""
    what = ("notebook 07b's search of the mass / pointing front over 3 sides (`paper_calibrated`, tolerant designs): the "
            "stored run on 2 cores, a short search on 1 and 2 Dask workers, extrapolated to N")
    command, target = "`python benchmarks/front_search.py --report --scaling`", "-"
    path = results / "front_search.json"
    if not path.exists():
        return ("`front_search.py`", what, command, "not measured yet", "-", target)
    f = json.loads(path.read_text())
    rep, sc = f["report"], f["scaling"]
    ext = ", ".join(f"{x['workers']}: {x['wall_min']:.0f} min" for x in f["extrapolation"])
    figures = (f"{rep['wall_time_min']:.0f} min on 2 workers for {rep['distinct_evaluations']} distinct evaluations "
               f"({len(rep['seeds'])} seeds x {rep['n_initial']} + {rep['population']} x {rep['generations']}; "
               f"{rep['per_evaluation_s']['total']:.0f} s each, proposals {rep['propose_s']:.0f} s in all, workers waiting "
               f"{rep['worker_waiting_s'] / 60:.0f} min); short search ({sc['runs']['1']['evaluations']} evaluations) "
               f"{sc['runs']['1']['wall_s']:.0f} s on 1 worker, {sc['runs']['2']['wall_s']:.0f} s on 2 (x{sc['speedup_2']:.2f}); "
               f"extrapolated (workers: wall time) {ext}")
    return ("`front_search.py`", what, command, figures, _machine(f["machine"]), target)


def _truss_row(results: Path) -> tuple[str, str, str, str, str, str]:
    """The row of the truss-of-cubes scaling (``truss_scaling.json``), or what is missing."""
    what = ("booms of 1-50 cubes and a 3 x 3 plate: the paper's block diagram (build, removal of the spurious poles, "
            "reduction) and the sparse constrained assembly, beside OpenSeesPy; time ~ cubes^p")
    command, target = "`python benchmarks/truss_scaling.py`", "a 20-cube boom built, reduced and validated under 60 s (goal: 50 cubes under 2 min, 4 GiB)"
    path = results / "truss_scaling.json"
    if not path.exists():
        return ("`truss_scaling.py`", what, command, "not measured yet", "-", target)
    t = json.loads(path.read_text())
    rows = {r["case"]: r for r in t["rows"]}
    p = {k: v for k, v in t["exponents"].items() if v is not None}
    names = {"build_s": "build", "remove_s": "removal", "reduce_s": "reduction", "sparse_s": "sparse", "opensees_s": "OpenSeesPy"}
    b20, b50 = rows.get("boom 20", {}), rows.get("boom 50", {})
    figures = (f"exponents p: {', '.join(f'{names[k]} {v:.2f}' for k, v in p.items())}; boom of 20 cubes: sparse "
               f"{b20.get('sparse_s', float('nan')):.2f} s + OpenSeesPy {b20.get('opensees_s', float('nan')):.1f} s"
               + (f", block diagram {b20['build_s'] + b20['remove_s'] + b20['reduce_s']:.0f} s" if "remove_s" in b20 else
                  ", block diagram not run (extrapolated)")
               + f"; boom of 50: sparse {b50.get('sparse_s', float('nan')):.2f} s ({b50.get('sparse_mb', float('nan')):.0f} MB)")
    t20 = b20.get("sparse_s", float("inf")) + b20.get("opensees_s", float("inf"))
    figures += f"; bar {'met' if t20 < 60 else 'NOT met'} by the sparse path ({t20:.0f} s built and validated)"
    return ("`truss_scaling.py`", what, command, figures, _machine(t["machine"]), target)


def _calibrated_row(results: Path) -> tuple[str, str, str, str, str, str]:
    """The row of notebook 07's headline co-design from scratch (``codesign_paper_calibrated.json``), or what is missing."""
    what = ("the calibrated co-design from scratch (24 x 20, `paper_calibrated`, designs tolerant to +-2 % of h, cold "
            "starts shared per h on a 0.1 mm resolution)")
    command, target = "`python benchmarks/codesign.py`", "under 2 h (goal: 30 min; the paper: 11 h 16 min on 24 cores)"
    path = results / "codesign_paper_calibrated.json"
    if not path.exists():
        return ("`codesign.py`", what, command, "not measured yet", "-", target)
    c = json.loads(path.read_text())
    e = c["per_evaluation_s"]
    done = "" if c["complete"] else f" (INCOMPLETE: {c['iterations']} of 20 iterations)"
    figures = (f"{c['wall_time_min']:.1f} min on {c['workers']} workers{done}; {c['evaluations']} distinct evaluations for "
               f"{c['particle_records']} particles; per evaluation: model {e['assembly'] + e['reduction']:.1f} s, shifted trusses "
               f"{e['tolerance_models']:.1f} s, synthesis {e['synthesis']:.1f} s; workers waiting {c['worker_waiting_s'] / 60:.1f} "
               f"min; best h = {100 * c['best']['h']:.2f} cm, J_c {c['best']['J_c']:.4f}")
    return ("`codesign.py`", what, command, figures, _machine(c["machine"]), target)


def markdown(results: Path = HERE / "results") -> str:
    """The table as Markdown (no trailing newline)."""
    lines = ["| benchmark | what it measures | command | latest figures | machine | target |", "|---|---|---|---|---|---|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows(results)]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--check", action="store_true", help="fail if benchmarks/README.md's table is not this output")
    group.add_argument("--write", action="store_true", help="rewrite benchmarks/README.md's table")
    args = parser.parse_args()
    table = markdown()
    if not (args.check or args.write):
        print(table)
        return
    readme = HERE / "README.md"
    text = readme.read_text()
    head, rest = text.split(START, 1)
    tail = rest.split(END, 1)[1]
    if args.write:
        readme.write_text(head + START + "\n" + table + "\n" + END + tail)
    elif rest.split(END, 1)[0] != "\n" + table + "\n":
        sys.exit("benchmarks/README.md's table is stale: run python benchmarks/table.py --write")


if __name__ == "__main__":
    main()
