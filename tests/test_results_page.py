"""docs/results.md is what ``scripts/results_page.py`` writes from the stored results, and it reads them."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from _scripts import load_script

ROOT = Path(__file__).parents[1]


def _generator():
    return load_script("results_page")


def _results_copy(tmp_path: Path) -> Path:
    """The stored notebook results, without any sub-folder of data/results (the page reads only the top-level files)."""
    shutil.copytree(ROOT / "data" / "results", tmp_path / "data" / "results",
                    ignore=lambda folder, names: [n for n in names if (Path(folder) / n).is_dir()])
    return tmp_path


def test_results_page_is_the_generators_output() -> None:
    page = (ROOT / "docs" / "results.md").read_text()
    assert page == _generator().page(ROOT), "docs/results.md is stale: run python scripts/results_page.py"


def test_results_page_has_no_history() -> None:
    """A results page, not a log: no commit ids, no dates, no archived runs."""
    page = (ROOT / "docs" / "results.md").read_text()
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", page)
    assert not re.search(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b", page)
    assert "data/results/box" not in page and "ball_minmax" not in page and ".." + "/shared" not in page


def test_results_page_follows_the_results_files(tmp_path: Path) -> None:
    """A changed result changes the page (nothing hard-coded); the page needs only the notebooks' own files; a missing
    file names the notebook to run."""
    root = _results_copy(tmp_path)
    generator = _generator()
    assert generator.page(root) == generator.page(ROOT)
    path = root / "data" / "results" / "06_robust_synthesis.json"
    stored = json.loads(path.read_text())
    stored["results"]["designs"]["2.139"]["J_c"] = 0.8765
    path.write_text(json.dumps(stored))
    assert "0.8765" in generator.page(root) and "0.8765" not in generator.page(ROOT)
    (root / "data" / "results" / "08_worst_case_mu.json").unlink()
    with pytest.raises(FileNotFoundError, match="run notebook 08"):
        generator.page(root)


def test_the_calibration_verdicts_follow_the_residuals(tmp_path: Path) -> None:
    """"Not met" is said only where a residual exceeds its tolerance: an edited residual changes the sentence."""
    generator = _generator()
    now = generator.page(ROOT)
    assert "not met: the critical angle and Z_c." in now and "**Calibrated, J_c and the critical frequency come back, not the critical angle or Z_c.**" in now
    root = _results_copy(tmp_path)
    path = root / "data" / "results" / "06b_calibration_tolerance.json"
    stored = json.loads(path.read_text())
    stored["results"]["residuals"][1].update(theta_residual_deg=-2.0, Z_c_residual=0.01, omega_residual=0.2)
    path.write_text(json.dumps(stored))
    edited = generator.page(root)
    assert "J_c, the critical angle and Z_c; not met: the critical frequency." in edited
    assert "**Calibrated, J_c, the critical angle and Z_c come back, not the critical frequency.**" in edited
    assert "the frequency match is as fragile" not in edited
