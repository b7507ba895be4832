"""The kept executed notebooks (``notebooks/executed/``, scripts/keep_executed.py) and the site (scripts/site.sh).

A reader with no main job run opens every notebook with its outputs: each kept copy was executed from the notebook's
current code, without an error, in the run that wrote the stored results. The site builds with no Sphinx warning,
every internal link and image of it resolves, and every public module, function and class and every notebook has its
page.
"""

from __future__ import annotations

import importlib
import inspect
import json
import os
import pkgutil
import re
import subprocess
import sys
from pathlib import Path

import pytest
from _scripts import load_script

ROOT = Path(__file__).resolve().parents[1]
keep = load_script("keep_executed")
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]*_*.ipynb"))


def _nb(path: Path) -> dict:
    return json.loads(path.read_text())


@pytest.mark.parametrize("source", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_notebook_is_kept_executed_from_its_current_code(source: Path) -> None:
    kept = ROOT / "notebooks" / "executed" / source.name
    assert kept.is_file(), f"no executed copy {kept.relative_to(ROOT)}: run the main job (bash scripts/run_notebooks.sh)"
    nb = _nb(kept)
    assert keep.code_cells(nb) == keep.code_cells(_nb(source)), (
        f"{kept.relative_to(ROOT)} shows another version of the notebook's code: rerun the main job"
    )
    code = [c for c in nb["cells"] if c["cell_type"] == "code"]
    assert all(c["execution_count"] is not None for c in code if "".join(c["source"]).strip()), "a cell never ran"
    assert not keep.failed(nb)
    assert any(c["outputs"] for c in code), "no outputs"
    assert "papermill" not in nb["metadata"] and not any("execution" in c.get("metadata", {}) for c in nb["cells"])


def test_every_kept_copy_has_its_notebook() -> None:
    """A renamed or removed notebook leaves no kept copy behind (the site would still publish it)."""
    kept = sorted(p.name for p in (ROOT / "notebooks" / "executed").glob("*.ipynb"))
    assert kept == sorted(p.name for p in NOTEBOOKS)


@pytest.mark.parametrize("source", NOTEBOOKS, ids=lambda p: p.stem)
def test_kept_copies_come_from_the_run_that_wrote_the_stored_results(source: Path) -> None:
    """The hashes a kept copy recorded are those of ``data/results/`` now: a notebook rerun (or a stored result
    edited) without its copy kept shows here."""
    meta = _nb(ROOT / "notebooks" / "executed" / source.name)["metadata"]["trusscodesign"]
    assert meta["source"] == f"notebooks/{source.name}"
    assert meta["results"] == keep.results_of(source.stem), (
        f"data/results/ was written by another run than notebooks/executed/{source.name}: rerun the main job"
    )


def _executed(cells: list[dict]) -> dict:
    return {"cells": cells, "metadata": {"papermill": {"duration": 1.0}}, "nbformat": 4, "nbformat_minor": 5}


def _code(src: str, outputs: list | None = None) -> dict:
    meta = {"papermill": {"duration": 1.0}, "execution": {"iopub.status.busy": "2026-01-01T00:00:00Z"}}
    return {"cell_type": "code", "source": src, "metadata": meta, "execution_count": 1, "outputs": outputs or []}


def test_keep_cleans_links_and_metadata_and_refuses_a_stale_or_failed_copy(tmp_path: Path) -> None:
    """The checks above can fail, and the copy is what a reader needs: timestamps gone, links one level deeper,
    the stored results hashed; another version's copy and a failed one are not kept, a removed notebook's copy goes."""
    src, run, kept, results = (tmp_path / d for d in ("notebooks", "run", "kept", "results"))
    for d in (src, run, results):
        d.mkdir()
    (results / "01_a.json").write_text("{}")
    (results / "01_a.json.lock").write_text("")
    (results / "02_b.json").write_text("{}")
    md = {"cell_type": "markdown", "source": "see [the page](../docs/titop.md) and [a](b.md)", "metadata": {}}
    (src / "01_a.ipynb").write_text(json.dumps(_executed([md, _code("x = 1")])))
    (run / "01_a.ipynb").write_text(json.dumps(_executed([md, _code("x = 1", [{"output_type": "stream", "text": "1"}])])))
    [path] = keep.keep(run, kept, src, results)
    nb = _nb(path)
    assert nb["metadata"]["trusscodesign"]["results"] == {"01_a.json": keep.results_of("01_a", results)["01_a.json"]}
    assert "".join(nb["cells"][0]["source"]) == "see [the page](../../docs/titop.md) and [a](b.md)"
    assert nb["cells"][1]["metadata"] == {} and "papermill" not in nb["metadata"]
    assert keep.keep(run, kept, src, results)[0].read_bytes() == path.read_bytes()  # a rerun changes no byte
    (src / "01_a.ipynb").write_text(json.dumps(_executed([md, _code("x = 2")])))
    assert keep.keep(run, kept, src, results) == [] and path.is_file()  # another version's copy: the old one stays
    error = {"output_type": "error", "ename": "E", "evalue": "", "traceback": []}
    (run / "01_a.ipynb").write_text(json.dumps(_executed([md, _code("x = 2", [error])])))
    assert keep.keep(run, kept, src, results) == []
    (src / "01_a.ipynb").write_text(json.dumps(_executed([md, _code("x = 1")])))
    (run / "01_a.ipynb").write_text(json.dumps(_executed([md, _code("x = 1")])))
    assert keep.keep(run, kept, src, results, names=["02_b"]) == []  # a job that ran 02 alone keeps 02 alone
    (src / "01_a.ipynb").unlink()
    keep.keep(run, kept, src, results)
    assert not path.exists()  # its notebook is gone: so is its copy


def _public_objects() -> dict[str, list[str]]:
    """Every public module of the package, with the public functions and classes it defines (those of ``__all__`` if it
    has one; a re-export is documented where it is defined)."""
    sys.path.insert(0, str(ROOT / "lib"))
    import trusscodesign

    out = {}
    for info in pkgutil.walk_packages(trusscodesign.__path__, "trusscodesign."):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        module = importlib.import_module(info.name)
        public = getattr(module, "__all__", None) or [n for n in vars(module) if not n.startswith("_")]
        out[info.name] = sorted(n for n in public if (inspect.isfunction(obj := getattr(module, n)) or inspect.isclass(obj))
                                and obj.__module__ == info.name)
    out["trusscodesign"] = []
    return out


_REF = re.compile(r'(?:href|src)="([^"#?]*)[^"]*"')


def _broken_links(site: Path) -> list[str]:
    broken = []
    for page in site.rglob("*.html"):
        if page.parts[len(site.parts)] == "_static":  # the theme's templates, not pages
            continue
        for target in _REF.findall(page.read_text(errors="replace")):
            if not target or re.match(r"[a-z]+:", target) or target.startswith("//"):
                continue
            if not (page.parent / target).exists():
                broken.append(f"{page.relative_to(site)} -> {target}")
    return broken


def test_the_site_builds_without_warning_and_has_every_page(tmp_path: Path) -> None:
    site = tmp_path / "site"
    run = subprocess.run(["bash", str(ROOT / "scripts" / "site.sh"), "--no-install", "--out", str(site)],
                         capture_output=True, text=True, env={**os.environ, "PYTHON": sys.executable})
    assert run.returncode == 0, f"the site does not build without warnings:\n{run.stdout}\n{run.stderr}"
    assert (site / "index.html").is_file()
    for source in NOTEBOOKS:
        page = site / "notebooks" / "executed" / f"{source.stem}.html"
        assert page.is_file(), f"no page for {source.name}"
        figures = sum("image/png" in o.get("data", {}) for c in _nb(ROOT / "notebooks" / "executed" / source.name)["cells"]
                      for o in c.get("outputs", []))
        assert page.read_text().count("<img") >= figures > 0, f"{page.name} does not show the notebook's figures"
    missing = []
    for module, names in _public_objects().items():
        page = site / "docs" / "api" / f"{module}.html"
        if not page.is_file():
            missing.append(f"{module}: no page")
            continue
        text = page.read_text()
        missing += [f"{module}.{n}" for n in names if f'id="{module}.{n}"' not in text]
    assert not missing, "public modules or objects without their entry in the API reference:\n" + "\n".join(missing)
    assert not _broken_links(site), "links or images of the site that lead nowhere:\n" + "\n".join(_broken_links(site))


def test_the_link_check_finds_what_leads_nowhere(tmp_path: Path) -> None:
    (tmp_path / "docs").mkdir()
    (tmp_path / "b.html").write_text("")
    (tmp_path / "docs" / "a.html").write_text('<a href="../b.html#x">b</a> <img src="fig.png"> <a href="https://example.org/">'
                                              '</a> <a href="#top"></a> <a href="mailto:x@y.z"></a>')
    assert _broken_links(tmp_path) == ["docs/a.html -> fig.png"]


def test_a_finished_run_is_told_from_a_cut_off_stale_or_failed_one(tmp_path: Path) -> None:
    source, executed = tmp_path / "01_a.ipynb", tmp_path / "run.ipynb"
    source.write_text(json.dumps(_executed([_code("x = 1")])))

    def run(src: str, status: str = "completed", outputs: list | None = None) -> None:
        cell = _code(src, outputs)
        cell["metadata"]["papermill"]["status"] = status
        executed.write_text(json.dumps(_executed([cell])))

    assert not keep.finished(executed, source)  # never run
    run("x = 1")
    assert keep.finished(executed, source)
    died = json.loads(executed.read_text())
    died["cells"][0]["execution_count"] = None  # its kernel died in the cell: papermill says completed, no error
    executed.write_text(json.dumps(died))
    assert not keep.finished(executed, source)
    run("x = 1", "running")
    assert not keep.finished(executed, source)
    run("x = 2")
    assert not keep.finished(executed, source)
    run("x = 1", outputs=[{"output_type": "error", "ename": "E", "evalue": "", "traceback": []}])
    assert not keep.finished(executed, source)
    executed.write_text('{"cells": [')  # cut off while written
    assert not keep.finished(executed, source)


def test_the_site_refuses_to_replace_a_folder_that_is_not_a_site(tmp_path: Path) -> None:
    (tmp_path / "keep.txt").write_text("mine")
    run = subprocess.run(["bash", str(ROOT / "scripts" / "site.sh"), "--no-install", "--out", str(tmp_path)],
                         capture_output=True, text=True, env={**os.environ, "PYTHON": sys.executable})
    assert run.returncode == 2 and "is no earlier build of the site" in run.stderr
    assert (tmp_path / "keep.txt").read_text() == "mine"
