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
# read here, at collection: tests/conftest.py removes it from the environment of every test
LOG = Path(os.environ.get(smoke_asserts.LOG_ENV, ROOT / "build/smoke/asserts"))


def test_no_two_notebooks_share_a_cell_with_asserts() -> None:
    """The log knows a cell by its code: two notebooks with the same cell would count one's run for the other."""
    cells = [(a["cell"], nb.name) for nb in NOTEBOOKS for a in smoke_asserts.notebook_asserts(nb)]
    shared = {c for c, _ in cells if len({n for c2, n in cells if c2 == c}) > 1}
    assert not shared, f"cells with asserts in more than one notebook: {sorted((n, c) for c, n in cells if c in shared)}"


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=[nb.stem for nb in NOTEBOOKS])
def test_every_assert_ran_under_the_smoke_parameters(notebook: Path) -> None:
    assert list(LOG.glob("*.jsonl")), f"no assert log in {LOG}: run the notebooks by scripts/test.sh first"
    asserts = smoke_asserts.notebook_asserts(notebook)
    assert asserts, f"{notebook.name} has no assert: a notebook's checks are its asserts"
    missing = smoke_asserts.not_run(LOG, [notebook])[notebook.name]
    assert not missing, f"{notebook.name}: {len(missing)} of {len(asserts)} asserts did not run under tests/smoke/: " + "; ".join(
        f"cell {a['cell_number']} line {a['line']}: assert {a['text']}" for a in missing)
