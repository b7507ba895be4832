"""After the notebooks' smoke runs (``scripts/test.sh`` runs this file last, by name): every assert of every notebook ran.

Smoke parameters shrink loops; they must not switch a check off. The kernels of the run logged each assert they ran
(``scripts/smoke_asserts.py``, to ``$SMOKE_ASSERT_LOG``); a notebook fails here, naming the cell, the line and the
assert, if one of its asserts never ran.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from _scripts import load_script

ROOT = Path(__file__).resolve().parents[1]
smoke_asserts = load_script("smoke_asserts")
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]*_*.ipynb"))


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=[nb.stem for nb in NOTEBOOKS])
def test_every_assert_ran_under_the_smoke_parameters(notebook: Path) -> None:
    log = Path(os.environ.get(smoke_asserts.LOG_ENV, ROOT / "build/smoke/asserts"))
    assert list(log.glob("*.jsonl")), f"no assert log in {log}: run the notebooks by scripts/test.sh first"
    asserts = smoke_asserts.notebook_asserts(notebook)
    assert asserts, f"{notebook.name} has no assert: a notebook's checks are its asserts"
    missing = smoke_asserts.not_run(log, [notebook])[notebook.name]
    assert not missing, f"{notebook.name}: {len(missing)} of {len(asserts)} asserts did not run under tests/smoke/: " + "; ".join(
        f"cell {a['cell_number']} line {a['line']}: assert {a['text']}" for a in missing)
