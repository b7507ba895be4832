"""The main-job script: a failing notebook does not stop the later ones, and the job still fails at the end."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from _scripts import load_script

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
    notebooks = sorted(p.name for p in (ROOT / "notebooks").glob("[0-9][0-9]*_*.ipynb"))
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
    # papermill runs the kernel in notebooks/: "import trusscodesign" must find this checkout's package (whose paths.ROOT decides
    # where figures and results go), not whichever checkout was last installed in editable mode
    roots = tmp_path / "roots.txt"
    import sys
    env = _fake(tmp_path, f"cd notebooks && {sys.executable} -c 'import trusscodesign.infra.paths; print(trusscodesign.infra.paths.ROOT)' >> {roots}\n")
    subprocess.run(["bash", "scripts/run_notebooks.sh", "--out", str(tmp_path / "r")], cwd=ROOT, env=env, capture_output=True, text=True)
    assert set(roots.read_text().split()) == {str(ROOT.resolve())}


def test_a_parameter_folder_gives_each_notebook_its_own_file_after_the_common_one(tmp_path: Path) -> None:
    """``--params DIR``: all.yaml for every notebook, then NN_name.yaml for that notebook only (overriding it, as
    papermill applies later -f files over earlier ones); a notebook without its own file gets all.yaml alone."""
    calls = tmp_path / "calls"
    calls.mkdir()
    # logs each call's arguments into a file named after the input notebook
    env = _fake(tmp_path, f"[ \"$2\" != papermill ] || printf '%s\\n' \"$@\" > {calls}/$(basename \"$7\" .ipynb)\n")
    study = tmp_path / "study"
    study.mkdir()
    (study / "all.yaml").write_text("seed: 3\n")
    (study / "07_pso_codesign.yaml").write_text("n_grid: 5\n")
    run = subprocess.run(["bash", str(ROOT / "scripts" / "run_notebooks.sh"), "--params", "study", "--out", "runs/s"],
                         cwd=tmp_path, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    for nb in sorted((ROOT / "notebooks").glob("[0-9][0-9]*_*.ipynb")):
        args = (calls / nb.stem).read_text().split("\n")
        files = [args[i + 1] for i, a in enumerate(args) if a == "-f"]
        own = [str(study / f"{nb.stem}.yaml")] if nb.stem == "07_pso_codesign" else []
        assert files == [str(study / "all.yaml"), *own]


def _notebook(path: Path, source: str) -> None:
    import nbformat

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(source)]
    nbformat.write(nb, path)


def _test_sh_calls(tmp_path: Path, workers: str) -> list[list[str]]:
    """The pytest command lines of scripts/test.sh (every python call faked: it logs its arguments, one call a line)."""
    import shutil

    # a copy of the checkout's layout (the script clears build/ beside it: never the running suite's own)
    copy = tmp_path / "checkout"
    shutil.copytree(ROOT / "scripts", copy / "scripts")
    shutil.copytree(ROOT / "tests" / "smoke", copy / "tests" / "smoke")
    (copy / "notebooks").mkdir()
    for nb in (ROOT / "notebooks").glob("*.ipynb"):
        (copy / "notebooks" / nb.name).touch()
    calls = tmp_path / "calls.txt"
    env = _fake(tmp_path, f"echo \"$*\" >> {calls}\n")
    env["TEST_WORKERS"] = workers
    run = subprocess.run(["bash", "scripts/test.sh", "-x"], cwd=copy, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return [line.split() for line in calls.read_text().splitlines() if line.startswith("-m pytest")]


def test_the_test_command_runs_notebooks_07_and_08_alone_and_in_order(tmp_path: Path) -> None:
    """Two processes: notebook 08 reads what 07 stores, so the chain (07, then 08) has one process, followed by 06c
    (which reads only data/results/) and the site's build, to balance the two; the other process gets the other unit
    tests (the new-range rerun of 07 among them) and every other notebook; no test-distribution plugin is asked for."""
    notebooks = sorted(p.stem for p in (ROOT / "notebooks").glob("[0-9][0-9]*_*.ipynb"))
    calls = _test_sh_calls(tmp_path, "2")  # the two processes run side by side: their lines come in either order
    assert len(calls) == 3
    *both, asserts = calls  # once both are done: did every notebook assert run under the smoke parameters?
    assert "tests/smoke_asserts_ran.py" in asserts and asserts[-1] == "-x"
    chain, main = sorted(both, key=lambda call: "tests" in call)
    assert [Path(a).stem for a in chain if a.endswith(".ipynb")] == ["07_pso_codesign", "08_worst_case_mu", "06c_pma_authority"]
    assert [Path(a).stem for a in main if a.endswith(".ipynb")] == [n for n in notebooks if not n.startswith(("06c_", "07_", "08_"))]
    assert "tests" in main and "tests" not in chain
    # the site's build runs once, after the chain's notebooks
    assert chain[-2] == "tests/test_site.py" and "--ignore=tests/test_site.py" in main
    # the README's new-range rerun (two smoke runs of 07) is one of the unit tests, in the other process
    assert not any("test_new_h_range" in a for a in chain + main)
    assert chain[-1] == main[-1] == "-x"  # the caller's arguments reach both
    assert not any(a in ("-n", "--dist") for a in chain + main)


def test_the_test_command_in_one_process_keeps_the_chain_in_order(tmp_path: Path) -> None:
    only, asserts = _test_sh_calls(tmp_path, "1")
    assert "tests/smoke_asserts_ran.py" in asserts
    stems = [Path(a).stem for a in only if a.endswith(".ipynb")]
    assert stems.index("08_worst_case_mu") == stems.index("07_pso_codesign") + 1
    assert sorted(stems) == sorted(p.stem for p in (ROOT / "notebooks").glob("[0-9][0-9]*_*.ipynb"))
    assert "tests" in only and not any("--ignore" in a for a in only)  # the site's test among the unit tests


def test_pytest_runs_notebooks_in_the_order_given(tmp_path: Path) -> None:
    """What the chain rests on: one pytest process runs the files in the order of its command line, each notebook's
    cells in order in one kernel. 07 sleeps before it writes a file that 08 reads."""
    import sys

    mark = tmp_path / "written"
    _notebook(tmp_path / "07_writes.ipynb", f"import time\ntime.sleep(1)\nopen({str(mark)!r}, 'w').write('07')")
    _notebook(tmp_path / "08_reads.ipynb", f"assert open({str(mark)!r}).read() == '07'")
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--nbval-lax", "--nbval-current-env",
                          str(tmp_path / "07_writes.ipynb"), str(tmp_path / "08_reads.ipynb")], cwd=tmp_path,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    assert "2 passed" in run.stdout


def test_the_asserts_a_smoke_run_skips_are_named(tmp_path: Path) -> None:
    """scripts/smoke_asserts.py end to end: a notebook run by nbval with the startup file of scripts/test.sh logs the
    asserts that ran; an assert behind a branch the parameters left out, one in an empty loop and one in a function never
    called are named, with their cell and line; magics do not confuse the cell's identity; the startup file leaves no
    import in the notebook's namespace."""
    import sys

    import nbformat

    smoke_asserts = load_script("smoke_asserts")
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell("check = False\nshifts = []"),
                nbformat.v4.new_code_cell("%time x = 1\nassert x == 1\nif check:\n    assert x > 0, 'skipped'\nfor s in shifts:\n    assert s"),
                nbformat.v4.new_code_cell("def f():\n    assert True\nassert [1 for _ in range(2)]"),
                nbformat.v4.new_code_cell("assert set(dir()) & {'os', 'importlib', 'sys', 'smoke_asserts'} == set()")]
    path = tmp_path / "nb.ipynb"
    nbformat.write(nb, path)
    log, ipython = tmp_path / "log", tmp_path / "ipython"
    (ipython / "profile_default" / "startup").mkdir(parents=True)
    (ipython / "profile_default" / "startup" / "00.py").write_text(smoke_asserts.STARTUP)  # as scripts/test.sh writes it
    env = dict(os.environ, SMOKE_ASSERT_LOG=str(log), SMOKE_ASSERT_SCRIPT=str(ROOT / "scripts" / "smoke_asserts.py"),
               IPYTHONDIR=str(ipython))
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--nbval-lax", "--nbval-current-env", str(path)],
                         cwd=tmp_path, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    listed = smoke_asserts.notebook_asserts(path)
    assert [(a["cell_number"], a["line"]) for a in listed] == [(1, 2), (1, 4), (1, 6), (2, 2), (2, 3), (3, 1)]
    missing = smoke_asserts.not_run(log, [path])["nb.ipynb"]
    assert [(a["cell_number"], a["line"], a["text"]) for a in missing] == [(1, 4, "x > 0"), (1, 6, "s"), (2, 2, "True")]
    assert smoke_asserts.main([str(log), str(path)]) == 1
    # a cell the kernel would log under another identity, or not at all, is refused rather than passed over
    for bad, message in (("%%time\nassert x == 1", "cell magic"), ("assert (", "does not parse"), (nb.cells[1].source, "same code")):
        nb.cells.append(nbformat.v4.new_code_cell(bad))
        nbformat.write(nb, path)
        with pytest.raises(ValueError, match=f"nb.ipynb, cell 4: .*{message}"):
            smoke_asserts.notebook_asserts(path)
        nb.cells = nb.cells[:-1]


def _summary(tmp_path: Path, *runs: str) -> subprocess.CompletedProcess:
    import sys

    return subprocess.run([sys.executable, str(ROOT / "scripts" / "test_summary.py"), *runs], cwd=tmp_path,
                          capture_output=True, text=True)


def test_the_summary_line_adds_up_both_reports(tmp_path: Path) -> None:
    for name, (tests, failures, errors, skipped) in {"a": (10, 1, 0, 2), "b": (5, 0, 1, 0)}.items():
        (tmp_path / f"{name}.xml").write_text(f'<testsuites><testsuite tests="{tests}" failures="{failures}" errors="{errors}" '
                                              f'skipped="{skipped}"/></testsuites>')
    run = _summary(tmp_path, "a=a.xml=1", "b=b.xml=1")
    assert run.stdout.strip() == "total: 11 passed, 2 failed, 2 skipped" and run.returncode == 1
    (tmp_path / "c.xml").write_text('<testsuites><testsuite tests="3" failures="0" errors="0" skipped="0"/></testsuites>')
    assert _summary(tmp_path, "c=c.xml=0").stdout.strip() == "total: 3 passed, 0 failed, 0 skipped"


def test_the_summary_line_is_never_green_for_a_run_that_did_not_pass(tmp_path: Path) -> None:
    """A process killed before it wrote its report, or one that exited non-zero with a clean report (interrupted,
    usage error), is named and counted as a failure."""
    (tmp_path / "main.xml").write_text('<testsuites><testsuite tests="10" failures="0" errors="0" skipped="0"/></testsuites>')
    run = _summary(tmp_path, "main=main.xml=0", "chain=chain.xml=137")
    assert "chain: no readable report" in run.stdout and "exit status 137" in run.stdout
    assert run.stdout.splitlines()[-1] == "total: 10 passed, 1 failed, 0 skipped" and run.returncode == 1
    run = _summary(tmp_path, "main=main.xml=2")
    assert "main: exit status 2" in run.stdout and run.stdout.splitlines()[-1] == "total: 10 passed, 1 failed, 0 skipped"


def test_the_test_command_refuses_an_unknown_worker_count(tmp_path: Path) -> None:
    env = _fake(tmp_path, "exit 0\n")
    env["TEST_WORKERS"] = "4"
    run = subprocess.run(["bash", "scripts/test.sh"], cwd=ROOT, env=env, capture_output=True, text=True)
    assert run.returncode == 2 and "TEST_WORKERS must be 1" in run.stderr


def _real_run(tmp_path: Path, params: Path) -> subprocess.CompletedProcess:
    """The main job with the real parameter check and a stand-in for papermill (which logs to calls.txt)."""
    import sys

    calls = tmp_path / "calls.txt"
    env = _fake(tmp_path, f'case "$1" in scripts/check_params.py) exec {sys.executable} "$@";; esac\necho "$*" >> {calls}\n')
    return subprocess.run(["bash", "scripts/run_notebooks.sh", "--params", str(params), "--out", str(tmp_path / "run")],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)


def test_a_misnamed_per_notebook_file_is_refused_before_any_notebook(tmp_path: Path) -> None:
    study = tmp_path / "study"
    study.mkdir()
    (study / "07_pso_codsign.yaml").write_text("n_grid: 5\n")  # a typo of 07_pso_codesign
    run = _real_run(tmp_path, study)
    assert run.returncode == 2 and "07_pso_codsign.yaml" in run.stderr and "07_pso_codesign.yaml" in run.stderr
    assert not (tmp_path / "calls.txt").exists()  # no notebook ran


def test_an_unknown_parameter_name_is_refused_with_the_allowed_ones(tmp_path: Path) -> None:
    (tmp_path / "study.yaml").write_text("h_mni: 0.02\n")
    run = _real_run(tmp_path, tmp_path / "study.yaml")
    assert run.returncode == 2 and "unknown parameter(s) ['h_mni']" in run.stderr and "'h_min'" in run.stderr
    study = tmp_path / "study"
    study.mkdir()
    (study / "07_pso_codesign.yaml").write_text("n_tau: 5\n")  # notebook 08's name, not 07's
    run = _real_run(tmp_path, study)
    assert run.returncode == 2 and "unknown parameter(s) ['n_tau'] for notebook 07_pso_codesign" in run.stderr
    assert not (tmp_path / "calls.txt").exists()
    (study / "07_pso_codesign.yaml").write_text("n_grid: 5\n")  # a good folder passes the check: the notebooks run
    run = _real_run(tmp_path, study)
    assert run.returncode == 0, run.stderr
    assert len((tmp_path / "calls.txt").read_text().splitlines()) == len(list((ROOT / "notebooks").glob("[0-9][0-9]*_*.ipynb")))


def test_the_smoke_parameters_are_the_notebooks_own() -> None:
    """tests/smoke/ is a parameter folder like any other: every file is named after a notebook, every name declared."""

    module = load_script("check_params")
    assert module.problems(ROOT / "tests" / "smoke", module.declared()) == []


def test_the_main_job_resumes_after_the_notebooks_it_ran_to_the_end(tmp_path: Path) -> None:
    """--resume skips the notebooks, from the first on, that the stopped job ran to the end (a copy newer than the
    job's start, every cell run: scripts/keep_executed.py decides; papermill's injected parameters do not count as
    code), and runs everything from the first one that was not: a copy cut off, or older than the job."""
    import json
    import sys

    run_dir = tmp_path / "run" / "notebooks"
    run_dir.mkdir(parents=True)
    notebooks = sorted((ROOT / "notebooks").glob("[0-9][0-9]*_*.ipynb"))
    stamp = run_dir / ".job-start"
    stamp.touch()
    os.utime(stamp, (1e9, 1e9))

    def executed(nb: Path, status: str = "completed", mtime: float | None = None) -> None:
        copy = json.loads(nb.read_text())
        for i, cell in enumerate(copy["cells"]):
            cell.setdefault("metadata", {})["papermill"] = {"status": status}
            cell["execution_count"] = i + 1
        injected = {"cell_type": "code", "execution_count": 0, "metadata": {"tags": ["injected-parameters"],
                    "papermill": {"status": "completed"}}, "outputs": [], "source": "results_dir = 'x'"}
        copy["cells"].insert(1, injected)
        (run_dir / nb.name).write_text(json.dumps(copy))
        if mtime is not None:
            os.utime(run_dir / nb.name, (mtime, mtime))

    executed(notebooks[0])
    executed(notebooks[1], "running")  # cut off: rerun, and every notebook after it
    executed(notebooks[2])
    calls = tmp_path / "calls.txt"
    # stands in for python: the resume check is the real script, papermill logs its input notebook
    env = _fake(tmp_path, f'case "$1" in scripts/*) exec {sys.executable} "$@";; esac\n'
                          f'[ "$2" != papermill ] || echo "$7" >> {calls}\n')

    def resume() -> list[str]:
        calls.unlink(missing_ok=True)
        run = subprocess.run(["bash", "scripts/run_notebooks.sh", "--out", str(tmp_path / "run"), "--resume"], cwd=ROOT,
                             env=env, capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        return [Path(line).name for line in calls.read_text().split()]

    assert resume() == [nb.name for nb in notebooks[1:]]
    executed(notebooks[0], mtime=1e8)  # written before the job began: an older job's copy
    assert resume() == [nb.name for nb in notebooks]
    stamp.unlink()
    run = subprocess.run(["bash", "scripts/run_notebooks.sh", "--out", str(tmp_path / "run"), "--resume"], cwd=ROOT, env=env,
                         capture_output=True, text=True)
    assert run.returncode == 2 and "no stopped job to resume" in run.stderr


def test_the_main_job_runs_only_the_notebooks_named(tmp_path: Path) -> None:
    """--only runs the notebooks named, in the project's order whatever the order given; an unknown name, or --only with
    --resume, is refused before anything runs."""
    calls = tmp_path / "calls.txt"
    env = _fake(tmp_path, f'[ "$2" != papermill ] || echo "$7" >> {calls}\n')
    run = subprocess.run(["bash", "scripts/run_notebooks.sh", "--out", str(tmp_path / "run"), "--only",
                          "08_worst_case_mu,04_t_truss_spacecraft"], cwd=ROOT, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert [Path(line).name for line in calls.read_text().split()] == ["04_t_truss_spacecraft.ipynb", "08_worst_case_mu.ipynb"]
    for args, message in ((["--only", "04_truss"], "--only: no notebook 04_truss; the notebooks are: 01_titop_beam"),
                          (["--only", "08_worst_case_mu", "--resume"], "--resume and --only exclude each other")):
        run = subprocess.run(["bash", "scripts/run_notebooks.sh", "--out", str(tmp_path / "run"), *args], cwd=ROOT, env=env,
                             capture_output=True, text=True)
        assert run.returncode == 2 and message in run.stderr, run.stderr
