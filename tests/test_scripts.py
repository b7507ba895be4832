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


def _fake(tmp_path: Path, body: str) -> dict:
    fake = tmp_path / "fakepython"
    fake.write_text("#!/usr/bin/env bash\n" + body)
    fake.chmod(0o755)
    env = dict(os.environ, PYTHON=str(fake), NO_INSTALL="1")
    env.pop("PYTHONPATH", None)
    return env


def test_relative_out_and_params_are_taken_from_the_callers_folder(tmp_path: Path) -> None:
    calls = tmp_path / "calls.txt"
    env = _fake(tmp_path, f"printf '%s\\n' \"$@\" > {calls}\n")
    (tmp_path / "study.yaml").write_text("n_omega: 50\n")
    run = subprocess.run(["bash", str(ROOT / "scripts" / "run_notebooks.sh"), "--params", "study.yaml", "--out", "runs/s"],
                         cwd=tmp_path, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    args = calls.read_text().split("\n")
    assert args[args.index("-f") + 1] == str(tmp_path / "study.yaml")
    assert args[args.index("figures_dir") + 1] == str(tmp_path / "runs" / "s" / "figures")
    assert args[args.index("results_dir") + 1] == str(tmp_path / "runs" / "s" / "results")


def test_missing_params_file_is_refused_before_any_notebook(tmp_path: Path) -> None:
    calls = tmp_path / "calls.txt"
    env = _fake(tmp_path, f"echo x >> {calls}\n")
    run = subprocess.run(["bash", "scripts/run_notebooks.sh", "--params", str(tmp_path / "nope.yaml"), "--out", str(tmp_path / "r")],
                         cwd=ROOT, env=env, capture_output=True, text=True)
    assert run.returncode == 2 and not calls.exists()


def test_notebooks_import_the_library_of_this_checkout(tmp_path: Path) -> None:
    # papermill runs the kernel in notebooks/: "import lib" must find this checkout's lib (whose paths.ROOT decides
    # where figures and results go), not whichever checkout was last installed in editable mode
    roots = tmp_path / "roots.txt"
    import sys
    env = _fake(tmp_path, f"cd notebooks && {sys.executable} -c 'import lib.paths; print(lib.paths.ROOT)' >> {roots}\n")
    subprocess.run(["bash", "scripts/run_notebooks.sh", "--out", str(tmp_path / "r")], cwd=ROOT, env=env, capture_output=True, text=True)
    assert set(roots.read_text().split()) == {str(ROOT.resolve())}


def test_a_parameter_folder_gives_each_notebook_its_own_file_after_the_common_one(tmp_path: Path) -> None:
    """``--params DIR``: all.yaml for every notebook, then NN_name.yaml for that notebook only (overriding it, as
    papermill applies later -f files over earlier ones); a notebook without its own file gets all.yaml alone."""
    calls = tmp_path / "calls"
    calls.mkdir()
    # logs each call's arguments into a file named after the input notebook
    env = _fake(tmp_path, f"printf '%s\\n' \"$@\" > {calls}/$(basename \"$7\" .ipynb)\n")
    study = tmp_path / "study"
    study.mkdir()
    (study / "all.yaml").write_text("seed: 3\n")
    (study / "07_pso_codesign.yaml").write_text("n_grid: 5\n")
    run = subprocess.run(["bash", str(ROOT / "scripts" / "run_notebooks.sh"), "--params", "study", "--out", "runs/s"],
                         cwd=tmp_path, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    for nb in sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb")):
        args = (calls / nb.stem).read_text().split("\n")
        files = [args[i + 1] for i, a in enumerate(args) if a == "-f"]
        own = [str(study / f"{nb.stem}.yaml")] if nb.stem == "07_pso_codesign" else []
        assert files == [str(study / "all.yaml"), *own]


def _notebook(path: Path, source: str) -> None:
    import nbformat

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(source)]
    nbformat.write(nb, path)


def test_notebooks_07_and_08_run_on_one_worker_in_order(tmp_path: Path) -> None:
    """The test command runs on 2 pytest-xdist workers: notebook 08, which reads what notebook 07 stores, must run after
    07 on the same worker, whatever else is queued (tests/conftest.py groups them). Here 07 waits 3 s before it writes
    its worker's name, and 08 fails unless it finds that file with its own worker's name: on separate workers, 08 would
    start while 07 waits."""
    import shutil
    import sys

    shutil.copy(ROOT / "tests" / "conftest.py", tmp_path / "conftest.py")
    mark = tmp_path / "written_by"
    _notebook(tmp_path / "01_other.ipynb", "x = 1")
    _notebook(tmp_path / "07_writes.ipynb", f"import os, time\ntime.sleep(3)\nopen({str(mark)!r}, 'w').write(os.environ['PYTEST_XDIST_WORKER'])")
    _notebook(tmp_path / "08_reads.ipynb", f"import os\nassert open({str(mark)!r}).read() == os.environ['PYTEST_XDIST_WORKER']")
    _notebook(tmp_path / "02_other.ipynb", "y = 2")
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--nbval-lax", "--nbval-current-env", "-n", "2",
                          "--dist", "loadgroup", "--no-loadscope-reorder", str(tmp_path)], cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    assert "4 passed" in run.stdout


def test_notebooks_07_and_08_are_queued_first(tmp_path: Path) -> None:
    """The chain is the longest group (about 15 of 25 min): it is collected first, 07 then 08, so the first worker starts
    it at once and the other groups keep their order behind it."""
    import shutil
    import sys

    shutil.copy(ROOT / "tests" / "conftest.py", tmp_path / "conftest.py")
    for name in ("01_a", "08_reads", "02_b", "07_writes"):
        _notebook(tmp_path / f"{name}.ipynb", "x = 1")
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "--collect-only", "-p", "no:cacheprovider", "--nbval-lax", str(tmp_path)],
                         cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    files = [line.split("::")[0] for line in run.stdout.splitlines() if "::" in line]
    assert files == ["07_writes.ipynb", "08_reads.ipynb", "01_a.ipynb", "02_b.ipynb"]
