"""The README's first design in Python runs as printed, and what it prints is right: the model against notebook 06's,
the stored design's worst case against notebook 06's result and against the certified H-infinity norm, the new
synthesis against its own certified norm and the effort bound (30 s to 2 min)."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
from trusscodesign.control import synthesis

ROOT = Path(__file__).parents[1]


def _example() -> str:
    readme = (ROOT / "README.md").read_text()
    start, end = "<!-- example:start -->\n```python\n", "```\n<!-- example:end -->"
    assert readme.count(start) == 1 and readme.count(end) == 1, "the README's example block markers are missing"
    return readme[readme.index(start) + len(start):readme.index(end)]


def test_readme_example_runs_and_its_numbers_are_right() -> None:
    ns: dict = {}
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(_example(), "README.md example", "exec"), ns)  # noqa: S102 - the README's own code
    printed = out.getvalue()
    assert printed.count("\n") == 3, printed
    # 1. the same model as notebook 06's design, and the reduced model's order that notebook 05 stores at this h
    stored = json.loads((ROOT / "data" / "results" / "06_robust_synthesis.json").read_text())["results"]["designs"]["2.139"]
    assert abs(ns["models"].truss_mass - stored["truss_mass_kg"]) < 1e-6
    reduction = json.loads((ROOT / "data" / "results" / "05_lft_reduction.json").read_text())["results"]["reduction"]
    assert np.shape(ns["models"].g_r.a)[0] == next(r["order_G_r"] for r in reduction if r["h_cm"] == 2.139)
    # 2. the search finds notebook 06's worst case (within the 2 % of its densified check), the peak of the
    #    peak-aware grid is the certified norm
    assert abs(ns["worst"].value["rpe"] / stored["J_c"] - 1) < 0.02
    assert ns["certified"] and abs(ns["j_exact"] / ns["worst"].value["rpe"] - 1) < 1e-4
    # 3. the new design: its reported worst case is the certified norm at that scenario; a valid design meets the bound
    new, m = ns["new"], ns["design"].models_at(0.022)
    for group in ("rpe", "effort"):
        plant = synthesis.plant_at(m.g_r, new.worst.scenario[group], m.inertia, ns["settings"])
        norm, _, ok = synthesis.exact_norms(plant, new.gain)[group]
        assert ok and abs(norm / new.worst.value[group] - 1) < 1e-4, (group, norm, new.worst.value[group])
    assert new.z_c >= new.worst.value["effort"] and new.j_c >= new.worst.value["rpe"]
    # the example's design is a valid one: converged, within the effort bound, and its J_c is what the README prints
    assert new.success, new.message
    assert new.z_c < ns["settings"].gamma_u
    assert f"h = 2.2 cm: J_c {new.j_c:.5f}, Z_c {new.z_c:.3f}, valid True" in printed
