"""One robust design at a section side h: models, open-loop worst case, synthesis with a spillover check.

Paper: "Co-design optimization architecture", Steps 1-3 for one particle: the reduced uncertain open loop
``F_u(G_r(h), Delta)`` (Step 1), the closed loop with the ACS designed on the rigid inertia at h (Step 2) and
the robust structured synthesis of ``K_PMA`` (Step 3, :func:`trusscodesign.control.synthesis.synthesize`).

One addition to the paper's recipe, measured in notebook 06: a gain tuned on ``G_r`` (modes below 500 rad/s)
alone destabilises 33 modes of ``G_r_low`` between 504 and 17251 rad/s at 2.139 cm (spillover of the non-collocated entries
of the 4x8 gain), and a gain kept merely stable on the nominal ``G_r_low`` leaves one of them with a damping
ratio of 1e-10, which the uncertain parameters then destabilise. The nominal ``G_r_low`` closed loop is therefore
a stability-only model of the synthesis (``spillover=True``) whose modes above the cut frequency of ``G_r`` must
keep half the truss damping (5e-4; they have at least 7e-4 with the PMAs passive), and the design is then
analysed on ``G_r_low`` over the whole box (notebook 08).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import control as ct
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..model import reduction, spacecraft
from ..infra import results
from ..control.closedloop import LoopSettings
from ..model.lft import LFT
from ..control.synthesis import NOT_STABILISED, Scenario, SynthesisOptions, SynthesisResult, WorstCase, plant_at, synthesize, worst_case

__all__ = ["DesignModels", "design_record", "tolerant_designs", "in_design_range", "models_at", "open_loop_worst_case", "robust_design", "stored_design", "stored_preset", "TABLE_DESIGNS", "table_design", "truss_shift_check", "shifted_sides",
           "truss_variants"]


@dataclass
class DesignModels:
    """The models of one design point.

    Attributes
    ----------
    h : float or dict str -> float
        Section side [m], or sides [m] by member group, cube or group of one cube (the keys of
        :func:`trusscodesign.model.spacecraft.truss_sections`).
    g_r, g_r_low : trusscodesign.model.lft.LFT
        ``F_u(G_r(h), Delta)`` (modes up to ``omega_max``) and ``F_u(G_r_low(h), Delta)`` (all flexible modes); as
        named ``control.StateSpace`` objects: :attr:`G_r` and :attr:`G_r_low`.
    g_check : trusscodesign.model.lft.LFT
        ``G_r_low`` reduced at ``omega_spill`` (1e4 rad/s by default, 20 x ``omega_max``): the spillover model of the
        synthesis (its eigen-decomposition per iteration costs half that of ``G_r_low``; ``G_r_low`` itself is
        analysed afterwards, notebook 08).
    inertia : ndarray (3, 3)
        Rigid inertia of the spacecraft at P1 at nominal parameters [kg m^2] (ACS design).
    truss_mass : float
        T-truss mass [kg]: ``rho h^2`` times the beams' length, summed over the members.
    build_time_s : float
        Time to build and reduce the models [s] (of which ``assembly_time_s`` to assemble the uncertain model).
    omega_max : float
        Cut frequency of ``G_r`` [rad/s].
    truss_damping : float
        Damping ratio of the truss beams in the parameters the models were built from (paper: 1e-3): the synthesis
        keeps the spillover modes damped at half of it (:func:`robust_design`).
    """

    h: float | dict[str, float]
    g_r: LFT
    g_r_low: LFT
    g_check: LFT
    inertia: NDArray[np.float64]
    truss_mass: float
    build_time_s: float
    omega_max: float = 500.0
    assembly_time_s: float = 0.0
    truss_damping: float = 1e-3

    @property
    def G_r(self) -> ct.StateSpace:
        """``G_r`` as a ``control.StateSpace`` named as the open loop (``spacecraft.INPUTS``, ``spacecraft.OUTPUTS``), its
        Delta channels open first (``w_<parameter>_<i>``, ``z_<parameter>_<i>``)."""
        return self.g_r.to_ss(spacecraft.INPUTS, spacecraft.OUTPUTS, name="G_r")

    @property
    def G_r_low(self) -> ct.StateSpace:
        """``G_r_low`` (every flexible mode, the spurious slow poles removed) as a named ``control.StateSpace``, as
        :attr:`G_r`."""
        return self.g_r_low.to_ss(spacecraft.INPUTS, spacecraft.OUTPUTS, name="G_r_low")


def in_design_range(h: float, params: dict | None = None) -> bool:
    """Whether the section side ``h`` [m] lies in the design range of the parameters (paper: [0.015, 0.03] m), to
    1e-12 m."""
    low_h, high_h = (params or spacecraft.load_parameters())["truss"]["h_range"]
    return bool(low_h - 1e-12 <= h <= high_h + 1e-12)


def models_at(h: float | Mapping[str, float], params: dict | None = None, omega_max: float = 500.0, omega_min: float = 0.01,
              omega_spill: float = 1e4) -> DesignModels:
    """Build ``G_r`` and ``G_r_low`` at section side h [m] (one assembly, one slow-pole split), or at sides by member
    group, cube or group of one cube (a mapping, as :func:`trusscodesign.model.spacecraft.open_loop` takes).

    Raises
    ------
    ValueError
        For a side outside the design range of the parameters (paper: [0.015, 0.03] m).
    """
    p = params or spacecraft.load_parameters()
    low_h, high_h = p["truss"]["h_range"]
    sides = dict(h) if isinstance(h, Mapping) else {"": h}
    for key, side in sides.items():
        if not (isinstance(side, (int, float, np.floating)) and in_design_range(side, p)):
            name = f"h[{key!r}]" if key else "h"
            raise ValueError(f"{name} must be a section side in [{low_h}, {high_h}] m, got {side!r}")
    return _models({k: float(v) for k, v in h.items()} if isinstance(h, Mapping) else float(h), p, omega_max, omega_min,
                   omega_spill)


def _models(h: float | dict[str, float], p: dict, omega_max: float = 500.0, omega_min: float = 0.01,
            omega_spill: float = 1e4) -> DesignModels:
    """:func:`models_at` without the design-range check: a truss variant (a model error of a design) may lie a few per
    cent beyond the range the co-design searches."""
    t0 = time.perf_counter()
    if not omega_min < omega_max < omega_spill:
        raise ValueError(f"the frequencies must satisfy omega_min < omega_max < omega_spill [rad/s], got {omega_min!r}, "
                         f"{omega_max!r}, {omega_spill!r}")
    lft = spacecraft.open_loop(h, uncertain=True, params=p).uncertain().grouped()
    t_build = time.perf_counter() - t0
    low = reduction.modal_reduction(lft.a, lft.b, lft.c, lft.d, omega_min=omega_min)
    g_low = LFT(*low.reduced, lft.blocks, lft.params)
    # G_r_low is free of slow poles: residualise it at omega_spill and at omega_max, without splitting off (and
    # checking) its slow part again. Residualising the spillover model at omega_max instead would save a Schur form
    # but changes small entries of G_r by up to 1e-7 of their size (measured at 1.5 cm): kept as the reference path.
    spill, _ = reduction.residualize_above(*low.reduced, omega_spill)
    g_check = LFT(*spill, lft.blocks, lft.params)
    red, _ = reduction.residualize_above(*low.reduced, omega_max)
    g_r = LFT(*red, lft.blocks, lft.params)
    return DesignModels(h, g_r, g_low, g_check, spacecraft.inertia_at_p1(g_r), spacecraft.truss_mass(h, p),
                        time.perf_counter() - t0, float(omega_max), t_build, float(p["truss"]["damping"]))


def open_loop_worst_case(models: DesignModels, settings: LoopSettings | None = None, **kwargs) -> WorstCase:
    """Worst case over the box with ``K_PMA = 0`` (the PMAs passive): the reference for the robust J_c."""
    return worst_case(models.g_r, np.zeros((4, 8)), models.inertia, settings or LoopSettings.from_parameters(), **kwargs)


def truss_variants(models: DesignModels, shifts: Sequence[float], params: dict | None = None) -> list[DesignModels]:
    """The models of the same spacecraft with its truss section side moved by the relative ``shifts`` (beyond the paper).

    A proxy for an error of the truss model: at ``h (1 + shift)`` every bending frequency of the members moves by
    ``1 + shift`` (bending stiffness ~ h^4, mass ~ h^2; axial and torsional frequencies do not depend on h), as in the
    truss-shift study of notebook 08. Each variant carries its own rigid inertia (its ACS is re-tuned, as for any design
    at that h). A variant is a model error, not a design: it may leave the design range (3 cm + 2 % is 3.06 cm).

    Parameters
    ----------
    models : DesignModels
        The nominal design point (its ``h`` and ``omega_max`` are used; the spillover cut is the default of
        :func:`models_at`).
    shifts : sequence of float
        Relative changes of the section side, nonzero, in (-0.5, 0.5).
    params : dict, optional
        Spacecraft parameters (default :func:`trusscodesign.model.spacecraft.load_parameters`); pass the ones ``models`` was built with.

    Returns
    -------
    list of DesignModels
        One per shift, in the order given.

    Raises
    ------
    ValueError
        If a shift is zero (the nominal model itself) or not a finite number in (-0.5, 0.5).
    """
    p = params or spacecraft.load_parameters()
    for shift in shifts:
        if not (isinstance(shift, (int, float, np.floating)) and np.isfinite(shift) and 0 < abs(shift) < 0.5):
            raise ValueError(f"each truss shift must be a nonzero relative change in (-0.5, 0.5), got {shift!r}")
    return [_models(shifted_sides(models.h, float(shift), p), p, models.omega_max) for shift in shifts]


def shifted_sides(h: float | Mapping[str, float], shift: float, params: dict | None = None) -> float | dict[str, float]:
    """The section side ``h`` [m], or every side of a mapping by key, moved by the relative ``shift`` and checked
    (:func:`trusscodesign.model.spacecraft.check_section_side`; not against the design range: a shifted truss is a model
    error, not a design)."""
    p = params or spacecraft.load_parameters()
    if isinstance(h, Mapping):  # every side moved by the same relative error
        return {str(k): spacecraft.check_section_side(float(v) * (1.0 + shift), p, f"h[{k!r}]") for k, v in h.items()}
    return spacecraft.check_section_side(h * (1.0 + shift), p)


def truss_shift_check(h: float | Mapping[str, float], gains: Mapping[str, ArrayLike], shifts: Sequence[float], settings: LoopSettings | None = None,
                      spillover: bool = False, params: dict | None = None,
                      progress: Callable[[Iterable], Iterable] = iter, **search) -> list[dict]:
    """Worst case of designs at ``h`` [m] on the spacecraft with its truss section side moved by each relative shift.

    The proxy of :func:`truss_variants`: at ``h (1 + shift)`` the spacecraft is rebuilt (its ACS re-tuned on its rigid
    inertia) and the gains are kept; the worst case over the uncertainty box is searched on ``G_r``
    (:func:`trusscodesign.control.synthesis.worst_case`). Shift 0 (the designs on their own truss) is always included; a shifted
    truss may leave the design range (it is a model error, not a design).

    Parameters
    ----------
    h : float or mapping str -> float
        Section side of the designs [m], or their sides by key (:func:`models_at`; a shift moves every side).
    gains : mapping of str to array_like (4, 8)
        The PMA gains checked, by name.
    shifts : sequence of float
        Relative changes of the section side.
    settings : LoopSettings, optional
    spillover : bool
        Also require the nominal spillover loop (``G_r_low`` up to 1e4 rad/s) of the shifted spacecraft to be stable.
    params : dict, optional
        Spacecraft parameters (default :func:`trusscodesign.model.spacecraft.load_parameters`).
    progress : callable
        Wraps the iterable of shifts (e.g. a tqdm progress bar).
    **search
        Options of the worst-case search (:func:`trusscodesign.control.synthesis.worst_case`), e.g. ``thetas_deg`` for a
        denser set of panel angles than the synthesis searched.

    Returns
    -------
    list of dict
        One per checked shift and gain: ``design``, ``shift_pct`` [%], ``h_cm`` [cm] (the largest side for sides by key), ``J_c``, ``omega_J_rad_s``, ``Z_c``,
        ``unstable_box_points``, ``evaluations``, ``spillover_stable`` (with ``spillover``) and ``valid`` (no unstable
        box point, ``Z_c < gamma_u`` and, with ``spillover``, a stable spillover loop).
    """
    settings = settings or LoopSettings.from_parameters()
    p = params or spacecraft.load_parameters()
    low_h, high_h = p["truss"]["h_range"]
    for key, side in (h.items() if isinstance(h, Mapping) else [("", h)]):
        if not (isinstance(side, (int, float, np.floating)) and not isinstance(side, bool) and in_design_range(side, p)):
            raise ValueError(f"{f'h[{key!r}]' if key else 'h'} must be a section side in [{low_h}, {high_h}] m, got {side!r}")
    shifts = list(shifts)
    for shift in shifts:
        if not (isinstance(shift, (int, float, np.integer, np.floating)) and not isinstance(shift, bool)
                and np.isfinite(shift) and abs(shift) < 1):
            raise ValueError(f"each truss shift must be a finite relative change in (-1, 1), e.g. 0.01 for 1 %, got {shift!r}: "
                             "in percent? (divide by 100)")
    checked: dict[str, NDArray] = {name: np.asarray(gain, dtype=float) for name, gain in gains.items()}
    for name, k in checked.items():
        if k.shape != (4, 8) or not np.all(np.isfinite(k)):
            raise ValueError(f"gains[{name!r}] must be a finite 4x8 matrix, got shape {k.shape}")
    rows: list[dict] = []
    for rel in progress(sorted({0.0, *(float(s) for s in shifts)})):
        h_s = shifted_sides(h, rel, p)
        m_s = _models(h_s, p)
        for name, gain in checked.items():
            wc = worst_case(m_s.g_r, gain, m_s.inertia, settings, **search)
            row = {"design": name, "shift_pct": 100 * rel, "h_cm": 100 * max(h_s.values()) if isinstance(h_s, dict) else 100 * h_s, "J_c": wc.value["rpe"], "omega_J_rad_s": wc.omega["rpe"],
                   "Z_c": wc.value["effort"], "unstable_box_points": len(wc.unstable), "evaluations": wc.evaluations}
            valid = not wc.unstable and wc.value["effort"] < settings.gamma_u
            if spillover:
                loop = plant_at(m_s.g_check, Scenario(), m_s.inertia, settings)
                row["spillover_stable"] = bool(loop.closed_loop_poles(gain).real.max() < 0)
                valid = valid and row["spillover_stable"]
            rows.append({**row, "valid": bool(valid)})
    return rows


def robust_design(models: DesignModels, settings: LoopSettings | None = None, options: SynthesisOptions | None = None,
                  gain0: ArrayLike | None = None, variants: Sequence[DesignModels] = (),
                  scenarios: Sequence[Scenario] | None = None, workers: int | None = None) -> SynthesisResult:
    """Robust structured synthesis of ``K_PMA`` at the design point (:func:`trusscodesign.control.synthesis.synthesize` on ``G_r``).

    Parameters
    ----------
    models : DesignModels
    settings : LoopSettings, optional
    options : SynthesisOptions, optional
        The synthesis's options (default ``SynthesisOptions()``), of which two are the design's own, below.
    options.spillover : bool
        Add the nominal closed loop on ``models.g_check`` (``G_r_low`` up to 1e4 rad/s) as a stability-only model
        (see the module docstring), whose modes above the cut frequency of ``G_r`` (``options.omega_check``; None: ``models.omega_max``)
        must keep a damping ratio of ``options.min_damping``: by default (None) half the truss damping ratio
        ``models.truss_damping`` (5e-4 for the paper's 1e-3; the passive spacecraft has at least 0.73 times it there,
        at 2.139 cm). A fixed 5e-4 would make a truss damped
        at 1e-4 (passive: 7.4e-5 there) infeasible from any starting gain.
    options.restarts : int
        How many times a failed synthesis is started again from its final gain, with the starting scenario set (default
        0: a failure is returned, flagged, as the co-design's stored runs had it). Not after a failure to stabilise
        from the starting gain (the gain has not moved); a failure to stabilise the scenarios a later round added is
        restarted (from the last round's gain, with the starting scenario set). The result is valid on its own checks
        (the last attempt's scenario set, search and final evaluation). A case it rescued: ``docs/experiments.md``
        ("Restarting a failed synthesis").
    gain0 : array_like (4, 8), optional
        Starting gain (default: all -1, as the paper; or the gain of a neighbouring design).
    variants : sequence of DesignModels
        Further models the gain must serve as well (e.g. :func:`truss_variants`): their ``G_r`` enter the synthesis as
        variants of the scenario set (see :func:`trusscodesign.control.synthesis.synthesize`) and, with ``spillover``, their nominal
        spillover loops as stability-only models. Default none: the paper's synthesis.
    scenarios : sequence of Scenario, optional
        The starting scenario set (default :func:`trusscodesign.control.synthesis.default_scenarios`).
    workers : int, optional
        Threads of the synthesis (``workers=1`` on a Dask worker).
    """
    opts = SynthesisOptions() if options is None else options
    if not isinstance(opts, SynthesisOptions):
        raise TypeError(f"options must be a SynthesisOptions, got {type(opts).__name__}")
    settings = settings or LoopSettings.from_parameters()
    checks = [plant_at(m.g_check, Scenario(), m.inertia, settings) for m in (models, *variants)] if opts.spillover else []
    opts = opts.replace(omega_check=models.omega_max if opts.omega_check is None else opts.omega_check,
                        min_damping=0.5 * models.truss_damping if opts.min_damping is None else opts.min_damping)

    def run(start: ArrayLike | None) -> SynthesisResult:
        return synthesize(models.g_r, models.inertia, settings, opts, gain0=start, scenarios=scenarios, stability_models=checks,
                          variants=[(m.g_r, m.inertia) for m in variants], workers=workers)

    res, first = run(gain0), ""
    for attempt in range(1, opts.restarts + 1):
        if res.success or res.message == NOT_STABILISED:  # later rounds' failures to stabilise are restarted
            break
        first = first or res.message
        again = run(res.gain)
        res = replace(again, iterations=res.iterations + again.iterations, time_s=res.time_s + again.time_s,
                      evaluations=res.evaluations + again.evaluations, history=res.history + again.history,
                      fallbacks=res.fallbacks + again.fallbacks, searches=res.searches + again.searches, restarts=attempt,
                      message=f"{again.message} (after {attempt} restart(s) from the final gain of a failed attempt; first: {first})")
    return res


def design_record(res: SynthesisResult) -> dict[str, Any]:
    """What a robust design is reported and stored with (JSON-able): ``success``, ``message``, ``restarts``, ``J_c``,
    ``Z_c``, the critical frequency [rad/s] and panel angle [deg] of each (``critical_omega``, ``critical_theta_deg``,
    ``effort_omega``, ``effort_theta_deg``; NaN when no gain stabilised the scenarios), ``gain``, ``iterations``,
    ``n_scenarios`` and ``synthesis_time_s``."""
    worst = res.worst
    out: dict[str, Any] = {"success": bool(res.success), "message": res.message, "restarts": res.restarts,
                           "J_c": float(res.j_c), "Z_c": float(res.z_c)}
    for group, name in (("rpe", "critical"), ("effort", "effort")):
        out[f"{name}_omega"] = float(worst.omega[group]) if worst else np.nan
        out[f"{name}_theta_deg"] = float(np.rad2deg(worst.scenario[group].theta)) if worst else np.nan
    return {**out, "gain": np.asarray(res.gain).tolist(), "iterations": res.iterations, "n_scenarios": len(res.scenarios),
            "synthesis_time_s": res.time_s}


def tolerant_designs(h: float, shifts: Sequence[float], params: dict | None = None, settings: LoopSettings | None = None,
                     options: SynthesisOptions | None = None, workers: int | None = None) -> dict[str, dict[str, Any]]:
    """The paper's recipe (the exact truss) and a truss-tolerant design at ``h`` [m], as :func:`design_record` records.

    The tolerant design serves the truss at ``h (1 + shift)`` for each of ``shifts`` as well (:func:`truss_variants`,
    :func:`robust_design` with ``variants``). Both start from all gains at -1.

    Parameters
    ----------
    h : float
        Section side [m], in the design range.
    shifts : sequence of float
        Relative changes of the section side the tolerant design must serve (nonzero, in (-0.5, 0.5)).
    params, settings
        Spacecraft parameters (default: the package's) and loop settings (default: those of ``params``).
    options, workers
        As :func:`robust_design` (``workers=1`` on a Dask worker).

    Returns
    -------
    dict
        ``{"recipe": record, "tolerant": record}``, each record with ``time_s`` [s] (models included).
    """
    p = params or spacecraft.load_parameters()
    settings = settings or LoopSettings.from_parameters(p)
    t0 = time.perf_counter()
    m = models_at(h, p)
    variants = truss_variants(m, shifts, p)  # bad shifts refused before the first synthesis
    out = {}
    for name, extra in (("recipe", []), ("tolerant", variants)):
        res = robust_design(m, settings, options, variants=extra, workers=workers)
        out[name] = {**design_record(res), "time_s": time.perf_counter() - t0}
        t0 = time.perf_counter()
    return out


def stored_design(source: str | int = "auto", results_dir: str = "data/results", h_fallback: float = 0.02139) -> tuple[str, float, NDArray]:
    """A stored design: ``(source, h [m], gain (4, 8))``.

    ``source``: ``"07"`` (notebook 07's co-design optimum), ``"06"`` (notebook 06's design at ``h_fallback`` [m]) or
    ``"auto"`` (07's if stored, else 06's). 6 and 7 are accepted too (papermill's ``-p`` turns ``"06"`` into 6).

    Raises
    ------
    ValueError
        For another ``source``, if notebook 06 stored no design at ``h_fallback``, or if the design read was computed
        from other spacecraft parameters or another model than today's (:func:`trusscodesign.model.spacecraft.inputs_key`).
    FileNotFoundError
        If the results file of the notebook asked for is missing.
    """
    name = str(source).strip().lower()
    name = {"6": "06", "7": "07"}.get(name, name)
    if name not in ("auto", "06", "07"):
        raise ValueError(f"design_source must be 'auto', '06' or '07', got {source!r}")
    if name in ("auto", "07"):
        try:
            stored07 = results.load_results("07_pso_codesign", results_dir)
        except FileNotFoundError:  # "auto" without notebook 07's results: notebook 06's design
            if name == "07":
                raise
        else:
            best = _field(stored07, ("results", "optimum"), results.resolve(results_dir, create=False) / "07_pso_codesign.json")
            _check_inputs(stored07, "notebook 07's optimum", "07")
            if isinstance(best, dict) and best.get("status", "ok") != "ok":  # files before 2026-12-03 hold no status
                raise ValueError(f"notebook 07's optimum is not a valid design ({best['status']}): rerun notebook 07")
            return "07", *_checked_design(best.get("h") if isinstance(best, dict) else None,
                                          best.get("gain") if isinstance(best, dict) else None, "notebook 07's optimum")
    if not (isinstance(h_fallback, (int, float, np.floating)) and not isinstance(h_fallback, bool) and np.isfinite(h_fallback)):
        raise ValueError(f"h_fallback must be a finite section side [m], got {h_fallback!r}")
    stored06 = results.load_results("06_robust_synthesis", results_dir)
    _check_inputs(stored06, "notebook 06's designs", "06")
    stored = _field(stored06, ("results", "designs"), results.resolve(results_dir, create=False) / "06_robust_synthesis.json")
    key = f"{100 * h_fallback:.3f}"
    if key not in stored or abs(float(key) - 100 * h_fallback) > 1e-9:  # the keys hold h to 1e-5 cm: another h is not it
        raise ValueError(f"notebook 06 stored no design at h = {h_fallback} m (it has {sorted(stored)} cm): rerun it with this h")
    if stored[key].get("success") is False:
        raise ValueError(f"notebook 06's design at {key} cm failed its synthesis ({stored[key].get('message')}): not a design to analyse")
    return "06", *_checked_design(float(h_fallback), stored[key].get("gain"), f"notebook 06's design at {key} cm")


def stored_preset(source: str | int = "auto", results_dir: str = "data/results") -> str:
    """The spacecraft parameters :func:`stored_design` ``(source, results_dir)``'s design was made for: the preset name
    notebook 07 stored with its optimum (:func:`trusscodesign.model.spacecraft.study_parameters`), or ``"stated"`` (notebook 06's
    designs, and notebook 07's runs stored before the co-design took a preset).

    Raises
    ------
    ValueError
        If the preset's parameters are no longer those the design was made with (an edited preset file), naming it.
    """
    name, _, _ = stored_design(source, results_dir)  # (its checks: the file, the inputs, the design)
    if name != "07":
        return spacecraft.STATED
    best = results.load_results("07_pso_codesign", results_dir)["results"]["optimum"]
    preset = str(best.get("preset", spacecraft.STATED))
    stored = best.get("parameters_sha256")
    if stored is not None and stored != spacecraft.parameters_fingerprint(spacecraft.study_parameters(preset)):
        raise ValueError(f"notebook 07's optimum was made for the preset {preset!r} as it was then, not as it is now "
                         "(its parameters' fingerprint differs): rerun notebook 07")
    return preset


TABLE_DESIGNS = ("paper_h", "optimum")  # the designs of notebook 08's table on one spacecraft (:func:`table_design`)


def table_design(preset: str, kind: str, results_dir: str = "data/results", h_paper: float = 0.02139) -> tuple[float, NDArray]:
    """A stored design on the spacecraft of ``preset`` (``"stated"`` or a preset name): ``(h [m], gain (4, 8))``.

    ``kind``: ``"paper_h"``, the paper's recipe at ``h_paper`` [m] (the design of the paper's mu table; notebook 06b's
    ``tolerance`` entry, made with ``tolerance_presets`` holding ``preset`` and ``h_values`` holding ``h_paper``), or
    ``"optimum"``, notebook 07's co-design optimum on that spacecraft (its run ``runs[preset]``).

    Raises
    ------
    ValueError
        For another ``kind``, if the notebook stored no such design or a failed one, or if the design was made with other
        spacecraft parameters than ``preset``'s today (an edited parameters or preset file), naming what to rerun.
    FileNotFoundError
        If the results file of that notebook is missing.
    """
    if kind not in TABLE_DESIGNS:
        raise ValueError(f"kind must be one of {TABLE_DESIGNS}, got {kind!r}")
    params = spacecraft.study_parameters(preset)  # (an unknown preset: a ValueError naming the presets)
    now = spacecraft.inputs_key(params)
    if kind == "optimum":
        stored = results.load_results("07_pso_codesign", results_dir)
        path = results.resolve(results_dir, create=False) / "07_pso_codesign.json"
        runs = _field(stored, ("results", "runs"), path)
        if preset not in runs:
            how = "run_baseline = True (its stated-values baseline)" if preset == spacecraft.STATED else f"preset = {preset!r}"
            raise ValueError(f"notebook 07 stored no co-design on {preset!r} (it has {sorted(runs)}): rerun it with {how}")
        run = runs[preset]
        _check_inputs(stored, "notebook 07's runs", "07")  # the stated parameters and the model
        made = run.get("parameters_sha256", spacecraft.parameters_fingerprint(spacecraft.load_parameters()))
        if made != now["spacecraft_parameters"]:
            raise ValueError(f"notebook 07's optimum on {preset!r} was made with other parameters than the preset's today: rerun notebook 07")
        best = run.get("optimum") or {}
        if best.get("status", "ok") != "ok":
            raise ValueError(f"notebook 07's optimum on {preset!r} is not a valid design ({best.get('status')}): rerun notebook 07")
        return _checked_design(best.get("h"), best.get("gain"), f"notebook 07's optimum on {preset!r}")
    stored = results.load_results("06b_calibration_tolerance", results_dir)
    path = results.resolve(results_dir, create=False) / "06b_calibration_tolerance.json"
    entries = _field(stored, ("results", "tolerance"), path)
    key = f"{preset}|{100 * h_paper:.3f}"
    if key not in entries:
        raise ValueError(f"notebook 06b stored no design at {100 * h_paper:.3f} cm on {preset!r} (it has {sorted(entries)}): rerun it "
                         f"with {preset!r} in tolerance_presets and {h_paper} in h_values")
    if preset == spacecraft.STATED:
        made = stored.get("inputs")
    else:  # 06b records the parameters of the preset it calibrates
        info = _field(stored, ("results", "preset"), path)
        if info.get("name") != preset:
            raise ValueError(f"notebook 06b's designs on {preset!r} cannot be checked against the preset's file (its run calibrated "
                             f"{info.get('name')!r}): rerun notebook 06b with preset = {preset!r}")
        made = info.get("inputs")
    if made != now:
        raise ValueError(f"notebook 06b's design on {preset!r} was made with other parameters or another model than today's: rerun notebook 06b")
    recipe = _field(entries, (key, "recipe"), path)
    if recipe.get("success") is False:
        raise ValueError(f"notebook 06b's recipe at {100 * h_paper:.3f} cm on {preset!r} failed ({recipe.get('message')}): not a design to analyse")
    return _checked_design(float(h_paper), recipe.get("gain"), f"notebook 06b's recipe at {100 * h_paper:.3f} cm on {preset!r}")


def _field(payload: dict, keys: tuple[str, ...], path: object) -> Any:
    """``payload[keys[0]][keys[1]]...``, or a ValueError naming the file and the missing field (a malformed file)."""
    value: Any = payload
    for depth, key in enumerate(keys):
        if not isinstance(value, dict) or key not in value:
            raise ValueError(f"{path} is malformed: it has no field {'.'.join(keys[:depth + 1])!r}: rerun the notebook that writes it")
        value = value[key]
    return value


def _check_inputs(payload: dict, what: str, notebook: str) -> None:
    """Raise a ValueError naming what changed unless a results file was computed from the current spacecraft parameters
    and model (:func:`trusscodesign.model.spacecraft.inputs_key`)."""
    stored, now = payload.get("inputs") or {}, spacecraft.inputs_key()
    if stored != now:
        changed = "; ".join(f"{k}: {stored.get(k)!r} stored, {now[k]!r} now" for k in now if stored.get(k) != now[k])
        raise ValueError(f"{what}: computed from other inputs than today's ({changed}): rerun notebook {notebook} "
                         "with the current spacecraft parameters, or restore the parameters it was computed with")


def _checked_design(h: object, gain: object, what: str) -> tuple[float, NDArray]:
    """``(h, gain)`` of a stored design, or a ValueError naming it unless h is in the design range and the gain finite 4x8."""
    try:
        k = np.array(gain, dtype=float) if isinstance(gain, (list, np.ndarray)) else np.full(0, np.nan)
    except ValueError:  # ragged
        k = np.full(0, np.nan)
    if not (isinstance(h, (int, float)) and not isinstance(h, bool) and in_design_range(h)) or k.shape != (4, 8) \
            or not np.all(np.isfinite(k)):
        raise ValueError(f"{what} is not a stored design (h = {h!r} m in the design range, a finite 4x8 gain): got h = {h!r}, "
                         f"gain of shape {k.shape}; rerun the notebook")
    return float(h), k
