"""The structural model: sub-structured (TITOP/NINOP) multi-port models up to the uncertain spacecraft.

``statespace`` (checked state-space arrays, channel inversion, static closure, frequency responses), ``lft``
(uncertain/tunable parameters and LFT algebra), ``frames`` (DCMs, kinematic model tau, rotation LFTs), ``ports``
(multi-port models: causality, inversion, frame change, delta ports), ``interconnect`` (their assembly at shared nodes), ``titop`` (analytical Euler-Bernoulli beam, h-parametrised LFT
beam), ``mechanisms`` (L-chain, triangle, square), ``cube``, ``nastran`` (the cube's stored Nastran/SDT tables, read
and checked), ``cubetruss`` (any truss of cubes: its description, checks, member groups and model), ``truss``
(T-truss), ``modal`` (participation factors, models from modal data), ``reduction`` (spurious
slow poles, modal reduction), ``bodies`` (hub, antenna, PMA, solar panel on SADM), ``schema`` (the spacecraft
parameters' fields, units and ranges), ``spacecraft`` (open-loop G, the reduced uncertain model), ``assembly``
(direct constrained assembly), ``frame_fe`` and ``opensees_fe`` (finite-element references).

It imports the plumbing (:mod:`trusscodesign.infra`) only.
"""
