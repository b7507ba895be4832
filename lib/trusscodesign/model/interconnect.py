"""Interconnection of multi-port models at their shared nodes: the paper's block-diagram assembly.

Paper: the block diagrams of sections "2D Mechanisms" and "3D Mechanisms". Mathematics: ``docs/titop.md`` section e
(the connection rule: accelerations shared, wrenches summed, with the causality of each channel).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..infra.checks import check_option
from .ports import COMPONENTS, MultiPortModel, Port
from .statespace import close_static

__all__ = ["connect"]


def connect(models: Sequence[MultiPortModel], name: str = "assembly", order: Sequence[str] | None = None, atol: float = 1e-9) -> MultiPortModel:
    """Interconnect models at their shared nodes (the paper's block-diagram assembly).

    At each node and for each of its six components, at most one model may
    have the channel free (``"w"``): its acceleration output drives the models
    clamped there (``"a"``), and it receives the external wrench plus their
    reaction wrenches (kinematic constraint and wrench balance). The resulting
    channel is free. When all models are clamped at a channel, they share the
    imposed acceleration and their reactions add; the channel stays clamped.

    Parameters
    ----------
    models : sequence of MultiPortModel
        Models expressed in one common frame.
    name : str
        Name of the assembly.
    order : sequence of str, optional
        Order of the assembly's ports (default: order of first appearance); delta
        ports not listed follow the listed ones.
    atol : float
        Tolerance on the agreement of node positions [m].

    Raises
    ------
    ValueError
        If positions of a shared node disagree, a scalar port is shared, or a
        channel is free in two models (a loop needs one of them inverted).
    """
    if not models:
        raise ValueError("connect needs at least one model")
    check_option("atol", atol, 0.0, np.inf, open_high=True)  # [m]; a negative or NaN atol refused every shared node
    offs_x = np.cumsum([0] + [m.nstates for m in models])
    offs_c = np.cumsum([0] + [m.nchannels for m in models])
    n_x, n_c = int(offs_x[-1]), int(offs_c[-1])
    a = np.zeros((n_x, n_x))
    b = np.zeros((n_x, n_c))
    c = np.zeros((n_c, n_x))
    d = np.zeros((n_c, n_c))
    for i, m in enumerate(models):
        sx, sc = slice(offs_x[i], offs_x[i + 1]), slice(offs_c[i], offs_c[i + 1])
        a[sx, sx], b[sx, sc], c[sc, sx], d[sc, sc] = m.a, m.b, m.c, m.d

    # Occurrences of each node: list of (model index, port).
    nodes: dict[str, list[tuple[int, Port]]] = {}
    for i, m in enumerate(models):
        for p in m.ports:
            nodes.setdefault(p.name, []).append((i, p))
    names = list(order) if order is not None else list(nodes)
    if order is not None:  # delta ports (uncertainty channels) follow the listed ports
        names += [n for n, occ in nodes.items() if occ[0][1].parameter is not None and n not in names]
    if sorted(names) != sorted(nodes):
        raise ValueError(f"order must list each node once: got {list(names)}, nodes are {list(nodes)}")

    k = np.zeros((n_c, n_c))
    e_cols, f_rows, ports = [], [], []
    for node in names:
        occ = nodes[node]
        first = occ[0][1]
        if first.is_scalar or any(p.is_scalar for _, p in occ):
            if len(occ) > 1:
                raise ValueError(f"scalar port {node!r} appears in several models: scalar channels cannot be shared")
            i, p = occ[0]
            ch = offs_c[i] + models[i].offset(node)
            e_cols.append(ch)
            f_rows.append([(ch, 1.0)])
            ports.append(p)
            continue
        for i, p in occ[1:]:
            if not np.allclose(p.position, first.position, rtol=0.0, atol=atol):
                raise ValueError(
                    f"node {node!r} is at {first.position} in {models[occ[0][0]].name!r} but at "
                    f"{p.position} in {models[i].name!r}: express the models in one frame"
                )
        caus = []
        for comp in range(6):
            chans = [(offs_c[i] + models[i].offset(node) + comp, p.causality[comp]) for i, p in occ]
            free = [ch for ch, cz in chans if cz == "w"]
            clamped = [ch for ch, cz in chans if cz == "a"]
            if len(free) > 1:
                owners = [models[i].name for i, p in occ if p.causality[comp] == "w"]
                raise ValueError(
                    f"node {node!r}, component {COMPONENTS[comp]}: free in several models {owners}; "
                    "a closed kinematic loop needs all but one of them inverted (clamped)"
                )
            if free:
                (fch,) = free
                for ch in clamped:
                    k[ch, fch] = 1.0  # clamped model gets the free model's acceleration
                    k[fch, ch] = 1.0  # free model gets the clamped model's reaction wrench
                e_cols.append(fch)
                f_rows.append([(fch, 1.0)])
                caus.append("w")
            else:
                e_cols.append(clamped)
                f_rows.append([(ch, 1.0) for ch in clamped])
                caus.append("a")
        ports.append(Port(node, first.position.copy(), tuple(caus)))

    n_ext = len(e_cols)
    e = np.zeros((n_c, n_ext))
    f = np.zeros((n_ext, n_c))
    for j, col in enumerate(e_cols):
        e[col, j] = 1.0
    for j, row in enumerate(f_rows):
        for ch, val in row:
            f[j, ch] = val
    a2, b2, c2, d2 = close_static(a, b, c, d, k, e, f, np.zeros((n_ext, n_ext)))
    params: dict = {}
    for m in models:
        for key, val in m.params.items():
            if key in params and params[key] != val:
                raise ValueError(f"parameter {key!r} is defined differently in two models")
            params[key] = val
    return MultiPortModel(a2, b2, c2, d2, ports, name, params)

