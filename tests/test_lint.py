"""Lint and types: ruff with the project's rules (``pyproject.toml``) over the library, tests, benchmarks, scripts, the
site's configuration and the notebooks; mypy over the library, benchmarks and scripts (annotations are checked, not decoration)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).parents[1]
TARGETS = ["lib", "tests", "benchmarks", "scripts", "docs", "notebooks"]


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


def _mypy(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", "--cache-dir", os.devnull, *args],
                          cwd=cwd, capture_output=True, text=True, check=False)


def test_code_type_checks() -> None:
    run = _mypy()  # files and settings from pyproject.toml: lib/trusscodesign/, benchmarks/, scripts/
    assert run.returncode == 0, f"mypy found type errors (fix them; an ignore needs its reason):\n{run.stdout}{run.stderr}"


def test_type_check_catches_real_mistakes(tmp_path: Path) -> None:
    # the project's configuration, on a module that passes a possibly-None value where a float is required
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    for folder in ("lib/trusscodesign", "benchmarks", "scripts"):  # the folders pyproject.toml names, each with a clean module
        (tmp_path / folder).mkdir(parents=True)
        (tmp_path / folder / f"ok_{Path(folder).name}.py").write_text("")
    (tmp_path / "lib" / "trusscodesign" / "bad.py").write_text("def half(x: float) -> float:\n    return x / 2\n\n\n"
                                            "def f(d: dict[str, float]) -> float:\n    return half(d.get('a'))\n")
    run = _mypy(cwd=tmp_path)
    assert run.returncode == 1
    assert "arg-type" in run.stdout and "bad.py:6" in run.stdout
