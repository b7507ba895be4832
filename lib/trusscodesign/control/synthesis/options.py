"""The options of a robust synthesis, checked when created, and the optimiser's fixed parameters.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from ...infra.checks import check_option as _check_option
from .scenarios import _thetas_deg

__all__ = ['SynthesisOptions']


@dataclass(frozen=True)
class SynthesisOptions:
    """The options of a robust synthesis, checked when created (a ``TypeError`` or ``ValueError`` naming the option).

    One object travels from a notebook through the co-design, the design helpers and the sensitivity study to
    :func:`synthesize`; :meth:`key` is what stored results record of it.

    Attributes
    ----------
    min_damping, omega_check : float
        Damping ratio that every pole of the stability models above ``omega_check`` [rad/s] (the modes ``G_r``
        residualises) must keep (None: 5e-4 in :func:`synthesize`, half the truss damping in
        :func:`trusscodesign.study.design.robust_design`; they have at least 7e-4 with the PMAs
        passive; None: 500 rad/s, and the models' cut frequency in the design). A margin: left on the stability boundary, these modes would be pushed across by the uncertain
        parameters. Below ``omega_check`` the stability models need only be stable.
    min_damping_all : float
        Damping ratio every closed-loop pole of every scenario of the set must keep (default 2e-4; capped at half
        the scenario's passive least damping, 3.2e-4 on this spacecraft): without it the optimiser parks modes at a
        damping of 1e-4 or less, where the mu analysis can no longer certify robustness.
    max_iter : int
        Trust-region iterations per round.
    max_rounds : int
        Rounds of (optimise on the set, search the box, add the worst scenarios). A round whose optimisation
        stopped at ``max_iter`` is followed by another even when the search adds nothing; if the last one still
        does, the design is returned as valid (stable, feasible, covered by the search) with that message.
    search_thetas_deg : sequence of float, optional
        Panel angles of the worst-case search grid [deg] (default 10, every 20 deg from 0 to 180).
    tol : float
        Relative decrease of J over the last 5 accepted steps of a round's optimisation phase below which it stops
        (default 2e-3; the co-design's 1e-2, :data:`trusscodesign.study.objective.CODESIGN_OPTIONS`).
    fast : bool
        Evaluate the scenario plants and stability-only plants during the optimisation through their open-loop
        modal form (:mod:`trusscodesign.control.modalloop`: ``O(n^2)`` per gain instead of a dense eigen-decomposition); the final
        evaluation of the scenario set and the worst-case searches stay dense, so ``j_c``, ``z_c`` and ``success``
        are always from the dense path. Default False (the reference path).
    trust_region : {"box", "ball"}
        Region of each step: the box ``|d_i| <= r_i`` on the gain entries (default: each step a linear program; every
        stored result) or that box intersected with the ball ``||d / r||_2 <= sqrt(32) / 2`` (a second-order cone program,
        Clarabel). In the box, the steps of a cold start at the thin end of the h range can sit in a corner of the box
        while several pole-damping rows are active, and the synthesis can stop on that plateau; the ball takes those
        stalls to the neighbours' J_c (what was measured: ``docs/experiments.md``, "The ball trust region").
    restoration : {"minmax", "least_change"}
        The steps that restore stability (a start, or a scenario a search added, unstable at the current gain) and then
        ``Z < gamma_u``. ``"minmax"`` (default: every stored result): minimise the largest linearised pole margin (then
        the largest effort peak) in the trust region, which moves the gain to the edge of the region. ``"least_change"``:
        the smallest step inside the trust region whose linearised margins pass their targets by a quarter of their
        violation, then whose effort peaks reach ``gamma_u (1 - margin)`` (this phase lasting until
        ``Z < gamma_u (1 - margin / 2)``); the min-max step where no such step fits in the region, and for the rest of a
        stabilisation once a least-change trial has failed. A min-max step can overshoot the required margin by orders
        of magnitude and throw J away (what was measured: ``docs/experiments.md``, "Min-max against least-change
        restoration").
    spillover : bool
        Used by :func:`trusscodesign.study.design.robust_design`: the nominal loops on the models' ``G_r_low`` as
        stability-only plants (default True).
    restarts : int
        Used by :func:`trusscodesign.study.design.robust_design`: how many times a failed synthesis is started again
        from its final gain (default 0).
    """

    min_damping: float | None = None
    omega_check: float | None = None
    min_damping_all: float = 2e-4
    max_iter: int = 60
    max_rounds: int = 6
    search_thetas_deg: tuple[float, ...] | None = None
    tol: float = 2e-3
    fast: bool = False
    trust_region: str = "box"
    restoration: str = "minmax"
    spillover: bool = True
    restarts: int = 0

    def __post_init__(self) -> None:
        if not (isinstance(self.trust_region, str) and self.trust_region in ("box", "ball")):
            raise ValueError(f"trust_region must be 'box' or 'ball', got {self.trust_region!r}")
        if not (isinstance(self.restoration, str) and self.restoration in ("minmax", "least_change")):
            raise ValueError(f"restoration must be 'minmax' or 'least_change', got {self.restoration!r}")
        for name in ("min_damping", "min_damping_all"):
            if getattr(self, name) is not None:
                _check_option(name, getattr(self, name), 0.0, 1.0, open_high=True)
        if self.omega_check is not None:
            _check_option("omega_check", self.omega_check, 0.0)
        _check_option("tol", self.tol, 0.0, 1.0, open_low=True, open_high=True)
        for name in ("max_iter", "max_rounds"):
            _check_option(name, getattr(self, name), 1, integer=True)
        _check_option("restarts", self.restarts, 0, integer=True)
        for name in ("fast", "spillover"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise TypeError(f"{name} must be True or False, got {getattr(self, name)!r}")
        if self.search_thetas_deg is not None:
            object.__setattr__(self, "search_thetas_deg", tuple(float(x) for x in _thetas_deg(self.search_thetas_deg, "search_thetas_deg")))

    def replace(self, **changes: Any) -> "SynthesisOptions":
        """A copy with ``changes``, checked."""
        return replace(self, **changes)

    def key(self) -> dict[str, Any]:
        """The options that differ from the defaults, by name, in JSON types: what stored results record (the co-design's
        ``{"tol": 0.01, "fast": true, "trust_region": "ball", "restoration": "least_change"}``)."""
        out: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if value != f.default:
                out[f.name] = list(value) if isinstance(value, tuple) else value
        return out

    @classmethod
    def from_key(cls, key: Mapping[str, Any] | None) -> "SynthesisOptions":
        """The options a stored :meth:`key` describes (None: the defaults); a ``TypeError`` names an option this version
        no longer has."""
        key = dict(key or {})
        unknown = sorted(set(key) - {f.name for f in fields(cls)})
        if unknown:
            raise TypeError(f"unknown synthesis option(s) {unknown}; SynthesisOptions has {[f.name for f in fields(cls)]}")
        return cls(**key)


# The optimiser's fixed parameters (options once, never set by any stored result, default or notebook)
_MIN_DECAY = 1e-7  # stability margin on the closed-loop poles [1/s]


_SEARCH_DAMPING = 0.75  # fraction of min_damping_all the worst-case search over the box requires (a margin, like _MARGIN)


_BAND = 0.7  # peaks within this fraction of the maximum enter the local model


_MARGIN = 0.02  # the linearised effort peaks are kept below gamma_u (1 - _MARGIN)


_COVER_TOL = 1e-2  # relative excess over the set's J (or Z) below which a searched worst case counts as covered


_RADIUS0 = 1.0  # initial trust radius on each gain entry (relative, at least 1)


_STALL_STEPS = 5  # the stopping test's window of accepted steps (see SynthesisOptions.tol)


_MAX_UNSTABLE = 1  # unstable scenarios a round adds from its search
