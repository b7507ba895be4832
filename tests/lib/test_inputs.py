"""Bad inputs a user could plausibly give: a clear error, before any long computation (review of the public API)."""

import numpy as np
import pytest

from trusscodesign import codesign, modal, spacecraft, synthesis
from trusscodesign.closedloop import LoopSettings


@pytest.mark.parametrize("kwargs, match", [(dict(h=3.0), "cm or mm"), (dict(h=21.39), "cm or mm"), (dict(theta=90.0), "degrees")])
def test_open_loop_refuses_cm_and_degrees_before_building(kwargs, match):
    with pytest.raises(ValueError, match=match):  # was built: a truss of 3 m beams in 4 s, 1.8e6 kg
        spacecraft.open_loop(**kwargs)
    with pytest.raises(ValueError, match="cm or mm"):
        spacecraft.truss_mass(3.0)
    assert spacecraft.truss_mass(0.03) == pytest.approx(183.11, rel=1e-3)


def test_transposed_participation_factors_are_refused():
    omega = np.array([2.5, 5.0, 9.0])
    factors = np.array([[0, 0, 5.0, 0, 1.0, 0], [0, 0, 2.0, 0, 0.5, 0], [1.0, 0, 0, 0, 0, 0.2]])
    rigid = np.diag([80, 80, 80, 50, 50, 50.0])
    modal.cantilever_from_modes(rigid, omega, factors)
    with pytest.raises(ValueError, match=r"shape \(n, 6\)"):  # was reshaped (scrambled) into a 3x6 array silently
        modal.cantilever_from_modes(rigid, omega, factors.T)
    modal.cantilever_from_modes(rigid, omega[:1], factors[0])  # one mode: a row of 6 is fine


@pytest.mark.parametrize("thetas", [np.deg2rad([0.0, 45.0, 90.0, 135.0, 180.0]), [0.0, 1.0, 2.0, 3.0]])
def test_panel_angle_grids_in_radians_are_refused(thetas):
    with pytest.raises(ValueError, match="radians"):
        synthesis.default_scenarios(thetas)
    with pytest.raises(ValueError, match="radians"):  # before any plant is built (the model is not even looked at)
        synthesis.worst_case(None, np.zeros((4, 8)), np.eye(3), LoopSettings(), thetas_deg=thetas)
    assert len(synthesis.default_scenarios([0.0, 90.0])) == 9 and len(synthesis.default_scenarios([0.0])) == 5


def test_synthesize_checks_search_thetas_before_optimising():
    # up front: with no model, anything computed first would fail otherwise (was raised by the first worst-case
    # search, after 14-30 s of optimisation)
    with pytest.raises(ValueError, match="search_thetas_deg"):
        synthesis.synthesize(None, np.eye(3), LoopSettings(), search_thetas_deg=[0.0, 200.0])


@pytest.mark.parametrize("options, error", [({"tolx": 1e-2}, TypeError), ({"tol": -1.0}, ValueError), ({"restarts": 1.5}, TypeError),
                                            ({"search_thetas_deg": [0.0, 270.0]}, ValueError), ({"gain0": None}, TypeError)])
def test_codesign_checks_synthesis_options_before_any_particle(monkeypatch, options, error):
    def never(*args, **kwargs):
        raise AssertionError("a particle was evaluated")

    monkeypatch.setattr(codesign, "evaluate_particle", never)
    for run in (lambda: codesign.run_codesign(2, 1, synthesis_options=options, progress=False, log=lambda s: None),
                lambda: codesign.evaluate_grid([0.02], synthesis_options=options, progress=False)):
        with pytest.raises(error):
            run()
    codesign._check_synthesis_options({"tol": 1e-2, "fast": True, "restarts": 1, "search_thetas_deg": (0.0, 90.0, 180.0)})


@pytest.mark.parametrize("hs, kwargs, match", [([1.5, 3.0], {}, "design range"), ([0.02], {"m0": -1.0}, "m0")])
def test_grid_and_swarm_check_h_and_m0_before_any_particle(monkeypatch, hs, kwargs, match):
    def never(*args, **kw):
        raise AssertionError("a particle was evaluated")

    monkeypatch.setattr(codesign, "evaluate_particle", never)
    with pytest.raises(ValueError, match=match):  # h in cm: every point failed with a finite f; m0: after each synthesis
        codesign.evaluate_grid(hs, progress=False, **kwargs)
    with pytest.raises(ValueError, match=match):
        codesign.evaluate_swarm(hs, None, progress=False, **kwargs)


def test_rpe_bound_in_microradians_is_refused():
    with pytest.raises(ValueError, match="eps_max"):
        LoopSettings(eps_max=50.0)
    assert LoopSettings(eps_max=50e-6).eps_max == 50e-6


@pytest.mark.parametrize("h_min, h_max, n_particles, match", [
    (0.015, 0.025, 0, r"n_particles must be an integer in \[2, inf\), got 0"),
    (0.025, 0.02, 24, r"h_min = 0.025 m must be below h_max = 0.02 m"),
    (0.02, 0.02, 24, r"h_min = 0.02 m must be below h_max = 0.02 m"),
    (1.5, 3.0, 24, r"h_min = 1.5 m must lie in the design range \[0.015, 0.03\] m .*in centimetres\? 1.5 cm is 0.015 m"),
    (0.015, 0.04, 24, r"h_max = 0.04 m must lie in the design range"),
])
def test_a_codesign_study_is_checked_before_any_model(h_min, h_max, n_particles, match):
    """Notebook 07's range and sizes (an empty AssertionError, or an error only after the grid, before)."""
    with pytest.raises(ValueError, match=match):
        codesign.check_study(h_min, h_max, n_particles, 20, 31)


def test_a_codesign_range_given_as_text_names_the_parameter_and_unit():
    with pytest.raises(TypeError, match=r"h_min must be a real number \[m\], got str '2cm'"):
        codesign.check_study("2cm", 0.03, 24, 20, 31)
    codesign.check_study(0.02, 0.025, 24, 20, 31)  # a new range inside the design range is fine


@pytest.mark.parametrize("value, match", [(3.0, r"h_fe\[1\] must be a section side in metres in \(0, 0.1\].*cm or mm"),
                                          ("2cm", r"h_fe\[1\] \[m\] must be a real number, got str"),
                                          (0.0, r"h_fe\[1\] \[m\] must be a finite positive number")])
def test_a_section_side_names_the_parameter_its_unit_and_range(value, match):
    """Notebook 04's sides (h = 3, cm typed as m, gave an empty AssertionError on the slow-pole count)."""
    with pytest.raises((TypeError, ValueError), match=match):
        spacecraft.check_section_side(value, name="h_fe[1]")
    assert spacecraft.check_section_side(0.02139) == 0.02139
