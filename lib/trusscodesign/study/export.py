"""A design for MATLAB and Simulink: the PMA gain, the reduced uncertain plant and the nominal closed loop in a ``.mat``
file (:func:`scipy.io.savemat`), and read back as ``control.StateSpace`` objects.

The file holds ``K_PMA`` (4 x 8, PMA commands [N] per measured acceleration [m/s^2 or rad/s^2]), ``h_m`` (the section
side [m]; for sides by member group, NaN, with ``side_keys`` (cell of char) and ``sides_m`` beside it), and two structs with fields ``A``, ``B``, ``C``, ``D``, ``InputName`` and ``OutputName`` (cell arrays of
char): ``G_r``, the reduced open loop with its Delta channels open first (``w_<parameter>_<i>`` / ``z_<parameter>_<i>``,
normalised parameters, :attr:`trusscodesign.study.design.DesignModels.G_r`), and ``closed_loop``, the generalized plant
closed by ``K_PMA`` at the nominal scenario (``[w; p~] -> [z; RPE; W~u]``,
:meth:`trusscodesign.control.closedloop.GeneralizedPlant.closed_loop`). In MATLAB:
``s = load(f); G = ss(s.G_r.A, s.G_r.B, s.G_r.C, s.G_r.D, 'InputName', s.G_r.InputName, 'OutputName', s.G_r.OutputName)``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import control as ct
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import io

from ..control.closedloop import LoopSettings
from ..control.synthesis import Scenario, plant_at
from .design import DesignModels

__all__ = ["save_design_mat", "load_design_mat"]


def _struct(sys: ct.StateSpace) -> dict[str, Any]:
    """A state-space model as the fields of a MATLAB struct (names as cell arrays of char)."""
    return {"A": np.asarray(sys.A), "B": np.asarray(sys.B), "C": np.asarray(sys.C), "D": np.asarray(sys.D),
            "InputName": np.array(sys.input_labels, dtype=object), "OutputName": np.array(sys.output_labels, dtype=object)}


def _model(fields: dict[str, Any], name: str) -> ct.StateSpace:
    """The struct written by :func:`_struct` as a named ``control.StateSpace``."""
    a, b, c, d = (np.atleast_2d(np.asarray(fields[k], dtype=float)) for k in ("A", "B", "C", "D"))
    inputs, outputs = ([str(s) for s in np.atleast_1d(fields[k])] for k in ("InputName", "OutputName"))
    return ct.ss(a, b.reshape(a.shape[0], len(inputs)), c.reshape(len(outputs), a.shape[0]), d.reshape(len(outputs), len(inputs)),
                 inputs=inputs, outputs=outputs, name=name)


def save_design_mat(path: str | Path, gain: ArrayLike, models: DesignModels, settings: LoopSettings) -> Path:
    """Write the design ``gain`` on ``models`` (closed with ``settings``) to the ``.mat`` file ``path``.

    Parameters
    ----------
    path : str or Path
        The file to write (``.mat``; its folder must exist).
    gain : array_like (4, 8)
        ``K_PMA`` [N per m/s^2 or rad/s^2].
    models : DesignModels
        The models at the design's section side (:func:`trusscodesign.study.design.models_at`).
    settings : LoopSettings
        The loop settings the design was made with.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ValueError
        If ``gain`` is not a finite 4x8 matrix or the folder of ``path`` does not exist.
    """
    k = np.array(gain, dtype=float)
    if k.shape != (4, 8) or not np.all(np.isfinite(k)):
        raise ValueError(f"gain must be a finite 4x8 matrix K_PMA [N per m/s^2 or rad/s^2], got shape {k.shape}")
    out = Path(path)
    if not out.parent.is_dir():
        raise ValueError(f"path: the folder {out.parent} does not exist (create it first)")
    loop = plant_at(models.g_r, Scenario(), models.inertia, settings).closed_loop(k)
    if isinstance(models.h, dict):  # sides by member group: their keys and values beside a NaN h
        side: dict[str, Any] = {"h_m": float("nan"), "side_keys": np.array(list(models.h), dtype=object),
                                "sides_m": np.array(list(models.h.values()))}
    else:
        side = {"h_m": float(models.h)}
    io.savemat(out, {"K_PMA": k, **side, "G_r": _struct(models.G_r), "closed_loop": _struct(loop)}, do_compression=True)
    return out


def load_design_mat(path: str | Path) -> dict[str, Any]:
    """Read a file of :func:`save_design_mat`: ``{"K_PMA": (4, 8) array, "h_m": float or dict, "G_r": control.StateSpace,
    "closed_loop": control.StateSpace}`` (the models with their signal names; ``h_m`` the sides by key [m] for a
    design with sides by member group)."""
    raw = io.loadmat(Path(path), simplify_cells=True)
    gain: NDArray[np.float64] = np.asarray(raw["K_PMA"], dtype=float)
    h: float | dict[str, float] = float(raw["h_m"])
    if "side_keys" in raw:
        keys, values = np.atleast_1d(raw["side_keys"]), np.atleast_1d(raw["sides_m"])
        h = {str(key): float(v) for key, v in zip(keys, values)}
    return {"K_PMA": gain, "h_m": h, "G_r": _model(raw["G_r"], "G_r"), "closed_loop": _model(raw["closed_loop"], "closed_loop")}
