"""trusscodesign: sub-structured (TITOP/NINOP) modelling and robust co-design of flexible space trusses.

Modules: ``frames`` (DCMs, kinematic model tau), ``ports`` (multi-port models,
channel inversion, interconnection), ``titop`` (analytical Euler-Bernoulli beam),
``mechanisms`` (L-chain, triangle, square), ``frame_fe`` (reference 3D frame
finite elements), ``reduction`` (removal of spurious slow poles), ``paths``,
``plotting``, ``results``.
"""

__version__ = "0.1.0"
