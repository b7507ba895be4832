"""Project paths: repository root, data, figures and results folders."""

from __future__ import annotations

from pathlib import Path

__all__ = ["ROOT", "DATA", "FIGURES", "RESULTS", "resolve"]

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"
FIGURES = ROOT / "figures"
RESULTS = DATA / "results"


def resolve(path: str | Path, create: bool = True) -> Path:
    """Absolute path: ``path`` as is if absolute, else relative to the repository root.

    Notebooks take their output folders as papermill parameters relative to the
    root, so that runs from any working directory write to the same place.
    """
    out = Path(path)
    if not out.is_absolute():
        out = ROOT / out
    if create:
        out.mkdir(parents=True, exist_ok=True)
    return out
