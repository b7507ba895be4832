"""More bad inputs of the public API (second review): a clear ValueError/TypeError naming the argument, never a silent
wrong result or an error deep inside numpy; the valid inputs next to them behave as before."""

import numpy as np
import pytest

from trusscodesign import bodies, design, frames, ports, robustness, spacecraft, synthesis, titop, truss
from trusscodesign.closedloop import LoopSettings, generalized_plant
from trusscodesign.lft import LFT, Parameter
from trusscodesign.synthesis import Scenario

SEC = titop.Section.square(0.02)


def test_percent_parameter_refuses_a_range_reaching_zero():
    with pytest.raises(ValueError, match="below 100.*cross zero"):  # was [-400, 2000] kg: a negative hub mass
        Parameter.percent("M_SC", 800.0, 150.0)
    with pytest.raises(ValueError, match="below 100"):
        Parameter.percent("M_SC", 800.0, 100)
    p = Parameter.percent("M_SC", 800.0, 20.0)
    assert (p.low, p.high) == (640.0, 960.0)


def test_from_delta_refuses_extrapolation():
    p = Parameter.percent("m", 800.0, 20.0)
    for delta in (2.0, -1.5, np.nan):
        with pytest.raises(ValueError, match=r"delta must be a normalised value in \[-1, 1\]"):  # 2 was 1120 kg, out of range
            p.from_delta(delta)
    assert p.from_delta(1.0) == 960.0 and p.from_delta(-1.0) == 640.0
    assert p.from_delta(0.3) == p.center + p.half_range * 0.3 and p.from_delta(1 + 1e-13) == p.center + p.half_range * (1 + 1e-13)


def test_plant_at_refuses_unknown_kept_names(monkeypatch):
    monkeypatch.setattr(synthesis, "generalized_plant", lambda *args, **kwargs: "plant")
    params = spacecraft.uncertain_parameters()
    model = sum((LFT.param(p) for p in params.values()), LFT.constant([[0.0]]))
    assert synthesis.plant_at(model, Scenario(), np.eye(3), LoopSettings(), keep=robustness.KEEP) == "plant"
    with pytest.raises(ValueError, match=r"not parameters of the model.*'Iyy_SC', 'M_SC', 'omega1_SP', 'tau'"):
        synthesis.plant_at(model, Scenario(), np.eye(3), LoopSettings(), keep=["hub_mass"])  # was ignored: M_SC substituted
    with pytest.raises(TypeError, match="keep"):
        synthesis.plant_at(model, Scenario(), np.eye(3), LoopSettings(), keep="M_SC")


@pytest.mark.parametrize("hub_mass, error", [(-5.0, ValueError), (np.nan, ValueError), ("800", TypeError)])
def test_component_masses_checks_hub_mass(hub_mass, error):
    with pytest.raises(error, match="hub_mass"):  # was returned as given
        spacecraft.component_masses(0.03, hub_mass=hub_mass)
    assert spacecraft.component_masses(0.03, hub_mass=900)["hub"] == 900


@pytest.mark.parametrize("n, error", [(0, ValueError), (-1, ValueError), (True, TypeError), (2.0, TypeError)])
def test_analytic_frequencies_needs_a_count_of_at_least_one(n, error):
    with pytest.raises(error, match="n must be an integer"):  # 0: an empty array; True: one frequency
        titop.analytic_frequencies(1.0, SEC, "bending_y", n=n)
    assert titop.analytic_frequencies(1.0, SEC, "bending_y", n=np.int64(2)).shape == (2,)


def test_ports_refuse_fractional_channels_complex_matrices_and_bad_atol():
    beam = titop.clamped_free(1.0, SEC)
    with pytest.raises(TypeError, match="integer"):  # was channel 5
        beam.invert([5.7])
    with pytest.raises(TypeError, match="integer"):
        beam.invert([1.0, 2.0], one_based=True)
    assert beam.invert(np.arange(6)).nstates == beam.nstates
    port = ports.scalar_port("s", "f", "x")
    with pytest.raises(TypeError, match="A must be real"):  # was a ComplexWarning and the imaginary part dropped
        ports.MultiPortModel([[-1.0 + 2.0j]], [[1.0]], [[1.0]], [[0.0]], [port])
    for atol in (-1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="atol"):
            ports.connect([beam], atol=atol)
    with pytest.raises(TypeError, match="atol"):
        ports.connect([beam], atol="1e-9")
    ports.connect([beam], atol=0)


@pytest.mark.parametrize("rot", [frames.rot_x, frames.rot_y, frames.rot_z])
def test_rotations_refuse_non_finite_angles(rot):
    for angle in (np.nan, np.inf):
        with pytest.raises(ValueError, match="angle must be a finite"):  # was a NaN matrix
            rot(angle)
    with pytest.raises(TypeError, match="angle must be a real number"):
        rot("0.5")
    assert np.array_equal(rot(0.5), rot(np.float64(0.5)))


def test_truss_shift_check_refuses_shifts_in_percent(monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("a model was built")

    monkeypatch.setattr(design, "models_at", never)
    for shifts in ([5, 10], [0.01, 100.0], [1.0]):
        with pytest.raises(ValueError, match="e.g. 0.01 for 1 %.*in percent"):  # 5, 10: both skipped silently
            design.truss_shift_check(0.02, {"d": np.zeros((4, 8))}, shifts)


def test_synthesize_refuses_an_empty_scenario_set():
    with pytest.raises(ValueError, match="at least one Scenario"):  # was "max() arg is an empty sequence"
        synthesis.synthesize(None, np.eye(3), LoopSettings(), scenarios=[])
    with pytest.raises(TypeError, match=r"scenarios\[0\] must be a Scenario"):
        synthesis.synthesize(None, np.eye(3), LoopSettings(), scenarios=[(0.0, 0.0, 0.0, 0.0)])


def test_beam_builders_need_a_section():
    for build in (lambda: titop.clamped_free(2.0, 0.02), lambda: titop.beam(("A", [0, 0, 0]), ("B", [1, 0, 0]), 0.02),
                  lambda: titop.modal_data(2.0, 0.02), lambda: titop.analytic_frequencies(2.0, 0.02, "axial"),
                  lambda: titop.rigid_mass(2.0, 0.02)):
        with pytest.raises(TypeError, match=r"section must be a trusscodesign.titop.Section.*Section.square\(h\)"):  # AttributeError
            build()


def _fake_open_loop(n: int = 4):
    rng = np.random.default_rng(0)
    return -np.eye(n), rng.normal(size=(n, 12)), rng.normal(size=(20, n)), np.zeros((20, 12))


@pytest.mark.parametrize("min_pole, error", [(-1.0, ValueError), (np.nan, ValueError), ("1e-3", TypeError)])
def test_generalized_plant_checks_min_pole(min_pole, error):
    with pytest.raises(error, match="min_pole"):  # -1 and NaN skipped the pole check: a LinAlgError later
        generalized_plant(*_fake_open_loop(), np.eye(3), LoopSettings(), min_pole=min_pole)


def test_generalized_plant_refuses_non_finite_matrices():
    a, b, c, d = _fake_open_loop()
    a[0, 0] = np.nan
    with pytest.raises(ValueError, match="must be finite"):  # was a LinAlgError of eigvals
        generalized_plant(a, b, c, d, np.eye(3), LoopSettings())


def test_rigid_hub_needs_a_positive_definite_inertia_and_mass_range():
    pts = {"P1": [0.0, 0.0, 0.0], "A": [1.0, 0.0, 0.0]}
    for inertia in (np.zeros((3, 3)), np.diag([1.0, 0.0, 1.0])):
        with pytest.raises(ValueError, match="positive-definite"):  # was a LinAlgError (singular matrix)
            bodies.rigid_hub(800.0, inertia, pts)
    with pytest.raises(ValueError, match="positive range"):
        bodies.rigid_hub(Parameter("M_SC", 1.0, -1.0, 3.0), np.eye(3), pts)
    assert bodies.rigid_hub(800.0, np.diag([500.0, 600.0, 700.0]), pts).d.shape == (12, 12)


@pytest.mark.parametrize("name", ["../parameters", "../presets/paper_match"])
def test_load_preset_takes_names_of_presets_only(name):
    with pytest.raises(ValueError, match=r"unknown preset.*available: \['paper_calibrated', 'paper_match'\]"):  # ../parameters was returned
        spacecraft.load_preset(name)
    assert "closed_loop" in spacecraft.load_preset("paper_match")


def test_sweep_refuses_angles_in_degrees_before_any_angle(monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("an angle was analysed")

    monkeypatch.setattr(robustness, "bounds_at_angle", never)
    with pytest.raises(ValueError, match="degrees"):  # was refused by the first angle beyond pi, after the others
        robustness.sweep(None, [0.0, 1.0, 45.0, 90.0], -np.ones((4, 8)), np.eye(3), LoopSettings())


def test_strings_for_numbers_are_named():
    with pytest.raises(TypeError, match="nominal must be a real number"):
        Parameter("m", "800", 600.0, 1000.0)
    with pytest.raises(TypeError, match="high must be a real number"):
        Parameter("m", 800.0, 600.0, "1000")
    with pytest.raises(TypeError, match="nominal must be a real number"):
        Parameter.percent("m", "800", 20.0)
    with pytest.raises(TypeError, match="percent must be a real number"):
        Parameter.percent("m", 800.0, "20")
    with pytest.raises(TypeError, match="Scenario.d_mass must be a real number"):
        Scenario(d_mass="0.5")
    with pytest.raises(TypeError, match="Scenario.theta must be a real number"):
        Scenario(theta="1.0")
    with pytest.raises(TypeError, match="cube side a must be a real number"):
        truss.truss_nodes("1")
    assert Parameter("m", 800, 600, 1000).center == 800.0 and Scenario(1, 0, 0, 0).d_mass == 1
    assert len(truss.truss_nodes(2)) == 24
