"""Spacecraft bodies as multi-port models: rigid hub, rigid appendage, proof-mass actuator,
flexible solar panel on a revolute joint driven by a SADM.

Paper: section "Proof Mass Actuators (PMAs) Model" and "System Modeling / Full order
LPV model" (central body, solar panels, antenna), appendix tables "Spacecraft mechanical
data" and "Definition of connection points". Conventions of :mod:`trusscodesign.model.ports`: a clamped
6-dof port takes the acceleration imposed by the parent and returns the wrench applied
by the body on it; a free port takes the wrench applied on the body and returns the
acceleration.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg

from . import frames
from .lft import LFT, Parameter
from .modal import cantilever_from_modes
from .interconnect import connect
from .ports import MultiPortModel, node_port, scalar_port
from .statespace import close_static

__all__ = [
    "rigid_mass_matrix",
    "rigid_hub",
    "rigid_appendage",
    "pma",
    "pma_block",
    "solar_panel",
]


def _mass_inertia(mass: float, inertia: ArrayLike) -> NDArray[np.float64]:
    if isinstance(mass, bool) or not isinstance(mass, (int, float, np.integer, np.floating)):
        raise TypeError(f"mass must be a real number [kg], got {type(mass).__name__}")
    if not (np.isfinite(mass) and mass > 0):
        raise ValueError(f"mass must be a finite positive number [kg], got {mass!r}")
    j = np.asarray(inertia, dtype=float)
    if j.shape != (3, 3) or not np.all(np.isfinite(j)):
        raise ValueError(f"inertia must be a finite 3x3 matrix [kg m^2], got shape {j.shape}")
    if not np.allclose(j, j.T, atol=1e-12 * max(1.0, np.abs(j).max())):
        raise ValueError("inertia must be symmetric")
    if np.linalg.eigvalsh(j).min() < 0:
        raise ValueError(f"inertia must be positive semi-definite, eigenvalues {np.linalg.eigvalsh(j)}")
    return j


def _nonnegative(value: float, name: str, unit: str, strict: bool) -> float:
    """Check a finite positive (``strict``) or non-negative scalar."""
    if not (np.isfinite(value) and (value > 0 if strict else value >= 0)):
        raise ValueError(f"{name} must be a finite {'positive' if strict else 'non-negative'} number [{unit}], got {value!r}")
    return float(value)


def _unit(vector: ArrayLike, name: str) -> NDArray[np.float64]:
    """Check a unit 3-vector."""
    v = frames.as_vector3(vector, name)
    if not np.isclose(np.linalg.norm(v), 1.0):
        raise ValueError(f"{name} must be a unit vector, got {vector!r}")
    return v


def rigid_mass_matrix(mass: float, inertia_g: ArrayLike, r_pg: ArrayLike = (0.0, 0.0, 0.0)) -> NDArray[np.float64]:
    """Rigid mass matrix at P (6x6) of a body of ``mass`` [kg] and inertia ``inertia_g`` [kg m^2] at its CoG G.

    ``r_pg`` is the vector from P to G [m]: ``D_P = tau_GP^T diag(m I, J_G) tau_GP``.
    """
    j = _mass_inertia(mass, inertia_g)
    t_gp = frames.tau(-frames.as_vector3(r_pg, "r_pg"))
    return t_gp.T @ linalg.block_diag(mass * np.eye(3), j) @ t_gp


def rigid_hub(mass, inertia: ArrayLike, ports: Mapping[str, ArrayLike], reference: str = "P1", iyy=None) -> MultiPortModel:
    """Static multi-port model of a free-floating rigid body (direct dynamics).

    Parameters
    ----------
    mass : float or trusscodesign.model.lft.Parameter
        Mass [kg]; a Parameter makes it uncertain (3 occurrences: ``1/m`` on the
        three translations).
    inertia : array_like (3, 3)
        Inertia at the CoG, which is the ``reference`` port [kg m^2].
    ports : mapping name -> position (3,)
        Connection points [m] in the body frame (the reference at the CoG).
    iyy : trusscodesign.model.lft.Parameter, optional
        Makes ``inertia[1, 1]`` uncertain (1 occurrence); the y axis must then be a
        principal axis (``inertia[0, 1] = inertia[1, 2] = 0``).

    Returns
    -------
    MultiPortModel
        All ports free: inputs the wrenches applied on the hub at each port, outputs
        their accelerations, ``a = T D^-1 T^T W`` with ``a_Pi = tau(r_Pi P1) a_P1``
        (6N x 6N, no state; 42x42 for the paper's seven points).
    """

    if isinstance(mass, Parameter) and not mass.low > 0:
        raise ValueError(f"mass parameter {mass.name!r} must have a positive range [kg] (1/m over it), got [{mass.low}, {mass.high}]")
    m_nom = mass.center if isinstance(mass, Parameter) else mass
    j = _mass_inertia(m_nom, inertia).copy()
    eig = np.linalg.eigvalsh(j)
    if not eig.min() > 1e-12 * eig.max():  # a free body: D^-1 needs J invertible (a zero or singular J was a LinAlgError)
        raise ValueError(f"inertia of the hub must be symmetric positive-definite [kg m^2], got eigenvalues {eig}")
    if reference not in ports:
        raise ValueError(f"reference port {reference!r} must be one of the ports {list(ports)}")
    r_ref = frames.as_vector3(ports[reference], "reference position")
    t = np.vstack([frames.tau(r_ref - frames.as_vector3(r, f"position of {n}")) for n, r in ports.items()])
    plist = [node_port(n, r, "free") for n, r in ports.items()]
    if not isinstance(mass, Parameter) and iyy is None:
        dd = t @ np.linalg.solve(rigid_mass_matrix(m_nom, j), t.T)
        return MultiPortModel(np.zeros((0, 0)), np.zeros((0, dd.shape[0])), np.zeros((dd.shape[0], 0)), dd, plist, "hub")
    t_t, t_r = t[:, :3], t[:, 3:]
    inv_m = LFT.param(mass).inv() if isinstance(mass, Parameter) else LFT.constant([[1.0 / m_nom]])
    if iyy is None:
        rot = LFT.constant(t_r @ np.linalg.solve(j, t_r.T))
    else:
        if abs(j[0, 1]) > 0 or abs(j[1, 2]) > 0:
            raise ValueError("an uncertain Iyy needs y to be a principal axis of the inertia (Ixy = Iyz = 0)")
        xz = [0, 2]
        inv_xz = np.zeros((3, 3))
        inv_xz[np.ix_(xz, xz)] = np.linalg.inv(j[np.ix_(xz, xz)])
        rot = LFT.constant(t_r @ inv_xz @ t_r.T) + np.outer(t_r[:, 1], t_r[:, 1]) * LFT.param(iyy).inv()
    hub = (t_t @ t_t.T) * inv_m + rot
    return MultiPortModel.from_lft(hub, plist, "hub")


def rigid_appendage(mass: float, inertia_g: ArrayLike, node: str, position: ArrayLike, r_pg: ArrayLike = (0.0, 0.0, 0.0),
                    name: str = "rigid") -> MultiPortModel:
    """Rigid body clamped on its parent at ``node``: ``W = -D_P a_P`` (6x6, static)."""
    d = rigid_mass_matrix(mass, inertia_g, r_pg)
    return MultiPortModel(np.zeros((0, 0)), np.zeros((0, 6)), np.zeros((6, 0)), -d, [node_port(node, position, "clamped")], name)


def pma(node: str, position: ArrayLike, rotation: ArrayLike, casing_mass: float, casing_inertia: ArrayLike, r_og: ArrayLike,
        proof_mass: float, stiffness: float, damping: float, axis: ArrayLike = (0.0, 1.0, 0.0), r_op: ArrayLike = (0.0, 0.0, 0.0),
        label: str = "pma") -> MultiPortModel:
    """Proof-mass actuator ``D_P^B(s)`` (7x7, 2 states), expressed in the parent frame.

    Paper equations (PMA section), in the PMA frame R_a with origin O: the proof mass m
    at the casing CoG G slides along the unit axis v, ``m (v^T a_G + x'') = -k x - d x' + u``,
    and the wrench on the parent at P is ``W_P = -tau_GP^T (M_B tau_GP a_P + m [v; 0] x'')``.
    Here ``M_B = diag((M + m) I, I_G)``: the proof mass rides with the casing in the
    directions other than v, so the DC gain ``a_P -> W_P`` is minus the *total* rigid
    mass (the paper's table calls M the casing mass).

    Parameters
    ----------
    node, position : str, array_like (3,)
        Connection node and its position in the parent frame [m].
    rotation : array_like (3, 3)
        DCM from the PMA frame to the parent frame.
    casing_mass, casing_inertia : float, array_like (3, 3)
        Casing mass [kg] and inertia at G in the PMA frame [kg m^2].
    r_og, r_op : array_like (3,)
        G and the connection point P in the PMA frame [m].
    proof_mass, stiffness, damping : float
        m [kg], k [N/m], d [N s/m] of the spring-mass-damper along ``axis``.

    Returns
    -------
    MultiPortModel
        Ports: the node (clamped: acceleration in, wrench out) and a scalar port
        ``label`` (force ``u_<label>`` [N] in, stroke ``x_<label>`` [m] out).
    """
    _nonnegative(proof_mass, "proof_mass", "kg", strict=True)
    _nonnegative(stiffness, "stiffness", "N/m", strict=True)
    _nonnegative(damping, "damping", "N s/m", strict=False)
    v = _unit(axis, "axis")
    m_b = linalg.block_diag((casing_mass + proof_mass) * np.eye(3), _mass_inertia(casing_mass, casing_inertia))
    t = frames.tau(frames.as_vector3(r_op, "r_op") - frames.as_vector3(r_og, "r_og"))  # tau_GP: a_G = tau_GP a_P
    w = np.r_[v, 0.0, 0.0, 0.0]
    m, k, d = proof_mass, stiffness, damping
    a = np.array([[0.0, 1.0], [-k / m, -d / m]])
    b = np.vstack([np.zeros(7), np.r_[-(w @ t), 1.0 / m]])
    c = np.vstack([np.column_stack([k * t.T @ w, d * t.T @ w]), [1.0, 0.0]])
    dmat = np.zeros((7, 7))
    dmat[:6, :6] = -t.T @ (m_b - m * np.outer(w, w)) @ t
    dmat[:6, 6] = -t.T @ w
    ports = [node_port(node, frames.as_vector3(r_op, "r_op"), "clamped"), scalar_port(label, f"u_{label}", f"x_{label}")]
    local = MultiPortModel(a, b, c, dmat, ports, label)
    # The node sits at the connection point P: move the frame's origin there, then rotate and place.
    return local.translate(-frames.as_vector3(r_op, "r_op")).reproject(rotation).translate(position)


def pma_block(pmas: list[MultiPortModel]) -> MultiPortModel:
    """Several PMAs as one block (PMAs on the same node share its acceleration; wrenches add)."""
    return connect(pmas, name="PMAs")


def solar_panel(node: str, position: ArrayLike, rotation: ArrayLike, mass: float, r_og: ArrayLike, inertia_g: ArrayLike,
                omega: ArrayLike, damping: float | ArrayLike, factors: ArrayLike, joint_axis: ArrayLike, stiffness: float,
                friction: float, label: str = "SP", omega1=None, tau=None) -> MultiPortModel:
    """Flexible solar panel on a revolute joint driven by a SADM, expressed in the parent frame.

    Steps (``docs/titop.md`` section f): the single-port flexible model of the panel
    (clamped at its root O, 3 modes) is augmented with the relative joint acceleration
    ``theta''`` about the joint axis e (panel frame) and the torque ``e^T W`` transmitted
    about it; that scalar channel is inverted (torque in, ``theta''`` out), and the joint
    is closed by the SADM law: the torque applied by the hub on the panel about e is
    ``T = -(k theta + f theta') + p``, with ``theta``, ``theta'`` from two integrators.
    k > 0 makes the joint a spring (k = 0 would leave a free rotation, two poles at 0).

    Parameters
    ----------
    node, position : str, array_like (3,)
        Joint node and its position in the parent frame [m].
    rotation : array_like (3, 3)
        DCM from the panel frame to the parent frame at the current panel angle.
    mass, r_og, inertia_g : float, array_like (3,), array_like (3, 3)
        Panel mass [kg], CoG in the panel frame [m] and inertia at the CoG [kg m^2].
    omega, damping, factors : array_like
        Flexible modes of the panel clamped at O: frequencies [rad/s], damping ratios,
        participation factors at O (n x 6).
    joint_axis : array_like (3,)
        Unit joint axis in the panel frame.
    stiffness, friction : float
        SADM stiffness k [N m/rad] (> 0) and viscous friction f [N m s/rad] (>= 0).
    omega1 : trusscodesign.model.lft.Parameter, optional
        Uncertain first panel frequency (2 occurrences, see :func:`trusscodesign.model.modal.cantilever_from_modes`).
    tau : trusscodesign.model.lft.Parameter, optional
        Uncertain panel angle through ``tau = tan(theta / 4)``: ``rotation`` is then the
        base DCM at theta = 0 and the model is ``R6(tau) M R6(tau)^T`` (16 occurrences:
        8 for the twice DCM on each side).

    Returns
    -------
    MultiPortModel
        Ports: the node (clamped), and a scalar port ``label`` with input ``p_<label>``
        (SADM disturbance torque [N m]) and output ``theta_<label>`` (joint angle
        deflection [rad]), then the delta ports of omega1 and tau if any. 2 n + 2 states.
    """
    _nonnegative(stiffness, "stiffness (k = 0 leaves a free joint)", "N m/rad", strict=True)
    _nonnegative(friction, "friction", "N m s/rad", strict=False)
    e3 = _unit(joint_axis, "joint_axis")
    d_o = rigid_mass_matrix(mass, inertia_g, r_og)
    flex = cantilever_from_modes(d_o, omega, factors, damping, node=node, name=label, omega1=omega1)
    # 1. Augment with the joint: theta'' adds e theta'' to the root acceleration; e^T W is the
    #    torque of the panel on the hub about the axis. 2. Invert that scalar channel.
    aug = flex.with_axis_channel(node, np.r_[0.0, 0.0, 0.0, e3], "joint", "thetadd", "Tj")
    inv = aug.invert(aug.channels("joint"))
    # 3. Close the SADM loop with two integrators: e^T W = -T = k theta + f theta' - p.
    n_ch, j = inv.nchannels, inv.offset("joint")
    a = linalg.block_diag(inv.a, np.array([[0.0, 1.0], [0.0, 0.0]]))
    b = linalg.block_diag(inv.b, np.array([[0.0], [1.0]]))
    c = linalg.block_diag(inv.c, np.eye(2))
    d = linalg.block_diag(inv.d, np.zeros((2, 1)))
    # stacked inputs: [inv channels, integrator input]; outputs: [inv channels, theta, theta']
    kmat = np.zeros((n_ch + 1, n_ch + 2))
    kmat[j, n_ch] = stiffness
    kmat[j, n_ch + 1] = friction
    kmat[n_ch, j] = 1.0
    # external channels: the node (6), p (replacing the joint input), then the delta ports
    node_ch = inv.channels(node)
    delta_ch = [i for p in inv.delta_ports for i in inv.channels(p.name)]
    ext = node_ch + [j] + delta_ch
    emat = np.zeros((n_ch + 1, len(ext)))
    fmat = np.zeros((len(ext), n_ch + 2))
    for col, ch in enumerate(ext):
        emat[ch, col] = -1.0 if ch == j else 1.0  # joint input gets -p
        fmat[col, n_ch if ch == j else ch] = 1.0  # joint slot outputs theta
    a2, b2, c2, d2 = close_static(a, b, c, d, kmat, emat, fmat, np.zeros((len(ext), len(ext))))
    ports = [node_port(node, np.zeros(3), "clamped"), scalar_port(label, f"p_{label}", f"theta_{label}")] + inv.delta_ports
    model = MultiPortModel(a2, b2, c2, d2, ports, label, inv.params)
    if tau is not None:
        return model.reproject_lft(frames.twice_dcm_lft(tau, rotation)).translate(position)
    return model.reproject(rotation).translate(position)
