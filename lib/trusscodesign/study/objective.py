"""The co-design's objective at one section side h: the nested ``f^n`` and one particle's evaluation.

Paper: "Co-design optimization architecture" (Steps 1-4). For a particle h: build the reduced uncertain model (Step 1),
close the loop with the ACS of that h (Step 2), tune ``K_PMA`` by the robust synthesis (Step 3), and evaluate

``f^n(h) = m(h)/m0 + |0.9 - J_c(h, K(h))|`` if ``J_c <= 2``, else ``m(h)/m0 + 10``   (Step 4),

with ``m(h)`` the T-truss mass from the DC gain ``W_P1 -> a_P1`` (the whole spacecraft's rigid mass minus the
other bodies, checked against ``rho h^2 * total beam length``). A failed synthesis gets the penalty and its reason
is recorded; it never stops the run.
"""

from __future__ import annotations

import time
import traceback
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..control.closedloop import LoopSettings
from ..control.synthesis import Scenario, SynthesisOptions
from ..model import spacecraft

__all__ = ['M0_PAPER', 'H_M0', 'TARGET_JC', 'PENALTY', 'JC_LIMIT', 'CODESIGN_OPTIONS', 'synthesis_options', 'objective_value', 'tolerance_shifts', 'truss_mass_from_dc', 'NUMERICAL_FAILURES', 'NOT_NUMERICAL', 'evaluate_particle', 'lost_evaluation']


M0_PAPER = 183.11  # kg, the paper's truss mass at h = 3 cm (m0)


H_M0 = 0.03  # m, the section side of the paper's reference truss, whose mass is m0 (whatever the design range)


TARGET_JC = 0.9


PENALTY = 10.0


JC_LIMIT = 2.0


# Stopping rule of the synthesis inside the co-design: less than 1 % decrease of J over 5 accepted steps (the
# synthesis default is 0.2 %). J_c enters f^n through |0.9 - J_c| with J_c of a few 1e-2, so the looser rule moves
# f^n little: measured by benchmarks/robust_synthesis.py on a cold start at 2.5 cm, J_c 0.01871 with the default rule
# and 0.01930 with this one (f^n 0.04 % apart), in 101 iterations instead of 145 (41.7 s instead of 55.6 s).
CODESIGN_OPTIONS = SynthesisOptions(tol=1e-2)


def synthesis_options(fast: bool = False, trust_region: str = "box", restoration: str = "minmax") -> SynthesisOptions:
    """The co-design's synthesis options (:data:`CODESIGN_OPTIONS`) with the fast path, a trust-region shape and a
    restoration step (those of :class:`trusscodesign.control.synthesis.SynthesisOptions`; a ValueError for an unknown
    shape or restoration). Notebook 07's stored runs use ``(True, "ball", "least_change")``."""
    return CODESIGN_OPTIONS.replace(fast=fast, trust_region=trust_region, restoration=restoration)


def objective_value(mass: float, j_c: float, m0: float) -> float:
    """The paper's nested objective ``f^n`` (penalty 10 when ``J_c > 2`` or the synthesis failed, ``J_c = inf`` or NaN).

    ``mass`` and ``m0`` [kg] must be finite and positive, ``j_c`` non-negative (or NaN / inf for a failed synthesis).
    """
    for name, value in (("mass", mass), ("m0", m0)):
        if not (isinstance(value, (int, float, np.integer, np.floating)) and np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite positive mass [kg], got {value!r}")
    if j_c < 0:
        raise ValueError(f"j_c must be a non-negative H-infinity norm (inf or NaN for a failed synthesis), got {j_c!r}")
    if not (np.isfinite(j_c) and j_c <= JC_LIMIT):
        return mass / m0 + PENALTY
    return mass / m0 + abs(TARGET_JC - j_c)


def tolerance_shifts(truss_tolerance: float) -> tuple[float, ...]:
    """The relative section-side errors a truss-tolerant design is synthesised against: ``-t, -t/2, t/2, t`` for the
    tolerance ``t`` (none for 0: the paper's recipe, the exact truss only).

    Four shifts rather than the two ends: notebook 06b's designs made against these pass all 9 shifts of a finer check
    within +-2 % (with 37 panel angles), which a check between the synthesised shifts could otherwise fail.

    Raises
    ------
    ValueError
        Unless ``truss_tolerance`` is a relative error in [0, 0.2) (0.02 for 2 %).
    """
    if isinstance(truss_tolerance, bool) or not isinstance(truss_tolerance, (int, float, np.integer, np.floating)) \
            or not (0.0 <= float(truss_tolerance) < 0.2):
        raise ValueError(f"truss_tolerance must be a relative section-side error in [0, 0.2) (0.02 for +-2 %; 0 for the "
                         f"paper's recipe), got {truss_tolerance!r}: in percent? (divide by 100)")
    t = float(truss_tolerance)
    return () if t == 0.0 else (-t, -t / 2, t / 2, t)


def truss_mass_from_dc(models, params: dict | None = None) -> float:
    """T-truss mass [kg] from the DC gain ``W_P1 -> a_P1`` of the reduced model at nominal parameters.

    The 6x6 DC gain is inverted (the CoG is not at P1); its (1, 1) entry is the spacecraft mass, from which the
    hub, panels, antenna and PMAs are subtracted.
    """
    p = params or spacecraft.load_parameters()
    a, b, c, d = models.g_r.evaluate({k: v.nominal for k, v in models.g_r.params.items()})
    ii = [spacecraft.INPUTS.index(f"W_P1_{x}") for x in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")]
    oo = [spacecraft.OUTPUTS.index(f"a_P1_{x}") for x in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")]
    mass = float(np.linalg.inv(d[np.ix_(oo, ii)] - c[oo] @ np.linalg.solve(a, b[:, ii]))[0, 0])
    others = {k: v for k, v in spacecraft.component_masses(models.h, params=p).items() if k != "truss"}
    return mass - sum(others.values())


#: What a failed evaluation raises: a model that cannot be built at h, a singular matrix, a synthesis or solver that
#: does not converge, an overflow. The particle is penalised and the run goes on.
NUMERICAL_FAILURES: tuple[type[Exception], ...] = (ArithmeticError, ValueError, RuntimeError)


#: Subclasses of those that are programming errors, not numerics: they stop the run with their traceback.
NOT_NUMERICAL: tuple[type[Exception], ...] = (NotImplementedError, RecursionError, UnicodeError)


def evaluate_particle(h: float | Mapping[str, float], gain0: ArrayLike | None = None, settings: LoopSettings | None = None, params: dict | None = None,
                      m0: float = M0_PAPER, fail: bool = False, synthesis_options: SynthesisOptions | None = None,
                      scenarios0: Sequence[Sequence[float]] | None = None, truss_tolerance: float = 0.0) -> dict:
    """One objective evaluation (Steps 1-4 for one particle); a numerical failure is a penalised particle, not an error.

    Parameters
    ----------
    h : float or mapping str -> float
        Section side [m], or sides [m] by member group, cube or group of one cube (the keys of
        :func:`trusscodesign.model.spacecraft.truss_sections`; the truss-tolerant shifts move every side).
    gain0 : array_like (4, 8), optional
        Warm start (default: all gains at -1).
    settings, params
        Closed-loop settings and spacecraft parameters (defaults: the data files).
    m0 : float
        Reference mass [kg] (the paper's 183.11 kg, truss at 3 cm).
    fail : bool
        Raise inside the evaluation (to test that a failure is penalised and logged, not fatal).
    synthesis_options : SynthesisOptions, optional
        Of :func:`trusscodesign.study.design.robust_design` (default :data:`CODESIGN_OPTIONS`).
    scenarios0 : sequence of 4-vectors, optional
        Initial scenario set of the synthesis, normalised ``(d_mass, d_iyy, d_omega1, theta)`` (default: the
        21 of :func:`trusscodesign.control.synthesis.default_scenarios`); the warm start passes the set the best particle ended with,
        so that the scenarios its worst-case searches found are there from the start.
    truss_tolerance : float
        Relative section-side error the design must survive (0.02: +-2 %): the gain is synthesised on the truss at h and
        at ``h (1 + s)`` for each shift of :func:`tolerance_shifts` (the truss-tolerant synthesis of notebook 06b), so a
        design that cannot serve them all is a failed, penalised particle. Default 0: the paper's recipe (the exact truss).

    Returns
    -------
    dict
        ``h``, ``f``, ``J_c``, ``Z_c``, their critical frequencies [rad/s] and panel angles [deg] (``critical_omega``,
        ``critical_theta_deg``, ``effort_omega``, ``effort_theta_deg``, as :func:`trusscodesign.study.design.design_record`),
        ``mass`` (from the DC gain), ``mass_check`` (rho h^2 L), ``status``
        (``"ok"``, ``"penalty: J_c > 2"`` or ``"failed: <reason>"``), ``gain`` (4x8 list or None), and the times
        ``t_model`` (= ``t_build`` + ``t_reduction`` + ``t_variants``, the shifted trusses' models), ``t_synthesis`` [s],
        ``scenarios`` (the final set, as
        4-vectors, or None). A :data:`NUMERICAL_FAILURES` raised inside (including a bad ``h``) makes the record
        failed, with ``traceback``.

    Raises
    ------
    Exception
        Any other error (TypeError, NameError, AttributeError, KeyError, ...: a programming error), with its traceback.
    """
    from threadpoolctl import threadpool_limits

    from . import design

    t0 = time.perf_counter()
    out = _new_record(h)
    p = params or spacecraft.load_parameters()
    side = _side(h)
    try:
        out["mass"] = out["mass_check"] = spacecraft.truss_mass(side, p)  # inside: a bad h is a failed particle
        with threadpool_limits(1):
            if fail:
                raise RuntimeError("injected failure (test)")
            models = design.models_at(side, params=p)
            out["t_build"], out["t_reduction"] = models.assembly_time_s, models.build_time_s - models.assembly_time_s
            t1 = time.perf_counter()
            variants = design.truss_variants(models, tolerance_shifts(truss_tolerance), p)
            out["t_variants"] = time.perf_counter() - t1
            out["t_model"] = time.perf_counter() - t0
            mass_dc = truss_mass_from_dc(models, p)
            if not abs(mass_dc - out["mass_check"]) <= 1e-6 * out["mass_check"]:  # (NaN fails too)
                raise RuntimeError(f"the truss mass from the DC gain, {mass_dc:.6f} kg, differs from rho h^2 L = "
                                   f"{out['mass_check']:.6f} kg: the reduced model does not keep the rigid mass")
            out["mass"] = mass_dc
            t1 = time.perf_counter()
            scen = None if scenarios0 is None else [Scenario.from_vector(v) for v in scenarios0]
            opts = CODESIGN_OPTIONS if synthesis_options is None else synthesis_options
            res = design.robust_design(models, settings, opts, gain0=gain0, variants=variants, scenarios=scen, workers=1)
            out["t_synthesis"] = time.perf_counter() - t1
        record = design.design_record(res)  # with the critical frequencies [rad/s] and panel angles [deg]
        out.update({k: record[k] for k in _CRITICAL})
        out.update(J_c=float(res.j_c), Z_c=float(res.z_c), gain=np.asarray(res.gain).tolist(), iterations=res.iterations,
                   scenarios=[sc.vector().tolist() for sc in res.scenarios])
        out["status"] = "ok" if res.success else f"failed: {res.message}"
        if not res.success:
            out["J_c"] = np.inf
    except NUMERICAL_FAILURES as exc:  # a failed particle is penalised and logged; a programming error stops the run
        if isinstance(exc, NOT_NUMERICAL):
            raise
        out["status"] = f"failed: {type(exc).__name__}: {exc}"
        out["traceback"] = traceback.format_exc(limit=3)
    out["t_total"] = time.perf_counter() - t0
    return _with_objective(out, m0)


_CRITICAL = ("critical_omega", "critical_theta_deg", "effort_omega", "effort_theta_deg")


def _side(h: float | Mapping[str, float]) -> float | dict[str, float]:
    """``h`` as a float, or the sides by key as floats (as a record stores them)."""
    return {str(k): float(v) for k, v in h.items()} if isinstance(h, Mapping) else float(h)


def _new_record(h: float | Mapping[str, float]) -> dict[str, Any]:
    """A particle's record before its evaluation: no design yet (J_c, Z_c infinite), no mass, no times."""
    return {"h": _side(h), "J_c": np.inf, "Z_c": np.inf, "gain": None, "scenarios": None, "t_model": 0.0, "t_build": 0.0,
            "t_reduction": 0.0, "t_variants": 0.0, "t_synthesis": 0.0, **dict.fromkeys(_CRITICAL), "mass": np.nan, "mass_check": np.nan, "t_total": 0.0}


def _with_objective(out: dict[str, Any], m0: float) -> dict[str, Any]:
    """``out`` with its status made a penalty where ``J_c > 2`` and its objective value ``f`` (infinite without a mass)."""
    if out["status"] == "ok" and not out["J_c"] <= JC_LIMIT:  # NaN too
        out["status"] = "penalty: J_c > 2"
    try:
        out["f"] = objective_value(out["mass"], out["J_c"], m0) if np.isfinite(out["mass"]) else np.inf
    except ValueError as exc:  # e.g. a bad m0: the particle fails, the run goes on
        out["status"], out["f"] = f"failed: {exc}", np.inf
    return out


def lost_evaluation(h: float | Mapping[str, float], reason: str, params: dict | None = None, m0: float = M0_PAPER) -> dict[str, Any]:
    """The record of a particle whose evaluation never returned (it killed every worker that ran it): failed, with its
    reason, and penalised like any failed synthesis (``f = m(h)/m0 + 10``).

    Raises
    ------
    ValueError
        If ``h`` is not a section side (the swarm's particles always are: a bad one is a programming error).
    """
    out = _new_record(h)
    out["mass"] = out["mass_check"] = spacecraft.truss_mass(_side(h), params or spacecraft.load_parameters())
    out["status"] = f"failed: {reason}"
    return _with_objective(out, m0)
