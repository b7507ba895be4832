"""The README's first design in Python runs as printed, and what it prints is right: the TITOP beam against the
Euler-Bernoulli closed form, the stored design's worst case against notebook 06's result and against the certified
H-infinity norm, the new synthesis against its own certified norm and the effort bound (about 30 s)."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np

from trusscodesign import synthesis

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
    assert printed.count("\n") == 5, printed
    # 1. each closed-form bending frequency has a TITOP pole next to it, above it (Rayleigh-Ritz) by the error of notebook
    #    01's convergence study at this order (28: 5.8e-5 and 1.09e-3 for the first two bending modes)
    closed = ns["titop"].analytic_frequencies(2.0, ns["section"], "bending_y", n=2)
    near = np.array([ns["omega_model"][np.argmin(abs(ns["omega_model"] - w))] for w in closed])
    conv = json.loads((ROOT / "data" / "results" / "01_titop_beam.json").read_text())["results"]["convergence"]
    expected = [conv["relative_errors"][f"bending_y {k}"][conv["orders"].index(28)] for k in (1, 2)]
    assert ns["beam"].a.shape[0] == 28 and np.allclose(near / closed - 1, expected, rtol=1e-3), (near / closed - 1, expected)
    # 2. the same model as notebook 06's design
    stored = json.loads((ROOT / "data" / "results" / "06_robust_synthesis.json").read_text())["results"]["designs"]["2.139"]
    assert abs(ns["models"].truss_mass - stored["truss_mass_kg"]) < 1e-6
    # 3. the search finds notebook 06's worst case (within the 2 % of its densified check), the peak of the
    #    peak-aware grid is the certified norm
    assert abs(ns["worst"].value["rpe"] / stored["J_c"] - 1) < 0.02
    assert ns["certified"] and abs(ns["j_exact"] / ns["worst"].value["rpe"] - 1) < 1e-4
    # 4. the new design: its reported worst case is the certified norm at that scenario; a valid design meets the bound
    new, m = ns["new"], ns["design"].models_at(0.022)
    for group in ("rpe", "effort"):
        plant = synthesis.plant_at(m.g_r, new.worst.scenario[group], m.inertia, ns["settings"])
        norm, _, ok = synthesis.exact_norms(plant, new.gain)[group]
        assert ok and abs(norm / new.worst.value[group] - 1) < 1e-4, (group, norm, new.worst.value[group])
    assert new.z_c >= new.worst.value["effort"] and new.j_c >= new.worst.value["rpe"]
    assert not new.success or new.z_c < ns["settings"].gamma_u
