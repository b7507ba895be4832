"""The whole spacecraft: hub, T-truss, two solar panels on SADMs, antenna, four PMAs.

Paper: section "System Modeling / Full order LPV model" and its open-loop figure. The
open-loop model ``G(s)`` (order 1324 with order-20 beams) has

* 12 inputs: ``p_SP1, p_SP2`` (SADM disturbance torques [N m]), ``W_P1`` (6, wrench on the
  hub at its CoG P1: force [N], moment [N m]), ``u_PMA1..4`` (PMA forces [N]);
* 20 outputs: ``LOS`` elevation/azimuth angular accelerations (2, [rad/s^2]: the angular
  acceleration of the antenna node N20 about x and y), ``x_PMA1..4`` (proof-mass strokes [m]),
  ``a_P1`` (6: [m/s^2], [rad/s^2]), and the linear and angular accelerations of N17 and N20
  along and around x and y (8).

Parameters are plain numbers (h, theta and the uncertain hub mass, hub Iyy and first panel
frequency) or, with ``open_loop(..., uncertain=True)`` / ``tunable=True``, LFT parameters (``trusscodesign.model.lft``).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import cast

import control as ct
import numpy as np
from numpy.typing import ArrayLike

from . import bodies, frames
from ..infra import paths
from ..infra.checks import check_panel_angles
from .lft import LFT, Parameter
from .interconnect import connect
from .ports import MultiPortModel
from .reduction import modal_reduction, static_gain
from .titop import DAMPING_MODELS, Section
from .truss import t_truss, t_truss_cubes, truss_members, truss_nodes
from .cubetruss import truss_model as cube_truss_model

__all__ = ["MODEL", "STATED", "study_parameters", "DISTURBANCES", "PMA_LAYOUTS", "load_parameters", "parameters_fingerprint", "inputs_key", "LOOP_CHOICES", "model_inputs", "check_section_side", "OpenLoop", "open_loop", "uncertain_parameters", "tunable_h", "INPUTS", "OUTPUTS", "component_masses", "truss_mass",
           "reduced_uncertain_model", "scenario", "inertia_at_p1", "with_choices", "load_preset", "preset_parameters"]

INPUTS = ["p_SP1", "p_SP2"] + [f"W_P1_{c}" for c in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")] + [f"u_PMA{i}" for i in range(1, 5)]
OUTPUTS = (["LOS_el", "LOS_az"] + [f"x_PMA{i}" for i in range(1, 5)] + [f"a_P1_{c}" for c in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")]
           + [f"a_{n}_{c}" for n in ("N17", "N20") for c in ("Tx", "Ty", "Rx", "Ry")])


# Version of the model built from the parameters (the TITOP beams, their damping, the assembly, the reduction): stored
# with every result and cache key beside the parameters' fingerprint, so that results of another model are never
# reused. Change it with any change of the code that moves the model's poles, residues or DC gains.
MODEL = "TITOP T-truss spacecraft v1"

_LOADED: dict[tuple[str, int, int], dict] = {}  # the parameters as last read, keyed by the file's path, time and size


def load_parameters() -> dict:
    """The spacecraft parameters of ``lib/trusscodesign/data/spacecraft/parameters.json``, checked against their schema
    (:func:`trusscodesign.model.schema.check_parameters`: a missing field or a bad value names the file and the field).

    Read again whenever the file changes (its modification time or size), so that a kernel that ran before an edit
    does not go on with the old values (nor key new results with their fingerprint). Treat the result as read-only.
    """
    from ..infra.results import read_json
    from .schema import check_parameters

    path = paths.PACKAGE_DATA / "spacecraft" / "parameters.json"
    stat = path.stat()
    key = (str(path), stat.st_mtime_ns, stat.st_size)
    if key not in _LOADED:
        params = read_json(path)
        check_parameters(params, str(path))
        _LOADED.clear()
        _LOADED[key] = params
    return _LOADED[key]


def parameters_fingerprint(params: dict | None = None) -> str:
    """SHA-256 of the spacecraft parameters' values (default: :func:`load_parameters`), the key under which results
    computed from them are stored.

    Canonical JSON (sorted keys) of the parameters with the keys that start with ``_`` (provenance and notes, text for
    the reader) left out at every level: any change of a value changes the fingerprint, a change of a note does not.
    """

    def values(node: object) -> object:
        if isinstance(node, dict):
            return {k: values(v) for k, v in node.items() if not str(k).startswith("_")}
        if isinstance(node, list):
            return [values(v) for v in node]
        return node

    text = json.dumps(values(load_parameters() if params is None else params), sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def inputs_key(params: dict | None = None) -> dict[str, str]:
    """What a result computed from the spacecraft model depends on besides its own settings: the parameters'
    fingerprint (:func:`parameters_fingerprint`, default: the package's parameters) and the model's version
    (:data:`MODEL`); stored with the results (:func:`trusscodesign.infra.results.save_results`' ``inputs``)."""
    return {"spacecraft_parameters": parameters_fingerprint(params), "model": MODEL}


LOOP_CHOICES = ("xi_pma", "effort")  # choices that are loop settings (LoopSettings.from_parameters), not model inputs


def model_inputs(params: dict) -> dict:
    """The parameters the open-loop models are built from: all but the loop settings (``closed_loop`` and the choices
    :data:`LOOP_CHOICES`). Two parameter sets with equal model inputs give the same models."""
    return {k: v for k, v in params.items() if k != "closed_loop"} | {
        "choices": {k: v for k, v in params["choices"].items() if k not in LOOP_CHOICES}}


def _finite(value: float, name: str, positive: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    if not np.isfinite(value) or (positive and value <= 0):
        raise ValueError(f"{name} must be a finite{' positive' if positive else ''} number, got {value!r}")
    return float(value)


def check_section_side(h: object, params: dict | None = None, name: str = "h") -> float:
    """``h`` [m] checked and returned as a float: finite, positive and at most a tenth of the cube side (Euler-Bernoulli
    members need a slenderness of 10 or more), so that a side given in cm or mm is refused instead of building a truss of
    metre-thick beams. ``name`` is the parameter named in the error (default ``"h"``)."""
    value = _finite(cast(float, h), f"{name} [m]", positive=True)
    tr = (params or load_parameters())["truss"]
    limit = tr["cube_side"] / 10.0
    if value > limit:
        raise ValueError(f"{name} must be a section side in metres in (0, {limit:g}] (a tenth of the cube side: Euler-Bernoulli "
                         f"members; design range {tr['h_range']} m), got {h!r}: a value in cm or mm?")
    return value


def _panel_angle(theta: float) -> float:
    """``theta`` [rad] checked: finite and in [-pi, pi] (as :func:`scenario`), so that an angle in degrees is refused."""
    theta = _finite(theta, "theta")
    check_panel_angles("theta", theta)
    return theta


def truss_mass(h: float | Mapping[str, float], params: dict | None = None) -> float:
    """T-truss mass ``rho h^2 * (total beam length)`` [kg] (183.11 kg at h = 3 cm), or with section sides by member
    group (:func:`truss_sections`) the sum over the members."""
    p = params or load_parameters()
    if isinstance(h, Mapping):
        return t_truss_cubes(p["truss"]["cube_side"]).mass(truss_sections(h, p))
    h = check_section_side(h, p)
    nodes = truss_nodes(p["truss"]["cube_side"])
    length = sum(np.linalg.norm(nodes[a] - nodes[b]) for a, b in truss_members(p["truss"]["cube_side"]))
    return p["truss"]["density"] * h**2 * length


def truss_section(h: float, params: dict | None = None, name: str = "h") -> Section:
    """The truss members' square section of side ``h`` [m] (checked: :func:`check_section_side`), with the
    parameters' material, torsion constant and damping; ``name`` is the parameter an error names."""
    p = params or load_parameters()
    tr = p["truss"]
    h = check_section_side(h, p, name)
    return Section.square(h, young=tr["young"], poisson=tr["poisson"], density=tr["density"], damping=tr["damping"],
                          torsion=tr["torsion"], damping_model=tr["damping_model"])


def truss_sections(sides: Mapping[str, float], params: dict | None = None) -> dict[str, Section]:
    """Sections by key of :meth:`trusscodesign.model.cubetruss.CubeTruss.sections` (``"longerons"``, ``"C4"``,
    ``"C4/longerons"``, ``"all"``, ...) from their square sides [m], each checked as ``h``."""
    if not sides:
        raise ValueError("sides must give at least one section side [m] by key ('all', a member group or a cube)")
    return {key: truss_section(side, params, f"sides[{key!r}]") for key, side in sides.items()}


def component_masses(h: float | Mapping[str, float], hub_mass: float | None = None, params: dict | None = None) -> dict[str, float]:
    """Mass of each component [kg]: hub, truss, panels, antenna, PMAs (casing + proof mass)."""
    p = params or load_parameters()
    pm = p["pma"]
    if hub_mass is not None:
        _finite(hub_mass, "hub_mass", positive=True)  # as open_loop (the value itself is returned, unconverted)
    return {
        "hub": p["hub"]["mass"] if hub_mass is None else hub_mass,
        "truss": truss_mass(h, p),
        "solar_panels": 2 * p["solar_panel"]["mass"],
        "antenna": p["antenna"]["mass"],
        "pmas": 4 * (pm["casing_mass"] + pm["proof_mass"]),
    }


@dataclass
class OpenLoop:
    """The open-loop spacecraft model and its parts.

    Attributes
    ----------
    G : control.StateSpace
        12-input, 20-output model with named signals (``INPUTS``, ``OUTPUTS``).
    model : MultiPortModel
        The assembled multi-port model (all ports), spacecraft frame (origin P1).
    blocks : dict
        The blocks: hub, truss, panels, antenna, PMA block.
    parameters : dict
        The values used (h, theta, hub mass and Iyy, first panel frequency, SADM k, f); None for those that are LFT
        parameters of ``lft`` (h if tunable; theta, hub mass, Iyy and panel frequency if uncertain). With section sides
        by member group, h is None and each side is ``h_<key>``.
    lft : trusscodesign.model.lft.LFT or None
        For ``open_loop(..., uncertain=True)``: the uncertain model ``F_u(G, Delta)``
        (12 inputs, 20 outputs); ``G`` then holds its certain part, delta channels first.
    """

    G: ct.StateSpace
    model: MultiPortModel
    blocks: dict[str, MultiPortModel] = field(repr=False)
    parameters: dict[str, float | None]
    lft: LFT | None = None

    def uncertain(self) -> LFT:
        """The uncertain model ``F_u(G, Delta)`` (``lft``); a ValueError if the model was built without uncertainty."""
        if self.lft is None:
            raise ValueError("this open loop has no uncertain model: build it with open_loop(..., uncertain=True)")
        return self.lft

    def rigid_mass_at_p1(self) -> np.ndarray:
        """Rigid mass matrix of the whole spacecraft at P1 (6x6): the inverse of the DC gain ``W_P1 -> a_P1``."""
        model = self.model.substitute({k: p.nominal for k, p in self.model.params.items()}) if self.model.params else self.model
        dc = static_gain(model)
        i = model.channels("P1")
        return np.linalg.inv(dc[np.ix_(i, i)])

    def mass(self) -> float:
        """Spacecraft mass [kg] from the DC gain ``W_P1 -> a_P1``, as the paper does.

        The 6x6 DC gain is inverted first: the spacecraft's CoG is not at P1, so the
        translational entries of the gain alone are not 1/m.
        """
        return float(self.rigid_mass_at_p1()[0, 0])


def uncertain_parameters(params: dict | None = None) -> dict[str, Parameter]:
    """The paper's uncertain parameters: hub mass and Iyy (+-20 %), first panel frequency (+-20 %), tau = tan(theta/4)."""

    p = params or load_parameters()
    hub, sp = p["hub"], p["solar_panel"]
    return {
        "M_SC": Parameter.percent("M_SC", hub["mass"], 100 * hub["mass_uncertainty"]),
        "Iyy_SC": Parameter.percent("Iyy_SC", hub["inertia"][1][1], 100 * hub["iyy_uncertainty"]),
        "omega1_SP": Parameter.percent("omega1_SP", sp["omega"][0], 100 * sp["omega1_uncertainty"]),
        "tau": Parameter("tau", 0.0, -1.0, 1.0),
    }


def tunable_h(params: dict | None = None) -> Parameter:
    """The tunable section side h [m] over the design range (nominal: the upper bound, the paper's baseline)."""

    tr = (params or load_parameters())["truss"]
    low, high = tr["h_range"]
    return Parameter("h", tr["h_nominal"], low, high, tunable=True)


def open_loop(h: float | Mapping[str, float] = 0.03, theta: float = 0.0, hub_mass: float | None = None, hub_iyy: float | None = None,
              panel_omega1: float | None = None, n_modes: int = 1, params: dict | None = None, uncertain: bool = False,
              tunable: bool = False) -> OpenLoop:
    """Build the open-loop spacecraft model ``G(s)``.

    Parameters
    ----------
    h : float or mapping str -> float
        Side of the truss beams' square section [m] (the paper's range 0.015-0.03), or sides by member group, cube or
        group of one cube (:func:`truss_sections`; e.g. ``{"longerons": 0.025, "all": 0.02}``): the truss is then
        assembled member by member (:func:`trusscodesign.model.cubetruss.truss_model`, equal to the paper's cube-by-cube
        block diagram to round-off with one side for all).
    theta : float
        Solar panel angle [rad] (both panels), about the spacecraft x axis.
    hub_mass, hub_iyy, panel_omega1 : float, optional
        Hub mass [kg], hub inertia Iyy [kg m^2], first panel frequency [rad/s]
        (default: the nominal values).
    n_modes : int
        Beam basis enrichment (1: order-20 beams, G of order 1324).
    params : dict, optional
        Parameters (default: ``lib/trusscodesign/data/spacecraft/parameters.json``).
    uncertain : bool
        If True, the hub mass and Iyy, the first panel frequency and the panel angle
        (through tau = tan(theta/4)) are the uncertain parameters of
        :func:`uncertain_parameters` (``hub_mass``, ``hub_iyy``, ``panel_omega1`` and
        ``theta`` are then ignored): ``G`` is the certain part of ``F_u(G, Delta)``
        with the delta channels first, and :attr:`OpenLoop.lft` the uncertain model.
    tunable : bool
        If True, the section side h is an LFT parameter too (:func:`tunable_h`, ``h`` is
        then ignored): the beams work on scaled signals converted at the truss ports
        (:func:`trusscodesign.model.titop.clamped_free_lft`). Implies nothing about ``uncertain``.

    Raises
    ------
    ValueError
        For non-positive h, masses, inertias or frequencies, h above a tenth of the cube side (e.g. given in cm), or theta
        outside [-pi, pi] (e.g. given in degrees).
    """
    if params is not None:  # the package's own are checked on load
        from .schema import check_parameters

        check_parameters(params, "params")
    p = params or load_parameters()
    if isinstance(h, Mapping):
        if tunable:
            raise ValueError("tunable scales one section side h: give h as a number, not sides by member group")
        sections = truss_sections(h, p)
    else:
        h = check_section_side(h, p)
    theta = _panel_angle(theta)
    hub = p["hub"]
    m_hub = _finite(hub["mass"] if hub_mass is None else hub_mass, "hub_mass", positive=True)
    inertia = np.array(hub["inertia"], dtype=float)
    inertia[1, 1] = _finite(inertia[1, 1] if hub_iyy is None else hub_iyy, "hub_iyy", positive=True)
    sp = p["solar_panel"]
    omega = np.array(sp["omega"], dtype=float)
    omega[0] = _finite(omega[0] if panel_omega1 is None else panel_omega1, "panel_omega1", positive=True)
    ch = p["choices"]
    tr = p["truss"]
    unc = uncertain_parameters(p) if uncertain else {}

    # Hub: the truss base points carry the truss node names.
    points: dict[str, list[float]] = dict(hub["points"])
    rename = {v: k for k, v in tr["base_points"].items()}
    hub_model = bodies.rigid_hub(unc.get("M_SC", m_hub), inertia, {rename.get(k, k): v for k, v in points.items()}, iyy=unc.get("Iyy_SC"))

    origin = np.asarray(points[tr["base_points"]["N1"]], dtype=float)
    if isinstance(h, Mapping):
        truss_model = cube_truss_model(t_truss_cubes(tr["cube_side"]), sections, ["N1", "N2", "N3", "N4"], ["N17", "N20"],
                                       n_modes, name="T_str").translate(origin)
    else:  # the paper's cube-by-cube block diagram, on which the stored results were computed
        truss_model = t_truss(truss_section(h, p), tr["cube_side"], n_modes, h_param=tunable_h(p) if tunable else None).translate(origin)

    panels = {}
    for label in ("SP1", "SP2"):
        turn = np.deg2rad(ch.get("panel_turn_z_deg", {"SP1": 90.0, "SP2": -90.0})[label])
        rot = frames.rot_z(turn) if uncertain else frames.rot_x(theta) @ frames.rot_z(turn)
        axis = frames.rot_z(turn).T @ np.array([1.0, 0.0, 0.0])  # spacecraft x in the panel frame
        node = sp["points"][label]
        panels[label] = bodies.solar_panel(node, points[node], rot, sp["mass"], sp["r_og"], sp["inertia_g"], omega, sp["damping"],
                                           sp["factors"], axis, ch["sadm_stiffness"], ch["sadm_friction"], label=label,
                                           omega1=unc.get("omega1_SP"), tau=unc.get("tau"))

    ant = p["antenna"]
    n20 = origin + truss_nodes(tr["cube_side"])[ant["node"]]
    antenna = bodies.rigid_appendage(ant["mass"], ant["inertia"], ant["node"], n20, name="ANT")

    pm = p["pma"]
    turns = {"x": frames.rot_z(-np.pi / 2), "y": np.eye(3)}  # the PMA axis v = y of its frame
    truss_ports = sorted(pt.name for pt in truss_model.ports)
    for i, spec in enumerate(ch["pma_layout"]):  # a node the truss does not expose would be left clamped to the ground
        if spec.get("node") not in truss_ports or spec.get("direction") not in turns:
            raise ValueError(f"choices.pma_layout[{i}] = {spec}: the node must be one of the truss ports {truss_ports} and "
                             f"the direction one of {sorted(turns)}")
    if ant["node"] not in truss_ports:
        raise ValueError(f"antenna.node {ant['node']!r} must be one of the truss ports {truss_ports}")
    pma_list = []
    for i, spec in enumerate(ch["pma_layout"], start=1):
        pos = origin + truss_nodes(tr["cube_side"])[spec["node"]]
        pma_list.append(bodies.pma(spec["node"], pos, turns[spec["direction"]], pm["casing_mass"], pm["casing_inertia"], pm["r_og"],
                                   pm["proof_mass"], pm["stiffness"], pm["damping"], pm["axis"], pm["r_op"], label=f"PMA{i}"))
    pma_model = bodies.pma_block(pma_list)

    model = connect([hub_model, truss_model, panels["SP1"], panels["SP2"], antenna, pma_model], name="spacecraft")
    in_names = ["p_SP1", "p_SP2"] + [f"W_P1_{c}" for c in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")] + [f"u_PMA{i}" for i in range(1, 5)]
    out_names = ([f"a_{ant['node']}_Rx", f"a_{ant['node']}_Ry"] + [f"x_PMA{i}" for i in range(1, 5)] + [f"a_P1_{c}" for c in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")]
                 + [f"a_{n}_{c}" for n in ("N17", "N20") for c in ("Tx", "Ty", "Rx", "Ry")])
    lft = model.to_lft(in_names, out_names)
    if ch.get("disturbance", "sadm") == "hub":  # a reading of the paper (notebook 06c): the torques on the hub alone
        lft = _torques_on_hub(lft)
    nd = lft.n_delta
    g = lft.to_ss(INPUTS, OUTPUTS, name="G")
    blocks = {"hub": hub_model, "truss": truss_model, "SP1": panels["SP1"], "SP2": panels["SP2"], "antenna": antenna, "pmas": pma_model}
    values: dict[str, float | None] = dict(h=None if isinstance(h, Mapping) else h, theta=theta, hub_mass=m_hub, hub_iyy=float(inertia[1, 1]), panel_omega1=float(omega[0]),
                                           sadm_stiffness=ch["sadm_stiffness"], sadm_friction=ch["sadm_friction"], n_delta=nd)
    if isinstance(h, Mapping):  # sides by member group: h_<key> for each
        values.update({f"h_{key}": float(side) for key, side in h.items()})
    if tunable:  # the arguments given for these were not used: the model holds them as LFT parameters
        values["h"] = None
    if uncertain:
        values.update(theta=None, hub_mass=None, hub_iyy=None, panel_omega1=None)
    return OpenLoop(g, model, blocks, values, lft if (uncertain or tunable) else None)


def _torques_on_hub(lft: LFT) -> LFT:
    """The model with the SADM torque inputs ``p_SP1``, ``p_SP2`` applied to the hub alone, about x at P1 (the drive axis,
    the column of ``W_P1_Rx``), instead of between the hub and each panel."""
    nd = len(lft.blocks)
    b, d = lft.b.copy(), lft.d.copy()
    hub = nd + INPUTS.index("W_P1_Rx")
    for name in ("p_SP1", "p_SP2"):
        b[:, nd + INPUTS.index(name)], d[:, nd + INPUTS.index(name)] = b[:, hub], d[:, hub]
    return LFT(lft.a, b, lft.c, d, lft.blocks, lft.params)


DISTURBANCES = ("sadm", "hub")  # where the SADM torques act: between the hub and each panel (the model), or on the hub alone
PMA_LAYOUTS = {  # readings of the paper's "two couples acting in the same direction at N17 and N20"
    "couples": [("N17", "x"), ("N17", "y"), ("N20", "x"), ("N20", "y")],
    "all at N17": [("N17", "x"), ("N17", "y"), ("N17", "x"), ("N17", "y")],
    "all at N20": [("N20", "x"), ("N20", "y"), ("N20", "x"), ("N20", "y")],
}


def reduced_uncertain_model(h: float, omega_max: float | None = 500.0, omega_min: float = 0.01, params: dict | None = None) -> LFT:
    """``F_u(G_r(h), Delta)``: the uncertain open loop at section side h, modally reduced.

    The certain part of :func:`open_loop` ``(h, uncertain=True)`` (its 40 Delta channels kept as
    inputs and outputs, grouped by parameter) loses its spurious slow poles (``|s| < omega_min``)
    and, unless ``omega_max`` is None (``G_r_low``), its modes above ``omega_max`` [rad/s] by
    residualisation (paper: section "System Reduction"). Every uncertainty scenario is then a
    static closure of the Delta channels of this one reduced model.
    """
    lft = open_loop(h, uncertain=True, params=params).uncertain().grouped()
    red = modal_reduction(lft.a, lft.b, lft.c, lft.d, omega_min=omega_min, omega_max=omega_max)
    return LFT(*red.reduced, lft.blocks, lft.params)


def scenario(theta: float = 0.0, hub_mass: float | None = None, hub_iyy: float | None = None, panel_omega1: float | None = None,
             params: dict | None = None) -> dict[str, float]:
    """Physical values of the uncertain parameters for :meth:`trusscodesign.model.lft.LFT.substitute` (``tau = tan(theta / 4)``).

    Parameters
    ----------
    theta : float
        Panel angle [rad], in [-pi, pi].
    hub_mass, hub_iyy, panel_omega1 : float, optional
        Hub mass [kg], hub Iyy [kg m^2], first panel frequency [rad/s] (nominal if omitted).
    """
    theta = _panel_angle(theta)  # tau = tan(theta/4) in [-1, 1]
    unc = uncertain_parameters(params)
    out = {"tau": float(np.tan(theta / 4))}
    for name, value in (("M_SC", hub_mass), ("Iyy_SC", hub_iyy), ("omega1_SP", panel_omega1)):
        out[name] = unc[name].nominal if value is None else _finite(value, name)
    return out


def inertia_at_p1(model: LFT) -> np.ndarray:
    """Rigid inertia of the whole spacecraft at P1 [kg m^2] (3x3), from the DC gain ``W_P1 -> a_P1`` at nominal values.

    The 6x6 DC gain is inverted (the CoG is not at P1) and its rotational block returned:
    the ``J_tot`` of the paper's ACS design.
    """
    a, b, c, d = model.evaluate({name: p.nominal for name, p in model.params.items()})
    ii = [INPUTS.index(f"W_P1_{x}") for x in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")]
    oo = [OUTPUTS.index(f"a_P1_{x}") for x in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")]
    dc = d[np.ix_(oo, ii)] - c[oo] @ np.linalg.solve(a, b[:, ii])
    return np.linalg.inv(dc)[3:, 3:]


def with_choices(params: dict | None = None, sadm_stiffness: float | None = None, sadm_friction: float | None = None,
                 truss_damping: float | None = None, antenna_node: str | None = None, panel_turn_z_deg: dict | None = None,
                 truss_damping_model: str | None = None, disturbance: str | None = None, pma_layout: str | None = None,
                 pma_r_og: ArrayLike | None = None) -> dict:
    """A copy of the parameters with some of the paper's unpublished choices changed (for sensitivity studies).

    Parameters
    ----------
    sadm_stiffness, sadm_friction : float, optional
        SADM joint stiffness [N m/rad] and viscous friction [N m s/rad].
    truss_damping : float, optional
        Modal damping ratio of the truss beams (paper: 0.001).
    truss_damping_model : {"clamped_modes", "stiffness"}, optional
        How the beams dissipate (:class:`trusscodesign.model.titop.Section`): the paper's ratio on each beam's clamped-at-P
        modes, or stiffness-proportional damping, which does not depend on the beams' orientation.
    antenna_node : str, optional
        ``"N20"`` (default, the top node) or ``"N17"`` (the PMA node below it); the LOS is measured there.
    panel_turn_z_deg : dict, optional
        ``{"SP1": deg, "SP2": deg}``: turn of each panel frame about z before the panel angle rotation about x
        (default +90 / -90: the panels' long axes along the rotation axis; 0 / 0 is the literal ``R_x(theta)``).
    disturbance : {"sadm", "hub"}, optional
        Where the SADM torques ``p`` act: between the hub and each panel (the default, the drive's internal torque) or on
        the hub alone (:data:`DISTURBANCES`).
    pma_layout : str, optional
        A named layout of :data:`PMA_LAYOUTS` (default: ``choices.pma_layout``, which is ``"couples"``).
    pma_r_og : array_like (3,), optional
        The PMA casing's centre of mass in the PMA frame [m] (default ``pma.r_og``, 5 cm off the node).
    """
    import copy

    p = copy.deepcopy(params or load_parameters())
    ch = p["choices"]
    if sadm_stiffness is not None:
        ch["sadm_stiffness"] = _finite(sadm_stiffness, "sadm_stiffness", positive=True)
    if sadm_friction is not None:
        ch["sadm_friction"] = _finite(sadm_friction, "sadm_friction")
        if ch["sadm_friction"] < 0:
            raise ValueError(f"sadm_friction must be >= 0 [N m s/rad], got {sadm_friction!r}")
    if truss_damping is not None:
        damping = _finite(truss_damping, "truss_damping")
        if not 0 <= damping < 1:
            raise ValueError(f"truss_damping must be in [0, 1), got {truss_damping!r}")
        p["truss"]["damping"] = damping
    if truss_damping_model is not None:
        if truss_damping_model not in DAMPING_MODELS:
            raise ValueError(f"truss_damping_model must be one of {list(DAMPING_MODELS)}, got {truss_damping_model!r}")
        p["truss"]["damping_model"] = truss_damping_model
    if antenna_node is not None:
        if antenna_node not in ("N17", "N20"):
            raise ValueError(f"antenna_node must be 'N17' or 'N20' (the truss ports), got {antenna_node!r}")
        p["antenna"]["node"] = antenna_node
    if disturbance is not None:
        if disturbance not in DISTURBANCES:
            raise ValueError(f"disturbance must be one of {list(DISTURBANCES)}, got {disturbance!r}")
        ch["disturbance"] = disturbance
    if pma_layout is not None:
        if pma_layout not in PMA_LAYOUTS:
            raise ValueError(f"pma_layout must be one of {list(PMA_LAYOUTS)}, got {pma_layout!r}")
        ch["pma_layout"] = [{"node": n, "direction": d} for n, d in PMA_LAYOUTS[pma_layout]]
    if pma_r_og is not None:
        r = np.asarray(pma_r_og, dtype=float)
        if r.shape != (3,) or not np.all(np.isfinite(r)):
            raise ValueError(f"pma_r_og must be a finite 3-vector [m], got {pma_r_og!r}")
        p["pma"]["r_og"] = r.tolist()
    if panel_turn_z_deg is not None:
        if set(panel_turn_z_deg) != {"SP1", "SP2"}:
            raise ValueError(f"panel_turn_z_deg needs the keys 'SP1' and 'SP2', got {sorted(panel_turn_z_deg)}")
        ch["panel_turn_z_deg"] = {k: _finite(v, f"panel_turn_z_deg[{k}]") for k, v in panel_turn_z_deg.items()}
    return p


def load_preset(name: str) -> dict:
    """A named preset of ``lib/trusscodesign/data/spacecraft/presets/<name>.json``: ``{"closed_loop": {...}, "choices": {...}}`` overrides.

    Presets are separate studies (e.g. ``paper_match``), never the default parameters.
    """
    folder = paths.PACKAGE_DATA / "spacecraft" / "presets"
    known = sorted(p.stem for p in folder.glob("*.json"))
    if not isinstance(name, str) or name not in known:  # a name, not a path: "../parameters" must not reach other files
        raise ValueError(f"unknown preset {name!r}: give the name of a file of {folder} without .json; available: {known}")
    return json.loads((folder / f"{name}.json").read_text())


STATED = "stated"  # the name of the paper's stated values (no preset) where a study takes a preset name


def study_parameters(name: str) -> dict:
    """The spacecraft parameters of a study: the package's (the paper's stated values) for :data:`STATED`, else those of
    the preset ``name`` (:func:`preset_parameters`).

    Raises
    ------
    ValueError
        For a name that is neither ``"stated"`` nor a preset (naming the presets).
    """
    if name == STATED:
        return load_parameters()
    try:
        return preset_parameters(name)
    except ValueError as exc:
        if "unknown preset" in str(exc):
            raise ValueError(f"{exc}, or {STATED!r} for the paper's stated values") from None
        raise


def preset_parameters(name: str, params: dict | None = None) -> dict:
    """The spacecraft parameters with the named preset applied (a copy; ``params`` default: the package's).

    A preset's ``closed_loop`` and ``choices`` entries replace those of the parameters (the loop settings follow:
    ``LoopSettings.from_parameters``); its ``model`` entries are keywords of :func:`with_choices` (truss damping and
    its model, antenna node, SADM joint, panel frames). Everything is in the parameters, so every cached or stored
    result keyed on them (:func:`inputs_key`) knows the preset.

    Raises
    ------
    ValueError
        For an unknown preset, or a preset entry the parameters do not have (naming it and the allowed ones).
    """
    import copy

    preset = load_preset(name)
    p = copy.deepcopy(params or load_parameters())
    for section in ("closed_loop", "choices"):
        entries = {k: v for k, v in preset.get(section, {}).items() if not k.startswith("_")}
        unknown = sorted(set(entries) - set(p[section]))
        if unknown:
            raise ValueError(f"preset {name!r}: unknown {section} entries {unknown}; allowed: "
                             f"{sorted(k for k in p[section] if not k.startswith('_'))}")
        p[section].update(entries)
    import inspect

    model = {k: v for k, v in preset.get("model", {}).items() if not k.startswith("_")}
    allowed = [k for k in inspect.signature(with_choices).parameters if k != "params"]
    unknown = sorted(set(model) - set(allowed))
    if unknown:
        raise ValueError(f"preset {name!r}: unknown model entries {unknown}; allowed: {allowed}")
    return with_choices(p, **model)
