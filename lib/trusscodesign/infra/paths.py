"""Where things are: the input data shipped with the package, and the folders that runs write to.

``PACKAGE_DATA`` is the package's own data folder (spacecraft parameters and presets, the stored Nastran tables of the cube);
it is installed with the package, so that a plain ``pip install`` builds the models from any folder. ``ROOT`` is the
repository checkout that holds this package (``lib/trusscodesign`` under it), or ``None`` when the package runs from an
installed copy; the notebooks' relative output folders (``data/results``, ``figures``) are taken from it.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["PACKAGE_DATA", "ROOT", "resolve"]

_PACKAGE = Path(__file__).resolve().parents[1]  # lib/trusscodesign (this module is in its infra/)
PACKAGE_DATA = _PACKAGE / "data"


def _checkout_root() -> Path | None:
    """The repository holding this package (``<root>/lib/trusscodesign``, with ``<root>/pyproject.toml``), if any."""
    root = _PACKAGE.parents[1]
    here_in_lib = _PACKAGE.parent == root / "lib"
    return root if here_in_lib and (root / "pyproject.toml").is_file() else None


ROOT = _checkout_root()


def resolve(path: str | Path, create: bool = True) -> Path:
    """Absolute path: ``path`` as is if absolute, else relative to the checkout's root (the current folder when the
    package is an installed copy, outside any checkout).

    Notebooks take their output folders as papermill parameters relative to the root, so that runs from any working
    directory write to the same place.
    """
    out = Path(path)
    if not out.is_absolute():
        out = (ROOT if ROOT is not None else Path.cwd()) / out
    if create:
        out.mkdir(parents=True, exist_ok=True)
    return out
