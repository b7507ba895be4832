"""Keep the main job's executed notebooks with the project, in ``notebooks/executed/``, for readers and for the site.

``python scripts/keep_executed.py RUN_DIR [NOTEBOOK ...]`` copies each executed notebook of ``RUN_DIR`` (the main
job's ``runs/latest/notebooks``; only the notebooks named, if any: those the job ran) to ``notebooks/executed/``, with:

- the volatile metadata removed (papermill's and the kernel's timestamps and durations), so that a rerun that
  reproduces the same outputs changes no byte (the figures are deterministic PNGs);
- Markdown links relative to ``notebooks/`` made relative to ``notebooks/executed/`` (one level deeper);
- in the notebook's metadata, under ``trusscodesign``, the source notebook it was run from and the SHA-256 of each
  stored result the notebook writes (``data/results/NN_*``), so that a test can tell a kept copy from a stale one.

Only the main job with its defaults calls it (``scripts/run_notebooks.sh`` without ``--out`` or ``--params``): the kept
copies are the run that wrote ``data/results/`` and ``figures/``.
"""

from __future__ import annotations

import hashlib
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
KEPT = NOTEBOOKS / "executed"
RESULTS = ROOT / "data" / "results"

# a Markdown link or image whose target climbs out of notebooks/ ("](../docs/titop.md)")
_UP_LINK = re.compile(r"\]\(\.\./")


def results_of(name: str, results_dir: Path = RESULTS) -> dict[str, str]:
    """SHA-256 of each stored result of the notebook ``name`` (``NN_title``): the files ``NN_*`` of ``results_dir``."""
    prefix = name.split("_", 1)[0] + "_"
    return {
        p.name: hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(results_dir.glob(prefix + "*"))
        if p.is_file() and not p.name.endswith(".lock")
    }


def clean(nb: dict, name: str, results_dir: Path = RESULTS) -> dict:
    """The executed notebook ``nb`` as it is kept (see the module's docstring); ``nb`` is not modified."""
    out = json.loads(json.dumps(nb))
    out["metadata"].pop("papermill", None)
    out["metadata"]["trusscodesign"] = {"source": f"notebooks/{name}.ipynb", "results": results_of(name, results_dir)}
    for cell in out["cells"]:
        cell.get("metadata", {}).pop("papermill", None)
        cell.get("metadata", {}).pop("execution", None)
        if cell["cell_type"] == "markdown":
            src = "".join(cell["source"]) if isinstance(cell["source"], list) else cell["source"]
            cell["source"] = _UP_LINK.sub("](../../", src).splitlines(keepends=True)
    return out


def code_cells(nb: dict) -> list[str]:
    """The source of each code cell, in order, papermill's injected parameters left out (what a kept copy must share
    with its notebook)."""
    return ["".join(c["source"]) if isinstance(c["source"], list) else c["source"] for c in nb["cells"]
            if c["cell_type"] == "code" and "injected-parameters" not in c.get("metadata", {}).get("tags", [])]


def failed(nb: dict) -> bool:
    """True if a cell of the executed notebook ``nb`` ended in an error (papermill stopped there)."""
    return any(o.get("output_type") == "error" for c in nb["cells"] for o in c.get("outputs", []))


def problem(nb: dict, source: dict) -> str | None:
    """Why the executed notebook ``nb`` is not a complete run of the notebook ``source``'s current code, or None.

    A cell whose kernel died has no execution count (papermill marks it completed, with no error), nor has any cell
    after a stop.
    """
    if code_cells(nb) != code_cells(source):
        return "it was executed from another version of the notebook's code"
    if failed(nb):
        return "a cell failed (see its error cell)"
    code = [c for c in nb["cells"] if c["cell_type"] == "code" and "".join(c["source"]).strip()]
    if any(c.get("execution_count") is None or c.get("metadata", {}).get("papermill", {}).get("status", "completed")
           != "completed" for c in code):
        return "a cell did not run to its end (the run was stopped or its kernel died)"
    return None


def _read(path: Path) -> dict | None:
    try:
        return json.loads(path.read_text())
    except (OSError, json.JSONDecodeError):  # missing, or cut off while papermill was writing it
        return None


def finished(executed: Path, source: Path) -> bool:
    """True if ``executed`` is a complete run of the current ``source`` (:func:`problem` finds nothing): the main job's
    ``--resume`` skips such a notebook."""
    nb = _read(executed)
    return nb is not None and problem(nb, json.loads(source.read_text())) is None


def keep(run_dir: Path, kept: Path = KEPT, notebooks: Path = NOTEBOOKS, results_dir: Path = RESULTS,
         names: list[str] | None = None) -> list[Path]:
    """Copy every complete executed notebook of ``run_dir`` whose source is in ``notebooks`` (those of ``names``, the
    notebooks a job ran, if given) to ``kept``; returns the copies. A notebook that is not a complete run of its current code (:func:`problem`) is not kept: its earlier kept
    copy, if any, stays, and a line on standard error says why. A kept copy whose notebook no longer exists is removed.
    """
    kept.mkdir(parents=True, exist_ok=True)
    for old in sorted(kept.glob("*.ipynb")):
        if not (notebooks / old.name).is_file():
            old.unlink()
            print(f"removed {old.name}: no such notebook", file=sys.stderr)
    written = []
    for path in sorted(run_dir.glob("[0-9][0-9]*_*.ipynb")):
        source = notebooks / path.name
        if not source.is_file() or (names is not None and path.stem not in names):
            continue
        nb = _read(path)
        why = "it cannot be read" if nb is None else problem(nb, json.loads(source.read_text()))
        if nb is None or why is not None:
            print(f"not kept: {path.name}: {why}", file=sys.stderr)
            continue
        text = json.dumps(clean(nb, path.stem, results_dir), indent=1, ensure_ascii=False) + "\n"
        (kept / path.name).write_text(text)
        written.append(kept / path.name)
    return written


def main(argv: list[str]) -> int:
    if len(argv) == 3 and argv[0] == "--finished":  # exit status 0 if argv[1] is a complete run of the notebook argv[2]
        return 0 if finished(Path(argv[1]), Path(argv[2])) else 1
    if not argv or not Path(argv[0]).is_dir():
        print("usage: python scripts/keep_executed.py RUN_DIR [NOTEBOOK ...] (the main job's runs/latest/notebooks, and "
              "the notebooks it ran, default all), or --finished EXECUTED SOURCE", file=sys.stderr)
        return 2
    for path in keep(Path(argv[0]), names=argv[1:] or None):
        print(f"kept {path.relative_to(ROOT)} ({path.stat().st_size / 1e6:.2f} MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
