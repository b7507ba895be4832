"""Results files: one JSON per notebook, so that runs can be compared by a program."""

from __future__ import annotations

import dataclasses
import json
import os
import platform
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from .paths import resolve
from .versions import ALGORITHM

__all__ = ["to_jsonable", "from_jsonable", "write_json", "read_json", "run_lock", "read_keyed", "normalise_key", "save_results", "load_results",
           "moved_numbers", "load_reference"]


def to_jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays (and nested containers, dataclass instances) to plain JSON types.

    Raises
    ------
    ValueError
        If two keys of a dict have the same ``str`` (e.g. ``1`` and ``"1"``): one entry would be lost.
    """
    if isinstance(value, dict):
        out = {str(k): to_jsonable(v) for k, v in value.items()}
        if len(out) != len(value):
            raise ValueError(f"dict keys {list(value)!r} collide as JSON strings: one entry would be lost")
        return out
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return to_jsonable({f.name: getattr(value, f.name) for f in dataclasses.fields(value)})
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
    if isinstance(value, (complex, np.complexfloating)):
        return {"re": to_jsonable(float(value.real)), "im": to_jsonable(float(value.imag))}
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


def write_json(path: str | Path, payload: Any, indent: int | None = None) -> Path:
    """Write ``to_jsonable(payload)`` to ``path`` atomically: a crash while writing leaves the previous file intact.

    The text goes to a temporary file of a unique name in the same folder, flushed to disk, then renamed over
    ``path``: writers that share a folder never write into one another's temporary file, and a reader sees the old
    file or the new one, never a part.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(to_jsonable(payload), indent=indent, allow_nan=False)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)  # as an ordinary new file (mkstemp's are the owner's only): shared folders stay shared
        with os.fdopen(fd, "w") as fh:
            fh.write(text + "\n" if indent is not None else text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def read_json(path: str | Path) -> Any:
    """The JSON value of the file at ``path`` (as written, see :func:`from_jsonable` for the non-finite floats).

    Raises
    ------
    ValueError
        The file is not valid JSON (e.g. truncated by a copy or an edit): the message names the file and the place.
    """
    path = Path(path)
    try:
        return json.loads(path.read_text())
    except json.JSONDecodeError as err:
        raise ValueError(f"{path} is not valid JSON ({err.msg} at line {err.lineno}, column {err.colno}): the file is "
                         "damaged or truncated; restore it (git checkout, a backup) or delete it to recompute") from err


@contextmanager
def run_lock(target: str | Path) -> Iterator[Path]:
    """Hold ``<target>.lock`` while a run writes ``target`` (a checkpoint, a grid cache), so that two runs never share one.

    The lock is the operating system's (``flock``): it is released when the run ends, however it ends, so a killed run
    leaves no stale lock behind. The lock file records its holder (process id, host, start time) for the message that
    another run gets.

    Raises
    ------
    RuntimeError
        Another live process holds the lock: the message names it, and the way out (wait, or another results folder).
    """
    import fcntl
    import socket

    lock = Path(str(target) + ".lock")
    lock.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        holder = lock.read_text().strip() or "a process that has not yet written its name"
        os.close(fd)
        who = "this process itself, in another call" if holder.startswith(f"process {os.getpid()} ") else "another run"
        raise RuntimeError(f"{target} is in use by {who} ({holder}): wait for it to finish, or give this run "
                           "another results folder (results_dir)") from None
    except OSError as err:  # e.g. a network file system mounted without locks
        os.close(fd)
        raise RuntimeError(f"cannot lock {lock} ({err.strerror}): the file system of the results folder does not support "
                           "locks; use a local results folder (results_dir)") from err
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"process {os.getpid()} on {socket.gethostname()}, since {time.strftime('%Y-%m-%d %H:%M:%S')}".encode())
        yield lock
    finally:
        os.close(fd)  # releases the lock


def read_keyed(path: str | Path | None, key: Any) -> tuple[dict | None, Any]:
    """A file written by :func:`write_json` as ``{"key": key, ...}`` (None if absent or written with another key), and
    the key as it reads back from a file (what to write with new results).

    The key holds what the stored results depend on (settings, gains, versions): results computed with another key are
    never reused. Objects JSON cannot hold are keyed by their ``str`` (give arrays as lists)."""
    key = normalise_key(key)
    if path is not None and Path(path).exists():
        raw = read_json(path)
        # compared as written (non-finite floats as strings), so that NaN matches NaN
        if isinstance(raw, dict) and raw.get("key") == key:
            return from_jsonable(raw), key
    return None, key


def normalise_key(key: Any) -> Any:
    """A key of :func:`read_keyed` as :func:`write_json` writes it (arrays and numpy scalars exactly, non-finite floats
    as strings; other objects JSON cannot hold by their ``str``)."""
    return json.loads(json.dumps(to_jsonable(key), default=str))


def save_results(name: str, results: dict[str, Any], results_dir: str | Path = "data/results",
                 parameters: dict[str, Any] | None = None, inputs: dict[str, str] | None = None) -> Path:
    """Write ``results`` (and the run's ``parameters``) to ``<results_dir>/<name>.json``.

    The file also records the library version, the version of the synthesis optimiser
    (:data:`trusscodesign.infra.versions.ALGORITHM`), on which every robust design depends, and ``inputs``: what identifies
    the input data the results were computed from (e.g. :func:`trusscodesign.model.spacecraft.inputs_key`, the spacecraft
    parameters' fingerprint and the model's version), against which a reader checks them.

    Returns the path written.
    """
    folder = resolve(results_dir)
    payload = {
        "notebook": name,
        "library_version": __version__,
        "synthesis_algorithm": ALGORITHM,
        "python": platform.python_version(),
        "parameters": to_jsonable(parameters or {}),
        "inputs": dict(inputs or {}),
        "results": to_jsonable(results),
    }
    return write_json(folder / f"{name}.json", payload, indent=2)  # atomic: an interrupted save keeps the previous file


def load_results(name: str, results_dir: str | Path = "data/results") -> dict[str, Any]:
    """Read a results file written by :func:`save_results` (non-finite floats restored, see :func:`from_jsonable`)."""
    path = resolve(results_dir, create=False) / f"{name}.json"
    if not path.exists():
        raise FileNotFoundError(f"no results file {path}: run notebook {name} first")
    return from_jsonable(read_json(path))


def moved_numbers(what: str, now: dict[str, float], stored: dict[str, float], tolerance: dict[str, tuple[str, float]],
                  stored_inputs: dict | None = None, inputs: dict | None = None) -> list[str]:
    """The numbers of a rerun that moved from the stored ones beyond their tolerance, each as a sentence naming it.

    Parameters
    ----------
    what : str
        What the numbers are, e.g. ``"notebook 06b, paper_calibrated at h = 2.139 cm"`` (starts each sentence).
    now, stored : dict
        The recomputed and the stored numbers, by name (the names of ``tolerance``); a non-finite value (an unstable
        loop: infinite; a failed evaluation: NaN) matches only itself, and so does a stored 0 with a relative tolerance.
    tolerance : dict
        Per name, ``("rel", r)`` (``|now / stored - 1| <= r``) or ``("abs", a)`` (``|now - stored| <= a``, in the
        number's unit).
    stored_inputs, inputs : dict, optional
        The inputs keys of the stored run and of the rerun (:func:`trusscodesign.model.spacecraft.inputs_key`): when they
        differ, each sentence says so (the stored results are then to be regenerated, or the inputs restored).

    Returns
    -------
    list of str
        Empty when every number is within its tolerance (``assert not moved, "\\n".join(moved)`` in a notebook).
    """
    if set(tolerance) - set(now) or set(tolerance) - set(stored):
        raise KeyError(f"{what}: no value for {sorted((set(tolerance) - set(now)) | (set(tolerance) - set(stored)))} to compare")
    changed = "" if stored_inputs is None or inputs is None or stored_inputs == inputs else (
        " (the inputs differ from the stored run's: "
        + ", ".join(k for k in sorted(set(inputs) | set(stored_inputs)) if inputs.get(k) != stored_inputs.get(k)) + ")")
    out = []
    for name, (kind, tol) in tolerance.items():
        a, b = float(now[name]), float(stored[name])
        if np.isnan(a) or np.isnan(b):
            off, ok = ("not a number", np.isnan(a) and np.isnan(b))
        elif not (np.isfinite(a) and np.isfinite(b)):
            off, ok = ("an infinite norm is an unstable loop", a == b)
        elif kind == "rel" and b == 0.0:
            off, ok = (f"{a:+.3g} from 0, tolerance relative", a == 0.0)
        elif kind == "rel":
            off, ok = (f"{100 * (a / b - 1):+.3g} %, tolerance {100 * tol:.3g} %", abs(a / b - 1) <= tol)
        elif kind == "abs":
            off, ok = (f"{a - b:+.3g}, tolerance {tol:.3g}", abs(a - b) <= tol)
        else:
            raise ValueError(f"tolerance kind of {name!r} must be 'rel' or 'abs', got {kind!r}")
        if not ok:
            out.append(f"{what}: {name} moved: {a:.6g} now, {b:.6g} stored ({off}){changed}")
    return out


def load_reference(name: str, reference_dir: str | Path | None) -> dict[str, Any] | None:
    """The stored results of notebook ``name`` that a rerun's headline numbers are compared with (:func:`moved_numbers`),
    read before any long work; None without ``reference_dir``.

    Raises
    ------
    TypeError
        If ``reference_dir`` is neither None nor a folder name.
    FileNotFoundError
        If the folder holds no ``<name>.json``.
    """
    if reference_dir is None:
        return None
    if not isinstance(reference_dir, (str, Path)) or not str(reference_dir):
        raise TypeError(f"reference_dir must be a folder of stored results, e.g. 'data/results', or None, got {reference_dir!r}")
    path = resolve(reference_dir, create=False) / f"{name}.json"
    if not path.is_file():
        raise FileNotFoundError(f"reference_dir = {str(reference_dir)!r}: no stored results {path} to compare this run with "
                                "(None: no comparison)")
    return load_results(name, reference_dir)
