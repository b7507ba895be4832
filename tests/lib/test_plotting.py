"""Figures of the library: what they show, checked on their artists (not on pixels)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

from lib import plotting  # noqa: E402


def test_objective_grid_keeps_penalised_points_off_the_curve():
    """A penalised grid point (f = m/m0 + 10) is marked, not drawn on the f^n curve, whose scale stays readable."""
    records = [dict(h=0.015 + 0.001 * i, f=0.9 + 0.05 * i, J_c=0.02, mass=50.0 + 5 * i) for i in range(6)]
    records[3].update(f=10.3, J_c=float("inf"))
    fig = plotting.objective_grid(records, best=records[0], jc_limit=2.0)
    ax_f = fig.axes[0]
    curve = next(line for line in ax_f.get_lines() if line.get_label() == "dense grid")
    assert np.all(curve.get_ydata() < 2.0) and len(curve.get_xdata()) == 5
    marks = [line for line in ax_f.get_lines() if line.get_label().startswith("penalised")]
    assert len(marks) == 1 and np.allclose(marks[0].get_xdata(), [1.8])
    assert ax_f.get_ylim()[1] < 2.0
