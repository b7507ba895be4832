"""Two-sided sensitivity of the pointing loop to the inputs the paper does not publish or states ambiguously.

A *lever* is one input swept over a plausible physical range around the value used by default (stated by the paper, or
chosen in notebook 04 where the paper is silent), on a log scale where the range spans decades. Each case, one lever at
one value with every other input at its default, gets the open-loop worst case (PMAs passive) and a robust synthesis
(:func:`trusscodesign.study.design.robust_design`), with its critical frequency and panel angle: notebook 06, section 7.

A case may also set several levers at once (a mapping ``{lever name: value}``): the calibration of notebook 06b combines
them. The cases are independent: :func:`study` runs them in this process or on a Dask client, saving each as it
finishes, so an interrupted study loses only the cases under way.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import authority, design
from ..model import spacecraft
from ..control import synthesis
from ..control.closedloop import LoopSettings
from ..infra.results import read_keyed, run_lock, write_json

__all__ = ["STUDY_OPTIONS", "Lever", "levers", "case_inputs", "combined_inputs", "preset_case", "check_cases", "evaluate_case", "study", "open_loop_map"]

# the robust designs of the study: the synthesis's defaults, a failed synthesis restarted twice from its final gain
STUDY_OPTIONS = synthesis.SynthesisOptions(restarts=2)

Case = tuple[str, Any] | Mapping[str, Any]  # one lever at one value, or {lever name: value} for several


@dataclass(frozen=True)
class Lever:
    """One input of the study.

    Attributes
    ----------
    name : str
        Identifier (``"u_max"``, ``"truss_damping"``, ...).
    label : str
        Axis label, with the unit.
    values : tuple
        The values swept (numbers in the unit of ``label``, or names for a choice).
    default : float or str
        The value every other case uses (one of ``values``).
    setting : str
        The :class:`~trusscodesign.control.closedloop.LoopSettings` field it sets, or ``""`` for a model input.
    model : str
        The keyword of :func:`trusscodesign.model.spacecraft.with_choices` it sets, or ``""`` for a loop setting.
    fixed : dict
        Further :func:`~trusscodesign.model.spacecraft.with_choices` changes of every case of the lever (e.g. the damping model).
    mapping : dict
        For a choice whose name is not the value given to the model (the panel frames), the value of each name.
    why : str
        Where the range comes from.
    """

    name: str
    label: str
    values: tuple
    default: float | str
    setting: str = ""
    model: str = ""
    fixed: dict = field(default_factory=dict)
    mapping: dict = field(default_factory=dict)
    why: str = ""

    @property
    def numeric(self) -> bool:
        """Whether the values are numbers (plotted on a log axis) rather than names of choices."""
        return not isinstance(self.default, str)


def levers(params: dict | None = None) -> dict[str, Lever]:
    """The levers of the study, with their default ranges, around the values of ``params`` (default: the package's).

    The SADM joint's stiffness and friction are swept by factors of their chosen values (joint mode 1 Hz, 5 % damping;
    notebook 04), the loop settings around the paper's stated values.
    """
    p = params or spacecraft.load_parameters()
    cl, ch, xi = p["closed_loop"], p["choices"], p["truss"]["damping"]
    k, c = ch["sadm_stiffness"], ch["sadm_friction"]
    damping = (1e-5, 1e-4, 1e-3, 1e-2)
    out = [
        Lever("u_max", r"effort bound $u_{max}$ [N]", (0.1, 0.5, 1.5, 5.0, cl["u_max"], 50.0), cl["u_max"], setting="u_max",
              why="PMA force range: 0.1 N (a small proof-mass actuator) to 50 N (a large one); the paper states 15 N"),
        Lever("truss_damping", r"truss damping ratio $\xi$ (paper's beam model) [-]", tuple(sorted({*damping, xi})), xi,
              model="truss_damping", fixed={"truss_damping_model": "clamped_modes"},
              why="bolted aluminium trusses: 1e-4 to 1e-2 measured on orbit and on ground; 1e-5 a welded limit"),
        Lever("truss_damping_stiffness", r"truss damping ratio $\xi$ (stiffness-proportional) [-]", tuple(sorted({*damping, xi})), xi,
              model="truss_damping", fixed={"truss_damping_model": "stiffness"},
              why="the same ratios, with the damping model that does not depend on the beams' orientation (notebook 04)"),
        Lever("t_delta", r"RPE window $t_\Delta$ [s]", tuple(sorted({1e-3, cl["t_delta"], 1e-2, 3e-2, 0.1, 1.0})), cl["t_delta"],
              setting="t_delta", why="pointing-error windows of 1 ms (a detector frame) to 1 s (an exposure); the paper states 3 ms"),
        Lever("p_max", r"SADM torque bound $p_{max}$ [N m]", tuple(sorted({0.04, 0.12, cl["p_max"], 1.2})), cl["p_max"], setting="p_max",
              why="stepper-motor detent and drive torque harmonics, x0.1 to x3 of the paper's 0.382 N m"),
        Lever("eps_max", r"RPE bound $\epsilon_{max}$ [rad]", tuple(sorted({1e-5, cl["eps_max"], 2e-4})), cl["eps_max"], setting="eps_max",
              why="10 to 200 urad: fine to coarse pointing; the paper states 50 urad"),
        Lever("sadm_stiffness", r"SADM joint stiffness [N m/rad]", tuple(float(k * f) for f in (0.1, 0.25, 1.0, 4.0, 10.0)), float(k),
              model="sadm_stiffness", why="joint mode of the rigid panel 0.32 to 3.2 Hz (chosen: 1 Hz), friction unchanged"),
        Lever("sadm_friction", r"SADM joint friction [N m s/rad]", tuple(float(c * f) for f in (0.1, 0.2, 1.0, 5.0)), float(c),
              model="sadm_friction", why="joint damping ratio 0.5 % to 25 % (chosen: 5 %), stiffness unchanged"),
        Lever("xi_pma", r"PMA filter damping $\xi_{PMA}$ [-]", tuple(sorted({0.1, 0.3, ch["xi_pma"], 1.0, 2.0})), ch["xi_pma"],
              setting="xi_pma", why="not given by the paper: lightly damped to overdamped wash-out; chosen 0.7"),
        Lever("effort", "effort measured as", ("command", "transmitted"), ch["effort"], setting="effort",
              why="the command u, or the force the PMA transmits to the structure (u - k x - d x')"),
        Lever("antenna_node", "antenna (and LOS) node", ("N20", "N17"), "N20", model="antenna_node",
              why="the top node, or the PMA node below it; the paper's figure is ambiguous"),
        Lever("panel_frame", "panel frames", ("turned", "literal"), "turned", model="panel_turn_z_deg",
              mapping={"turned": dict(ch["panel_turn_z_deg"]), "literal": {"SP1": 0.0, "SP2": 0.0}},
              why="panels' long axes along the rotation axis (chosen), or the literal R_x(theta) of the paper's table"),
        # readings of the paper (notebook 06c): conventions and layouts its text allows
        Lever("u_convention", "PMA command u read as", ("force", "proof-mass acceleration"), "force", setting="u_max",
              mapping={"force": cl["u_max"], "proof-mass acceleration": p["pma"]["proof_mass"] * cl["u_max"]},
              why="u_max a force [N], or an acceleration of the proof mass [m/s^2] (the force bound is then m u_max)"),
        Lever("p_max_convention", "p_max bounds", ("both torques", "each torque"), "both torques", setting="p_max",
              mapping={"both torques": cl["p_max"], "each torque": float(np.sqrt(2) * cl["p_max"])},
              why="the 2-norm of the two SADM torques, or each torque (their 2-norm then up to sqrt(2) p_max)"),
        Lever("disturbance", "SADM torques act", tuple(spacecraft.DISTURBANCES), "sadm", model="disturbance",
              why="between the hub and each panel (a drive's internal torque), or on the hub alone"),
        Lever("pma_layout", "PMA layout", tuple(spacecraft.PMA_LAYOUTS), "couples", model="pma_layout",
              why="two couples (x and y at N17 and at N20), or all four PMAs at one node"),
        Lever("pma_r_og", "PMA casing centre of mass", ("offset", "on the node"), "offset", model="pma_r_og",
              mapping={"offset": list(p["pma"]["r_og"]), "on the node": [0.0, 0.0, 0.0]},
              why="r_OG of the paper's PMA table (5 cm off the node), or at the node"),
    ]
    return {lv.name: lv for lv in out}


def case_inputs(lever: Lever, value: Any, params: dict, settings: LoopSettings) -> tuple[dict, LoopSettings]:
    """The parameters and loop settings of one case: ``lever`` at ``value``, every other input as given.

    Raises
    ------
    ValueError
        If ``value`` is not one of the lever's choices (for a choice), or is refused by the model or the settings.
    """
    if not lever.numeric and value not in lever.values:
        raise ValueError(f"{lever.name} must be one of {list(lever.values)}, got {value!r}")
    v = lever.mapping.get(value, value) if lever.mapping else value
    if lever.setting:
        return params, settings.replace(**{lever.setting: v})
    changes = {**lever.fixed, lever.model: v}
    return spacecraft.with_choices(params, **changes), settings


def combined_inputs(changes: Mapping[str, Any], params: dict, settings: LoopSettings,
                    table: Mapping[str, Lever] | None = None) -> tuple[dict, LoopSettings]:
    """The parameters and loop settings with several levers changed at once (:func:`case_inputs` for each, in turn).

    Parameters
    ----------
    changes : mapping of str to value
        ``{lever name: value}``, at least one.
    params, settings
        The inputs of every other lever.
    table : mapping, optional
        The levers (default :func:`levers` of ``params``).

    Raises
    ------
    ValueError
        For an unknown lever, an empty case, two levers that set the same input (``truss_damping`` and
        ``truss_damping_stiffness``), or a value refused (naming the lever, the value and its unit).
    """
    table = table if table is not None else levers(params)
    if not changes:
        raise ValueError("a case must change at least one lever, got an empty mapping")
    unknown = sorted(set(changes) - set(table))
    if unknown:
        raise ValueError(f"unknown levers {unknown}; allowed: {sorted(table)}")
    targets: dict[str, str] = {}
    for name in changes:
        target = table[name].setting or table[name].model
        if target in targets:
            raise ValueError(f"levers {targets[target]} and {name} both set {target}: give one of them")
        targets[target] = name
    p, s = params, settings
    for name, value in changes.items():
        try:
            p, s = case_inputs(table[name], value, p, s)
        except (TypeError, ValueError) as err:
            raise ValueError(f"lever {name} at {value!r} ({table[name].label}): {err}") from None
    return p, s


def preset_case(name: str, params: dict | None = None) -> dict[str, Any]:
    """The case ``{lever name: value}`` that sets what the preset ``name`` changes from ``params`` (default: the
    package's stated values): each entry of its ``model``, ``closed_loop`` and ``choices`` that differs from the
    lever's default, by the lever that sets that input and whose ``fixed`` inputs the preset names (the damping model
    picks ``truss_damping`` or ``truss_damping_stiffness``). :func:`combined_inputs` of the case gives the preset's inputs.

    Raises
    ------
    ValueError
        If an entry of the preset is set by no lever (no case reproduces the preset).
    """
    raw = spacecraft.load_preset(name)
    model = {k: v for k, v in raw.get("model", {}).items() if not k.startswith("_")}
    entries = {**model, **{k: v for section in ("closed_loop", "choices") for k, v in raw.get(section, {}).items()
                           if not k.startswith("_")}}
    case: dict[str, Any] = {}
    used: set[str] = set()
    table = levers(params)
    plain = {lv.setting or lv.model for lv in table.values() if not lv.mapping}
    for lever in table.values():
        target = lever.setting or lever.model
        if lever.mapping and target in plain:  # a named reading of an input another lever sets by value (u_convention)
            continue
        if target in entries and all(model.get(k) == v for k, v in lever.fixed.items()):
            used |= {target, *lever.fixed}
            if entries[target] != lever.default or lever.fixed:
                case[lever.name] = entries[target]
    if set(entries) - used:
        raise ValueError(f"preset {name!r}: no lever sets its entries {sorted(set(entries) - used)}")
    return case


def _changes(case: Case) -> dict[str, Any]:
    """A case as ``{lever name: value}``."""
    if isinstance(case, Mapping):
        return dict(case)
    name, value = case
    return {name: value}


def check_cases(cases: Sequence[Case], params: dict | None = None,
                settings: LoopSettings | None = None) -> list[tuple[dict, LoopSettings]]:
    """The inputs of each case, ``(lever name, value)`` or ``{lever name: value, ...}`` (:func:`combined_inputs`),
    every case checked first.

    Raises
    ------
    ValueError
        Naming the lever and the value, for an unknown lever or a value the lever, the model or the settings refuse.
    """
    params = params or spacecraft.load_parameters()
    settings = settings or LoopSettings.from_parameters(params)
    table = levers(params)
    unknown = sorted({name for case in cases for name in _changes(case)} - set(table))
    if unknown:
        raise ValueError(f"unknown levers {unknown}; allowed: {sorted(table)}")
    return [combined_inputs(_changes(case), params, settings, table) for case in cases]


class _Sized:
    """An iterator with a length, so that a progress bar (tqdm) knows its total."""

    def __init__(self, it: Iterable, n: int):
        self._it, self._n = iter(it), n

    def __iter__(self):
        return self._it

    def __len__(self) -> int:
        return self._n


def evaluate_case(h: float, changes: Mapping[str, Any], params: dict, settings: LoopSettings, robust: bool = True,
                  options: synthesis.SynthesisOptions = STUDY_OPTIONS, models: design.DesignModels | None = None,
                  workers: int | None = None) -> dict[str, Any]:
    """Open-loop worst case and robust design at section side ``h`` [m] of one case.

    Parameters
    ----------
    h : float
        Truss section side [m].
    changes : mapping of str to value
        The case: ``{lever name: value}`` (:func:`combined_inputs`).
    params, settings
        The inputs of every other lever.
    robust : bool
        Also run the robust synthesis (default); False: the open loop only.
    options : SynthesisOptions
        Of the robust design (:func:`trusscodesign.study.design.robust_design`; default :data:`STUDY_OPTIONS`: two
        restarts of a failed synthesis).
    models : DesignModels, optional
        The models at ``h`` for ``params``, reused when the case changes loop settings only (built here otherwise).
    workers : int, optional
        Threads of the synthesis (:func:`trusscodesign.control.synthesis.synthesize`; default: up to 2); 1 on a Dask worker,
        whose process is one of several sharing the cores.

    Returns
    -------
    dict
        The open loop's ``open_loop_J_c``, ``open_loop_omega`` [rad/s] and ``open_loop_theta_deg``, the PMAs' authority share
        there (``open_loop_share``, :func:`trusscodesign.study.authority.authority_share` at the passive worst case), and with ``robust``
        the design's record (:func:`trusscodesign.study.design.design_record`: ``J_c``, ``Z_c``, the critical frequencies and
        panel angles, ``gain``, ...); ``time_s``.
    """
    t0 = time.perf_counter()
    table = levers(params)
    p, s = combined_inputs(changes, params, settings, table)
    settings_only = all(table[name].setting for name in changes)
    m = models if models is not None and settings_only else design.models_at(h, params=p)
    ol = design.open_loop_worst_case(m, s)
    plant = synthesis.plant_at(m.g_r, ol.scenario["rpe"], m.inertia, s)
    row: dict[str, Any] = {"open_loop_J_c": ol.value["rpe"], "open_loop_omega": ol.omega["rpe"],
                           "open_loop_theta_deg": float(np.rad2deg(ol.scenario["rpe"].theta)),
                           "open_loop_share": float(authority.authority_share(plant, [ol.omega["rpe"]])[0])}
    if robust:
        row.update(design.design_record(design.robust_design(m, s, options, workers=workers)))
    row["time_s"] = time.perf_counter() - t0
    return row


def study(h: float, cases: Sequence[Case], params: dict | None = None, settings: LoopSettings | None = None,
          robust: bool = True, options: synthesis.SynthesisOptions = STUDY_OPTIONS, client=None,
          partial: str | Path | None = None,
          progress: Callable[[Iterable], Iterable] = iter) -> list[dict[str, Any]]:
    """:func:`evaluate_case` for each case of ``cases``, in the order given.

    Parameters
    ----------
    h : float
        Truss section side [m].
    cases : sequence of (str, value) or of mappings
        The cases: ``(lever name, value)`` (e.g. every value of every lever of :func:`levers`) or
        ``{lever name: value, ...}`` for several levers at once.
    params, settings
        Defaults: the package's parameters and their loop settings.
    robust, options
        As :func:`evaluate_case`.
    client : dask.distributed.Client, optional
        Runs the cases in parallel (e.g. :func:`trusscodesign.study.cluster.local_client`); default: this process.
    partial : path, optional
        JSON file where each finished case is saved at once; a study with the same h, parameters, settings, options,
        model version and synthesis algorithm takes the cases it holds from it. Removed once every case is done.
    progress : callable
        Wraps the iterable of finished evaluations: one per distinct spacecraft and loop among the cases (the default
        value of every lever is one evaluation).

    Raises
    ------
    ValueError
        For an unknown lever or a value the lever refuses, before any case runs.
    """
    from ..control.synthesis import ALGORITHM

    params = params or spacecraft.load_parameters()
    settings = settings or LoopSettings.from_parameters(params)
    h = spacecraft.check_section_side(h, params)
    table = levers(params)
    # every case's inputs checked before the first synthesis; cases with the same inputs (the default value of each
    # lever is the same spacecraft and loop) are evaluated once
    tags = [_tag(*inputs) for inputs in check_cases(cases, params, settings)]
    first: dict[str, dict[str, Any]] = {}
    for t, c in zip(tags, cases):
        first.setdefault(t, _changes(c))
    key = dict(h=h, inputs=spacecraft.inputs_key(params), settings=settings.__dict__, robust=robust, options=options.key(),
               algorithm=ALGORITHM)
    with run_lock(partial) if partial is not None else nullcontext():
        stored, key = read_keyed(partial, key)
        done: dict[str, dict] = stored["cases"] if stored else {}
        todo = [(t, c) for t, c in first.items() if t not in done]
        base = design.models_at(h, params=params) if todo else None

        def finished():
            yield from ((t, done[t]) for t in first if t in done)
            if client is None:
                for t, changes in todo:
                    yield t, evaluate_case(h, changes, params, settings, robust, options, base)
                return
            from .cluster import as_finished

            m = client.scatter(base, broadcast=True)
            futures = {client.submit(evaluate_case, h, changes, params, settings, robust, options, m, 1,
                                     pure=False, retries=1): t for t, changes in todo}
            for fut in as_finished(client, futures):
                yield futures[fut], fut.result()

        for tag, row in progress(_Sized(finished(), len(first))):
            if tag not in done and partial is not None:
                done[tag] = row
                write_json(partial, {"key": key, "cases": done})
            done[tag] = row
        if partial is not None and Path(partial).exists():
            Path(partial).unlink()
    return [{**done[t], **_labels(_changes(c), table)} for t, c in zip(tags, cases)]


def _labels(changes: dict[str, Any], table: Mapping[str, Lever]) -> dict[str, Any]:
    """How a case is reported: ``lever`` and ``value`` (for several levers, their names joined by ``+`` and the mapping),
    and ``default``, whether every lever is at its default."""
    default = all(v == table[n].default for n, v in changes.items())
    if len(changes) == 1:
        (name, value), = changes.items()
        return {"lever": name, "value": value, "default": default}
    return {"lever": "+".join(changes), "value": changes, "default": default}


def _tag(params: dict, settings: LoopSettings) -> str:
    """What identifies a case's inputs: the parameters' fingerprint and the loop settings."""
    return f"{spacecraft.parameters_fingerprint(params)[:16]}|{sorted(settings.__dict__.items())!r}"


def open_loop_map(h: float, lever_a: str, values_a: Sequence[Any], lever_b: str, values_b: Sequence[Any],
                  params: dict | None = None, settings: LoopSettings | None = None) -> dict[str, np.ndarray]:
    """Open-loop worst-case J_c over two levers at once (a model input and a loop setting, or two loop settings).

    Returns
    -------
    dict
        ``J_c`` and ``omega`` [rad/s], arrays of shape ``(len(values_a), len(values_b))``.
    """
    params = params or spacecraft.load_parameters()
    settings = settings or LoopSettings.from_parameters(params)
    table = levers(params)
    a, b = table[lever_a], table[lever_b]
    if b.model:
        raise ValueError(f"lever_b must be a loop setting (the model is built once per value of lever_a), got {lever_b!r}")
    j = np.empty((len(values_a), len(values_b)))
    w = np.empty_like(j)
    for i, va in enumerate(values_a):
        pa, sa = case_inputs(a, va, params, settings)
        m = design.models_at(h, params=pa)
        for k, vb in enumerate(values_b):
            _, sb = case_inputs(b, vb, pa, sa)
            wc = design.open_loop_worst_case(m, sb)
            j[i, k], w[i, k] = wc.value["rpe"], wc.omega["rpe"]
    return {"J_c": j, "omega": w}
