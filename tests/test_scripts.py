"""The main-job script: a failing notebook does not stop the later ones, and the job still fails at the end."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

ROOT = Path(__file__).parents[1]


def test_main_job_runs_every_notebook_and_reports_the_failed_one(tmp_path: Path) -> None:
    calls = tmp_path / "calls.txt"
    fake = tmp_path / "fakepython"
    # stands in for "python -m papermill ... <input> <output> ...": logs the input notebook, fails on notebook 07
    fake.write_text(f"#!/usr/bin/env bash\necho \"$7\" >> {calls}\ncase \"$7\" in *07_*) exit 1;; esac\n")
    fake.chmod(0o755)
    env = dict(os.environ, PYTHON=str(fake), NO_INSTALL="1")
    run = subprocess.run(["bash", "scripts/run_notebooks.sh", "--out", str(tmp_path / "run")], cwd=ROOT, env=env,
                         capture_output=True, text=True)
    notebooks = sorted(p.name for p in (ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
    assert [Path(line).name for line in calls.read_text().split()] == notebooks  # 08 ran after 07 failed
    assert run.returncode == 1
    assert "FAILED" in run.stderr and "07_pso_codesign.ipynb" in run.stderr
    assert "08_worst_case_mu" not in run.stderr
