"""Time-domain worst case (trusscodesign.study.timedomain): the time stepping and the closed form against a 1-DOF oscillator solved by
hand, the build-up to the H-infinity gain on a MIMO system, and the spacecraft's closed loop against its peaks."""

import numpy as np
import pytest
from trusscodesign.control.closedloop import LoopSettings
from trusscodesign.control.synthesis import Scenario, loop_peaks, plant_at
from trusscodesign.study import design, timedomain

WN, ZETA = 3.0, 0.02


def oscillator():
    """x'' + 2 zeta wn x' + wn^2 x = u, y = x (states x, x')."""
    a = np.array([[0.0, 1.0], [-WN**2, -2 * ZETA * WN]])
    return a, np.array([[0.0], [1.0]]), np.array([[1.0, 0.0]]), np.zeros((1, 1))


def oscillator_by_hand(w, t):
    """Response from rest to cos(w t): steady state plus the free response that cancels its initial state."""
    g = 1.0 / (WN**2 - w**2 + 2j * ZETA * WN * w)
    x0, v0 = g.real, (1j * w * g).real  # steady-state position and velocity at t = 0
    wd = WN * np.sqrt(1 - ZETA**2)
    amp_c = -x0
    amp_s = (-v0 + ZETA * WN * amp_c) / wd
    return (g * np.exp(1j * w * t)).real + np.exp(-ZETA * WN * t) * (amp_c * np.cos(wd * t) + amp_s * np.sin(wd * t))


@pytest.mark.parametrize("w", [WN, 0.5 * WN, 2.2 * WN])
def test_oscillator_from_rest_against_hand_solution(w):
    a, b, c, d = oscillator()
    res = timedomain.sine_response(a, b, c, d, w, duration=60.0, samples_per_period=64)
    ref = oscillator_by_hand(w, res.t)
    scale = np.abs(ref).max()
    assert np.allclose(res.direction, [1.0])  # a single input: its direction is the input itself
    # time stepping: exact for an input linear between samples; the error is that of the interpolated cosine
    assert np.abs(res.outputs[0] - ref).max() < 2e-3 * scale
    assert np.abs(timedomain.exact_sine_response(a, b, c, d, w, [1.0], res.t)[0] - ref).max() < 1e-10 * scale
    assert res.sigma == pytest.approx(1.0 / abs(WN**2 - w**2 + 2j * ZETA * WN * w), rel=1e-12)


def test_error_of_the_time_step_falls_as_its_square():
    a, b, c, d = oscillator()
    errors = []
    for n in (16, 32, 64):
        res = timedomain.sine_response(a, b, c, d, WN, duration=30.0, samples_per_period=n)
        errors.append(np.abs(res.outputs[0] - oscillator_by_hand(WN, res.t)).max())
    assert 3.0 < errors[0] / errors[1] < 5.0 and 3.0 < errors[1] / errors[2] < 5.0


def mimo():
    """Two lightly damped modes (1 and 1.3 rad/s), two inputs, two outputs, coupled."""
    rng = np.random.default_rng(7)
    blocks = [np.array([[0.0, 1.0], [-w**2, -2 * 0.01 * w]]) for w in (1.0, 1.3)]
    a = np.block([[blocks[0], np.zeros((2, 2))], [np.zeros((2, 2)), blocks[1]]])
    return a, rng.normal(size=(4, 2)), rng.normal(size=(2, 4)), np.zeros((2, 2))


def test_mimo_builds_up_to_the_largest_singular_value_along_the_worst_direction():
    a, b, c, d = mimo()
    w = 1.0
    sigma, v = timedomain.worst_direction(a, b, c, d, w)
    s = np.linalg.svd(c @ np.linalg.solve(1j * w * np.eye(4) - a, b), compute_uv=False)
    assert sigma == pytest.approx(s[0], rel=1e-12)
    # 12 time constants of the slower mode (1 / (0.01 x 1 rad/s) = 100 s): the transient is below 1e-5 of the steady state
    res = timedomain.sine_response(a, b, c, d, w, duration=1200.0, samples_per_period=64)
    assert np.allclose(res.direction, v)
    assert np.linalg.norm(res.amplitude(periods=10)) == pytest.approx(sigma, rel=2e-3)
    assert np.abs(res.outputs - timedomain.exact_sine_response(a, b, c, d, w, v, res.t)).max() < 2e-3 * sigma
    # the other direction reaches the second singular value only
    other = timedomain.sine_response(a, b, c, d, w, duration=1200.0, samples_per_period=64,
                                     direction=np.linalg.svd(c @ np.linalg.solve(1j * w * np.eye(4) - a, b))[2][1].conj())
    assert np.linalg.norm(other.amplitude()) == pytest.approx(s[1], rel=2e-3)
    # early on, the envelope is still far below: 20 s is 0.2 time constants
    early = timedomain.sine_response(a, b, c, d, w, duration=20.0, samples_per_period=64)
    assert np.linalg.norm(early.amplitude(periods=1)) < 0.3 * sigma


def test_spacecraft_closed_loop_at_its_peak(model, inertia):
    """At notebook 06's design, on one scenario: the worst sinusoid at the RPE peak of loop_peaks has that peak as its
    gain, and the simulated response (dense 200-state closed loop) follows the closed form."""
    settings = LoopSettings.from_parameters()
    _, _, gain = design.stored_design("06", "data/results", 0.02139)
    plant = plant_at(model, Scenario(1.0, -1.0, 1.0, np.deg2rad(60.0)), inertia, settings)
    peaks = loop_peaks(plant, gain)
    w = peaks.omega("rpe")
    res = timedomain.loop_sine_response(plant, gain, "rpe", w, duration=40 * 2 * np.pi / w)
    assert res.sigma == pytest.approx(peaks.norm("rpe"), rel=1e-6)
    a, b, c, d = plant.closed_loop_matrices(gain)
    sl = plant.slices()
    at = np.linspace(0, res.t.size - 1, 60).astype(int)
    exact = timedomain.exact_sine_response(a, b[:, sl["p"]], c[sl["rpe"]], d[sl["rpe"], sl["p"]], w, res.direction, res.t[at])
    assert np.abs(res.outputs[:, at] - exact).max() < 5e-3 * res.sigma
    assert res.outputs.shape == (2, res.t.size) and res.inputs.shape == (2, res.t.size)


@pytest.mark.parametrize("kwargs, match", [
    (dict(omega=0.0), "omega"),
    (dict(omega=-1.0), "omega"),
    (dict(duration=1.0), "duration"),  # shorter than the period (2 pi / 3 s)
    (dict(duration=np.inf), "duration"),
    (dict(samples_per_period=4), "samples_per_period"),
    (dict(samples_per_period=32.0), "samples_per_period"),
    (dict(direction=[1.0, 0.0]), "direction"),
    (dict(direction=[0.0]), "direction"),
])
def test_bad_inputs_are_refused(kwargs, match):
    a, b, c, d = oscillator()
    args = dict(omega=WN, duration=10.0) | kwargs
    with pytest.raises((ValueError, TypeError), match=match):
        timedomain.sine_response(a, b, c, d, **args)


def test_bad_shapes_group_and_fit_window_are_refused():
    a, b, c, d = oscillator()
    with pytest.raises(ValueError, match="shapes"):
        timedomain.sine_response(a, b.T, c, d, WN, 10.0)
    with pytest.raises(ValueError, match="finite"):
        timedomain.sine_response(a * np.nan, b, c, d, WN, 10.0)
    res = timedomain.sine_response(a, b, c, d, WN, 10.0)
    with pytest.raises(ValueError, match="periods"):
        res.amplitude(periods=20)  # 10 s hold 4.8 periods
    with pytest.raises(ValueError, match="group"):
        timedomain.loop_sine_response(None, np.zeros((4, 8)), "los", WN, 10.0)


@pytest.mark.parametrize("n", [16, 32])
def test_steady_amplitude_is_low_by_the_interpolation_factor(n):
    """The input linear between samples has, at omega, sinc^2(pi / n) of the sinusoid's amplitude: once the transient
    has decayed (zeta 0.02 at 3 rad/s: 1000 s are 60 time constants) the fitted amplitude is that factor of sigma."""
    a, b, c, d = oscillator()
    res = timedomain.sine_response(a, b, c, d, WN, duration=1000.0, samples_per_period=n)
    ratio = np.abs(res.amplitude(periods=10)[0]) / res.sigma
    assert ratio == pytest.approx(np.sinc(1.0 / n) ** 2, rel=1e-5)


# ---- mutation-testing additions (review of 2026-12-03)
def test_fitted_amplitude_has_the_phase_of_the_steady_state():
    """Fourier coefficient 2/T int y e^{-j w t} dt: at resonance the oscillator's steady state is
    g = 1 / (2 j zeta wn^2), purely imaginary; the fit (transient decayed: 400 s is 24 time constants) gives g, phase
    included, and so does ``steady``."""
    a, b, c, d = oscillator()
    res = timedomain.sine_response(a, b, c, d, WN, duration=400.0, samples_per_period=64)
    g = 1.0 / (2j * ZETA * WN**2)
    assert abs(res.amplitude(periods=10)[0] - g) < 2e-3 * abs(g)
    assert abs(res.steady[0] - g) < 1e-12 * abs(g)


def test_steady_amplitude_is_the_transfer_along_the_complex_direction():
    """``steady`` = T(j w) v for the complex worst direction v, and the fit over the last periods tends to it."""
    a, b, c, d = mimo()
    w = 1.0
    res = timedomain.sine_response(a, b, c, d, w, duration=1200.0, samples_per_period=64)
    t_w = c @ np.linalg.solve(1j * w * np.eye(4) - a, b) + d
    assert np.abs(res.direction.imag).max() > 1e-3  # a genuinely complex direction
    assert np.allclose(res.steady, t_w @ res.direction, rtol=1e-12, atol=0)
    assert np.abs(res.amplitude(periods=10) - res.steady).max() < 3e-3 * np.linalg.norm(res.steady)


def test_simulated_record_covers_the_duration_with_the_asked_step():
    a, b, c, d = oscillator()
    period = 2 * np.pi / WN
    for duration in (10.0, 3 * period, 25.3):
        res = timedomain.sine_response(a, b, c, d, WN, duration=duration, samples_per_period=16)
        assert res.t[0] == 0.0 and res.t[-1] >= duration - 1e-12 and res.t[-1] < duration + period / 16
        assert np.allclose(np.diff(res.t), period / 16)


# ---- second review (2026-12-03): feedthrough, defective and unstable models
def test_feedthrough_enters_steady_state_and_closed_form():
    """With D != 0 (random stable 2x2 system) the closed form equals a dense reference, y = C x + D u with x from the
    matrix exponential of the augmented system, and the steady amplitude is T(jw) v including D."""
    from scipy.linalg import expm

    rng = np.random.default_rng(11)
    a = rng.normal(size=(4, 4)) - 4.0 * np.eye(4)
    b, c, d = rng.normal(size=(4, 2)), rng.normal(size=(2, 4)), rng.normal(size=(2, 2))
    w, v = 1.7, np.array([0.6, 0.8j])
    t = np.linspace(0.0, 6.0, 7)
    # reference: the input Re(v e^{jwt}) as the output of an exact oscillator (states cos, sin), one expm per time
    big = np.zeros((8, 8))
    big[:4, :4], big[:4, 4:6], big[:4, 6:8] = a, b @ np.diag(v.real), -b @ np.diag(v.imag)
    big[4:6, 6:8], big[6:8, 4:6] = -w * np.eye(2), w * np.eye(2)
    z0 = np.r_[np.zeros(4), np.ones(2), np.zeros(2)]  # cos = 1, sin = 0 at t = 0
    ref = []
    for tk in t:
        z = expm(big * tk) @ z0
        u = v.real * z[4:6] - v.imag * z[6:8]
        ref.append(c @ z[:4] + d @ u)
    got = timedomain.exact_sine_response(a, b, c, d, w, v, t)
    np.testing.assert_allclose(got, np.array(ref).T, rtol=1e-9, atol=1e-12)
    res = timedomain.sine_response(a, b, c, d, w, 10.0, direction=v)
    np.testing.assert_allclose(res.steady, (c @ np.linalg.solve(1j * w * np.eye(4) - a, b) + d) @ (v / np.linalg.norm(v)), rtol=1e-12)


def test_defective_unstable_and_nan_inputs_are_refused():
    jordan = np.array([[-0.5, 1.0], [0.0, -0.5]])
    b, c, d = np.array([[0.0], [1.0]]), np.array([[1.0, 0.0]]), np.zeros((1, 1))
    with pytest.raises(ValueError, match="defective"):
        timedomain.exact_sine_response(jordan, b, c, d, 1.0, [1.0], [0.0, 1.0])
    with pytest.raises(ValueError, match="not stable"):
        timedomain.sine_response(-jordan, b, c, d, 1.0, 10.0)
    with pytest.raises(ValueError, match="direction"):
        timedomain.exact_sine_response(*oscillator(), WN, [np.nan], [0.0])
