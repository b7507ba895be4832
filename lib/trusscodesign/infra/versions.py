"""Versions that stored results depend on beyond the library's own: the synthesis optimiser's.

A results file or cache records them (:func:`trusscodesign.infra.results.save_results`, the co-design's keys), so that
results of an earlier version are never mixed with new ones; :mod:`trusscodesign.control.synthesis` exports the same constant.
"""

__all__ = ["ALGORITHM"]

# Version of the optimiser: stored with cached results (co-design grid, swarm checkpoints) so that results of an
# earlier version are never mixed with new ones. 2: elastic effort constraint, margin gradients with the |lambda|
# term, stability constraints with a back-off (the version-1 optimiser stalled on constraint boundaries).
# 3: the poles linearised are those whose margin could rise highest within the trust region (version 2 linearised
# the least damped ones, and a well-damped but sensitive spillover mode could be destabilised by every step).
# 4: a round stopped by the iteration limit is followed by another (v3 declared convergence after it).
ALGORITHM = "trust-region SLP v4"
