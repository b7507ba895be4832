"""Plotting helpers shared by the notebooks (labelled axes, units, saved figures)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import matplotlib.pyplot as plt
from matplotlib.ticker import MaxNLocator
import numpy as np
from numpy.typing import ArrayLike

from .paths import resolve

if TYPE_CHECKING:
    from mpl_toolkits.mplot3d import Axes3D

__all__ = ["savefig", "magnitude_db", "plot_magnitude", "draw_structure", "draw_mode", "pso_panels", "objective_grid", "sine_build_up"]


def savefig(fig: plt.Figure, name: str, figures_dir: str | Path = "figures") -> Path:
    """Save ``fig`` as ``<figures_dir>/<name>.png`` (150 dpi) and return the path."""
    path = resolve(figures_dir) / f"{name}.png"
    fig.savefig(path, dpi=150, bbox_inches="tight")
    return path


def magnitude_db(response: ArrayLike) -> np.ndarray:
    """``20 log10 |response|`` [dB], with exact zeros mapped to -400 dB."""
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
    ax3 = cast("Axes3D", ax)  # used only when not planar
    for p, c in members:
        xyz = np.vstack([pos[p], pos[c]])
        if planar:
            ax.plot(xyz[:, 0], xyz[:, 1], "-", color="tab:blue", lw=2)
        else:
            ax3.plot(xyz[:, 0], xyz[:, 1], xyz[:, 2], "-", color="tab:blue", lw=2)
    for name, r in pos.items():
        style: dict[str, Any] = dict(marker="s", color="k", ms=9) if name in clamped else dict(marker="o", color="tab:orange", ms=6)
        if planar:
            ax.plot(r[0], r[1], ls="none", **style)
            ax.annotate(name, (r[0], r[1]), textcoords="offset points", xytext=(6, 6), fontsize=11)
        else:
            ax3.plot([r[0]], [r[1]], [r[2]], ls="none", **style)
            ax3.text(r[0], r[1], r[2], f"  {name}", fontsize=10)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if planar:
        ax.set_aspect("equal")
        ax.margins(0.2)
    else:
        ax3.set_zlabel("z [m]")
    if title:
        ax.set_title(title)


def draw_mode(ax: plt.Axes, nodes: Mapping[str, ArrayLike], members: Sequence[tuple[str, str]], displacement: ArrayLike,
              frequency: float, clamped: Sequence[str] = (), ports: Sequence[str] = (), scale: float | None = None,
              labels: bool = True) -> None:
    """Draw a mode shape on a 3D axes: the structure at rest (grey) and displaced (blue), members as straight lines
    between their displaced nodes; clamped nodes as black squares, ports as red triangles, nodes labelled.

    Parameters
    ----------
    ax : matplotlib 3D axes
    nodes : mapping str -> array_like (3,)
        Node positions [m].
    members : sequence of (str, str)
        Members between nodes.
    displacement : array_like, shape (n_nodes, 3)
        The mode's node translations, in the order of ``nodes`` (any normalisation).
    frequency : float
        The mode's natural frequency [rad/s] (in the title, also in Hz).
    clamped, ports : sequence of str
        Nodes marked as clamped and as ports.
    scale : float, optional
        Largest drawn displacement [m] (default: 15 % of the structure's largest dimension).
    labels : bool
        Label the nodes with their names.
    """
    names = list(nodes)
    pos = np.array([np.asarray(nodes[n], float) for n in names])
    disp = np.asarray(displacement, float)
    if disp.shape != pos.shape:
        raise ValueError(f"displacement must have one row (x, y, z) per node: shape {pos.shape}, got {disp.shape}")
    size = float(np.max(np.ptp(pos, axis=0)))
    peak = float(np.max(np.linalg.norm(disp, axis=1)))
    moved = pos + disp * ((0.15 * size if scale is None else scale) / peak if peak > 0 else 0.0)
    index = {n: i for i, n in enumerate(names)}
    ax3 = cast("Axes3D", ax)
    for p, c in members:
        for xyz, style in ((pos, dict(color="0.75", lw=0.8)), (moved, dict(color="tab:blue", lw=1.6))):
            seg = xyz[[index[p], index[c]]]
            ax3.plot(seg[:, 0], seg[:, 1], seg[:, 2], "-", **style)
    for group, style in ((clamped, dict(marker="s", color="k", ms=7)), (ports, dict(marker="^", color="tab:red", ms=9))):
        pts = moved[[index[n] for n in group]] if len(group) else np.zeros((0, 3))
        ax3.plot(pts[:, 0], pts[:, 1], pts[:, 2], ls="none", **style)
    if labels:
        for n, r in zip(names, moved):
            ax3.text(r[0], r[1], r[2], f" {n}", fontsize=7)
    ax3.set_xlabel("x [m]")
    ax3.set_ylabel("y [m]")
    ax3.set_zlabel("z [m]")
    ax3.set_box_aspect(tuple(np.maximum(np.ptp(pos, axis=0), 0.2 * size)))
    ax3.locator_params(nbins=4)
    ax.set_title(f"{frequency:.2f} rad/s ({frequency / (2 * np.pi):.3f} Hz)")


def pso_panels(history: Sequence[Mapping], n_iterations: int, h_range: tuple[float, float], jc_limit: float = 2.0) -> plt.Figure:
    """The paper's four-panel PSO figure from the particle records (``iteration``, ``h`` [m], ``J_c``, ``f``).

    (a) boxplots of h per iteration, (b) of the valid J_c per iteration (penalised or failed particles, ``J_c``
    infinite or above ``jc_limit``, are left out, as in the paper), the best particle of each iteration
    highlighted (yellow dots, as the paper); (c) the swarm's best f^n against the iteration; (d) h and J_c of the
    best particle of each iteration. Records read from a results file must be restored first (``inf`` is stored as a
    string): :func:`trusscodesign.infra.results.load_results` does it.
    """
    its = list(range(n_iterations))
    per = [[r for r in history if r["iteration"] == k] for k in its]
    per = [p for p in per if p]
    best = [min(p, key=lambda r: r["f"]) for p in per]
    x = np.arange(1, len(per) + 1)
    fig, axes = plt.subplots(2, 2, figsize=(13, 8))
    ax = axes[0, 0]
    ax.boxplot([[100 * r["h"] for r in p] for p in per], positions=x, widths=0.6)
    ax.plot(x, [100 * b["h"] for b in best], "o", color="gold", mec="k", label="best particle")
    ax.set(xlabel="iteration", ylabel="h [cm]", title="(a) particles: section side", ylim=(100 * h_range[0] - 0.05, 100 * h_range[1] + 0.05))
    ax.legend(fontsize=8)
    ax = axes[0, 1]
    def valid(j: float) -> bool:
        return bool(np.isfinite(j) and j <= jc_limit)

    ax.boxplot([[r["J_c"] for r in p if valid(r["J_c"])] or [np.nan] for p in per], positions=x, widths=0.6)
    ax.plot(x, [b["J_c"] if valid(b["J_c"]) else np.nan for b in best], "o", color="gold", mec="k", label="best particle")
    ax.set(xlabel="iteration", ylabel="$J_c$ (worst case)", title="(b) particles: robust pointing performance")
    ax.legend(fontsize=8)
    ax = axes[1, 0]
    ax.plot(x, np.minimum.accumulate([b["f"] for b in best]), "k.-")
    ax.set(xlabel="iteration", ylabel="$f^n$ of the swarm's best", title="(c) convergence")
    ax = axes[1, 1]
    ax.plot(x, [100 * b["h"] for b in best], "C0o-", label="h")
    ax.set(xlabel="iteration", ylabel="h [cm]", title="(d) best particle of each iteration")
    ax2 = ax.twinx()
    ax2.plot(x, [b["J_c"] for b in best], "C3s--", label="$J_c$")
    ax2.set_ylabel("$J_c$")
    lines = ax.get_lines() + ax2.get_lines()
    ax.legend(lines, [line.get_label() for line in lines], loc="upper center", fontsize=8)
    for a in axes.ravel():
        a.grid(alpha=0.3)
    for a in axes[1]:  # line plots: integer iterations (the boxplots label their own positions)
        a.xaxis.set_major_locator(MaxNLocator(integer=True))
    fig.tight_layout()
    return fig


def objective_grid(records: Sequence[Mapping], best: Mapping | None = None, title: str = "", jc_limit: float = 2.0,
                   history: Sequence[Mapping] = (), target: float = 0.9, m0: float | None = None) -> plt.Figure:
    """The co-design's landscape on a grid of h: ``f^n``, the robust ``J_c`` (with its target), ``Z_c`` and the truss mass.

    Parameters
    ----------
    records : sequence of mapping
        One per grid point, with ``h`` [m], ``f``, ``J_c``, ``Z_c`` (optional) and ``mass`` [kg]
        (:func:`trusscodesign.study.codesign.evaluate_grid`); penalised or failed points (``J_c`` infinite or above
        ``jc_limit``) are marked at the top of the f panel (their ``f^n``, the mass plus the penalty, would squash the
        valid curve) and left out of the J_c and Z_c panels.
    best : mapping, optional
        The swarm's best particle (same keys), marked on the f and J_c panels (left out if it is itself penalised).
    title : str
        Prefix of the panel titles.
    jc_limit : float
        ``J_c`` above which the objective is penalised (:data:`trusscodesign.study.objective.JC_LIMIT`).
    history : sequence of mapping, optional
        The swarm's particles (same keys): their valid evaluations drawn as small dots on the f, J_c and Z_c panels.
    target : float
        The ``J_c`` the objective aims at (0.9): drawn, with the h where the grid's ``J_c`` crosses it (linear
        interpolation between the two grid points around each crossing).
    m0 : float, optional
        Reference mass [kg] of the objective, drawn on the mass panel.
    """
    h = 100 * np.array([r["h"] for r in records])
    f, j_c, mass = (np.array([r[k] for r in records], dtype=float) for k in ("f", "J_c", "mass"))
    z_c = np.array([r.get("Z_c", np.nan) for r in records], dtype=float)
    valid = np.isfinite(j_c) & (j_c <= jc_limit)
    fig, axes = plt.subplots(2, 2, figsize=(13, 8), sharex=True)
    ax_f, ax_j, ax_z, ax_m = axes.ravel()
    ax_f.plot(h, np.where(valid, f, np.nan), "k.-", label="dense grid")  # NaN: the curve breaks at penalised points
    if valid.any():
        i = int(np.nanargmin(np.where(valid, f, np.nan)))
        ax_f.plot(h[i], f[i], "s", mfc="none", mec="C3", ms=10, label=f"grid minimum: {f[i]:.4f} at {h[i]:.2f} cm")
    if not valid.all():
        top = np.nanmax(f[valid]) * 1.05 if valid.any() else np.nanmax(f)
        ax_f.plot(h[~valid], np.full((~valid).sum(), top), "rx", clip_on=False,
                  label=f"penalised (failed or $J_c > {jc_limit:g}$),\ndrawn at the top: their $f^n$ is {np.nanmin(f[~valid]):.4g}"
                  + (f"-{np.nanmax(f[~valid]):.4g}" if np.sum(~valid) > 1 else ""))
    ax_j.plot(h, np.where(valid, j_c, np.nan), "C3.-", label="dense grid")
    ax_j.axhline(target, color="k", ls=":", label=f"target {target:g}")
    for k in np.flatnonzero(valid[:-1] & valid[1:] & (np.sign(j_c[:-1] - target) * np.sign(j_c[1:] - target) < 0)):
        x = h[k] + (target - j_c[k]) * (h[k + 1] - h[k]) / (j_c[k + 1] - j_c[k])
        for ax in (ax_f, ax_j):
            ax.axvline(x, color="C2", ls="--", lw=1, label=f"$J_c$ crosses {target:g} at {x:.2f} cm")
    ax_z.plot(h, np.where(valid, z_c, np.nan), "C4.-", label="dense grid")
    ax_z.axhline(1.0, color="k", ls=":", label="bound 1")
    swarm = [r for r in history if np.isfinite(float(r["J_c"])) and float(r["J_c"]) <= jc_limit]
    if swarm:
        hs = 100 * np.array([r["h"] for r in swarm])
        for ax, key in ((ax_f, "f"), (ax_j, "J_c"), (ax_z, "Z_c")):
            ax.plot(hs, [r.get(key, np.nan) for r in swarm], ".", color="0.55", ms=4, zorder=1,
                    label=f"swarm particles ({len(swarm)} valid of {len(history)})")
    if best is not None and np.isfinite(float(best["J_c"])) and float(best["J_c"]) <= jc_limit:
        ax_f.plot(100 * best["h"], best["f"], "o", color="gold", mec="k", label=f"PSO best: {best['f']:.4f} at {100 * best['h']:.2f} cm")
        ax_j.plot(100 * best["h"], best["J_c"], "o", color="gold", mec="k", label="PSO best")
    ax_m.plot(h, mass, "C0.-", label="truss mass")
    if m0 is not None:
        ax_m.axhline(m0, color="k", ls=":", label=f"$m_0$ = {m0:g} kg")
    for ax, ylabel, name in zip(axes.ravel(), ("$f^n$", "$J_c$ (robust, worst case)", "$Z_c$ (effort, worst case)", "truss mass [kg]"),
                                ("objective", "pointing performance", "actuator effort", "mass")):
        ax.set(ylabel=ylabel, title=f"{title}{name}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in axes[1]:
        ax.set_xlabel("h [cm]")
    fig.tight_layout()
    return fig


def sine_build_up(ax: plt.Axes, t: ArrayLike, outputs: ArrayLike, steady: ArrayLike, tau: float, scale: float, bound: float,
                  labels: Sequence[str], quantity: str, unit: str, zoom: float | None = None) -> None:
    """Outputs of a response from rest to a sinusoid (:func:`trusscodesign.study.timedomain.sine_response`) in physical units.

    Parameters
    ----------
    t : array_like (n,)
        Time [s].
    outputs : array_like (q, n)
        Normalised outputs; ``scale`` converts them to ``unit``.
    steady : array_like (q,), complex
        Their steady-state complex amplitudes: the envelope ``|steady_k| (1 - e^{-t/tau})`` is drawn for the largest.
    tau : float
        Time constant of the envelope [s].
    bound : float
        The requirement, in ``unit`` (drawn at ±bound).
    labels, quantity, unit : str
        Output names, the y-axis quantity and its unit.
    zoom : float, optional
        Length [s] of the end of the record shown again in an inset beside the axes (the waveform, which the full record
        hides).
    """
    t = np.asarray(t, dtype=float)
    y = np.atleast_2d(np.asarray(outputs, dtype=float)) * scale
    if len(labels) != y.shape[0]:
        raise ValueError(f"labels: one per output row, got {len(labels)} labels for {y.shape[0]} outputs")
    if zoom is not None and not 0 < zoom <= t[-1] - t[0]:
        raise ValueError(f"zoom must be in (0, {t[-1] - t[0]:g}] s (the record's length), got {zoom!r}")
    for k, lab in enumerate(labels):
        ax.plot(t, y[k], lw=0.4, color=f"C{k}", label=lab)
    amp = float(np.abs(np.asarray(steady)).max()) * scale
    env = amp * (1 - np.exp(-t / tau))
    ax.plot(t, env, "k--", lw=1, label=f"envelope of the largest steady amplitude ({amp:.3g} {unit}), tau = {tau:.0f} s")
    ax.plot(t, -env, "k--", lw=1)
    ax.axhline(bound, color="C3", lw=1, label=f"requirement ±{bound:g} {unit}")
    ax.axhline(-bound, color="C3", lw=1)
    ax.set(xlabel="time [s]", ylabel=f"{quantity} [{unit}]", xlim=(t[0], t[-1]))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=3, loc="lower left")
    if zoom is not None:
        end = t >= t[-1] - zoom
        inset = ax.inset_axes((1.03, 0.0, 0.2, 1.0), sharey=ax)  # beside the axes: the record fills them
        for k in range(len(labels)):
            inset.plot(t[end], y[k, end], lw=0.8, color=f"C{k}")
        inset.set_title(f"the last {zoom:.3g} s", fontsize=9)
        inset.set_xlabel("time [s]", fontsize=8)
        for level in (bound, -bound):
            inset.axhline(level, color="C3", lw=1)
        inset.tick_params(labelsize=7, labelleft=False)
        inset.grid(alpha=0.3)
