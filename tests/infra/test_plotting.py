"""Figures of the library: what they show, checked on their artists (not on pixels)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from trusscodesign.infra import plotting  # noqa: E402


def test_objective_grid_keeps_penalised_points_off_the_curve():
    """A penalised grid point (f = m/m0 + 10) is marked, not drawn on the f^n curve, whose scale stays readable."""
    records = [dict(h=0.015 + 0.001 * i, f=0.9 + 0.05 * i, J_c=0.02, mass=50.0 + 5 * i) for i in range(6)]
    records[3].update(f=10.3, J_c=float("inf"))
    fig = plotting.objective_grid(records, best=records[0], jc_limit=2.0)
    ax_f = fig.axes[0]
    curve = next(line for line in ax_f.get_lines() if line.get_label() == "dense grid")
    y = np.asarray(curve.get_ydata(), float)
    assert np.all(y[np.isfinite(y)] < 2.0) and np.isfinite(y).sum() == 5
    marks = [line for line in ax_f.get_lines() if line.get_label().startswith("penalised")]
    assert len(marks) == 1 and np.allclose(marks[0].get_xdata(), [1.8])
    assert ax_f.get_ylim()[1] < 2.0
    assert "their $f^n$ is 10.3" in marks[0].get_label()  # the legend gives the value the mark does not show


def test_objective_grid_marks_where_jc_crosses_its_target_and_the_swarms_particles():
    """The crossing of 0.9 is interpolated between the grid points around it (here J_c falls from 1.1 at 2 cm to 0.7 at
    2.2 cm: 0.9 at 2.1 cm); the swarm's valid particles are drawn, its penalised ones are not; m0 on the mass panel."""
    records = [dict(h=h, f=1.0, J_c=j, Z_c=0.95, mass=90.0) for h, j in ((0.018, 1.5), (0.02, 1.1), (0.022, 0.7), (0.024, 0.5))]
    history = [dict(h=0.021, f=0.6, J_c=0.9, Z_c=0.97), dict(h=0.015, f=10.4, J_c=3.0, Z_c=0.9)]
    fig = plotting.objective_grid(records, best=history[0], history=history, m0=183.11)
    ax_f, ax_j, ax_z, ax_m = fig.axes
    crossing = [line for line in ax_j.get_lines() if line.get_label().startswith("$J_c$ crosses")]
    assert len(crossing) == 1 and np.allclose(crossing[0].get_xdata(), 2.1) and "2.10 cm" in crossing[0].get_label()
    dots = next(line for line in ax_z.get_lines() if line.get_label().startswith("swarm particles"))
    assert np.allclose(dots.get_xdata(), [2.1]) and "(1 valid of 2)" in dots.get_label()
    assert any(line.get_label() == "$m_0$ = 183.11 kg" for line in ax_m.get_lines())


def _history(n_it=3, n_p=4):
    """Particle records: iteration k, particle i at h = 1.5 + 0.1 i cm; the best (lowest f) is particle (k + 1) % n_p."""
    recs = []
    for k in range(n_it):
        for i in range(n_p):
            recs.append(dict(iteration=k, particle=i, h=0.015 + 0.001 * i, J_c=0.02 + 0.01 * i,
                             f=1.0 if i == (k + 1) % n_p else 1.5 + 0.1 * i))
    return recs


def test_pso_panels_highlights_the_best_particle_of_each_iteration():
    fig = plotting.pso_panels(_history(), 3, (0.015, 0.03))
    gold = next(line for line in fig.axes[0].get_lines() if line.get_label() == "best particle")
    assert np.allclose(gold.get_xdata(), [1, 2, 3]) and np.allclose(gold.get_ydata(), [1.6, 1.7, 1.8])


def test_pso_panels_reads_records_from_a_results_file(tmp_path):
    """Records saved by trusscodesign.infra.results and read back by load_results (a failed synthesis: J_c infinite, stored as a string)."""
    from trusscodesign.infra import results
    recs = _history()
    recs[2].update(J_c=float("inf"), f=10.3)
    results.save_results("pso", {"history": recs}, tmp_path)
    back = results.load_results("pso", tmp_path)["results"]["history"]
    fig = plotting.pso_panels(back, 3, (0.015, 0.03))
    boxes = fig.axes[1].get_lines()
    assert all(np.all(np.isfinite(np.asarray(line.get_ydata(), float)[~np.isnan(np.asarray(line.get_ydata(), float))])) for line in boxes)


def test_pso_panels_leaves_penalised_particles_out_of_the_jc_boxplots():
    """J_c > 2 is penalised (f = m/m0 + 10) and, as in the paper's figure and objective_grid, not in the J_c panel."""
    recs = _history()
    recs[3].update(J_c=50.0, f=10.5)
    fig = plotting.pso_panels(recs, 3, (0.015, 0.03))
    ydata = np.concatenate([np.asarray(line.get_ydata(), float) for line in fig.axes[1].get_lines()])
    assert np.nanmax(ydata) < 2.0


def test_objective_grid_breaks_the_curves_at_penalised_points():
    """The f^n and J_c curves are not drawn across a penalised grid point as if it were valid."""
    records = [dict(h=0.015 + 0.001 * i, f=0.9 + 0.05 * i, J_c=0.02, Z_c=0.9, mass=50.0 + 5 * i) for i in range(6)]
    records[3].update(f=10.3, J_c=float("inf"), Z_c=float("inf"))
    fig = plotting.objective_grid(records, jc_limit=2.0)
    for ax in fig.axes[:3]:
        curve = next(line for line in ax.get_lines() if line.get_label() == "dense grid")
        x, y = np.asarray(curve.get_xdata(), float), np.asarray(curve.get_ydata(), float)
        assert np.isnan(y[np.isclose(x, 1.8)]).all() and np.isclose(x, 1.8).any()


def test_sine_build_up_in_physical_units_with_envelope_and_bounds():
    """Outputs scaled to their unit, the envelope of the largest steady amplitude, the requirement at +-bound."""
    import matplotlib.pyplot as plt

    t = np.linspace(0.0, 100.0, 501)
    outputs = np.vstack([0.2 * np.sin(t), 0.1 * np.cos(t)])
    fig, ax = plt.subplots()
    plotting.sine_build_up(ax, t, outputs, np.array([0.2j, 0.1]), tau=25.0, scale=50.0, bound=50.0,
                           labels=["LOS x", "LOS y"], quantity="weighted LOS error", unit="µrad")
    lines = {line.get_label(): line for line in ax.get_lines()}
    assert np.allclose(lines["LOS x"].get_ydata(), 10.0 * np.sin(t)) and np.allclose(lines["LOS y"].get_ydata(), 5.0 * np.cos(t))
    env = next(line for label, line in lines.items() if label.startswith("envelope"))
    assert np.allclose(env.get_ydata(), 10.0 * (1 - np.exp(-t / 25.0)))
    bounds = [line for label, line in lines.items() if label.startswith("requirement")]
    assert len(bounds) == 1 and np.allclose(bounds[0].get_ydata(), 50.0)
    assert ax.get_ylabel() == "weighted LOS error [µrad]" and ax.get_xlabel() == "time [s]"
    # the end of the record again in an inset
    fig, ax = plt.subplots()
    plotting.sine_build_up(ax, t, outputs, np.array([0.2j, 0.1]), 25.0, 50.0, 50.0, ["LOS x", "LOS y"], "error", "µrad", zoom=10.0)
    (inset,) = ax.child_axes
    x = inset.get_lines()[0].get_xdata()
    assert x.min() >= 90.0 - 1e-9 and x.max() == 100.0 and np.allclose(inset.get_lines()[0].get_ydata(), 10.0 * np.sin(x))


def test_a_mode_is_drawn_at_rest_and_displaced_with_its_marks():
    import matplotlib.pyplot as plt
    import pytest

    nodes = {"A": [0, 0, 0], "B": [1, 0, 0], "C": [1, 1, 1]}
    members = [("A", "B"), ("B", "C")]
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    plotting.draw_mode(ax, nodes, members, [[0, 0, 0], [0, 0, 2.0], [0, 1.0, 0]], 2 * np.pi, clamped=["A"], ports=["C"])
    lines = ax.get_lines()
    assert len(lines) == 2 * len(members) + 2  # at rest and displaced, then the clamped and port marks
    x, y, z = lines[1].get_data_3d()  # member A-B displaced: B, the largest displacement, drawn at 15 % of 1 m
    assert np.allclose([x[1], y[1], z[1]], [1, 0, 0.15])
    assert ax.get_title() == "6.28 rad/s (1.000 Hz)" and ax.get_zlabel() == "z [m]"
    with pytest.raises(ValueError, match="one row .x, y, z. per node"):
        plotting.draw_mode(ax, nodes, members, np.zeros((2, 3)), 1.0)
    plt.close(fig)
