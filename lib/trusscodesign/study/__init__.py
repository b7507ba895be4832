"""The studies built on the model and the control: what the notebooks run.

``design`` (the robust design at a beam side h), ``authority`` (the share of the PMA bound needed to cancel the
disturbance), ``sensitivity`` (the two-sided sensitivity study of notebook 06), ``robustness`` (mu sweep over the
panel angle), ``timedomain`` (worst-case sinusoid from rest), ``objective`` (the co-design's objective at one h),
``pso`` and ``codesign`` (the particle-swarm co-design), ``sizing`` (the truss sized by parts: a design vector of
section sides by member group), ``pareto`` (the mass / pointing front and the expected gain of a candidate), ``frontsearch`` (the search of that front over
the sides),
``cluster`` (the Dask clients),
``export`` (a design for MATLAB and Simulink, as a ``.mat`` file).

It may import every other layer; none imports it.
"""
