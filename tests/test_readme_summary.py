"""The README's summary table and its "results at a glance" paragraph are what ``scripts/summary.py`` prints from the
stored results, and they read them: a verdict follows from the numbers."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from _scripts import load_script

ROOT = Path(__file__).parents[1]


def _summary():
    return load_script("summary")


def test_readme_table_is_the_summary_of_the_stored_results() -> None:
    readme = (ROOT / "README.md").read_text()
    start, end = "<!-- summary:start -->\n", "\n<!-- summary:end -->"
    assert readme.count(start) == 1 and readme.count(end) == 1
    table = readme[readme.index(start) + len(start):readme.index(end)]
    assert table == _summary().markdown(ROOT), "README.md is stale: paste the output of python scripts/summary.py"


def _block(name: str) -> str:
    readme = (ROOT / "README.md").read_text()
    start, end = f"<!-- {name}:start -->\n", f"\n<!-- {name}:end -->"
    assert readme.count(start) == 1 and readme.count(end) == 1, f"the README's {name} markers are missing"
    return readme[readme.index(start) + len(start):readme.index(end)]


def test_readme_glance_is_generated_from_the_stored_results() -> None:
    """The "results at a glance" paragraph is ``python scripts/summary.py --glance``: its numbers are the stored ones."""
    summary = _summary()
    assert _block("glance") == summary.wrap(summary.glance(ROOT)), "README.md is stale: paste python scripts/summary.py --glance"


def _edited(tmp_path: Path, name: str, edit) -> Path:
    """A copy of the stored results with one file edited by ``edit(stored)``."""
    shutil.copytree(ROOT / "data" / "results", tmp_path / "data" / "results",
                    ignore=lambda folder, names: [n for n in names if (Path(folder) / n).is_dir()])
    path = tmp_path / "data" / "results" / f"{name}.json"
    stored = json.loads(path.read_text())
    edit(stored["results"])
    path.write_text(json.dumps(stored))
    return tmp_path


def test_glance_verdicts_follow_the_numbers(tmp_path: Path) -> None:
    """Its verdicts are conditions on the numbers: an edited residual or J_c changes the sentence, not only the number."""
    summary = _summary()
    now = summary.glance(ROOT)
    assert "The closed loop is not:" in now and "not the critical angle" in now

    def angle_met(r: dict) -> None:
        r["residuals"][1]["theta_residual_deg"] = 2.0

    edited = summary.glance(_edited(tmp_path / "a", "06b_calibration_tolerance", angle_met))
    assert "brings back J_c, the critical frequency and the critical angle" in edited and "not the critical angle" not in edited

    def loop_met(r: dict) -> None:
        r["designs"]["2.139"]["J_c"] = 0.95

    edited = summary.glance(_edited(tmp_path / "b", "06_robust_synthesis", loop_met))
    assert "The closed loop is: with the paper's stated values the robust design at h = 2.139 cm reaches J_c = 0.9500" in edited


def test_summary_follows_the_results_files(tmp_path: Path) -> None:
    """The table needs only the notebooks' own files (no sub-folder of data/results, no benchmark result); a changed
    result changes it (nothing hard-coded); a missing file names the notebook to run."""
    shutil.copytree(ROOT / "data" / "results", tmp_path / "data" / "results",
                    ignore=lambda folder, names: [n for n in names if (Path(folder) / n).is_dir()])
    summary = _summary()
    assert summary.markdown(tmp_path) == summary.markdown(ROOT)
    path = tmp_path / "data" / "results" / "06_robust_synthesis.json"
    stored = json.loads(path.read_text())
    stored["results"]["designs"]["2.139"]["J_c"] = 0.8765
    path.write_text(json.dumps(stored))
    row = next(r for r in summary.rows(tmp_path) if r[0].startswith("Robust design"))
    assert row[1] == "stated" and row[3].startswith("0.8765 / ")
    (tmp_path / "data" / "results" / "08_worst_case_mu.json").unlink()
    with pytest.raises(FileNotFoundError, match="run notebook 08"):
        summary.markdown(tmp_path)


def test_readme_is_for_users_not_a_log() -> None:
    """Under 200 lines, with no commit ids and no dates (history is git's; measurements are the benchmarks' and docs')."""

    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) < 200
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", readme)
    assert not re.search(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b", readme)
