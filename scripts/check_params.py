"""Check a parameter file or folder of the main job (scripts/run_notebooks.sh --params) against the notebooks'
parameters cells, before any notebook runs.

``python scripts/check_params.py PATH``: a YAML file applies to every notebook, so each of its names must be declared
by at least one notebook; a folder may hold ``all.yaml`` (the same rule) and ``NN_name.yaml`` files, one per notebook,
whose names that notebook must declare. Anything else (an unknown name, a file named after no notebook, a file that
is not a YAML mapping) is an error that says what was found and what is allowed. Exit status 2 on an error.
"""

from __future__ import annotations

import sys
from pathlib import Path

import papermill
import yaml

NOTEBOOKS = Path(__file__).resolve().parents[1] / "notebooks"


def declared() -> dict[str, set[str]]:
    """The parameters of each notebook's parameters cell, by notebook name (``NN_name``)."""
    return {nb.stem: set(papermill.inspect_notebook(str(nb))) for nb in sorted(NOTEBOOKS.glob("[0-9][0-9]*_*.ipynb"))}


def _mapping(path: Path) -> dict:
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as err:
        raise ValueError(f"{path} is not valid YAML: {err}") from err
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ValueError(f"{path} must be a YAML mapping of parameter names to values, got a {type(data).__name__}")
    return data


def problems(path: Path, params: dict[str, set[str]]) -> list[str]:
    """What is wrong with the parameter file or folder at ``path`` (empty if nothing)."""
    every = set().union(*params.values())
    out = []

    def unknown_in(file: Path, allowed: set[str], scope: str) -> None:
        bad = sorted(set(_mapping(file)) - allowed)
        if bad:
            out.append(f"{file}: unknown parameter(s) {bad} for {scope}; allowed: {sorted(allowed)}")

    if path.is_dir():
        names = {f"{stem}.yaml" for stem in params} | {"all.yaml"}
        for file in sorted(path.iterdir()):
            if file.suffix not in (".yaml", ".yml"):
                continue
            if file.name not in names:
                out.append(f"{file}: a parameter folder holds all.yaml and one NN_name.yaml per notebook; "
                           f"this name is none of {sorted(names)}")
            elif file.name == "all.yaml":
                unknown_in(file, every, "any notebook")
            else:
                unknown_in(file, params[file.stem], f"notebook {file.stem}")
    else:
        unknown_in(path, every, "any notebook")
    return out


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print("usage: python scripts/check_params.py PARAMS.yaml|PARAMS_DIR", file=sys.stderr)
        return 2
    try:
        found = problems(Path(argv[0]), declared())
    except ValueError as err:
        found = [str(err)]
    for line in found:
        print(line, file=sys.stderr)
    return 2 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
