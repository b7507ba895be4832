"""Analytical TITOP model of the 6-dof Euler-Bernoulli beam.

Paper: section "TITOP Approach" (the beam of the SDT library, after Chebbi et al.
2016). Mathematics: ``docs/titop.md`` sections b and c.

The beam (body x axis from P to C) is clamped at P and free at C. Its modal data
(frequencies, participation factors at P, modal displacements at C) come from a
Craig-Bampton-type Ritz basis per deformation field, clamped at P:

* axial and torsion: the static tip shape ``xi`` plus ``n_modes`` clamped-clamped
  modes ``sin(k pi xi)``;
* bending in each plane: the two static tip shapes ``xi^2`` (tip moment) and
  ``3 xi^2 - xi^3`` (tip force) plus ``n_modes`` clamped-clamped Euler-Bernoulli modes.

Because the exact static shapes are in the basis, the static tip compliance and
the rigid mass of the model are exact for any ``n_modes`` (plain truncation of
the clamped-free modes is not: the cube's first frequencies come out 5-23 % too high, ``docs/titop.md`` section b), and
clamped-clamped modes obtained by channel inversion are exact up to ``n_modes``.
With ``n_modes = 1`` the model has 10 modes, i.e. order 20, as in the paper.
"""

from __future__ import annotations

from collections.abc import Sequence

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg, optimize

from . import frames
from ..infra.checks import check_option
from .lft import LFT
from .ports import MultiPortModel, delta_port, node_port

__all__ = [
    "DAMPING_MODELS",
    "Section",
    "ModalData",
    "square_torsion_constant",
    "rigid_mass",
    "member_sections",
    "modal_data",
    "clamped_free",
    "clamped_free_lft",
    "beam",
    "analytic_frequencies",
]


def _positive(value: float, name: str, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number [{unit}], got {type(value).__name__}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a finite positive number [{unit}], got {value!r}")
    return float(value)


def square_torsion_constant(h: float) -> float:
    """Saint-Venant torsion constant of a full square section of side ``h`` [m] -> [m^4].

    ``J = (h^4 / 3) (1 - 192/pi^5 sum_{n odd} tanh(n pi / 2) / n^5)`` = 0.140577 h^4.
    """
    h = _positive(h, "h", "m")
    n = np.arange(1, 200, 2)
    return h**4 / 3.0 * (1.0 - 192.0 / np.pi**5 * np.sum(np.tanh(n * np.pi / 2.0) / n**5))


DAMPING_MODELS = ("clamped_modes", "stiffness")  # see Section.damping_model


@dataclass(frozen=True)
class Section:
    """Beam section and material.

    Parameters
    ----------
    area : float
        Section area S [m^2].
    iy, iz : float
        Second moments of area about the beam's y and z axes [m^4]; ``iz``
        governs bending with deflection along y, ``iy`` deflection along z.
    torsion_constant : float
        Torsion constant J [m^4] (the paper's SDT results use J = Iy + Iz).
    young : float
        Young modulus E [Pa].
    poisson : float
        Poisson ratio nu, in (-1, 0.5]; shear modulus G = E / (2 (1 + nu)).
    density : float
        Density rho [kg/m^3].
    damping : float
        Damping ratio xi in [0, 1): of every mode of the beam clamped at its P end with ``damping_model`` =
        ``"clamped_modes"``, of its first such mode with ``"stiffness"``.
    damping_model : {"clamped_modes", "stiffness"}
        ``"clamped_modes"`` (the paper's TITOP beam, as the Satellite Dynamics Toolbox builds it): the ratio ``xi`` on
        each mode of the beam clamped at P. The damping forces then depend on which end is P: an assembled structure's
        damping depends on the beams' orientation and assembly (``docs/titop.md``, section g). ``"stiffness"``:
        stiffness-proportional damping ``C = (2 xi / omega_1) K``, ``omega_1`` the beam's first clamped-free frequency
        (ratio ``xi omega_k / omega_1`` on mode k): it dissipates in proportion to the strain rate's energy, whichever
        end is P, so an assembled structure's poles do not depend on the orientation or order of its beams.
    """

    area: float
    iy: float
    iz: float
    torsion_constant: float
    young: float = 70e9
    poisson: float = 0.35
    density: float = 2700.0
    damping: float = 0.001
    damping_model: str = "clamped_modes"

    def __post_init__(self) -> None:
        for name, unit in (("area", "m^2"), ("iy", "m^4"), ("iz", "m^4"), ("torsion_constant", "m^4"), ("young", "Pa"), ("density", "kg/m^3")):
            _positive(getattr(self, name), name, unit)
        for name in ("poisson", "damping"):
            val = getattr(self, name)
            if isinstance(val, bool) or not isinstance(val, (int, float, np.integer, np.floating)):
                raise TypeError(f"{name} must be a real number, got {type(val).__name__}")
        if not (-1.0 < self.poisson <= 0.5):
            raise ValueError(f"poisson must be in (-1, 0.5], got {self.poisson!r}")
        if not (0.0 <= self.damping < 1.0):
            raise ValueError(f"damping must be in [0, 1), got {self.damping!r}")
        if self.damping_model not in DAMPING_MODELS:
            raise ValueError(f"damping_model must be one of {list(DAMPING_MODELS)}, got {self.damping_model!r}")

    @classmethod
    def square(cls, h: float, young: float = 70e9, poisson: float = 0.35, density: float = 2700.0,
               damping: float = 0.001, torsion: str = "polar", damping_model: str = "clamped_modes") -> "Section":
        """Full square section of side ``h`` [m]: S = h^2, Iy = Iz = h^4/12.

        Parameters
        ----------
        torsion : {"polar", "exact"}
            ``"polar"``: J = Iy + Iz = h^4/6, as the paper's SDT model;
            ``"exact"``: Saint-Venant value 0.1406 h^4.
        """
        h = _positive(h, "h", "m")
        if torsion == "polar":
            j = h**4 / 6.0
        elif torsion == "exact":
            j = square_torsion_constant(h)
        else:
            raise ValueError(f"torsion must be 'polar' or 'exact', got {torsion!r}")
        return cls(h**2, h**4 / 12.0, h**4 / 12.0, j, young, poisson, density, damping, damping_model)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa]."""
        return self.young / (2.0 * (1.0 + self.poisson))

    @property
    def polar(self) -> float:
        """Polar moment of area Ip = Iy + Iz [m^4] (torsional inertia rho Ip per length)."""
        return self.iy + self.iz

    @property
    def symmetric(self) -> bool:
        """Whether Iy = Iz (to 1e-12 relative): the bending stiffness is the same in every transverse direction, so
        the orientation of the beam frame about its axis does not matter."""
        return bool(np.isclose(self.iy, self.iz, rtol=1e-12, atol=0.0))


@dataclass(frozen=True)
class ModalData:
    """Clamped-at-P modal data of a body in its own frame.

    Attributes
    ----------
    omega : ndarray, shape (N,)
        Natural frequencies [rad/s], ascending.
    l_p : ndarray, shape (N, 6)
        Modal participation factors at P (mass-normalised modes).
    phi_c : ndarray, shape (6, N)
        Modal displacement of C (translations [m], rotations [rad]).
    d_p : ndarray, shape (6, 6)
        Rigid mass matrix at P [kg, kg m, kg m^2].
    r_pc : ndarray, shape (3,)
        Vector from P to C [m].
    damping : ndarray, shape (N,)
        Modal damping ratios.
    """

    omega: NDArray[np.float64]
    l_p: NDArray[np.float64]
    phi_c: NDArray[np.float64]
    d_p: NDArray[np.float64]
    r_pc: NDArray[np.float64]
    damping: NDArray[np.float64]


def _check_section(section: object) -> None:
    """A TypeError unless ``section`` is a :class:`Section` (a bare side h [m] is no section)."""
    if not isinstance(section, Section):
        raise TypeError(f"section must be a trusscodesign.model.titop.Section, got {type(section).__name__} {section!r}: for a square section "
                        "of side h [m] use Section.square(h)")


def rigid_mass(length: float, section: Section) -> NDArray[np.float64]:
    """Rigid mass matrix of the beam at P (6x6), body frame, P at the origin, C at (l, 0, 0).

    Mass ``m = rho S l`` at G = (l/2, 0, 0), inertia at G
    ``diag(rho Ip l, m l^2/12, m l^2/12)`` (Euler-Bernoulli: no section rotary
    inertia in bending).
    """
    length = _positive(length, "length", "m")
    _check_section(section)
    m = section.density * section.area * length
    j_g = np.diag([section.density * section.polar * length, m * length**2 / 12.0, m * length**2 / 12.0])
    t_gp = frames.tau([-length / 2.0, 0.0, 0.0])
    return t_gp.T @ linalg.block_diag(m * np.eye(3), j_g) @ t_gp


@lru_cache(maxsize=64)
def _cc_root(k: int) -> float:
    """k-th root (k >= 1) of cos(x) cosh(x) = 1: clamped-clamped beta*l."""
    f = lambda x: math.cos(x) - 1.0 / math.cosh(x)  # noqa: E731
    guess = (k + 0.5) * math.pi
    return optimize.brentq(f, guess - 0.5, guess + 0.5, xtol=1e-14)


def _cc_mode(k: int, xi: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Clamped-clamped EB mode k on xi in [0, 1]: value, d/dxi, d2/dxi2 (overflow-free form)."""
    b = _cc_root(k)
    x = b * xi
    den = (math.sinh(b) - math.sin(b)) * math.exp(-b)  # (sinh b - sin b) e^-b, O(1/2)
    one_minus_sigma_e = (-math.exp(-b) - math.sin(b) + math.cos(b)) / den  # (1 - sigma) e^b
    sigma = (math.cosh(b) - math.cos(b)) / (math.sinh(b) - math.sin(b))
    grow = 0.5 * one_minus_sigma_e * np.exp(x - b)  # (1 - sigma) e^x / 2
    decay = 0.5 * (1.0 + sigma) * np.exp(-x)
    phi = grow + decay - np.cos(x) + sigma * np.sin(x)
    dphi = b * (grow - decay + np.sin(x) + sigma * np.cos(x))
    ddphi = b**2 * (grow + decay + np.cos(x) - sigma * np.sin(x))
    return phi, dphi, ddphi


def _gauss(n: int) -> tuple[NDArray, NDArray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _field_basis(kind: str, n_modes: int, xi: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Basis values, first and second xi-derivatives, shape (n_basis, n_points)."""
    vals, d1, d2 = [], [], []
    if kind == "bar":
        vals.append(xi)
        d1.append(np.ones_like(xi))
        d2.append(np.zeros_like(xi))
        for k in range(1, n_modes + 1):
            vals.append(np.sin(k * np.pi * xi))
            d1.append(k * np.pi * np.cos(k * np.pi * xi))
            d2.append(-((k * np.pi) ** 2) * np.sin(k * np.pi * xi))
    else:
        vals += [xi**2, 3 * xi**2 - xi**3]
        d1 += [2 * xi, 6 * xi - 3 * xi**2]
        d2 += [2 * np.ones_like(xi), 6 - 6 * xi]
        for k in range(1, n_modes + 1):
            p, dp, ddp = _cc_mode(k, xi)
            vals.append(p)
            d1.append(dp)
            d2.append(ddp)
    return np.array(vals), np.array(d1), np.array(d2)


@lru_cache(maxsize=32)
def _field_eigen(kind: str, n_modes: int):
    """Dimensionless Ritz eigenproblem ``K^ q = lambda^ M^ q`` of one field (cached)."""
    xi, w = _gauss(48 + 12 * n_modes)
    val, d1, d2 = _field_basis(kind, n_modes, xi)
    strain = d1 if kind == "bar" else d2
    m = (val * w) @ val.T
    k = (strain * w) @ strain.T
    lam, q = linalg.eigh(k, m)
    v1, dv1, _ = _field_basis(kind, n_modes, np.array([1.0]))
    for arr in (lam, q, val, xi, w, v1, dv1):
        arr.setflags(write=False)
    return lam, q, val, xi, w, v1, dv1


def _field_modes(kind: str, n_modes: int, mass: float, stiffness: float) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """Ritz modes of one field: omega, int(phi), int(xi phi), phi(1), dphi/dxi(1).

    ``mass`` multiplies int(psi_i psi_j) dxi and ``stiffness`` int of the product
    of the derivatives that carry the strain energy (first for bars, second for bending).
    """
    lam_hat, q_hat, val, xi, w, v1, dv1 = _field_eigen(kind, n_modes)
    # Dimensionless eigenproblem solved once; the physical scaling is applied exactly, so that
    # models at different sizes differ by no eigen-solver rounding (the h-LFT relies on it).
    lam = lam_hat * (stiffness / mass)
    q = q_hat / np.sqrt(mass)
    return (
        np.sqrt(lam),
        q.T @ (val @ w),
        q.T @ ((val * xi) @ w),
        q.T @ v1[:, 0],
        q.T @ dv1[:, 0],
    )


def modal_data(length: float, section: Section, n_modes: int = 1) -> ModalData:
    """Clamped-at-P modal data of the beam (body frame: x from P to C).

    Parameters
    ----------
    length : float
        Beam length l [m].
    section : Section
        Section and material.
    n_modes : int
        Clamped-clamped modes per field in the Ritz basis (>= 1). The model has
        ``2 * (6 + 4 * n_modes)`` states: 20 for the default 1.

    Returns
    -------
    ModalData
        Modes sorted by frequency.
    """
    length = _positive(length, "length", "m")
    _check_section(section)
    if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 1:
        raise ValueError(f"n_modes must be an integer >= 1, got {n_modes!r}")
    s = section
    m = s.density * s.area * length
    i_x = s.density * s.polar * length
    omegas, l_rows, phi_cols = [], [], []

    def add(om, l_entries, phi_entries):
        for kk in range(om.size):
            omegas.append(om[kk])
            row = np.zeros(6)
            col = np.zeros(6)
            for slot, vals in l_entries:
                row[slot] = vals[kk]
            for slot, vals in phi_entries:
                col[slot] = vals[kk]
            l_rows.append(row)
            phi_cols.append(col)

    # Axial (Tx) and torsion (Rx): bars.
    om, i1, _, t1, _ = _field_modes("bar", n_modes, m, s.young * s.area / length)
    add(om, [(0, m * i1)], [(0, t1)])
    om, i1, _, t1, _ = _field_modes("bar", n_modes, i_x, s.shear_modulus * s.torsion_constant / length)
    add(om, [(3, i_x * i1)], [(3, t1)])
    # Bending v along y (E Iz): rigid fields Ty = 1, Rz = x.
    om, i1, ix, t1, dt1 = _field_modes("bend", n_modes, m, s.young * s.iz / length**3)
    add(om, [(1, m * i1), (5, m * length * ix)], [(1, t1), (5, dt1 / length)])
    # Bending w along z (E Iy): rigid fields Tz = 1, Ry = -x.
    om, i1, ix, t1, dt1 = _field_modes("bend", n_modes, m, s.young * s.iy / length**3)
    add(om, [(2, m * i1), (4, -m * length * ix)], [(2, t1), (4, -dt1 / length)])

    order = np.argsort(omegas, kind="stable")
    omega = np.asarray(omegas)[order]
    return ModalData(
        omega=omega,
        l_p=np.asarray(l_rows)[order],
        phi_c=np.asarray(phi_cols)[order].T,
        d_p=rigid_mass(length, section),
        r_pc=np.array([length, 0.0, 0.0]),
        damping=s.damping * (omega / omega[0] if s.damping_model == "stiffness" else np.ones(omega.size)),
    )


def titop_matrices(md: ModalData) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """State-space matrices of the clamped-P / free-C TITOP model from modal data.

    Inputs ``[W_C; a_P]``, outputs ``[a_C; W_P]`` (``docs/titop.md`` section b),
    states ``[eta; eta_dot]``. ``W_P`` is the wrench applied by the body on its parent.
    """
    n = md.omega.size
    om2 = np.diag(md.omega**2)
    zom = np.diag(2.0 * md.damping * md.omega)
    phi, lp = md.phi_c, md.l_p
    t_cp = frames.tau(-md.r_pc)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-om2, -zom]])
    b = np.block([[np.zeros((n, 12))], [phi.T, -lp]])
    c = np.block([[-phi @ om2, -phi @ zom], [lp.T @ om2, lp.T @ zom]])
    d = np.block([[phi @ phi.T, t_cp - phi @ lp], [t_cp.T - lp.T @ phi.T, -(md.d_p - lp.T @ lp)]])
    return a, b, c, d


def clamped_free(length: float, section: Section, n_modes: int = 1, p: str = "P", c: str = "C",
                 name: str = "beam") -> MultiPortModel:
    """TITOP beam model in its own frame: P at the origin (clamped), C at (l, 0, 0) (free).

    Channels 0-5 are port C (wrench in, acceleration out), channels 6-11 port P
    (acceleration in, wrench out), as the paper's ``D_PC(s)`` (12x12).
    """
    md = modal_data(length, section, n_modes)
    a, b, cc, d = titop_matrices(md)
    ports = [node_port(c, md.r_pc, "free"), node_port(p, np.zeros(3), "clamped")]
    return MultiPortModel(a, b, cc, d, ports, name)


def member_sections(section: Section | Sequence[Section], n_members: int) -> list[Section]:
    """One section per member: ``section`` repeated, or the sequence given (checked: one per member).

    Raises
    ------
    ValueError
        If a sequence does not have ``n_members`` sections.
    TypeError
        If an entry is not a :class:`Section`.
    """
    out = [section] * n_members if isinstance(section, Section) else list(section)
    if len(out) != n_members:
        raise ValueError(f"give one section for all members or one per member: {len(out)} sections for {n_members} members")
    for s in out:
        _check_section(s)
    return out


def beam(p: tuple[str, ArrayLike], c: tuple[str, ArrayLike], section: Section, n_modes: int = 1,
         y_hint: ArrayLike | None = None, name: str | None = None, h_param=None) -> MultiPortModel:
    """TITOP beam between two nodes, expressed in the common frame.

    Parameters
    ----------
    p, c : (str, array_like)
        Names and positions [m] of the clamped end P and the free end C.
    section : Section
        Section and material.
    n_modes : int
        Ritz enrichment (see :func:`modal_data`).
    y_hint : array_like, optional
        Direction of the beam's y axis (see :func:`trusscodesign.model.frames.beam_frame`); required when ``Iy != Iz`` (the default
        axis jumps between neighbouring beam directions, e.g. along x and 1e-9 off it, which swaps Iy and Iz).
    name : str, optional
        Model name (default ``"P-C"``).
    h_param : trusscodesign.model.lft.Parameter, optional
        Square-section side as an LFT parameter (scaled signals, see :func:`clamped_free_lft`).
    """
    _check_section(section)
    if y_hint is None and not section.symmetric:
        raise ValueError(f"a section with Iy = {section.iy:.4g} != Iz = {section.iz:.4g} [m^4] needs y_hint (the direction "
                         "of the beam's y axis in the common frame)")
    (pn, rp), (cn, rc) = p, c
    rp = frames.as_vector3(rp, f"position of {pn}")
    rc = frames.as_vector3(rc, f"position of {cn}")
    rot = frames.beam_frame(rp, rc, y_hint)
    length = float(np.linalg.norm(rc - rp))
    if h_param is None:
        local = clamped_free(length, section, n_modes, pn, cn, name or f"{pn}-{cn}")
    else:
        local = clamped_free_lft(length, section, h_param, n_modes, pn, cn, name or f"{pn}-{cn}")
    return local.reproject(rot).translate(rp)


def clamped_free_lft(length: float, section: Section, h_param, n_modes: int = 1, p: str = "P", c: str = "C",
                     name: str = "beam") -> MultiPortModel:
    """TITOP beam with a square section whose side h is an LFT parameter, in *scaled signals*.

    For a full square section of side h (S = h^2, Iy = Iz = h^4/12, J and Ip ~ h^4) with
    E, rho fixed, the Ritz modal data at h follow exactly from those at ``h0 =
    h_param.center`` with ``r = h / h0``: bending frequencies scale as r, axial and torsion
    frequencies do not, ``L_P = L_P0 H``, ``Phi_C = H^-1 Phi_C0``, ``D_P = H D_P0 H`` with
    ``H = r diag(1, 1, 1, r, 1, 1)``. Hence ``G(s; h) = diag(H^-1, H) G0(s; Omega(r)) diag(H^-1, H)``.
    The scalar factor r commutes with every rotation and interconnection, so it is taken
    out of the whole truss: this model works on **scaled signals** ``a * r`` (accelerations)
    and ``W / r`` (wrenches); convert at the truss boundary (:meth:`trusscodesign.model.ports.MultiPortModel.scale_ports_lft`).
    Occurrences of h: 2 per bending mode (``w v`` with ``v = w eta + 2 xi eta'``) and 4 for
    the torsion channels (the remaining factor r on Rx): 16 for the order-20 beam.

    Parameters
    ----------
    length : float
        Beam length [m].
    section : Section
        Material (E, nu, rho, xi) and torsion choice (J = Iy + Iz or the exact square value)
        of a square section; its size is ignored (h comes from ``h_param``).
    h_param : trusscodesign.model.lft.Parameter
        The section side h [m].
    """

    _check_section(section)
    # the torsion choice from J / (Iy + Iz), which is independent of h for a square section (both scale as h^4); an
    # absolute tolerance would take every J below 1e-8 m^4 (h < 2.5 cm) for polar
    ratio = section.torsion_constant / (section.iy + section.iz)
    kinds = {"polar": 1.0, "exact": square_torsion_constant(1.0) / (2.0 / 12.0)}
    torsion = next((k for k, r in kinds.items() if np.isclose(ratio, r, rtol=1e-9, atol=0.0)), None)
    if torsion is None or not section.symmetric:
        raise ValueError(f"clamped_free_lft needs a square section with polar (J = Iy + Iz) or exact (Saint-Venant) torsion; "
                         f"got Iy = {section.iy:.4g}, Iz = {section.iz:.4g}, J / (Iy + Iz) = {ratio:.6g} [m^4]")
    if section.damping_model != "clamped_modes":
        # with C = (2 xi / omega_1(h)) K the damping of the axial and torsion modes varies as 1/h, which this LFT in h
        # (only the bending frequencies vary) does not represent
        raise ValueError(f"clamped_free_lft builds the 'clamped_modes' damping model only, got {section.damping_model!r}: "
                         "build the model at a fixed h instead")
    sec0 = Section.square(h_param.center, section.young, section.poisson, section.density, section.damping, torsion)
    md = modal_data(length, sec0, n_modes)
    a, b, cmat, d = titop_matrices(md)
    n = md.omega.size
    bending = np.abs(md.l_p[:, [1, 2, 4, 5]]).max(axis=1) + np.abs(md.phi_c[[1, 2, 4, 5], :]).max(axis=0) > 0
    rho = h_param.half_range / h_param.center
    k_b = np.where(bending)[0]
    nd = 2 * k_b.size
    b = np.hstack([b, np.zeros((2 * n, nd))])
    cmat = np.vstack([cmat, np.zeros((nd, 2 * n))])
    d = np.block([[d, np.zeros((12, nd))], [np.zeros((nd, 12 + nd))]])
    for j, k in enumerate(k_b):
        cen, r, xi = md.omega[k], md.omega[k] * rho, md.damping[k]
        w1, w2 = 12 + 2 * j, 12 + 2 * j + 1
        b[n + k, [w1, w2]] = [-cen * r, -r]
        cmat[w1, k] = 1.0
        cmat[w2, k], cmat[w2, n + k] = cen, 2 * xi
        d[w2, w1] = r
        restoring_out = np.r_[-md.phi_c[:, k], md.l_p[k]]  # a_C -= Phi_k s_k, W_P += L_k^T s_k
        d[:12, w1] = restoring_out * cen * r
        d[:12, w2] = restoring_out * r
    dports = [delta_port(h_param.name) for _ in range(nd)]
    ports = [node_port(c, md.r_pc, "free"), node_port(p, np.zeros(3), "clamped")]
    g0 = MultiPortModel(a, b, cmat, d, ports + dports, name, {h_param.name: h_param})
    ratio = LFT.param(h_param) * (1.0 / h_param.center)
    inv_ratio = ratio.inv()
    one = LFT.constant([[1.0]])
    # diag(E^-1, E) on outputs [a_C; W_P] and inputs [W_C; a_P]: Rx of C scaled by 1/r, Rx of P by r
    scale = [one] * 3 + [inv_ratio] + [one] * 5 + [ratio] + [one] * 2
    scaled = LFT.blkdiag(*scale) @ g0.to_lft() @ LFT.blkdiag(*scale)
    return MultiPortModel.from_lft(scaled, ports, name)


# ----------------------------------------------------------------- closed form
_CF_BENDING = (1.8751040687119611, 4.6940911329741745, 7.8547574382376126, 10.995540734875467)


def analytic_frequencies(length: float, section: Section, motion: str, boundary: str = "clamped-free", n: int = 2) -> NDArray[np.float64]:
    """Closed-form Euler-Bernoulli / bar natural frequencies [rad/s].

    Parameters
    ----------
    motion : {"bending_y", "bending_z", "axial", "torsion"}
        ``bending_y``: deflection along y (stiffness E Iz); ``bending_z``: along z (E Iy).
    boundary : {"clamped-free", "clamped-clamped", "pinned-pinned"}
    n : int
        Number of frequencies.
    """
    length = _positive(length, "length", "m")
    _check_section(section)
    check_option("n", n, 1, integer=True)
    s = section
    k = np.arange(1, n + 1)
    if motion in ("axial", "torsion"):
        c = math.sqrt(s.young / s.density) if motion == "axial" else math.sqrt(s.shear_modulus * s.torsion_constant / (s.density * s.polar))
        factor = {"clamped-free": (2 * k - 1) * np.pi / 2, "clamped-clamped": k * np.pi}.get(boundary)
        if factor is None:
            raise ValueError(f"boundary {boundary!r} not available for {motion}")
        return np.asarray(factor * c / length, dtype=np.float64)
    if motion not in ("bending_y", "bending_z"):
        raise ValueError(f"motion must be bending_y, bending_z, axial or torsion, got {motion!r}")
    inertia = s.iz if motion == "bending_y" else s.iy
    if boundary == "clamped-free":
        roots = np.array([_CF_BENDING[i] if i < 4 else (i + 0.5) * np.pi for i in range(n)])
    elif boundary == "clamped-clamped":
        roots = np.array([_cc_root(i) for i in k])
    elif boundary == "pinned-pinned":
        roots = k * np.pi
    else:
        raise ValueError(f"unknown boundary {boundary!r}")
    return roots**2 * math.sqrt(s.young * inertia / (s.density * s.area * length**4))
