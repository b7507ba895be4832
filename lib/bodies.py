"""Spacecraft bodies as multi-port models: rigid hub, rigid appendage, proof-mass actuator,
flexible solar panel on a revolute joint driven by a SADM.

Paper: section "Proof Mass Actuators (PMAs) Model" and "System Modeling / Full order
LPV model" (central body, solar panels, antenna), appendix tables "Spacecraft mechanical
data" and "Definition of connection points". Conventions of :mod:`lib.ports`: a clamped
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
from .modal import cantilever_from_modes
from .ports import MultiPortModel, close_static, connect, node_port, scalar_port

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


def rigid_mass_matrix(mass: float, inertia_g: ArrayLike, r_pg: ArrayLike = (0.0, 0.0, 0.0)) -> NDArray[np.float64]:
    """Rigid mass matrix at P (6x6) of a body of ``mass`` [kg] and inertia ``inertia_g`` [kg m^2] at its CoG G.

    ``r_pg`` is the vector from P to G [m]: ``D_P = tau_GP^T diag(m I, J_G) tau_GP``.
    """
    j = _mass_inertia(mass, inertia_g)
    t_gp = frames.tau(-frames.as_vector3(r_pg, "r_pg"))
    return t_gp.T @ linalg.block_diag(mass * np.eye(3), j) @ t_gp


def rigid_hub(mass: float, inertia: ArrayLike, ports: Mapping[str, ArrayLike], reference: str = "P1") -> MultiPortModel:
    """Static multi-port model of a free-floating rigid body (direct dynamics).

    Parameters
    ----------
    mass : float
        Mass [kg].
    inertia : array_like (3, 3)
        Inertia at the CoG, which is the ``reference`` port [kg m^2].
    ports : mapping name -> position (3,)
        Connection points [m] in the body frame (the reference at the CoG).

    Returns
    -------
    MultiPortModel
        All ports free: inputs the wrenches applied on the hub at each port, outputs
        their accelerations, ``a = T D^-1 T^T W`` with ``a_Pi = tau(r_Pi P1) a_P1``
        (6N x 6N, no state; 42x42 for the paper's seven points).
    """
    d = rigid_mass_matrix(mass, inertia)
    if reference not in ports:
        raise ValueError(f"reference port {reference!r} must be one of the ports {list(ports)}")
    r_ref = frames.as_vector3(ports[reference], "reference position")
    t = np.vstack([frames.tau(r_ref - frames.as_vector3(r, f"position of {n}")) for n, r in ports.items()])
    dd = t @ np.linalg.solve(d, t.T)
    plist = [node_port(n, r, "free") for n, r in ports.items()]
    return MultiPortModel(np.zeros((0, 0)), np.zeros((0, dd.shape[0])), np.zeros((dd.shape[0], 0)), dd, plist, "hub")


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
    for val, nm, unit in ((proof_mass, "proof_mass", "kg"), (stiffness, "stiffness", "N/m")):
        if not (np.isfinite(val) and val > 0):
            raise ValueError(f"{nm} must be a finite positive number [{unit}], got {val!r}")
    if not (np.isfinite(damping) and damping >= 0):
        raise ValueError(f"damping must be a finite non-negative number [N s/m], got {damping!r}")
    v = frames.as_vector3(axis, "axis")
    if not np.isclose(np.linalg.norm(v), 1.0):
        raise ValueError(f"axis must be a unit vector, got {axis!r}")
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
                friction: float, label: str = "SP") -> MultiPortModel:
    """Flexible solar panel on a revolute joint driven by a SADM, expressed in the parent frame.

    Steps (``docs/titop_math.md`` section f): the single-port flexible model of the panel
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

    Returns
    -------
    MultiPortModel
        Ports: the node (clamped), and a scalar port ``label`` with input ``p_<label>``
        (SADM disturbance torque [N m]) and output ``theta_<label>`` (joint angle
        deflection [rad]). 2 n + 2 states.
    """
    if not (np.isfinite(stiffness) and stiffness > 0):
        raise ValueError(f"stiffness must be a finite positive number [N m/rad] (k = 0 leaves a free joint), got {stiffness!r}")
    if not (np.isfinite(friction) and friction >= 0):
        raise ValueError(f"friction must be a finite non-negative number [N m s/rad], got {friction!r}")
    e3 = frames.as_vector3(joint_axis, "joint_axis")
    if not np.isclose(np.linalg.norm(e3), 1.0):
        raise ValueError(f"joint_axis must be a unit vector, got {joint_axis!r}")
    d_o = rigid_mass_matrix(mass, inertia_g, r_og)
    flex = cantilever_from_modes(d_o, omega, factors, damping, node=node, name=label)
    e = np.r_[0.0, 0.0, 0.0, e3]
    # 1. Augment: inputs [a_O (6); theta''], outputs [W_O (6); e^T W_O].
    t_in = np.hstack([np.eye(6), e[:, None]])
    t_out = np.vstack([np.eye(6), e[None, :]])
    aug = MultiPortModel(flex.a, flex.b @ t_in, t_out @ flex.c, t_out @ flex.d @ t_in,
                         [node_port(node, np.zeros(3), "clamped"), scalar_port("joint", "thetadd", "Tj")], label)
    # 2. Invert the joint channel: input e^T W (torque of the panel on the hub), output theta''.
    inv = aug.invert([6])
    # 3. Close the SADM loop with two integrators: e^T W = -T = k theta + f theta' - p.
    n = inv.nstates
    a = linalg.block_diag(inv.a, np.array([[0.0, 1.0], [0.0, 0.0]]))
    b = linalg.block_diag(inv.b, np.array([[0.0], [1.0]]))
    c = linalg.block_diag(inv.c, np.eye(2))
    d = linalg.block_diag(inv.d, np.zeros((2, 1)))
    # stacked inputs: [a (6), eTW (1), theta'' into integrators (1)]; outputs: [W (6), theta'' (1), theta, theta']
    kmat = np.zeros((8, 9))
    kmat[6, 7] = stiffness
    kmat[6, 8] = friction
    kmat[7, 6] = 1.0
    emat = np.zeros((8, 7))
    emat[:6, :6] = np.eye(6)
    emat[6, 6] = -1.0  # p
    fmat = np.zeros((7, 9))
    fmat[:6, :6] = np.eye(6)
    fmat[6, 7] = 1.0  # theta
    a2, b2, c2, d2 = close_static(a, b, c, d, kmat, emat, fmat, np.zeros((7, 7)))
    assert a2.shape[0] == n + 2
    ports = [node_port(node, np.zeros(3), "clamped"), scalar_port(label, f"p_{label}", f"theta_{label}")]
    model = MultiPortModel(a2, b2, c2, d2, ports, label)
    return model.reproject(rotation).translate(position)
