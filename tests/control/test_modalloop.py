"""The fast closed-loop path (open-loop modal form, Aberth iteration) against the dense reference: poles against
LAPACK's eig, pole gradients against finite differences, responses against a direct solve, peaks and a synthesis
against the dense path."""

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment
from trusscodesign.control import hinf, synthesis
from trusscodesign.control.closedloop import GeneralizedPlant, LoopSettings
from trusscodesign.control.modalloop import ModalLoop, _symmetrise, aberth_poles, sigma_max
from trusscodesign.control.synthesis import Scenario, plant_at
from trusscodesign.model.statespace import frequency_response

ST = LoopSettings.from_parameters()
ROOT = Path(__file__).parents[2]
SCENARIOS = [Scenario(), Scenario(-1.0, 1.0, -0.5, np.deg2rad(130.0)), Scenario(1.0, -1.0, 1.0, np.deg2rad(45.0))]


@pytest.fixture(scope="module")
def gain():
    """Notebook 06's robust design at 2.139 cm: lightly damped closed-loop modes, the hard case."""
    res = json.loads((ROOT / "data" / "results" / "06_robust_synthesis.json").read_text())
    return np.array(res["results"]["designs"]["2.139"]["gain"])


def _matched_error(a: np.ndarray, b: np.ndarray) -> float:
    """Largest relative distance between two sets of poles, paired by the optimal assignment."""
    r, c = linear_sum_assignment(np.abs(a[:, None] - b[None, :]))
    return float(np.max(np.abs(a[r] - b[c]) / np.maximum(np.abs(b[c]), 1e-300)))


def _rank_4_system():
    """A real system of 30 lightly damped modes in modal form (2x2 blocks) with a 4x8 gain: ``A + B K C``, its open-loop
    poles ``mu`` and the residues ``m`` of ``P = C (s - A)^-1 B`` (rows: modes, as :func:`aberth_poles` takes them)."""
    rng = np.random.default_rng(3)
    w = np.sort(rng.uniform(1.0, 500.0, 30))
    a = np.zeros((60, 60))
    for i, wi in enumerate(w):
        a[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[0.0, 1.0], [-wi ** 2, -2e-3 * wi]]
    b, c = rng.normal(size=(60, 4)), rng.normal(size=(8, 60))
    k = 0.05 * rng.normal(size=(4, 8))
    mu, v = np.linalg.eig(a)
    m = ((c @ v).T[:, :, None] * np.linalg.solve(v, b)[:, None, :]).reshape(60, -1)
    return a + b @ k @ c, mu, m, k


def test_aberth_finds_every_eigenvalue_of_a_rank_4_update():
    """The iteration on ``det(I - K P(s))`` finds the eigenvalues of ``A + B K C`` computed by LAPACK, from the
    open-loop poles."""
    a_cl, mu, m, k = _rank_4_system()
    start = mu * (1 + 1e-3 * np.exp(2j * np.pi * np.arange(60) / 60))
    lam, sweeps, converged = aberth_poles(mu, m, k, start)
    assert converged and sweeps < 60
    assert _matched_error(lam, np.linalg.eigvals(a_cl)) < 1e-9


@pytest.mark.parametrize("offset", [0.0, 1e-15, 1e-12])
def test_aberth_from_starts_within_rounding_of_the_open_loop_poles(offset):
    """Starts on, or a few rounding units from, the open-loop poles (where P(s) is singular or nearly so): the
    iteration steps off them and still finds LAPACK's eigenvalues (a start 1e-15 away once gave a meaningless
    correction reported as converged, with an error of 0.49: found by an independent review)."""
    a_cl, mu, m, k = _rank_4_system()
    lam, _, converged = aberth_poles(mu, m, k, mu * (1 + offset * 1j))
    assert converged
    assert _matched_error(lam, np.linalg.eigvals(a_cl)) < 1e-9


@pytest.mark.parametrize("closed, start", [
    ((-1.0, -4.0), (-2.5 + 0.5j, -2.5 - 0.5j)),  # a pair that must split into two real roots
    ((-1.0 + 2.0j, -1.0 - 2.0j), (-0.5 + 0.0j, -1.5 + 0.0j))])  # two real approximations that must become a pair
def test_mirrored_iteration_lets_a_pair_split_or_form(closed, start):
    """Closed form, one mode pair: P(s) = (a s + b) / (s^2 + 2 s + 2) with K = 1 has the closed-loop polynomial
    s^2 + (2 - a) s + (2 - b). From conjugate-symmetric starts the iteration keeps pairs as pairs and real
    approximations real (half the cost); where the roots change kind it must still converge, without the dense fallback."""
    c1, c0 = -(closed[0] + closed[1]).real, (closed[0] * closed[1]).real
    a, b = 2.0 - c1, 2.0 - c0
    mu = np.array([-1.0 + 1.0j, -1.0 - 1.0j])
    m = np.array([(a * mu[0] + b) / (mu[0] - mu[1]), (a * mu[1] + b) / (mu[1] - mu[0])])[:, None]
    lam, sweeps, converged = aberth_poles(mu, m, np.ones((1, 1)), np.array(start))
    assert converged
    assert _matched_error(lam, np.array(closed)) < 1e-12


def test_mirrored_iteration_from_the_previous_poles(model, inertia, gain):
    """From the (exactly conjugate-symmetric) poles of a gain, the mirrored iteration finds those of a gain 1 % away:
    the same poles as the iteration of every approximation, to 1e-12 relative."""
    plant = plant_at(model, SCENARIOS[0], inertia, ST)
    ml = ModalLoop.of(plant)
    start = ml.poles(gain)[ml.coupled]
    k = gain * (1 + 0.01 * np.random.default_rng(7).normal(size=gain.shape))
    mu, m = ml.mu[ml.coupled], ml.m_yv[ml.coupled]
    mirrored, _, ok = aberth_poles(mu, m, k, start)
    every, _, ok_every = aberth_poles(mu, m, k, start * (1 + 1e-15j))  # not symmetric: every approximation iterated
    assert ok and ok_every
    assert _matched_error(mirrored, every) < 1e-12


def test_poles_match_dense_eig(model, inertia, gain):
    """Spacecraft plants at 2.139 cm (order 180): the poles at the design gain and at gains 1 % and 5 % away equal
    LAPACK's to 1e-8 relative, with no fallback to the dense path."""
    rng = np.random.default_rng(5)
    for sc in SCENARIOS:
        plant = plant_at(model, sc, inertia, ST)
        ml = ModalLoop.of(plant)
        for k in (gain, gain * (1 + 0.01 * rng.normal(size=gain.shape)), gain * (1 + 0.05 * rng.normal(size=gain.shape))):
            lam = ml.poles(k)
            assert _matched_error(lam, plant.closed_loop_poles(k)) < 1e-8
            # exactly conjugate-symmetric, as LAPACK's: the peak-aware grid must not get two points 1e-12 apart
            assert np.array_equal(np.sort_complex(lam), np.sort_complex(np.conj(lam)))
        assert ml.fallbacks == 0


def test_power_sums_reject_a_wrong_set_of_poles(model, inertia, gain):
    """The check that guards the iteration: a pole found twice (and one missed), or one pole moved by 1e-6 of its
    modulus, fails it; the right set passes."""
    plant = plant_at(model, Scenario(), inertia, ST)
    ml = ModalLoop.of(plant)
    lam = ml.poles(gain)
    assert ml._checks_pass(gain, lam)
    idx = np.flatnonzero(ml.coupled & (lam.imag > 1.0))
    twice = lam.copy()
    twice[idx[0]] = twice[idx[1]]
    assert not ml._checks_pass(gain, twice)
    moved = lam.copy()
    moved[idx[5]] += 1e-6 * abs(moved[idx[5]])
    assert not ml._checks_pass(gain, moved)


def test_pole_gradients_against_finite_differences(model, inertia, gain):
    """``d lambda / dK`` from the return-difference null vectors, for the least damped poles, against central
    differences of LAPACK's poles."""
    plant = plant_at(model, SCENARIOS[1], inertia, ST)
    ml = ModalLoop.of(plant)
    lam = ml.poles(gain)
    left, right = ml.pole_data(gain, lam)
    zeta = -lam.real / np.abs(lam)
    rng = np.random.default_rng(7)
    direction = rng.normal(size=gain.shape)
    h = 1e-6 * np.abs(gain).max()
    up, down = plant.closed_loop_poles(gain + h * direction), plant.closed_loop_poles(gain - h * direction)
    for i in np.argsort(zeta)[:6]:
        if lam[i].imag < 0:
            continue
        fd = (up[np.argmin(np.abs(up - lam[i]))] - down[np.argmin(np.abs(down - lam[i]))]) / (2 * h)
        grad = np.sum(np.outer(left[i], right[:, i]) * direction)
        assert abs(grad - fd) <= 1e-4 * abs(fd) + 1e-10 * abs(lam[i])


def test_response_against_direct_solve(model, inertia, gain):
    """The closed-loop response from the open-loop modal form, on a grid through every closed-loop pole frequency,
    against a direct solve of the closed loop: error below 2e-6 of the largest gain on the grid, per group, and 1e-7
    of it at the peak. (Measured on the three test scenarios: up to 7.8e-7 near 3.7 rad/s, where the two solar panels
    have close modes and the modal form loses digits to cancellation; 1e-10 to 8e-8 at the peaks.)"""
    plant = plant_at(model, SCENARIOS[2], inertia, ST)
    ml = ModalLoop.of(plant)
    lam = ml.poles(gain)
    w = np.unique(np.r_[np.geomspace(1e-2, 3e3, 60), np.abs(lam.imag[(lam.imag > 1e-2) & (lam.imag < 3e3)])])
    t = ml.responder(gain)(w)
    a, b, c, d = plant.closed_loop_matrices(gain)
    sl = plant.slices()
    ref = np.moveaxis(frequency_response(a, b[:, sl["p"]], c, d[:, sl["p"]], w), 2, 0)
    for rows in (slice(0, 2), slice(2, 6)):
        err, size = np.abs(t[:, rows] - ref[:, rows]).max(axis=(1, 2)), np.abs(ref[:, rows]).max(axis=(1, 2))
        assert err.max() < 2e-6 * size.max() and err[np.argmax(size)] < 1e-7 * size.max()
    for wi in (0.5, 97.7, 400.0):  # the open-loop response (the fast path's peak gradients use it)
        p_ref = plant.freqresp([wi])[:, :, 0]
        assert np.abs(ml.open_loop(wi) - p_ref).max() < 1e-7 * np.abs(p_ref).max()


def test_loop_peaks_fast_equals_dense(model, inertia, gain):
    """``loop_peaks`` by both paths: the same stability decision, J and Z peaks to 1e-6, margins to 1e-8, and the same
    linearised pole margins (value and gradient) for the optimiser."""
    for sc in SCENARIOS:
        plant = plant_at(model, sc, inertia, ST)
        dense = synthesis.loop_peaks(plant, gain, min_damping=2e-4)
        fast = synthesis.loop_peaks(plant, gain, min_damping=2e-4, modal=ModalLoop.of(plant))
        assert dense.stable and fast.stable
        for group in synthesis.GROUPS:
            assert fast.norm(group) == pytest.approx(dense.norm(group), rel=1e-6)
        assert fast.abscissa == pytest.approx(dense.abscissa, rel=1e-8)
        radius = np.full(32, 0.05)
        for (v1, g1, r1), (v2, g2, r2) in zip(dense.eigen.rows(4, radius), fast.eigen.rows(4, radius)):
            assert v2 == pytest.approx(v1, rel=1e-8) and r2 == pytest.approx(r1, rel=1e-8)
            assert np.abs(g2 - g1).max() <= 1e-6 * np.abs(g1).max()


def test_fast_synthesis_takes_the_dense_path_decisions(model, inertia):
    """A short synthesis (two scenarios, one round) by both paths: the same iterations and accepted steps, J and Z
    equal to 1e-5 and gains to 1e-4 of the largest entry (the LP's vertex moves with the 1e-7-level differences of the
    gradients; measured: 4.6e-5 and J equal to 2e-7). The fast path's result is re-evaluated densely at the end."""
    scen = [Scenario(), Scenario(1.0, 1.0, 1.0, np.deg2rad(90.0))]
    kw = dict(scenarios=scen, workers=1)
    opts = synthesis.SynthesisOptions(max_rounds=1, max_iter=12)
    dense = synthesis.synthesize(model, inertia, ST, opts, **kw)
    fast = synthesis.synthesize(model, inertia, ST, opts.replace(fast=True), **kw)
    assert fast.iterations == dense.iterations
    assert [e["phase"] for e in fast.history] == [e["phase"] for e in dense.history]
    assert np.abs(fast.gain - dense.gain).max() <= 1e-4 * np.abs(dense.gain).max()
    assert fast.j_c == pytest.approx(dense.j_c, rel=1e-5) and fast.z_c == pytest.approx(dense.z_c, rel=1e-5)


def _synthetic_plant(rng: np.random.Generator, n_modes: int = 14, weak: int = 0, seen_by_first_only: int = 0,
                     close_pair: bool = False, real_poles: tuple[float, ...] = ()) -> GeneralizedPlant:
    """A small generalized plant (inputs p~ 2, v 4; outputs RPE 2, effort 4, y 8) of lightly damped modes in
    2x2 blocks, with ``weak`` extra modes the measurements see at 1e-22 (unmoved by any gain), ``seen_by_first_only``
    modes seen by the first measurement alone, optionally two modes 1e-8 apart, and ``real_poles`` [rad/s]; states
    randomly permuted."""
    w = np.sort(rng.uniform(1.0, 300.0, n_modes + weak))
    if close_pair:
        w[1] = w[0] * (1 + 1e-8)
    n = 2 * w.size + len(real_poles)
    a = np.zeros((n, n))
    for i, wi in enumerate(w):
        a[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[0.0, 1.0], [-wi ** 2, -2e-3 * wi]]
    a[2 * w.size:, 2 * w.size:] = np.diag(real_poles)
    b, c = rng.normal(size=(n, 6)), rng.normal(size=(14, n))
    c[6:, n - 2 * weak:] *= 1e-22
    for i in range(seen_by_first_only):
        c[7:, 2 * i:2 * i + 2] = 0.0
    perm = rng.permutation(n)
    return GeneralizedPlant(a[np.ix_(perm, perm)], b[perm], c[:, perm], np.zeros((14, 6)), n_delta=0, rigid_rank=0)


def _dense_gradients(plant: GeneralizedPlant, gain: np.ndarray, lam: np.ndarray) -> list[np.ndarray]:
    """``d lambda / dK`` (4x8) of each pole, ``(w^H B_v)^T (C_y v)`` from LAPACK's right eigenvectors ``v`` of the closed
    loop ``A + B_v K C_y`` (``w^H`` the rows of their inverse), the pole matched by nearest distance."""
    b_v, c_y = plant.b[:, plant.n_exo:], plant.c[plant.n_reg:, :]
    poles, vr = np.linalg.eig(plant.a + b_v @ gain @ c_y)
    left, right = np.linalg.solve(vr, b_v), c_y @ vr
    return [np.outer(left[j], right[:, j]) for j in (int(np.argmin(np.abs(poles - x))) for x in lam)]


def test_a_fallback_keeps_the_unmoved_modes_in_their_places(monkeypatch):
    """When the iteration fails and the dense eig is used, the poles are put back in the modal order, so that
    the modes the gain cannot move keep their open-loop vectors and every pole's gradient is right (with the
    dense eig's own order, two lightly coupled poles got zero gradients and the unmoved ones gradients of 8e3)."""
    rng = np.random.default_rng(21)
    plant = _synthetic_plant(rng, weak=2)
    ml = ModalLoop.of(plant)
    assert (~ml.coupled).sum() == 4
    monkeypatch.setattr("trusscodesign.control.modalloop.aberth_poles", lambda mu, m, k, start: (start, 60, False))
    k = 0.05 * rng.normal(size=(4, 8))
    lam = ml.poles(k)
    assert ml.fallbacks == 1
    left, right = ml.pole_data(k, lam)
    for i, ref in enumerate(_dense_gradients(plant, k, lam)):
        assert np.abs(np.outer(left[i], right[:, i]) - ref).max() <= 1e-6 * np.abs(ref).max() + 1e-12


def test_a_pole_on_an_open_loop_pole_has_its_gradient():
    """A mode seen by the first measurement alone, with the first column of K zero: its pole stays exactly on the
    open-loop pole, the iteration converges there without falling back, and its gradient (nonzero in the first
    column of K) matches central differences of LAPACK's poles."""
    rng = np.random.default_rng(22)
    plant = _synthetic_plant(rng, seen_by_first_only=2)
    ml = ModalLoop.of(plant)
    k = 0.05 * rng.normal(size=(4, 8))
    k[:, 0] = 0.0
    lam = ml.poles(k)
    lam = ml.poles(k * (1 + 1e-3))  # and warm-started from a set with poles on open-loop poles
    k = k * (1 + 1e-3)
    assert ml.fallbacks == 0
    left, right = ml.pole_data(k, lam)
    on = [i for i in range(lam.size) if np.any(lam[i] == ml.mu)]
    assert len(on) == 4
    direction = rng.normal(size=k.shape)
    h = 1e-7
    up, down = plant.closed_loop_poles(k + h * direction), plant.closed_loop_poles(k - h * direction)
    for i in on:
        fd = (up[np.argmin(np.abs(up - lam[i]))] - down[np.argmin(np.abs(down - lam[i]))]) / (2 * h)
        grad = np.sum(np.outer(left[i], right[:, i]) * direction)
        assert abs(fd) > 1e-3 and abs(grad - fd) <= 1e-5 * abs(fd)


def test_checks_reject_a_close_pole_found_twice():
    """Two modes 1e-8 apart: the set with one of them twice and the other missed passes the power sums (the
    difference is below their tolerance) but not the distance check."""
    rng = np.random.default_rng(23)
    plant = _synthetic_plant(rng, close_pair=True)
    ml = ModalLoop.of(plant)
    k = 1e-9 * rng.normal(size=(4, 8))
    lam = ml.poles(k)
    assert ml._checks_pass(k, lam)
    upper = np.flatnonzero(lam.imag > 0)
    a, b = sorted(upper[np.argsort(lam[upper].imag)[:2]])
    assert abs(lam[a] - lam[b]) < 1e-7 * abs(lam[a])
    twice = lam.copy()
    twice[b], twice[np.argmin(np.abs(lam - np.conj(lam[b])))] = lam[a], np.conj(lam[a])
    assert abs(twice.sum() - lam.sum()) < 1e-9 * np.abs(lam).sum()  # below the power sums' tolerance
    assert abs((twice ** 2).sum() - (lam ** 2).sum()) < 1e-9 * (np.abs(lam) ** 2).sum()
    assert not ml._checks_pass(k, twice)


def test_checks_reject_a_real_pole_found_twice_with_real_poles_between():
    """Real roots carry imaginary rounding of either sign, so in the sort by imaginary part other real roots can lie
    between two copies of one (an independent review's case, accepted by a check of near neighbours only)."""
    rng = np.random.default_rng(11)
    plant = _synthetic_plant(rng, n_modes=10, real_poles=(-2.0, -2.0 - 1e-7, -3.0, -4.0, -5.0, -6.0, -7.0, -8.0))
    ml = ModalLoop.of(plant)
    k = 1e-9 * rng.normal(size=(4, 8))
    lam = ml.poles(k)
    assert ml.fallbacks == 0 and ml._checks_pass(k, lam)
    real = np.flatnonzero(lam.imag == 0)
    i1, i2 = (real[np.argmin(np.abs(lam[real] - x))] for x in (-2.0, -2.0 - 1e-7))
    twice = lam.copy()
    twice[i1], twice[i2] = lam[i1] + 1e-16j, lam[i1] - 1e-16j  # -2 twice, -2 - 1e-7 missed
    others = [j for j in real if j not in (i1, i2)]
    twice[others] = lam[others] + 1j * (-5e-17 + 1e-17 * np.arange(len(others)))
    assert abs(twice.sum() - lam.sum()) < 1e-9 * np.abs(lam).sum()  # below the power sums' tolerance
    assert not ml._checks_pass(k, twice)


def test_symmetrise_pairs_each_pole_with_its_own_conjugate():
    """Two pairs 5e-9 apart whose imaginary parts differ by less than the rounding of their conjugates (the lower
    ones in the opposite order): each pole is averaged with its own conjugate, not its neighbour's (a sort by
    imaginary part crossed them and moved both poles by 2.5e-9)."""
    from trusscodesign.control.modalloop import _symmetrise

    p1, p2 = -0.5 + 100.0j, -0.5 - 5e-7 + (100.0 + 1e-13) * 1j
    lam = np.array([p1, np.conj(p2), p2, np.conj(p1) - 2e-13j])
    out = _symmetrise(lam)
    assert np.array_equal(np.sort_complex(out), np.sort_complex(np.conj(out)))
    assert np.abs(out - lam).max() < 1e-12 * abs(p1)


def test_sigma_max_closed_form_against_svd():
    rng = np.random.default_rng(9)
    for shape in ((50, 4, 2), (50, 2, 2), (50, 6, 3)):
        t = rng.normal(size=shape) + 1j * rng.normal(size=shape)
        t[0] *= 1e-150  # no overflow or underflow in the Gram matrix at the scales met
        assert np.allclose(sigma_max(t), np.linalg.svd(t, compute_uv=False)[:, 0], rtol=1e-13, atol=0)


def test_modal_loop_refuses_open_delta_channels(model, inertia):
    with pytest.raises(ValueError, match="Delta"):
        ModalLoop.of(plant_at(model, Scenario(), inertia, ST, keep=("tau",)))


def _modes_plant(modes: list[tuple[float, float]], rng: np.random.Generator) -> GeneralizedPlant:
    """A small generalized plant of the given modes ``(omega [rad/s], damping)`` in 2x2 blocks, random B and C."""
    n = 2 * len(modes)
    a = np.zeros((n, n))
    for i, (w, z) in enumerate(modes):
        a[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[0.0, 1.0], [-w ** 2, -2 * z * w]]
    return GeneralizedPlant(a, rng.normal(size=(n, 6)), rng.normal(size=(14, n)), np.zeros((14, 6)), n_delta=0, rigid_rank=0)


def test_a_negative_passive_damping_never_lowers_the_requirement_below_stability():
    """A passive mode with damping -1e-3 made the capped floor negative: loops unstable by eig passed as stable with
    min_damping > 0 (an independent review's case), while min_damping = 0 rejected them."""
    k1 = np.random.default_rng(3).normal(size=(4, 8))
    found = 0
    for t in np.geomspace(1e-4, 1e-1, 25):
        for sign in (1.0, -1.0):
            plant = _modes_plant([(10.0, -1e-3), (37.0, 1e-2)], np.random.default_rng(1))
            k = sign * t * k1
            unstable = plant.closed_loop_poles(k).real.max() > 0
            found += unstable
            for lazy in (False, True):
                assert not (unstable and synthesis.loop_peaks(plant, k, min_damping=1e-4, lazy_cap=lazy).stable), (t, sign)
    assert found > 10


@pytest.mark.parametrize("omega", [3e-3, 5e3])
def test_a_peak_outside_the_default_range_is_found(omega):
    """A lightly damped mode below 0.01 or above 3000 rad/s: the grid is widened to it (was 97 % low at 5e3 rad/s)."""
    plant = _modes_plant([(omega, 1e-3), (20.0, 1e-2)], np.random.default_rng(4))
    k = np.zeros((4, 8))
    a, b, c, d = plant.closed_loop_matrices(k)
    sl = plant.slices()
    exact = hinf.hinf_norm(a, b[:, sl["p"]], c[sl["rpe"]], d[sl["rpe"], sl["p"]]).norm
    lp = synthesis.loop_peaks(plant, k)
    assert lp.norm("rpe") == pytest.approx(exact, rel=1e-6) and lp.omega("rpe") == pytest.approx(omega, rel=1e-2)


def test_symmetrise_with_only_real_roots():
    lam = np.array([-1.0 + 1e-14j, -2.0, -3.0 - 1e-13j])
    np.testing.assert_array_equal(_symmetrise(lam), [-1.0, -2.0, -3.0])  # was a ValueError (argmin of an empty array)


# ------------------------------------------------------------------ mutation-testing additions (review of 2026-12-03)
def test_a_weakly_but_really_coupled_mode_is_moved():
    """Two modes seen by the measurements at 1e-10 of the others (far above the 1e-18 of a mode no gain moves): the
    gain shifts them by about 1e-11 relative, which the fast poles must keep (dense eig agrees to 4e-15 here)."""
    rng = np.random.default_rng(31)
    w = np.sort(rng.uniform(1.0, 300.0, 12))
    n = 2 * w.size
    a = np.zeros((n, n))
    for i, wi in enumerate(w):
        a[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[0.0, 1.0], [-wi ** 2, -2e-3 * wi]]
    b, c = rng.normal(size=(n, 6)), rng.normal(size=(14, n))
    c[6:, :4] *= 1e-10
    plant = GeneralizedPlant(a, b, c, np.zeros((14, 6)), n_delta=0, rigid_rank=0)
    ml = ModalLoop.of(plant)
    assert ml.coupled.all()
    k = 0.05 * rng.normal(size=(4, 8))
    lam, dense = ml.poles(k), plant.closed_loop_poles(k)
    mu = np.linalg.eigvals(a)
    weak = mu[np.argmin(np.abs(mu - 1j * w[0]))]
    assert np.min(np.abs(dense - weak)) > 1e-12 * abs(weak)  # the premise: the gain moves the weak mode
    assert ml.fallbacks == 0 and _matched_error(lam, dense) < 1e-13


# ------------------------------------------------------------------ pinning the surviving mutants (review of 2026-12-03, second)
def test_a_root_found_twice_from_a_warm_start_falls_back_to_eig():
    """Two closed-loop poles 1.5e-8 apart (modes 1e-8 apart, gain 1e-9): a warm start with both approximations 3e-12 from
    the same one of them (and their conjugates) converges, as the iteration reports, to that root twice: the two copies
    swap places at each sweep, and the stagnation test (corrections below 1e-11 and no longer decreasing) stops them
    6e-12 apart, within the accuracy the iteration allows. The other root is missed by 1.5e-8 relative; the power sums
    differ by 4e-12 and 4e-11 (relative), below their tolerance of 1e-9, so only the distance check (1e-10) sees it:
    the poles returned must be LAPACK's (to 1e-12, against the 1.5e-8 of the set with the root twice). The warm start
    is set through ``_last``, the previous gain's poles, which is how :meth:`ModalLoop.poles` starts."""
    rng = np.random.default_rng(23)
    plant = _synthetic_plant(rng, close_pair=True)
    ml = ModalLoop.of(plant)
    k = 1e-9 * rng.normal(size=(4, 8))
    lam = ml.poles(k)
    dense = plant.closed_loop_poles(k)
    assert ml.fallbacks == 0 and _matched_error(lam, dense) < 1e-12
    upper = np.flatnonzero(lam.imag > 0)
    a, b = upper[np.argsort(lam[upper].imag)[:2]]
    assert abs(lam[a] - lam[b]) > 1e-8 * abs(lam[a])  # the premise: two distinct close roots
    start = lam.copy()
    ca, cb = (int(np.argmin(np.abs(lam - np.conj(lam[i])))) for i in (a, b))
    start[a], start[b] = lam[a] * (1 + 3e-12), lam[a] * (1 - 3e-12)
    start[ca], start[cb] = np.conj(start[a]), np.conj(start[b])
    assert ml.coupled.all()
    twice, _, converged = aberth_poles(ml.mu, ml.m_yv, k, start)
    assert converged and _matched_error(twice, dense) > 1e-9  # the premise: reported converged, one root twice
    assert ml._checks_pass(k, twice) is False
    ml._last = start
    got = ml.poles(k)
    assert ml.fallbacks == 1 and _matched_error(got, dense) < 1e-12
