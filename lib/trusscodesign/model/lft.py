"""Linear fractional transformations: uncertain and tunable real parameters, uncertain matrices
and systems (the Python counterpart of MATLAB's ``ureal`` / ``umat`` / ``uss``).

Paper: section "Full order LPV model" (the LFT ``F_u(G(s), Delta)`` with repeated real
scalar blocks) and "Co-design optimization architecture" (``F_l(., K_PMA)``).

An :class:`LFT` is ``F_u(M, Delta)``: a certain state-space model ``M`` whose inputs are
``[w (n_delta); u]`` and outputs ``[z (n_delta); y]``, closed by ``w = Delta z`` with
``Delta = diag(delta_1, ..., delta_n_delta)``; each Delta channel carries the *normalised*
value ``delta in [-1, 1]`` of one named :class:`Parameter` (a parameter appearing k times
is a k-times repeated real scalar block). Every operation (sum, product, inverse,
concatenation, feedback, lower LFT, star product, substitution) is a static
interconnection of the io channels with the Delta channels passed through, computed by
:func:`trusscodesign.model.statespace.close_static`; so the LFT form is kept exactly.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import control as ct
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

from ..infra.checks import check_real
from .statespace import close_static, frequency_response, invert_channels, ss_matrices, state_space_arrays

__all__ = ["Parameter", "LFT", "block_runs"]


@dataclass(frozen=True)
class Parameter:
    """A real parameter with a range, normalised as ``value = center + half_range * delta``, ``delta in [-1, 1]``.

    Parameters
    ----------
    name : str
        Unique name.
    nominal : float
        Nominal value (inside the range).
    low, high : float
        Range, ``low < high``.
    tunable : bool
        True for a design (tunable) parameter, False for an uncertain one.
    """

    name: str
    nominal: float
    low: float
    high: float
    tunable: bool = False

    def __post_init__(self) -> None:
        for val, nm in ((self.nominal, "nominal"), (self.low, "low"), (self.high, "high")):
            check_real(f"parameter {self.name!r}: {nm}", val)
            if not np.isfinite(val):
                raise ValueError(f"parameter {self.name!r}: {nm} must be finite, got {val!r}")
        if not self.low < self.high:
            raise ValueError(f"parameter {self.name!r}: need low < high, got [{self.low}, {self.high}]")
        if not self.low <= self.nominal <= self.high:
            raise ValueError(f"parameter {self.name!r}: nominal {self.nominal} outside [{self.low}, {self.high}]")

    @classmethod
    def percent(cls, name: str, nominal: float, percent: float, tunable: bool = False) -> "Parameter":
        """Parameter ``nominal * (1 +- percent/100)``, ``0 < percent < 100``."""
        check_real(f"parameter {name!r}: nominal", nominal)
        check_real(f"parameter {name!r}: percent", percent)
        if not percent > 0:
            raise ValueError(f"percent must be positive, got {percent!r}")
        if percent >= 100:
            raise ValueError(f"parameter {name!r}: percent must be below 100, got {percent!r}: the range nominal * (1 +- "
                             f"{percent!r} / 100) would reach or cross zero (the parameter would change sign)")
        span = abs(nominal) * percent / 100.0
        return cls(name, nominal, nominal - span, nominal + span, tunable)

    @property
    def center(self) -> float:
        """Value at ``delta = 0``."""
        return 0.5 * (self.low + self.high)

    @property
    def half_range(self) -> float:
        """Half of the range."""
        return 0.5 * (self.high - self.low)

    def to_delta(self, value: float) -> float:
        """Normalised value of a physical ``value``; raises if outside the range (tolerance 1e-12)."""
        delta = (value - self.center) / self.half_range
        if not (np.isfinite(delta) and abs(delta) <= 1.0 + 1e-12):
            raise ValueError(f"parameter {self.name!r}: value {value!r} outside its range [{self.low}, {self.high}]")
        return float(delta)

    def from_delta(self, delta: float) -> float:
        """Physical value of a normalised ``delta`` in [-1, 1] (tolerance 1e-12; no extrapolation out of the range)."""
        check_real(f"parameter {self.name!r}: delta", delta)
        if not (np.isfinite(delta) and abs(delta) <= 1.0 + 1e-12):
            raise ValueError(f"parameter {self.name!r}: delta must be a normalised value in [-1, 1], got {delta!r}: no "
                             f"extrapolation out of the range [{self.low}, {self.high}] (a physical value? it is the value itself)")
        return self.center + self.half_range * float(delta)


def _delta_values(params: Mapping[str, Parameter], values: Mapping[str, float], normalized: bool) -> dict[str, float]:
    """Normalised values of the given parameters, checked against their ranges."""
    out = {}
    for name, val in values.items():
        if name not in params:
            raise ValueError(f"unknown parameter {name!r}; parameters are {sorted(params)}")
        if normalized:
            if not abs(float(val)) <= 1.0 + 1e-12:
                raise ValueError(f"normalised value of {name!r} must be in [-1, 1], got {val!r}")
            out[name] = float(val)
        else:
            out[name] = params[name].to_delta(val)
    return out


def block_runs(blocks: Sequence[str]) -> list[tuple[str, int]]:
    """``[(name, repetitions), ...]`` of consecutive Delta channels of the same parameter, in channel order."""
    out: list[tuple[str, int]] = []
    for name in blocks:
        if out and out[-1][0] == name:
            out[-1] = (name, out[-1][1] + 1)
        else:
            out.append((name, 1))
    return out


class LFT:
    """Uncertain matrix or system ``F_u(M, Delta)``.

    Parameters
    ----------
    a, b, c, d : array_like
        Certain part; inputs ``[w; u]``, outputs ``[z; y]`` with ``len(blocks)`` Delta channels first.
    blocks : sequence of str
        Parameter name of each Delta channel.
    params : mapping str -> Parameter
        The parameters (every name in ``blocks`` must be here).
    """

    def __init__(self, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike, blocks: Sequence[str] = (),
                 params: Mapping[str, Parameter] | None = None):
        self.a, self.b, self.c, self.d = state_space_arrays(a, b, c, d)
        self.blocks = list(blocks)
        self.params = dict(params or {})
        missing = sorted(set(self.blocks) - set(self.params))
        if missing:
            raise ValueError(f"Delta channels name unknown parameters {missing}")
        nd = len(self.blocks)
        if self.d.shape[0] < nd or self.d.shape[1] < nd:
            raise ValueError(f"{nd} Delta channels but D is {self.d.shape}")

    # ----------------------------------------------------------------- builders
    @classmethod
    def constant(cls, value: ArrayLike) -> "LFT":
        """A certain matrix."""
        m = np.atleast_2d(np.asarray(value, float))
        return cls(np.zeros((0, 0)), np.zeros((0, m.shape[1])), np.zeros((m.shape[0], 0)), m)

    @classmethod
    def from_ss(cls, system: ArrayLike | ct.StateSpace, b: ArrayLike | None = None, c: ArrayLike | None = None,
                d: ArrayLike | None = None) -> "LFT":
        """A certain system, from a continuous-time ``control.StateSpace`` alone or from its four matrices.

        Every input and output of ``system`` becomes an io channel: the Delta channels of a model made by
        :meth:`to_ss` come back as ordinary inputs and outputs (the structure is in ``blocks`` and ``params``, which a
        StateSpace does not carry; keep the LFT itself to keep them).
        """
        return cls(*ss_matrices(system, b, c, d, name="LFT.from_ss"))

    @classmethod
    def param(cls, p: Parameter) -> "LFT":
        """The scalar ``center + half_range * delta`` (one occurrence)."""
        return cls(np.zeros((0, 0)), np.zeros((0, 2)), np.zeros((2, 0)), [[0.0, 1.0], [p.half_range, p.center]], [p.name], {p.name: p})

    # --------------------------------------------------------------- properties
    @property
    def n_delta(self) -> int:
        """Number of Delta channels."""
        return len(self.blocks)

    @property
    def shape(self) -> tuple[int, int]:
        """(outputs, inputs) of the io part."""
        return self.d.shape[0] - self.n_delta, self.d.shape[1] - self.n_delta

    @property
    def nstates(self) -> int:
        """Number of states of the certain part."""
        return self.a.shape[0]

    def occurrences(self) -> dict[str, int]:
        """Number of Delta channels of each parameter."""
        out: dict[str, int] = {}
        for name in self.blocks:
            out[name] = out.get(name, 0) + 1
        return out

    def delta_structure(self) -> list[tuple[str, int]]:
        """``[(name, repetitions), ...]`` in channel order after :meth:`grouped` (for mu-analysis)."""
        return block_runs(self.grouped().blocks)

    def grouped(self) -> "LFT":
        """The same LFT with its Delta channels sorted by parameter (one repeated block per parameter)."""
        order = sorted(range(self.n_delta), key=lambda i: (self.blocks[i], i))
        nd = self.n_delta
        pin = order + list(range(nd, self.d.shape[1]))
        pout = order + list(range(nd, self.d.shape[0]))
        return LFT(self.a, self.b[:, pin], self.c[pout, :], self.d[np.ix_(pout, pin)], [self.blocks[i] for i in order], self.params)

    def __repr__(self) -> str:
        occ = ", ".join(f"{k}x{v}" for k, v in self.occurrences().items()) or "certain"
        return f"LFT({self.shape[0]}x{self.shape[1]}, {self.nstates} states; {occ})"

    # ------------------------------------------------------------ combination
    def to_ss(self, inputs: Sequence[str] | None = None, outputs: Sequence[str] | None = None, name: str | None = None) -> ct.StateSpace:
        """The certain part ``M`` as a ``control.StateSpace`` with named signals, the Delta channels open.

        Inputs ``[w_<parameter>_<i>; inputs]`` and outputs ``[z_<parameter>_<i>; outputs]``, ``i`` the Delta channel's
        index; the io names default to ``u[k]`` and ``y[k]``. Close the Delta channels with :meth:`substitute` first for
        the model at given parameter values.
        """
        nd, (ny, nu) = self.n_delta, self.shape
        inputs = [f"u[{k}]" for k in range(nu)] if inputs is None else list(inputs)
        outputs = [f"y[{k}]" for k in range(ny)] if outputs is None else list(outputs)
        if len(inputs) != nu or len(outputs) != ny:
            raise ValueError(f"the LFT has {nu} inputs and {ny} outputs besides its {nd} Delta channels: got {len(inputs)} "
                             f"input and {len(outputs)} output names")
        return ct.ss(self.a, self.b, self.c, self.d, inputs=[f"w_{b}_{i}" for i, b in enumerate(self.blocks)] + inputs,
                     outputs=[f"z_{b}_{i}" for i, b in enumerate(self.blocks)] + outputs, **({"name": name} if name else {}))

    @staticmethod
    def _stack(parts: Sequence["LFT"]) -> tuple[tuple[NDArray, NDArray, NDArray, NDArray], list[str], dict[str, Parameter], int]:
        """Block-diagonal stack ordered ``[all Delta channels; all io channels]``: matrices, blocks, params, n_delta."""
        params: dict[str, Parameter] = {}
        for p in parts:
            for name, v in p.params.items():
                if name in params and params[name] != v:
                    raise ValueError(f"parameter {name!r} is defined differently in two operands")
                params[name] = v
        a = linalg.block_diag(*[p.a for p in parts]) if any(p.nstates for p in parts) else np.zeros((0, 0))
        nd = sum(p.n_delta for p in parts)
        n_in = nd + sum(p.shape[1] for p in parts)
        n_out = nd + sum(p.shape[0] for p in parts)
        b = np.zeros((a.shape[0], n_in))
        c = np.zeros((n_out, a.shape[0]))
        d = np.zeros((n_out, n_in))
        xo = do = 0
        io_in = nd
        io_out = nd
        for p in parts:
            n, k = p.nstates, p.n_delta
            ny, nu = p.shape
            rows = list(range(do, do + k)) + list(range(io_out, io_out + ny))
            cols = list(range(do, do + k)) + list(range(io_in, io_in + nu))
            b[xo : xo + n, cols] = p.b
            c[rows, xo : xo + n] = p.c
            d[np.ix_(rows, cols)] = p.d
            xo += n
            do += k
            io_in += nu
            io_out += ny
        blocks = [name for p in parts for name in p.blocks]
        return (a, b, c, d), blocks, params, nd

    @classmethod
    def _interconnect(cls, parts: Sequence["LFT"], k_io: NDArray, e_io: NDArray, f_io: NDArray, h_io: NDArray) -> "LFT":
        """Close ``u_io = K y_io + E w_ext``, ``y_ext = F y_io + H w_ext`` on the stacked io channels."""
        (a, b, c, d), blocks, params, nd = cls._stack(parts)
        n_io_in, n_io_out = d.shape[1] - nd, d.shape[0] - nd
        k = np.zeros((d.shape[1], d.shape[0]))
        k[nd:, nd:] = k_io
        e = np.zeros((d.shape[1], nd + e_io.shape[1]))
        e[:nd, :nd] = np.eye(nd)
        e[nd:, nd:] = e_io
        f = np.zeros((nd + f_io.shape[0], d.shape[0]))
        f[:nd, :nd] = np.eye(nd)
        f[nd:, nd:] = f_io
        h = np.zeros((f.shape[0], e.shape[1]))
        h[nd:, nd:] = h_io
        assert k_io.shape == (n_io_in, n_io_out)
        a2, b2, c2, d2 = close_static(a, b, c, d, k, e, f, h)
        return cls(a2, b2, c2, d2, blocks, params)

    @staticmethod
    def _as_lft(x) -> "LFT":
        if isinstance(x, LFT):
            return x
        return LFT.constant(x)

    def __add__(self, other) -> "LFT":
        """Sum; a certain scalar ``c`` added to a square LFT means ``c I`` (as ``L + 3.0`` in the models)."""
        other = self._as_lft(other)
        if other.shape != self.shape:
            scalar = [x for x in (self, other) if x.shape == (1, 1) and x.nstates == 0 and x.n_delta == 0]
            square = other if scalar and scalar[0] is self else self
            if not scalar or square.shape[0] != square.shape[1]:
                raise ValueError(f"cannot add {self.shape} and {other.shape} (a certain scalar adds as c I to a square LFT only)")
            return square + LFT.constant(scalar[0].d[0, 0] * np.eye(square.shape[0]))
        ny, nu = self.shape
        z = np.zeros((2 * nu, 2 * ny))
        e = np.vstack([np.eye(nu), np.eye(nu)])
        f = np.hstack([np.eye(ny), np.eye(ny)])
        return self._interconnect([self, other], z, e, f, np.zeros((ny, nu)))

    __radd__ = __add__

    def __neg__(self) -> "LFT":
        return LFT(self.a, self.b, self.c.copy() * np.r_[np.ones(self.n_delta), -np.ones(self.shape[0])][:, None],
                   self.d * np.r_[np.ones(self.n_delta), -np.ones(self.shape[0])][:, None], self.blocks, self.params)

    def __sub__(self, other) -> "LFT":
        return self + (-self._as_lft(other))

    def __rsub__(self, other) -> "LFT":
        return self._as_lft(other) + (-self)

    def __matmul__(self, other) -> "LFT":
        """Product ``self * other`` (series: ``other`` first)."""
        other = self._as_lft(other)
        if self.shape[1] != other.shape[0]:
            raise ValueError(f"cannot multiply {self.shape} by {other.shape}")
        ny, nm = self.shape
        nu = other.shape[1]
        # stacked io inputs [u_self (nm); u_other (nu)], outputs [y_self (ny); y_other (nm)]
        k = np.zeros((nm + nu, ny + nm))
        k[:nm, ny:] = np.eye(nm)
        e = np.vstack([np.zeros((nm, nu)), np.eye(nu)])
        f = np.hstack([np.eye(ny), np.zeros((ny, nm))])
        return self._interconnect([self, other], k, e, f, np.zeros((ny, nu)))

    def __rmatmul__(self, other) -> "LFT":
        return self._as_lft(other) @ self

    def __mul__(self, other) -> "LFT":
        """Multiplication by a scalar, a scalar LFT (repeated as needed) or a matrix (as ``@``)."""
        if np.isscalar(other):
            return self @ (float(other) * np.eye(self.shape[1]))  # type: ignore[arg-type]  # a real scalar (isscalar)
        o = self._as_lft(other)
        if self.shape == (1, 1) and o.shape != (1, 1):
            return self._scaled(o, self)
        if o.shape == (1, 1) and self.shape != (1, 1):
            return self._scaled(self, o)
        return self @ o

    def __rmul__(self, other) -> "LFT":
        """``other * self``: as :meth:`__mul__` when either side is a scalar (it commutes), else the product ``other @ self``."""
        o = self._as_lft(other)
        if np.isscalar(other) or o.shape == (1, 1) or self.shape == (1, 1):
            return self * other
        return o @ self

    @classmethod
    def _scaled(cls, mat: "LFT", scalar: "LFT") -> "LFT":
        """``scalar * mat`` with as few copies of the scalar as possible.

        For a certain matrix ``M = U S V`` of rank r, ``scalar * M = U S (scalar I_r) V``:
        r occurrences (e.g. 3 for the hub's translational ``T T^T / m``).
        """
        ny, nu = mat.shape
        if mat.nstates == 0 and mat.n_delta == 0:
            u, sv, vt = np.linalg.svd(mat.d)
            r = int(np.sum(sv > 1e-12 * max(sv.max(initial=0.0), 1e-300)))
            if r == 0:
                return cls.constant(np.zeros((ny, nu)))
            return cls.constant(u[:, :r] * sv[:r]) @ cls.blkdiag(*([scalar] * r)) @ cls.constant(vt[:r])
        if ny <= nu:
            return cls.blkdiag(*([scalar] * ny)) @ mat
        return mat @ cls.blkdiag(*([scalar] * nu))

    __array_ufunc__ = None  # numpy defers to the LFT operators (array * LFT, array @ LFT, ...)

    @classmethod
    def blkdiag(cls, *parts) -> "LFT":
        """Block-diagonal concatenation."""
        lfts = [cls._as_lft(p) for p in parts]
        nu = sum(p.shape[1] for p in lfts)
        ny = sum(p.shape[0] for p in lfts)
        return cls._interconnect(lfts, np.zeros((nu, ny)), np.eye(nu), np.eye(ny), np.zeros((ny, nu)))

    @classmethod
    def hstack(cls, *parts) -> "LFT":
        """``[P1, P2, ...]``: same outputs, inputs side by side."""
        lfts = [cls._as_lft(p) for p in parts]
        ny = lfts[0].shape[0]
        if any(p.shape[0] != ny for p in lfts):
            raise ValueError("hstack needs operands with the same number of outputs")
        nu = sum(p.shape[1] for p in lfts)
        f = np.hstack([np.eye(ny)] * len(lfts))
        return cls._interconnect(lfts, np.zeros((nu, ny * len(lfts))), np.eye(nu), f, np.zeros((ny, nu)))

    @classmethod
    def vstack(cls, *parts) -> "LFT":
        """``[P1; P2; ...]``: same inputs, outputs stacked."""
        lfts = [cls._as_lft(p) for p in parts]
        nu = lfts[0].shape[1]
        if any(p.shape[1] != nu for p in lfts):
            raise ValueError("vstack needs operands with the same number of inputs")
        ny = sum(p.shape[0] for p in lfts)
        e = np.vstack([np.eye(nu)] * len(lfts))
        return cls._interconnect(lfts, np.zeros((nu * len(lfts), ny)), e, np.eye(ny), np.zeros((ny, nu)))

    def inv(self) -> "LFT":
        """Inverse, kept in LFT form (inversion of the io channels of the certain part).

        Raises
        ------
        ValueError
            If the io feedthrough at ``Delta = 0`` is singular (no LFT inverse of this form).
        """
        ny, nu = self.shape
        if ny != nu:
            raise ValueError(f"only square LFTs can be inverted, got {self.shape}")
        nd = self.n_delta
        try:
            a, b, c, d = invert_channels(self.a, self.b, self.c, self.d, list(range(nd, nd + nu)))
        except ValueError as exc:
            raise ValueError(f"singular inverse: the feedthrough at nominal (delta = 0) is not invertible ({exc})") from None
        return LFT(a, b, c, d, self.blocks, self.params)

    @property
    def T(self) -> "LFT":
        """Transpose of a static LFT: ``F_u(M, Delta)^T = F_u(M^T, Delta)`` (Delta is diagonal)."""
        if self.nstates:
            raise ValueError("transpose is defined here for static LFTs only")
        return LFT(self.a, self.c.T, self.b.T, self.d.T, self.blocks, self.params)

    def feedback(self, other=None, sign: float = -1.0) -> "LFT":
        """Feedback ``y = P (u + sign * K y)`` (negative feedback by default; ``K = I`` if omitted)."""
        other = self._as_lft(np.eye(self.shape[1], self.shape[0]) if other is None else other)
        ny, nu = self.shape
        if other.shape != (nu, ny):
            raise ValueError(f"feedback needs K of shape {(nu, ny)}, got {other.shape}")
        k = np.zeros((nu + ny, ny + nu))
        k[:nu, ny:] = sign * np.eye(nu)  # u_P = w + sign * y_K
        k[nu:, :ny] = np.eye(ny)  # u_K = y_P
        e = np.vstack([np.eye(nu), np.zeros((ny, nu))])
        f = np.hstack([np.eye(ny), np.zeros((ny, nu))])
        return self._interconnect([self, other], k, e, f, np.zeros((ny, nu)))

    def lower(self, k_lft, n_meas: int, n_ctrl: int) -> "LFT":
        """Lower LFT ``F_l(self, K)``: the last ``n_meas`` outputs feed K, whose outputs are the last ``n_ctrl`` inputs."""
        k_lft = self._as_lft(k_lft)
        ny, nu = self.shape
        if k_lft.shape != (n_ctrl, n_meas):
            raise ValueError(f"K must be {n_ctrl}x{n_meas}, got {k_lft.shape}")
        nz, nw = ny - n_meas, nu - n_ctrl
        if nz < 0 or nw < 0:
            raise ValueError("n_meas / n_ctrl exceed the LFT's outputs / inputs")
        kk = np.zeros((nu + n_meas, ny + n_ctrl))
        kk[nw:nu, ny:] = np.eye(n_ctrl)
        kk[nu:, nz:ny] = np.eye(n_meas)
        e = np.zeros((nu + n_meas, nw))
        e[:nw] = np.eye(nw)
        f = np.zeros((nz, ny + n_ctrl))
        f[:, :nz] = np.eye(nz)
        return self._interconnect([self, k_lft], kk, e, f, np.zeros((nz, nw)))

    def star(self, other, n_inner_self: int, n_inner_other: int) -> "LFT":
        """Redheffer star product (as MATLAB's ``starp``): the last ``n_inner_self`` io outputs of ``self`` feed the first
        ``n_inner_self`` io inputs of ``other``, whose first ``n_inner_other`` io outputs feed the last ``n_inner_other``
        io inputs of ``self``."""
        other = self._as_lft(other)
        ny1, nu1 = self.shape
        ny2, nu2 = other.shape
        a1, b1 = n_inner_self, n_inner_other  # self's inner outputs feed other's inner inputs and vice versa
        kk = np.zeros((nu1 + nu2, ny1 + ny2))
        kk[nu1 - b1 : nu1, ny1 : ny1 + b1] = np.eye(b1)  # self inner inputs <- other's first outputs
        kk[nu1 : nu1 + a1, ny1 - a1 : ny1] = np.eye(a1)  # other's first inputs <- self inner outputs
        n_ext_in = (nu1 - b1) + (nu2 - a1)
        e = np.zeros((nu1 + nu2, n_ext_in))
        e[: nu1 - b1, : nu1 - b1] = np.eye(nu1 - b1)
        e[nu1 + a1 :, nu1 - b1 :] = np.eye(nu2 - a1)
        n_ext_out = (ny1 - a1) + (ny2 - b1)
        f = np.zeros((n_ext_out, ny1 + ny2))
        f[: ny1 - a1, : ny1 - a1] = np.eye(ny1 - a1)
        f[ny1 - a1 :, ny1 + b1 :] = np.eye(ny2 - b1)
        return self._interconnect([self, other], kk, e, f, np.zeros((n_ext_out, n_ext_in)))

    # ------------------------------------------------------------- evaluation
    def substitute(self, values: Mapping[str, float], normalized: bool = False) -> "LFT":
        """Close the Delta channels of the parameters in ``values`` (physical values unless ``normalized``)."""
        deltas = _delta_values(self.params, values, normalized)
        nd = self.n_delta
        close = [i for i, n in enumerate(self.blocks) if n in deltas]
        keep = [i for i, n in enumerate(self.blocks) if n not in deltas]
        ny, nu = self.shape
        n_in, n_out = self.d.shape[1], self.d.shape[0]
        k = np.zeros((n_in, n_out))
        for i in close:
            k[i, i] = deltas[self.blocks[i]]
        ext_in = keep + list(range(nd, n_in))
        ext_out = keep + list(range(nd, n_out))
        e = np.zeros((n_in, len(ext_in)))
        e[ext_in, np.arange(len(ext_in))] = 1.0
        f = np.zeros((len(ext_out), n_out))
        f[np.arange(len(ext_out)), ext_out] = 1.0
        try:
            a, b, c, d = close_static(self.a, self.b, self.c, self.d, k, e, f, np.zeros((len(ext_out), len(ext_in))))
        except ValueError as exc:
            raise ValueError(f"the LFT is ill-posed at the normalised values {deltas}: I - M11 Delta is singular ({exc})") from None
        return LFT(a, b, c, d, [self.blocks[i] for i in keep], {n: p for n, p in self.params.items() if n not in deltas})

    def evaluate(self, values: Mapping[str, float] | None = None, normalized: bool = False) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """Certain ``(A, B, C, D)`` at the given values; parameters not given take their nominal value."""
        values = dict(values or {})
        for name, p in self.params.items():
            if name not in values:
                values[name] = p.to_delta(p.nominal) if normalized else p.nominal
        out = self.substitute(values, normalized)
        return out.a, out.b, out.c, out.d

    def sample(self, n: int, rng: np.random.Generator | int | None = None, corners: bool = False) -> list[dict[str, float]]:
        """``n`` random normalised parameter draws (uniform in [-1, 1]; ``corners``: distinct vertices of the box)."""
        rng = np.random.default_rng(rng)
        names = sorted(self.params)
        if not corners:
            return [dict(zip(names, row)) for row in rng.uniform(-1, 1, (n, len(names)))]
        # distinct vertices of the box (all of them if n >= 2^k)
        k = len(names)
        if k < 30:
            picks = rng.choice(2**k, size=min(n, 2**k), replace=False)
            return [{nm: (1.0 if (v >> i) & 1 else -1.0) for i, nm in enumerate(names)} for v in picks]
        rows: dict[tuple, None] = {}  # 2^k too large to enumerate: random sign vectors, duplicates dropped
        while len(rows) < n:
            rows.setdefault(tuple(rng.choice([-1.0, 1.0], k)), None)
        return [dict(zip(names, row)) for row in rows]

    def freqresp(self, omega: ArrayLike, values: Mapping[str, float] | None = None, normalized: bool = False) -> NDArray:
        """Frequency response ``(n_out, n_in, n_w)`` at the given parameter values (nominal otherwise)."""
        return frequency_response(*self.evaluate(values, normalized), omega)
