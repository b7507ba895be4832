"""trusscodesign: sub-structured (TITOP/NINOP) modelling and robust co-design of flexible space trusses.

Modules: ``frames`` (DCMs, kinematic model tau, rotation LFTs), ``ports`` (multi-port models,
channel inversion, interconnection, delta ports), ``titop`` (analytical Euler-Bernoulli beam,
h-parametrised LFT beam), ``mechanisms`` (L-chain, triangle, square), ``cube``, ``nastran`` (the cube's stored Nastran/SDT tables, read and checked), ``truss``
(T-truss), ``bodies`` (hub, antenna, PMA, solar panel on SADM), ``spacecraft`` (open-loop G), ``schema`` (the spacecraft parameters' fields, units and ranges),
``lft`` (uncertain/tunable parameters and LFT algebra), ``reduction`` (spurious slow poles,
modal reduction), ``modal`` (participation factors, models from modal data), ``assembly``
(direct constrained assembly), ``frame_fe`` and ``opensees_fe`` (finite-element references),
``closedloop`` (the pointing study's generalized plant), ``hinf`` (exact H-infinity norms), ``mu`` and
``mu_interval`` (worst-case gain bounds, pointwise and certified over frequency intervals), ``synthesis``,
``modalloop`` and ``modalpool`` (robust structured synthesis of the PMA gain; the fast path, on worker processes),
``authority`` (the share of the PMA bound needed to cancel the disturbance), ``design``,
``sensitivity`` (the two-sided sensitivity study of notebook 06), ``robustness`` (mu sweep over the panel
angle), ``pso`` and ``codesign`` (the particle-swarm co-design), ``timedomain`` (worst-case sinusoid from rest),
``checks``, ``paths``, ``plotting``, ``results``.
"""

import logging
from importlib.metadata import PackageNotFoundError, version

# the library reports progress through logging (the synthesis: a line per round at INFO); silent unless the user
# configures logging, e.g. logging.basicConfig(level=logging.INFO)
logging.getLogger(__name__).addHandler(logging.NullHandler())

try:
    __version__ = version("trusscodesign")  # one version, pyproject.toml's
except PackageNotFoundError:  # run from a checkout on the path without being installed
    __version__ = "unknown"
