"""Robust structured H-infinity synthesis of the static PMA gain (the ``systune`` step of the paper).

Paper: section "Co-design optimization architecture", Step 3: find the 4x8 gain ``K_PMA`` that minimises
``J_c = max_Delta ||T_{p~ -> RPE}||_inf`` subject to the hard constraint ``Z_c = max_Delta ||T_{p~ -> W~u}||_inf
< gamma_u`` and closed-loop stability, for the uncertain closed loop of :mod:`trusscodesign.control.closedloop`.

Method (in the spirit of Apkarian and Noll's ``systune``, written here because no Python package does
multi-model structured H-infinity synthesis):

* **multi-model**: a finite set of uncertainty scenarios (nominal, box corners at several panel angles) is
  grown by a worst-case search over the whole parameter box (dynamic sampling; ``scenarios``, ``search``);
* **peaks**: for each scenario the closed loop is put in modal form; its largest singular value is
  evaluated on a peak-aware grid (log points plus every lightly damped closed-loop pole frequency) and
  each local maximum is refined by nested grids in log frequency; the peak is checked by a direct solve (``peaks``);
* **nonsmooth step**: every peak within a band of the current maximum is linearised (gradient from the
  singular vectors at the peak frequency, exact for a static gain) and a trust-region linear program
  (HiGHS) minimises the largest linearised RPE peak; the effort peaks are elastic (an l1 merit) above a
  target halfway between the current ``Z`` and ``0.98 gamma_u``, and a feasibility phase first brings ``Z``
  under ``gamma_u``; the pole margins that could rise highest within the trust region are linearised with a
  1 % back-off; a step is accepted only if all scenarios stay stable, ``Z < gamma_u`` holds and the merit
  decreases by at least 10 % of the predicted decrease (``steps``, ``optimiser``);
* **stabilisation**: from a destabilising start (e.g. a warm start from another h) the spectral abscissa
  is first pushed below a small negative margin by the same trust-region LP on eigenvalue gradients.

A synthesis that does not reach a stable, feasible, converged point is returned with
``success = False`` and the reason; it is never reported as a result.

Modules: ``options`` (:class:`SynthesisOptions`, the optimiser's fixed parameters), ``scenarios``, ``peaks``,
``search`` (the worst-case search), ``steps`` (the step sub-problems), ``optimiser`` (:func:`synthesize`), ``norms``
(certified norms), ``threads``.
"""

from ...infra.versions import ALGORITHM
from .norms import exact_norms, sigma_curve
from .optimiser import NOT_STABILISED, SynthesisResult, synthesize
from .options import SynthesisOptions
from .peaks import GROUPS, LoopPeaks, loop_peaks, peak_gradient
from .scenarios import CORNERS, Scenario, default_scenarios, plant_at, search_candidates
from .search import WorstCase, worst_case

__all__ = ["ALGORITHM", "NOT_STABILISED", "Scenario", "LoopPeaks", "loop_peaks", "peak_gradient", "SynthesisResult", "synthesize",
           "WorstCase", "worst_case", "search_candidates", "plant_at", "default_scenarios", "exact_norms", "sigma_curve",
           "SynthesisOptions", "GROUPS", "CORNERS"]
