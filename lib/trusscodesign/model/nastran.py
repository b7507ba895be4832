"""The paper's stored Patran/Nastran and SDT tables of the validation cube, read and checked.

Two CSV files ship with the package (``data/nastran_cube/``, provenance in its README): ``cube_parameters.csv`` (the
cube's data: sides, section, material, damping, each with its unit) and ``cube_modes.csv`` (for the Patran/Nastran
model and the paper's SDT model, the first modes of the cube clamped at N1: frequency [rad/s] and the participation
factors at N1). :func:`load_tables` refuses a damaged table with the file, the line and the field named: a truncated
or duplicated row, a missing parameter, a wrong unit, a value that is not a finite number, frequencies out of order.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..infra.paths import PACKAGE_DATA

__all__ = ["PARAMETER_UNITS", "MODELS", "FACTORS", "NastranTables", "load_tables"]

# every parameter of the cube's table and its unit there
PARAMETER_UNITS = {"lx": "m", "ly": "m", "lz": "m", "S": "m^2", "rho": "kg/m^3", "E": "GPa", "nu": "-", "Iy": "m^4",
                   "Iz": "m^4", "xi": "-"}
MODELS = ("patran_nastran", "paper_sdt")
FACTORS = ("T1", "T2", "T3", "R1", "R2", "R3")  # participation factors at N1: translations, then rotations


@dataclass(frozen=True)
class NastranTables:
    """The two tables, checked.

    Attributes
    ----------
    parameters : dict
        Name -> value, in the unit of :data:`PARAMETER_UNITS` (E in GPa).
    omega : dict
        Model (:data:`MODELS`) -> natural frequencies [rad/s], increasing, one per mode.
    participation : dict
        Model -> participation factors at N1, shape (modes, 6), columns :data:`FACTORS`.
    """

    parameters: dict[str, float]
    omega: dict[str, NDArray[np.float64]]
    participation: dict[str, NDArray[np.float64]]


def _rows(path: Path, columns: tuple[str, ...]) -> list[tuple[int, dict[str, str]]]:
    """The rows of a CSV file with exactly ``columns``, each with its line number, every field present."""
    with open(path, newline="") as fh:
        reader = csv.reader(fh)
        header = next(reader, None)
        if header is None or tuple(h.strip() for h in header) != columns:
            raise ValueError(f"{path}, line 1: the columns must be {list(columns)}, got {header}")
        out = []
        for row in reader:
            line = reader.line_num
            if not row or all(not f.strip() for f in row):
                continue
            if len(row) != len(columns):
                missing = list(columns[len(row):]) if len(row) < len(columns) else ["(extra fields)"]
                raise ValueError(f"{path}, line {line}: {len(row)} fields where {len(columns)} are expected "
                                 f"(missing or extra: {missing}); is the row truncated?")
            out.append((line, {c: f.strip() for c, f in zip(columns, row)}))
    return out


def _number(path: Path, line: int, field: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{path}, line {line}, field {field}: {text!r} is not a number") from None
    if not np.isfinite(value):
        raise ValueError(f"{path}, line {line}, field {field}: {text!r} is not a finite number")
    return value


def _parameters(path: Path) -> dict[str, float]:
    values: dict[str, float] = {}
    for line, row in _rows(path, ("parameter", "value", "unit", "description")):
        name = row["parameter"]
        if name not in PARAMETER_UNITS:
            raise ValueError(f"{path}, line {line}: unknown parameter {name!r}; the table holds {list(PARAMETER_UNITS)}")
        if name in values:
            raise ValueError(f"{path}, line {line}: parameter {name!r} is given twice")
        if row["unit"] != PARAMETER_UNITS[name]:
            raise ValueError(f"{path}, line {line}, field unit: {name} must be in {PARAMETER_UNITS[name]!r}, got {row['unit']!r}")
        values[name] = _number(path, line, "value", row["value"])
        if values[name] <= 0:
            raise ValueError(f"{path}, line {line}, field value: {name} must be positive, got {values[name]!r}")
    missing = [n for n in PARAMETER_UNITS if n not in values]
    if missing:
        raise ValueError(f"{path}: parameter(s) {missing} missing (the table must give all of {list(PARAMETER_UNITS)})")
    return values


def _modes(path: Path) -> tuple[dict[str, NDArray[np.float64]], dict[str, NDArray[np.float64]]]:
    found: dict[str, dict[int, tuple[int, list[float]]]] = {m: {} for m in MODELS}
    for line, row in _rows(path, ("mode", "model", "omega_rad_s", *FACTORS)):
        model = row["model"]
        if model not in found:
            raise ValueError(f"{path}, line {line}, field model: {model!r} is not one of {list(MODELS)}")
        mode = _number(path, line, "mode", row["mode"])
        if mode != int(mode) or mode < 1:
            raise ValueError(f"{path}, line {line}, field mode: a mode number is a positive integer, got {row['mode']!r}")
        if int(mode) in found[model]:
            raise ValueError(f"{path}, line {line}: mode {int(mode)} of {model} is given twice "
                             f"(first on line {found[model][int(mode)][0]})")
        found[model][int(mode)] = (line, [_number(path, line, f, row[f]) for f in ("omega_rad_s", *FACTORS)])
    omega, participation = {}, {}
    counts = {m: len(rows) for m, rows in found.items()}
    if len(set(counts.values())) != 1 or not min(counts.values()):
        raise ValueError(f"{path}: each model must give the same number of modes, at least one; got {counts}")
    for model, rows in found.items():
        if sorted(rows) != list(range(1, len(rows) + 1)):
            raise ValueError(f"{path}: the modes of {model} must be numbered 1 to {len(rows)}, got {sorted(rows)}")
        ordered = [rows[k] for k in range(1, len(rows) + 1)]
        w = np.array([values[0] for _, values in ordered])
        for (line, values), prev in zip(ordered[1:], w[:-1].tolist()):
            if not values[0] > prev:
                raise ValueError(f"{path}, line {line}, field omega_rad_s: the frequencies of {model} must increase with "
                                 f"the mode number; {values[0]!r} rad/s follows {prev!r} rad/s (a typo?)")
        if not w[0] > 0:
            raise ValueError(f"{path}, line {ordered[0][0]}, field omega_rad_s: a frequency must be positive, got {float(w[0])!r}")
        omega[model] = w
        participation[model] = np.array([values[1:] for _, values in ordered])
    return omega, participation


def load_tables(folder: str | Path | None = None) -> NastranTables:
    """Read and check the cube's tables in ``folder`` (default: the package's ``data/nastran_cube``).

    Raises
    ------
    ValueError
        A damaged table: the message names the file, the line and the field, and what was expected.
    """
    root = Path(folder) if folder is not None else PACKAGE_DATA / "nastran_cube"
    parameters = _parameters(root / "cube_parameters.csv")
    omega, participation = _modes(root / "cube_modes.csv")
    return NastranTables(parameters, omega, participation)
