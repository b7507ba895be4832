"""Plotting helpers shared by the notebooks (labelled axes, units, saved figures)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from numpy.typing import ArrayLike

from .paths import resolve

__all__ = ["savefig", "magnitude_db", "plot_magnitude", "draw_structure"]


def savefig(fig: plt.Figure, name: str, figures_dir: str | Path = "figures") -> Path:
    """Save ``fig`` as ``<figures_dir>/<name>.png`` (150 dpi) and return the path."""
    path = resolve(figures_dir) / f"{name}.png"
    fig.savefig(path, dpi=150, bbox_inches="tight")
    return path


def magnitude_db(response: ArrayLike) -> np.ndarray:
    """20 log10 |response| [dB], with exact zeros mapped to -400 dB."""
    mag = np.abs(np.asarray(response))
    return 20.0 * np.log10(np.maximum(mag, 1e-20))


def plot_magnitude(ax: plt.Axes, omega: ArrayLike, response: ArrayLike, label: str | None = None,
                   ylabel: str = "magnitude [dB]", **kwargs) -> None:
    """Magnitude (dB) against frequency (rad/s, log scale) with labelled axes."""
    ax.semilogx(omega, magnitude_db(response), label=label, **kwargs)
    ax.set_xlabel("frequency [rad/s]")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)


def draw_structure(ax: plt.Axes, nodes: Mapping[str, ArrayLike], members: Sequence[tuple[str, str]],
                   clamped: Sequence[str] = (), planar: bool = False, title: str | None = None) -> None:
    """Draw beams between labelled nodes; clamped nodes are marked with a filled square.

    ``ax`` must be a 3D axes unless ``planar`` (x-y drawing) is set.
    """
    pos = {k: np.asarray(v, float) for k, v in nodes.items()}
    for p, c in members:
        xyz = np.vstack([pos[p], pos[c]])
        if planar:
            ax.plot(xyz[:, 0], xyz[:, 1], "-", color="tab:blue", lw=2)
        else:
            ax.plot(xyz[:, 0], xyz[:, 1], xyz[:, 2], "-", color="tab:blue", lw=2)
    for name, r in pos.items():
        style = dict(marker="s", color="k", ms=9) if name in clamped else dict(marker="o", color="tab:orange", ms=6)
        if planar:
            ax.plot(r[0], r[1], ls="none", **style)
            ax.annotate(name, r[:2], textcoords="offset points", xytext=(6, 6), fontsize=11)
        else:
            ax.plot([r[0]], [r[1]], [r[2]], ls="none", **style)
            ax.text(r[0], r[1], r[2], f"  {name}", fontsize=10)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if planar:
        ax.set_aspect("equal")
        ax.margins(0.2)
    else:
        ax.set_zlabel("z [m]")
    if title:
        ax.set_title(title)
