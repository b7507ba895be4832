"""Multi-port (TITOP / NINOP) linear models: channel inversion, frame change, interconnection.

Paper: section "TITOP Approach" and the block diagrams of sections "2D Mechanisms"
and "3D Mechanisms". Mathematics: ``docs/titop.md`` sections a, d and e.

A :class:`MultiPortModel` is a square linear model whose input/output channels come
in *conjugated pairs*, grouped in ports. A 6-dof port is a node (a point with a
name and a position) and each of its six channels (Tx, Ty, Tz, Rx, Ry, Rz) has a
causality:

``"a"`` (clamped / parent side)
    the input is the acceleration twist imposed at the node, the output is the
    wrench applied **by** the model **on** the outside at that node;
``"w"`` (free / child side)
    the input is the wrench applied **on** the model at that node by the outside,
    the output is the acceleration twist of the node.

This single sign convention holds for every channel, inverted or not: channel
inversion swaps the causality *and* the sign of the wrench, so that any two models
can be connected by the same rule (accelerations shared, wrenches summed). With
it, every model's DC gain from an imposed acceleration to its reaction wrench is
minus its rigid mass matrix at that node.

Scalar ports (e.g. a proof-mass actuator force in / stroke out) carry one channel
with free-form input and output names; inverting them swaps the names only.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

import control as ct
import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import frames
from .lft import LFT
from .statespace import frequency_response, invert_channels, state_space_arrays

__all__ = [
    "COMPONENTS",
    "Port",
    "MultiPortModel",
    "delta_port",
    "node_port",
    "scalar_port",
]

COMPONENTS: tuple[str, ...] = ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")
_COMP_INDEX = {c: i for i, c in enumerate(COMPONENTS)}


@dataclass(frozen=True)
class Port:
    """One port of a multi-port model.

    Parameters
    ----------
    name : str
        Node name (e.g. ``"N1"``); ports of different models with the same name
        are the same physical point when models are connected.
    position : ndarray, shape (3,)
        Node position in the model's frame [m] (unused for scalar ports).
    causality : tuple of str
        Per channel ``"a"`` or ``"w"`` for a 6-dof port (see module docstring);
        ``("s",)`` for a scalar port.
    labels : tuple of str, optional
        Scalar ports only: ``(input_name, output_name)``.
    parameter : str, optional
        For an uncertainty channel (a "delta" port): the name of the parameter whose
        normalised value closes it, ``w = delta z`` (see :mod:`trusscodesign.model.lft`).
    """

    name: str
    position: NDArray[np.float64]
    causality: tuple[str, ...]
    labels: tuple[str, str] | None = None
    parameter: str | None = None

    @property
    def size(self) -> int:
        """Number of channels (6 or 1)."""
        return len(self.causality)

    @property
    def is_scalar(self) -> bool:
        """True for a scalar (1-channel) port."""
        return self.labels is not None

    @property
    def kind(self) -> str:
        """``"clamped"`` (all accelerations in), ``"free"`` (all wrenches in), ``"mixed"``, ``"scalar"`` or ``"delta"``."""
        if self.parameter is not None:
            return "delta"
        if self.is_scalar:
            return "scalar"
        if all(c == "a" for c in self.causality):
            return "clamped"
        if all(c == "w" for c in self.causality):
            return "free"
        return "mixed"

    def input_names(self) -> list[str]:
        """Signal names of the port's inputs."""
        if self.labels is not None:
            return [self.labels[0]]
        return [f"{'a' if c == 'a' else 'W'}_{self.name}_{k}" for c, k in zip(self.causality, COMPONENTS)]

    def output_names(self) -> list[str]:
        """Signal names of the port's outputs (the conjugates of the inputs)."""
        if self.labels is not None:
            return [self.labels[1]]
        return [f"{'W' if c == 'a' else 'a'}_{self.name}_{k}" for c, k in zip(self.causality, COMPONENTS)]


def node_port(name: str, position: ArrayLike, kind: str) -> Port:
    """A 6-dof port at node ``name`` and ``position`` [m], ``kind`` ``"clamped"`` or ``"free"``."""
    if kind not in ("clamped", "free"):
        raise ValueError(f"port kind must be 'clamped' or 'free', got {kind!r}")
    return Port(str(name), frames.as_vector3(position, f"position of {name}"), ("a" if kind == "clamped" else "w",) * 6)


def scalar_port(name: str, input_name: str, output_name: str) -> Port:
    """A scalar (1-channel) port with named input and output."""
    return Port(str(name), np.zeros(3), ("s",), (str(input_name), str(output_name)))


_DELTA_IDS = itertools.count(1)


def delta_port(parameter: str) -> Port:
    """A new uncertainty channel of ``parameter`` (unique name ``D<k>:<parameter>``)."""
    name = f"D{next(_DELTA_IDS)}:{parameter}"
    return Port(name, np.zeros(3), ("s",), (f"w_{name}", f"z_{name}"), str(parameter))


class MultiPortModel:
    """A square linear model with ports of conjugated input/output channels.

    Parameters
    ----------
    a, b, c, d : array_like
        State-space matrices; inputs and outputs are ordered port by port,
        in the order of ``ports``, each port's channels in ``COMPONENTS`` order.
    ports : sequence of Port
        The ports; node names must be unique.
    name : str
        A label for the model.
    params : mapping str -> trusscodesign.model.lft.Parameter, optional
        The parameters of the model's delta ports (uncertainty channels): the model is
        then the certain part ``M`` of the LFT ``F_u(M, Delta)``.
    """

    def __init__(self, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike, ports: Sequence[Port], name: str = "model",
                 params: Mapping | None = None):
        n_ch = sum(p.size for p in ports)
        if np.atleast_2d(np.asarray(d)).shape != (n_ch, n_ch):
            raise ValueError(f"D must be {n_ch}x{n_ch} for the given ports, got {np.atleast_2d(np.asarray(d)).shape}")
        self.a, self.b, self.c, self.d = state_space_arrays(a, b, c, d)
        names = [p.name for p in ports]
        if len(set(names)) != len(names):
            raise ValueError(f"port names must be unique, got {names}")
        self.ports: tuple[Port, ...] = tuple(ports)
        self.name = name
        self.params = dict(params or {})
        missing = sorted({p.parameter for p in self.ports if p.parameter is not None} - set(self.params))
        if missing:
            raise ValueError(f"delta ports name parameters {missing} that are not in params")

    def _like(self, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike, ports: Sequence[Port], name: str | None = None) -> "MultiPortModel":
        """A new model with this model's parameters."""
        return MultiPortModel(a, b, c, d, ports, name or self.name, self.params)

    # ------------------------------------------------------------------ access
    @property
    def nstates(self) -> int:
        """Number of states."""
        return self.a.shape[0]

    @property
    def nchannels(self) -> int:
        """Number of channels (inputs = outputs)."""
        return self.d.shape[0]

    @property
    def port_names(self) -> list[str]:
        """Names of the ports, in channel order."""
        return [p.name for p in self.ports]

    def port(self, name: str) -> Port:
        """The port named ``name``."""
        for p in self.ports:
            if p.name == name:
                return p
        raise ValueError(f"model {self.name!r} has no port {name!r}; ports are {self.port_names}")

    def offset(self, name: str) -> int:
        """Index of the first channel of port ``name``."""
        off = 0
        for p in self.ports:
            if p.name == name:
                return off
            off += p.size
        raise ValueError(f"model {self.name!r} has no port {name!r}; ports are {self.port_names}")

    def channels(self, name: str, components: Iterable[str] | None = None) -> list[int]:
        """0-based channel indices of port ``name`` (optionally only some components)."""
        port = self.port(name)
        off = self.offset(name)
        if components is None:
            return list(range(off, off + port.size))
        if port.is_scalar:
            raise ValueError(f"port {name!r} is scalar: it has no components")
        out = []
        for comp in components:
            if comp not in _COMP_INDEX:
                raise ValueError(f"unknown component {comp!r}; use one of {COMPONENTS}")
            out.append(off + _COMP_INDEX[comp])
        return out

    def input_names(self) -> list[str]:
        """All input signal names."""
        return [n for p in self.ports for n in p.input_names()]

    def output_names(self) -> list[str]:
        """All output signal names."""
        return [n for p in self.ports for n in p.output_names()]

    def to_statespace(self) -> ct.StateSpace:
        """Plain ``control.StateSpace`` with named inputs and outputs."""
        return ct.ss(self.a, self.b, self.c, self.d, inputs=self.input_names(), outputs=self.output_names(), name=self.name)

    def poles(self) -> NDArray[np.complex128]:
        """Eigenvalues of A [rad/s]."""
        return np.linalg.eigvals(self.a) if self.nstates else np.zeros(0, dtype=complex)

    def freqresp(self, omega: ArrayLike, outputs: Sequence[int] | None = None, inputs: Sequence[int] | None = None) -> NDArray:
        """Frequency response on ``omega`` [rad/s], shape ``(n_out, n_in, n_w)`` (optionally a sub-block)."""
        b = self.b if inputs is None else self.b[:, list(inputs)]
        c = self.c if outputs is None else self.c[list(outputs), :]
        d = self.d if outputs is None else self.d[list(outputs), :]
        d = d if inputs is None else d[:, list(inputs)]
        return frequency_response(self.a, b, c, d, omega)

    def static_compliance(self, port: str) -> NDArray[np.float64]:
        """Static compliance of a free port: ``lim_{s->0} G_{a<-W}(s) / s^2`` [m/N, rad/(N m), ...].

        For ``G(s) = D + C (sI - A)^-1 B`` with ``G(0) = G'(0) = 0`` on this block,
        the ``s^2`` coefficient is ``-C A^-3 B``. It is the displacement of the
        port per unit static wrench (6x6, translations then rotations).

        Raises
        ------
        ValueError
            If the port is not free, A has poles at 0 (their modulus below 1e-10 of the largest), or the port is not
            held (``G(0) = D - C A^-1 B`` on the block is not zero: a free body has no static compliance).
        """
        if self.port(port).kind != "free":
            raise ValueError(f"port {port!r} is {self.port(port).kind}: the compliance is defined for a free port")
        idx = self.channels(port)
        lam = np.abs(self.poles())
        if self.nstates == 0 or lam.min() <= 1e-10 * lam.max():  # scale-free (cond(A) grows with the frequency span)
            raise ValueError(f"{self.name!r} has poles at s = 0: remove them (trusscodesign.model.reduction) before asking for a compliance")
        x = np.linalg.solve(self.a, self.b[:, idx])
        d_blk, cab = self.d[np.ix_(idx, idx)], self.c[idx, :] @ x
        if np.linalg.norm(d_blk - cab) > 1e-8 * max(np.linalg.norm(d_blk), np.linalg.norm(cab)):
            raise ValueError(f"port {port!r} of {self.name!r} is not held (its DC acceleration per wrench is "
                             f"{np.linalg.norm(d_blk - cab):.3g}, not 0): a free body has no static compliance")
        x = np.linalg.solve(self.a, x)
        x = np.linalg.solve(self.a, x)
        return -self.c[idx, :] @ x

    def __repr__(self) -> str:
        desc = ", ".join(f"{p.name}:{p.kind}" for p in self.ports)
        return f"MultiPortModel({self.name!r}, {self.nstates} states, {self.nchannels} channels; {desc})"

    # ------------------------------------------------------------- operations
    def invert(self, channels: Iterable[int], one_based: bool = False, name: str | None = None) -> "MultiPortModel":
        """Channel inversion ``[M(s)]^{-1_I}``.

        Parameters
        ----------
        channels : iterable of int
            Channel indices (0-based by default; ``one_based=True`` takes the
            paper's 1-based indices, e.g. ``[1, 2, 3, 4, 6, 11]``).
        one_based : bool
            Interpret ``channels`` as 1-based.
        name : str, optional
            Name of the new model.

        Returns
        -------
        MultiPortModel
            Model with the inverted channels' causality swapped. The wrench of
            each inverted 6-dof channel keeps this module's sign convention.

        Raises
        ------
        ValueError
            If an index does not exist or the channel set is not invertible.
        """
        channels = list(channels)
        odd = [i for i in channels if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer))]
        if odd:
            raise TypeError(f"channels must be integer indices, got {odd!r}")
        idx = [int(i) - (1 if one_based else 0) for i in channels]
        bad = [i for i in idx if not 0 <= i < self.nchannels]
        if bad:
            shown = [i + (1 if one_based else 0) for i in bad]
            base = 1 if one_based else 0
            raise ValueError(
                f"channel index {shown} does not exist in {self.name!r}: valid "
                f"{'1' if one_based else '0'}-based indices are {base}..{self.nchannels - 1 + base}"
            )
        deltas = [i for p in self.ports if p.parameter is not None for i in self.channels(p.name) if i in idx]
        if deltas:
            raise ValueError(f"channels {deltas} are uncertainty (delta) channels: they cannot be inverted")
        a, b, c, d = invert_channels(self.a, self.b, self.c, self.d, idx)
        ports = []
        sign = np.ones(self.nchannels)
        off = 0
        new_caus = []
        for p in self.ports:
            caus = list(p.causality)
            for k in range(p.size):
                if off + k in idx and not p.is_scalar:
                    caus[k] = "w" if caus[k] == "a" else "a"
                    sign[off + k] = -1.0
            labels = p.labels
            if p.labels is not None and off in idx:  # a scalar port: its labels swap
                labels = (p.labels[1], p.labels[0])
            ports.append(replace(p, causality=tuple(caus), labels=labels))
            new_caus.extend(caus)
            off += p.size
        # Keep "wrench applied on the model" at inputs and "by the model" at outputs:
        # negate the wrench of each inverted 6-dof channel.
        in_sign = np.where((sign < 0) & (np.array(new_caus) == "w"), -1.0, 1.0)
        out_sign = np.where((sign < 0) & (np.array(new_caus) == "a"), -1.0, 1.0)
        b = b * in_sign
        c = out_sign[:, None] * c
        d = out_sign[:, None] * d * in_sign
        return self._like(a, b, c, d, ports, name or f"{self.name}^-1")

    def invert_ports(self, *names: str, name: str | None = None) -> "MultiPortModel":
        """Invert all channels of the named ports (free <-> clamped)."""
        idx = [i for n in names for i in self.channels(n)]
        return self.invert(idx, name=name)

    def _transform(self, t_in: Mapping[str, NDArray], t_out: Mapping[str, NDArray], ports: Sequence[Port], name: str) -> "MultiPortModel":
        """Apply per-port input/output maps: ``u_old = T_in u_new``, ``y_new = T_out y_old``."""
        tin = np.eye(self.nchannels)
        tout = np.eye(self.nchannels)
        for p in self.ports:
            if p.name in t_in:
                sl = slice(self.offset(p.name), self.offset(p.name) + p.size)
                tin[sl, sl] = t_in[p.name]
                tout[sl, sl] = t_out[p.name]
        return self._like(self.a, self.b @ tin, tout @ self.c, tout @ self.d @ tin, ports, name)

    def reproject(self, rot: ArrayLike, name: str | None = None) -> "MultiPortModel":
        """Express the model in another frame.

        Parameters
        ----------
        rot : array_like, shape (3, 3)
            DCM ``R_new,old`` (components in the model's frame -> new frame).
            All 6-dof port variables are mapped by the twice DCM and node
            positions by ``R`` (the origin is kept).
        """
        r6 = frames.twice_dcm(rot)
        rot = np.asarray(rot, dtype=float)
        six = [p for p in self.ports if not p.is_scalar]
        ports = [p if p.is_scalar else replace(p, position=rot @ p.position) for p in self.ports]
        return self._transform({p.name: r6.T for p in six}, {p.name: r6 for p in six}, ports, name or self.name)

    def translate(self, offset: ArrayLike, name: str | None = None) -> "MultiPortModel":
        """Move the whole model by ``offset`` [m] (positions only; dynamics unchanged)."""
        off = frames.as_vector3(offset, "offset")
        ports = [p if p.is_scalar else replace(p, position=p.position + off) for p in self.ports]
        return self._like(self.a, self.b, self.c, self.d, ports, name)

    def transport(self, port: str, position: ArrayLike, new_name: str | None = None) -> "MultiPortModel":
        """Move port ``port`` to another point rigidly attached to it, with the kinematic model tau.

        For a clamped port at P moved to Q: ``a_P = tau_PQ a_Q`` and the reaction
        becomes ``tau_PQ^T W_P``; for a free port: ``W_P = tau_QP^T W_Q`` and
        ``a_Q = tau_QP a_P``.

        Raises
        ------
        ValueError
            For a scalar or mixed-causality port (tau couples its components).
        """
        p = self.port(port)
        if p.kind not in ("clamped", "free"):
            raise ValueError(f"port {port!r} is {p.kind}: only clamped or free 6-dof ports can be transported")
        q = frames.as_vector3(position, "position")
        if p.kind == "clamped":
            t = frames.tau(q - p.position)  # tau_PQ
            t_in, t_out = t, t.T
        else:
            t = frames.tau(p.position - q)  # tau_QP
            t_in, t_out = t.T, t
        new = replace(p, name=new_name or p.name, position=q)
        ports = [new if x.name == port else x for x in self.ports]
        return self._transform({port: t_in}, {port: t_out}, ports, self.name)

    def rename(self, mapping: Mapping[str, str], name: str | None = None) -> "MultiPortModel":
        """Rename ports (nodes) with ``mapping`` old name -> new name."""
        for old in mapping:
            self.port(old)
        ports = [replace(p, name=mapping.get(p.name, p.name)) for p in self.ports]
        return self._like(self.a, self.b, self.c, self.d, ports, name)

    def select(self, keep: Sequence[str], name: str | None = None) -> "MultiPortModel":
        """Keep only the ports in ``keep`` (in that order); the others are closed.

        A dropped free channel gets no external wrench (the node is unloaded and
        not observed); a dropped clamped channel gets zero acceleration (the node
        is held fixed). States are kept as they are; delta ports are always kept.
        """
        missing = [n for n in keep if n not in self.port_names]
        if missing:
            raise ValueError(f"ports {missing} do not exist in {self.name!r}; ports are {self.port_names}")
        if len(set(keep)) != len(keep):
            raise ValueError(f"keep must list distinct ports, got {list(keep)}")
        keep = list(keep) + [p.name for p in self.ports if p.parameter is not None and p.name not in keep]
        idx = [i for n in keep for i in self.channels(n)]
        ports = [self.port(n) for n in keep]
        return self._like(self.a, self.b[:, idx], self.c[idx, :], self.d[np.ix_(idx, idx)], ports, name)

    # ---------------------------------------------------------- uncertainty
    @property
    def delta_ports(self) -> list[Port]:
        """The uncertainty channels (delta ports), in channel order."""
        return [p for p in self.ports if p.parameter is not None]

    @property
    def delta_parameters(self) -> list[str]:
        """The parameter of each uncertainty channel, in channel order."""
        return [p.parameter for p in self.ports if p.parameter is not None]

    def occurrences(self) -> dict[str, int]:
        """Number of delta channels of each parameter."""
        out: dict[str, int] = {}
        for name in self.delta_parameters:
            out[name] = out.get(name, 0) + 1
        return out

    def substitute(self, values: Mapping[str, float], normalized: bool = False, name: str | None = None) -> "MultiPortModel":
        """Close the delta ports of the parameters in ``values`` (physical values unless ``normalized``)."""
        io = [p for p in self.ports if p.parameter is None]
        return MultiPortModel.from_lft(self.to_lft().substitute(values, normalized), io, name or self.name)

    def to_lft(self, inputs: Sequence[str] | None = None, outputs: Sequence[str] | None = None):
        """The model as a :class:`trusscodesign.model.lft.LFT` with the named io signals (default: all non-delta channels)."""

        io_ports = [p for p in self.ports if p.parameter is None]
        in_names = [n for p in io_ports for n in p.input_names()] if inputs is None else list(inputs)
        out_names = [n for p in io_ports for n in p.output_names()] if outputs is None else list(outputs)
        all_in, all_out = self.input_names(), self.output_names()
        for n in in_names:
            if n not in all_in:
                raise ValueError(f"unknown input {n!r} of {self.name!r}")
        for n in out_names:
            if n not in all_out:
                raise ValueError(f"unknown output {n!r} of {self.name!r}")
        dch = [self.offset(p.name) for p in self.delta_ports]
        ii = dch + [all_in.index(n) for n in in_names]
        oo = dch + [all_out.index(n) for n in out_names]
        return LFT(self.a, self.b[:, ii], self.c[oo, :], self.d[np.ix_(oo, ii)], self.delta_parameters, self.params)

    @classmethod
    def from_lft(cls, lft, ports: Sequence[Port], name: str = "model") -> "MultiPortModel":
        """A multi-port model whose io channels (in port order) are those of ``lft``; its Delta channels become delta ports."""
        n_io = sum(p.size for p in ports)
        if lft.shape != (n_io, n_io):
            raise ValueError(f"the LFT is {lft.shape[0]}x{lft.shape[1]} but the ports have {n_io} channels")
        nd = lft.n_delta
        perm_in = list(range(nd, nd + n_io)) + list(range(nd))
        perm_out = list(range(nd, nd + n_io)) + list(range(nd))
        dports = [delta_port(name_) for name_ in lft.blocks]
        return cls(lft.a, lft.b[:, perm_in], lft.c[perm_out, :], lft.d[np.ix_(perm_out, perm_in)], list(ports) + dports, name, lft.params)

    def reproject_lft(self, r6, name: str | None = None) -> "MultiPortModel":
        """Express the model in another frame through an uncertain twice DCM ``r6`` (a 6x6 static LFT).

        Each 6-dof port maps as in :meth:`reproject` (``y -> R6 y``, ``u -> R6^T u``);
        the DCM's Delta channels become delta ports. The 6-dof ports must lie at the
        origin (the rotation's fixed point), e.g. a panel built at its joint before
        :meth:`translate`.
        """

        six = [p for p in self.ports if p.parameter is None and not p.is_scalar]
        if any(np.linalg.norm(p.position) > 0 for p in six):
            raise ValueError("reproject_lft needs the 6-dof ports at the origin: translate the model after rotating it")
        one = LFT.constant([[1.0]])
        io = [p for p in self.ports if p.parameter is None]
        return self._map_io_lft([r6 if not p.is_scalar else one for p in io], [r6.T if not p.is_scalar else one for p in io], name)

    def unscale_signals_lft(self, h_param, ports: Sequence[str], name: str | None = None) -> "MultiPortModel":
        """Convert the named 6-dof ports from scaled signals (``a r``, ``W / r``, ``r = h / h_param.center``) to physical ones.

        A clamped port takes the physical acceleration (the model gets ``r a``) and returns
        ``W = r W_scaled``; a free port takes the physical wrench (the model gets ``W / r``)
        and returns ``a = a_scaled / r``: 12 occurrences of h per port.
        """

        ratio = LFT.param(h_param) * (1.0 / h_param.center)
        inv_ratio = ratio.inv()
        io = [p for p in self.ports if p.parameter is None]
        outs, ins = [], []
        for p in io:
            if p.name in ports:
                if p.kind not in ("clamped", "free"):
                    raise ValueError(f"port {p.name!r} is {p.kind}: only clamped or free ports can be converted")
                g = ratio if p.kind == "clamped" else inv_ratio
                outs += [g] * 6
                ins += [g] * 6
            else:
                outs += [LFT.constant([[1.0]])] * p.size
                ins += [LFT.constant([[1.0]])] * p.size
        return self._map_io_lft(outs, ins, name)

    def _map_io_lft(self, outs: Sequence, ins: Sequence, name: str | None) -> "MultiPortModel":
        """``blkdiag(outs) @ M @ blkdiag(ins)`` on the io channels (blocks in io order), delta ports kept."""

        io = [p for p in self.ports if p.parameter is None]
        mapped = LFT.blkdiag(*outs) @ self.to_lft() @ LFT.blkdiag(*ins)
        return MultiPortModel.from_lft(mapped, io, name or self.name)

    def with_axis_channel(self, port: str, axis: ArrayLike, label: str, input_name: str, output_name: str) -> "MultiPortModel":
        """Add a scalar channel acting along the 6-vector ``axis`` of a clamped port.

        The new input ``v`` adds ``axis * v`` to the port's imposed acceleration and the
        new output is ``axis^T W`` (e.g. a revolute joint: relative angular acceleration
        in, torque transmitted about the joint axis out).
        """
        p = self.port(port)
        if p.kind != "clamped":
            raise ValueError(f"port {port!r} is {p.kind}: an axis channel needs a clamped port")
        e = np.asarray(axis, dtype=float).reshape(6)
        col = np.zeros(self.nchannels)
        col[self.channels(port)] = e
        t_in = np.hstack([np.eye(self.nchannels), col[:, None]])
        t_out = np.vstack([np.eye(self.nchannels), col[None, :]])
        ports = list(self.ports) + [scalar_port(label, input_name, output_name)]
        return self._like(self.a, self.b @ t_in, t_out @ self.c, t_out @ self.d @ t_in, ports)

    def reorder(self, order: Sequence[str], name: str | None = None) -> "MultiPortModel":
        """Reorder the ports; ``order`` must name every port once."""
        if sorted(order) != sorted(self.port_names):
            raise ValueError(f"order must list each port once: got {list(order)}, ports are {self.port_names}")
        perm = [i for n in order for i in self.channels(n)]
        ports = [self.port(n) for n in order]
        return self._like(self.a, self.b[:, perm], self.c[perm, :], self.d[np.ix_(perm, perm)], ports, name)
