"""Results files: one JSON per notebook, so that runs can be compared by a program."""

from __future__ import annotations

import json
import os
import platform
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from .paths import resolve

__all__ = ["to_jsonable", "from_jsonable", "write_json", "read_keyed", "save_results", "load_results"]


def to_jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays (and nested containers) to plain JSON types."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating, float)):
        return float(value) if np.isfinite(value) else str(value)
    if isinstance(value, complex):
        return {"re": value.real, "im": value.imag}
    return value


_NON_FINITE = {"inf": np.inf, "-inf": -np.inf, "nan": np.nan}  # how :func:`to_jsonable` writes non-finite floats


def from_jsonable(value: Any) -> Any:
    """Undo :func:`to_jsonable` for non-finite floats (the strings ``"inf"``, ``"-inf"``, ``"nan"``, in nested
    dicts and lists); everything else is returned as read."""
    if isinstance(value, dict):
        return {k: from_jsonable(v) for k, v in value.items()}
    if isinstance(value, list):
        return [from_jsonable(v) for v in value]
    return _NON_FINITE.get(value, value) if isinstance(value, str) else value


def write_json(path: str | Path, payload: Any) -> Path:
    """Write ``to_jsonable(payload)`` to ``path`` atomically: a crash while writing leaves the previous file intact."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(to_jsonable(payload)))
    os.replace(tmp, path)
    return path


def read_keyed(path: str | Path | None, key: Any) -> tuple[dict | None, Any]:
    """A file written by :func:`write_json` as ``{"key": key, ...}`` (None if absent or written with another key), and
    the key as it reads back from a file (what to write with new results).

    The key holds what the stored results depend on (settings, gains, versions): results computed with another key are
    never reused. Objects JSON cannot hold are keyed by their ``str`` (give arrays as lists)."""
    key = json.loads(json.dumps(key, default=str))
    if path is not None and Path(path).exists():
        stored = from_jsonable(json.loads(Path(path).read_text()))
        if stored.get("key") == key:
            return stored, key
    return None, key


def save_results(name: str, results: dict[str, Any], results_dir: str | Path = "data/results",
                 parameters: dict[str, Any] | None = None) -> Path:
    """Write ``results`` (and the run's ``parameters``) to ``<results_dir>/<name>.json``.

    The file also records the library version and the version of the synthesis optimiser
    (:data:`lib.synthesis.ALGORITHM`), on which every robust design depends.

    Returns the path written.
    """
    from .synthesis import ALGORITHM

    folder = resolve(results_dir)
    payload = {
        "notebook": name,
        "library_version": __version__,
        "synthesis_algorithm": ALGORITHM,
        "python": platform.python_version(),
        "parameters": to_jsonable(parameters or {}),
        "results": to_jsonable(results),
    }
    path = folder / f"{name}.json"
    path.write_text(json.dumps(payload, indent=2, sort_keys=False) + "\n")
    return path


def load_results(name: str, results_dir: str | Path = "data/results") -> dict[str, Any]:
    """Read a results file written by :func:`save_results`."""
    path = resolve(results_dir, create=False) / f"{name}.json"
    if not path.exists():
        raise FileNotFoundError(f"no results file {path}: run notebook {name} first")
    return json.loads(path.read_text())
