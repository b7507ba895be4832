"""The README's section "A new range of h" runs as printed (the calibrated co-design, with a smoke-sized swarm and check
added), and a rerun of it after an edit of the spacecraft parameters recomputes: the evaluations and the swarm are keyed
on the parameters' fingerprint, the stale checkpoint is set aside, never resumed (about 10 min on 2 cores)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

from trusscodesign.model import spacecraft

ROOT = Path(__file__).resolve().parents[1]
# a swarm, a grid and a check of the optimum small enough for CI; the README's preset, range, folders and notebook are
# kept. A 2 x 1 swarm's best is held to 10 % of the 2-point grid's minimum
SMOKE = ("-p n_particles 2 -p n_iterations 1 -p n_grid 2 -p pso_tolerance 0.1 -p run_baseline False -p n_workers 2 "
         "-p check_angles 10 -y 'check_shifts: [-0.02, 0.02]'")
H_RANGE = [0.018, 0.025]  # the README's


def _readme_commands() -> list[str]:
    """The shell commands of the README's first code block under "A new range of h", continuation lines joined."""
    readme = (ROOT / "README.md").read_text()
    section = readme[readme.index("## A new range of h"):]
    block = re.search(r"```bash\n(.*?)```", section, re.S)
    assert block, "no bash block under 'A new range of h' in the README"
    lines = block.group(1).replace("\\\n", " ").splitlines()
    return [re.sub(r"\s+#.*$", "", line).strip() for line in lines if line.strip()]


def _run(commands: list[str], folder: Path, env: dict[str, str]) -> subprocess.CompletedProcess:
    script = " && ".join(c.replace("runs/my_h", str(folder)) for c in commands)
    assert "papermill" in script and str(folder) in script, script
    return subprocess.run(["bash", "-c", script + " " + SMOKE], cwd=ROOT, env=env, capture_output=True, text=True, timeout=1800)


def _stored(folder: Path, name: str) -> dict:
    return json.loads((folder / "results" / f"{name}.json").read_text())


def test_the_readmes_new_h_range_runs_and_an_edit_of_the_parameters_recomputes(tmp_path: Path) -> None:
    commands = _readme_commands()
    assert any("-p preset paper_calibrated -p h_min 0.018 -p h_max 0.025" in c for c in commands), commands
    folder = tmp_path / "my_h"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    first = _run(commands, folder, env)
    assert first.returncode == 0, first.stderr[-3000:]
    res = _stored(folder, "07_pso_codesign")
    assert [res["parameters"][k] for k in ("h_min", "h_max")] == H_RANGE and res["parameters"]["preset"] == "paper_calibrated"
    assert res["inputs"] == spacecraft.inputs_key()
    run = res["results"]["runs"]["paper_calibrated"]
    grid = [r["h"] for r in run["grid"]]
    assert grid == H_RANGE and all(H_RANGE[0] <= r["h"] <= H_RANGE[1] for r in run["history"])
    assert all(r["valid"] for r in run["check"])
    assert (folder / "07_pso_codesign.ipynb").exists() and (folder / "figures" / "07_pso_codesign.png").exists()

    # a user edits the spacecraft parameters (here in a copy of the package, which the kernel and the Dask workers import)
    # and reruns the same command into the same folder
    package = tmp_path / "lib" / "trusscodesign"
    shutil.copytree(ROOT / "lib" / "trusscodesign", package, ignore=shutil.ignore_patterns("__pycache__"))
    params_file = package / "data" / "spacecraft" / "parameters.json"
    params = json.loads(params_file.read_text())
    params["hub"]["mass"] = 720.0  # 800 kg in the paper
    params_file.write_text(json.dumps(params, indent=2))
    edited = spacecraft.parameters_fingerprint(params)
    assert edited != res["inputs"]["spacecraft_parameters"]
    second = _run(commands, folder, {**env, "PYTHONPATH": str(tmp_path / "lib")})
    assert second.returncode == 0, second.stderr[-3000:]
    executed = (folder / "07_pso_codesign.ipynb").read_text()
    assert ("set aside as 07_pso_checkpoint_paper_calibrated.stale.json" in executed
            and "the spacecraft parameters (their fingerprint)" in executed)
    assert (folder / "results" / "07_pso_checkpoint_paper_calibrated.stale.json").exists()  # the first run's swarm, kept
    new = _stored(folder, "07_pso_codesign")
    assert new["inputs"]["spacecraft_parameters"] == edited
    calibrated = spacecraft.parameters_fingerprint(spacecraft.preset_parameters("paper_calibrated", params=params))
    store = json.loads((folder / "results" / "07_pso_checkpoint_paper_calibrated.evaluations.json").read_text())
    assert store["key"]["objective"]["params_sha256"] == calibrated
    checkpoint = json.loads((folder / "results" / "07_pso_checkpoint_paper_calibrated.json").read_text())
    assert checkpoint["extra"]["objective"]["params_sha256"] == calibrated
    # recomputed, not read back: the same h with another hub mass gives another objective
    old_grid, new_grid = res["results"]["runs"]["paper_calibrated"]["grid"], new["results"]["runs"]["paper_calibrated"]["grid"]
    assert [r["h"] for r in new_grid] == H_RANGE
    assert all(a["J_c"] != b["J_c"] for a, b in zip(old_grid, new_grid)), (old_grid, new_grid)
