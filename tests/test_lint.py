"""Lint: ruff with the project's rules (``pyproject.toml``) over the library, tests, benchmarks, scripts and notebooks."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).parents[1]
TARGETS = ["lib", "tests", "benchmarks", "scripts", "notebooks"]


def _ruff(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", "--output-format", "concise", *args],
                          cwd=cwd, capture_output=True, text=True, check=False)


def test_project_is_lint_clean() -> None:
    run = _ruff(*TARGETS)
    assert run.returncode == 0, f"ruff found problems (fix them, or justify an ignore in pyproject.toml):\n{run.stdout}{run.stderr}"


def test_lint_rules_catch_real_mistakes(tmp_path: Path) -> None:
    # the project's configuration, on a file with an unused import and a mutable default argument
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    (tmp_path / "bad.py").write_text("import os\n\n\ndef f(x=[]):\n    return x\n")
    run = _ruff("bad.py", cwd=tmp_path)
    assert run.returncode == 1
    assert "F401" in run.stdout and "B006" in run.stdout
