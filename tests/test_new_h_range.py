"""The README's section "A new range of h" runs as printed (with a smoke-sized swarm added), and a rerun of it after
an edit of the spacecraft parameters recomputes: the grid and the swarm are keyed on the parameters' fingerprint, the
stale checkpoint is set aside, never resumed (about 5 min on 2 cores)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

from trusscodesign import spacecraft

ROOT = Path(__file__).resolve().parents[1]
# a swarm and a grid small enough for CI; the README's range, folders and notebook are kept. A 2 x 1 swarm's best is
# its first particle, +6.4 % from the 2-point grid's minimum (measured with the notebook's seed): held to 10 %
SMOKE = "-p n_particles 2 -p n_iterations 1 -p n_grid 2 -p pso_tolerance 0.1 -p run_preset False -p n_workers 2"


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
    assert any("-p h_min 0.02 -p h_max 0.03" in c for c in commands), commands
    folder = tmp_path / "my_h"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    first = _run(commands, folder, env)
    assert first.returncode == 0, first.stderr[-3000:]
    res = _stored(folder, "07_pso_codesign")
    assert res["parameters"]["h_min"] == 0.02 and res["parameters"]["h_max"] == 0.03
    assert res["inputs"] == spacecraft.inputs_key()
    grid = [r["h"] for r in res["results"]["grid"]]
    assert grid == [0.02, 0.03] and all(0.02 <= r["h"] <= 0.03 for r in res["results"]["history"])
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
    assert "set aside as 07_pso_checkpoint.stale.json" in executed and "the spacecraft parameters (their fingerprint)" in executed
    assert (folder / "results" / "07_pso_checkpoint.stale.json").exists()  # the first run's swarm, kept
    new = _stored(folder, "07_pso_codesign")
    assert new["inputs"]["spacecraft_parameters"] == edited
    assert json.loads((folder / "results" / "07_grid.json").read_text())["key"]["parameters"] == edited
    checkpoint = json.loads((folder / "results" / "07_pso_checkpoint.json").read_text())
    assert checkpoint["extra"]["objective"]["params_sha256"] == edited
    # recomputed, not read back: the same h with another hub mass gives another objective
    old_grid, new_grid = res["results"]["grid"], new["results"]["grid"]
    assert [r["h"] for r in new_grid] == [0.02, 0.03]
    assert all(a["J_c"] != b["J_c"] for a, b in zip(old_grid, new_grid)), (old_grid, new_grid)
