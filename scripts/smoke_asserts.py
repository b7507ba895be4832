"""Which of the notebooks' asserts ran under their smoke parameters.

Smoke parameters may shrink a notebook's loops, never switch a check off. This script makes that checkable:

- in each kernel of the test run, an IPython AST transformer (:func:`install`, loaded by the startup file
  :data:`STARTUP` that ``scripts/test.sh`` writes with ``--startup``) follows every ``assert`` statement of a cell with a
  call that logs the assert as run;
- after the notebooks, ``python scripts/smoke_asserts.py LOG_DIR NOTEBOOK...`` lists every assert of each notebook and
  names those that never ran (a branch or a loop that the smoke parameters left out); it exits 1 if there is one.

An assert is known by its cell (a hash of the cell's syntax tree, so that moving lines or cells changes nothing) and
its order in the cell; the transformer and the lister compute both from the same source, as IPython parses it.
"""

from __future__ import annotations

import ast
import hashlib
import json
import os
import sys
from pathlib import Path
from typing import Any

RECORD = "__smoke_assert_ran__"  # the name of the logging function in the kernel's namespace
LOG_ENV = "SMOKE_ASSERT_LOG"  # the folder the kernels log to


def cell_tree(source: str) -> ast.Module | None:
    """A code cell's syntax tree as IPython parses it (magics turned into calls first); None if it does not parse."""
    from IPython.core.inputtransformer2 import TransformerManager

    try:
        return ast.parse(TransformerManager().transform_cell(source))
    except SyntaxError:
        return None


def fingerprint(tree: ast.Module) -> str:
    """The cell's identity: a hash of its syntax tree without positions."""
    return hashlib.sha1(ast.dump(tree, include_attributes=False).encode()).hexdigest()[:16]


def asserts_of(tree: ast.Module) -> list[ast.Assert]:
    """The cell's asserts in a fixed order (source order)."""
    found = [node for node in ast.walk(tree) if isinstance(node, ast.Assert)]
    return sorted(found, key=lambda node: (node.lineno, node.col_offset))


class _Recorder(ast.NodeTransformer):
    """Follows each assert of one cell with ``RECORD(cell, k)``; run before any other change to the tree."""

    def __init__(self, tree: ast.Module) -> None:
        self.cell = fingerprint(tree)
        self.index = {id(node): k for k, node in enumerate(asserts_of(tree))}

    def visit_Assert(self, node: ast.Assert) -> list[ast.stmt]:
        call = ast.Expr(ast.Call(ast.Name(RECORD, ast.Load()), [ast.Constant(self.cell), ast.Constant(self.index[id(node)])], []))
        return [node, ast.copy_location(call, node)]


def instrument(tree: ast.Module) -> ast.Module:
    """``tree`` with every assert followed by the call that logs it (the tree is changed in place)."""
    recorder = _Recorder(tree)
    return ast.fix_missing_locations(recorder.visit(tree))


class _Transformer(ast.NodeTransformer):
    """IPython's hook: ``visit`` receives each cell's module before it runs."""

    def visit(self, node: ast.AST) -> ast.AST:
        return instrument(node) if isinstance(node, ast.Module) else node


STARTUP = f"""# written by scripts/test.sh: log the asserts this kernel runs (scripts/smoke_asserts.py)
def _log_asserts():
    import importlib.util, os
    if os.environ.get("{LOG_ENV}"):
        spec = importlib.util.spec_from_file_location("smoke_asserts", os.environ["SMOKE_ASSERT_SCRIPT"])
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        module.install()
_log_asserts()
del _log_asserts
"""  # an IPython startup file (SMOKE_ASSERT_SCRIPT: this file's path). It leaves no name in the notebook's namespace but
# the logging call: a notebook that forgets an import must fail in the tests as it does for a user


def install(log_dir: str | os.PathLike | None = None) -> None:
    """Log every assert that runs in this IPython kernel to ``log_dir/<pid>.jsonl`` (default: ``$SMOKE_ASSERT_LOG``).

    Raises
    ------
    RuntimeError
        Under ``python -O`` (asserts compiled away: the log would record checks that never ran).
    """
    from IPython import get_ipython

    if sys.flags.optimize:
        raise RuntimeError("asserts are compiled away (python -O or PYTHONOPTIMIZE): the notebooks' checks would not run")
    ip = get_ipython()
    folder = Path(log_dir or os.environ[LOG_ENV])
    folder.mkdir(parents=True, exist_ok=True)
    log = folder / f"{os.getpid()}.jsonl"
    seen: set[tuple[str, int]] = set()

    def ran(cell: str, k: int) -> None:
        if (cell, k) not in seen:
            seen.add((cell, k))
            with open(log, "a") as f:
                f.write(json.dumps([cell, k]) + "\n")

    ip.user_ns[RECORD] = ran
    ip.ast_transformers.append(_Transformer())


def notebook_asserts(path: Path) -> list[dict[str, Any]]:
    """Every assert of a notebook: ``cell`` (fingerprint), ``k``, ``cell_number`` (0-based index), ``line``, ``text``.

    Raises
    ------
    ValueError
        For a code cell that does not parse, an assert inside a cell magic (the kernel would log it under another
        cell), or two cells with asserts and the same code (one's run would count for the other).
    """
    out: list[dict[str, Any]] = []
    for number, cell in enumerate(json.loads(path.read_text())["cells"]):
        if cell["cell_type"] != "code":
            continue
        source = "".join(cell["source"])
        if source.lstrip().startswith("%%") and "assert" in source:
            raise ValueError(f"{path.name}, cell {number}: an assert inside a cell magic cannot be followed; move it out")
        tree = cell_tree(source)
        if tree is None:
            raise ValueError(f"{path.name}, cell {number}: the cell does not parse")
        fp = fingerprint(tree)
        if asserts_of(tree) and any(a["cell"] == fp for a in out):
            raise ValueError(f"{path.name}, cell {number}: the same code as an earlier cell with asserts; make them differ")
        out += [{"cell": fp, "k": k, "cell_number": number, "line": node.lineno, "text": ast.unparse(node.test)[:100]}
                for k, node in enumerate(asserts_of(tree))]
    return out


def ran_asserts(log_dir: Path) -> set[tuple[str, int]]:
    """The asserts logged as run by every kernel of the run."""
    return {tuple(json.loads(line)) for f in log_dir.glob("*.jsonl") for line in f.read_text().splitlines() if line}


def not_run(log_dir: Path, notebooks: list[Path]) -> dict[str, list[dict[str, Any]]]:
    """Per notebook name, its asserts that no kernel logged as run."""
    ran = ran_asserts(log_dir)
    return {nb.name: [a for a in notebook_asserts(nb) if (a["cell"], a["k"]) not in ran] for nb in notebooks}


def main(argv: list[str]) -> int:
    if argv == ["--startup"]:
        print(STARTUP, end="")
        return 0
    if len(argv) < 2:
        print("usage: python scripts/smoke_asserts.py LOG_DIR NOTEBOOK...", file=sys.stderr)
        return 2
    log_dir, notebooks = Path(argv[0]), [Path(a) for a in argv[1:]]
    missing = not_run(log_dir, notebooks)
    for name, rows in missing.items():
        total = len(notebook_asserts(next(nb for nb in notebooks if nb.name == name)))
        print(f"{name}: {total - len(rows)} of {total} asserts ran")
        for a in rows:
            print(f"  NOT RUN: cell {a['cell_number']}, line {a['line']}: assert {a['text']}")
    return 1 if any(missing.values()) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
