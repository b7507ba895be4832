"""The README's summary table is what ``scripts/summary.py`` prints from the stored results, and it reads them."""

from __future__ import annotations

import importlib.util
import json
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]


def _summary():
    spec = importlib.util.spec_from_file_location("summary", ROOT / "scripts" / "summary.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_table_is_the_summary_of_the_stored_results() -> None:
    readme = (ROOT / "README.md").read_text()
    start, end = "<!-- summary:start -->\n", "\n<!-- summary:end -->"
    assert readme.count(start) == 1 and readme.count(end) == 1
    table = readme[readme.index(start) + len(start):readme.index(end)]
    assert table == _summary().markdown(ROOT), "README.md is stale: paste the output of python scripts/summary.py"


def test_summary_follows_the_results_files(tmp_path: Path) -> None:
    """A changed result changes the table (nothing hard-coded); a missing file names the notebook to run."""
    shutil.copytree(ROOT / "data" / "results", tmp_path / "data" / "results")
    path = tmp_path / "data" / "results" / "06_robust_synthesis.json"
    stored = json.loads(path.read_text())
    stored["results"]["designs"]["2.139"]["J_c"] = 0.8765
    path.write_text(json.dumps(stored))
    summary = _summary()
    row = next(r for r in summary.rows(tmp_path) if r[0].startswith("Robust design"))
    assert row[2].startswith("0.8765 / ")
    assert "by the fast path" not in summary.markdown(tmp_path)  # no benchmark results in this folder
    (tmp_path / "data" / "results" / "08_worst_case_mu.json").unlink()
    with pytest.raises(FileNotFoundError, match="run notebook 08"):
        summary.markdown(tmp_path)
