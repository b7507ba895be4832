"""Worst-case gain bound certified over frequency intervals (trusscodesign.control.mu_interval) against sampling and brute force."""

import numpy as np
import pytest
from test_mu import brute, freq_resp, lft_ss
from trusscodesign.control import mu
from trusscodesign.control.mu_interval import _centred_scalings, crossing_frequencies, lmi_value, wc_gain_upper_certified


def dense_brute(ss, sizes, lower):
    """Brute-force worst-case gain: a 21-point grid per block at 1500 log frequencies and the lower bound's."""
    ws = np.unique(np.r_[np.logspace(-2, 2, 1500), lower.omega])
    return max(brute(freq_resp(ss, w), sizes, 21) for w in ws)


def test_crossings_are_where_the_lmi_changes_sign():
    """With fixed scalings, lambda_max(Phi(jw)) changes sign exactly at the frequencies returned (dense sampling)."""
    rng = np.random.default_rng(3)
    sizes = (1, 2)
    ss = lft_ss(rng, sizes, 1, 2)
    w0 = 2.0
    m0 = freq_resp(ss, w0)
    gamma = 1.02 * mu.wc_gain_upper(m0, sizes).beta
    margin, dm, gm, left, right = _centred_scalings(m0, sizes, gamma)
    assert margin > 0
    n = sum(sizes)
    a, b, c, d = ss
    bs, cs, ds = b * right, left[:, None] * c, left[:, None] * d * right
    t = (gamma * left[n] * right[n]) ** 2
    cross = crossing_frequencies(a, bs, cs, ds, n, dm, gm, t)
    ws = np.linspace(1e-3, 12.0, 24001)
    lmax = np.array([np.linalg.eigvalsh(lmi_value(freq_resp((a, bs, cs, ds), w), n, dm, gm, t))[-1] for w in ws])
    flips = ws[np.flatnonzero(np.diff(np.sign(lmax)) != 0)]
    assert flips.size  # the level is exceeded somewhere, so the test can fail
    step = ws[1] - ws[0]
    for f in flips:  # every sampled sign change is a returned crossing
        assert np.min(np.abs(cross - f)) <= step
    assert lmax[np.argmin(np.abs(ws - w0))] < 0


@pytest.mark.parametrize("seed, sizes", [(11, (1, 1)), (12, (1, 2, 1))])
def test_certified_bound_brackets_brute_force_over_all_frequencies(seed, sizes):
    """The certified level is above the dense brute-force worst case and close to the lower bound, and the
    intervals cover every frequency."""
    rng = np.random.default_rng(seed)
    ss = lft_ss(rng, sizes, 2, 2)
    omegas = np.logspace(-0.5, 1.0, 40)
    lower = mu.wc_gain_lower(lambda w: freq_resp(ss, w), sizes, omegas, rng=0)
    cert = wc_gain_upper_certified(*ss, sizes, omegas, slack=0.02)
    assert cert.covered and cert.gaps.size == 0
    bf = dense_brute(ss, sizes, lower)
    assert lower.gain <= cert.gamma and bf <= cert.gamma
    assert cert.gamma <= 1.08 * lower.gain  # not vacuous: within the slack and the D-G conservatism of the lower bound
    # the intervals are those of the points, each containing its point, and together they cover [0, inf)
    assert len(cert.intervals) == len(cert.omegas) == len(cert.betas)
    assert np.all((cert.intervals[:, 0] <= cert.omegas) & (cert.omegas <= cert.intervals[:, 1]))
    # no point spent where an interval already certifies: starting points inside earlier intervals are skipped (an
    # empty interval), and each added point lies in a gap the earlier intervals left
    n0 = len(omegas)
    assert np.sum(cert.intervals[:n0, 0] == cert.intervals[:n0, 1]) > n0 // 2
    for i in range(n0, len(cert.omegas)):
        assert not np.any((cert.intervals[:i, 0] <= cert.omegas[i]) & (cert.omegas[i] <= cert.intervals[:i, 1]))
    print(f"\nseed {seed} {sizes}: certified {cert.gamma:.6g} with {len(cert.omegas)} points, lower {lower.gain:.6g}, "
          f"brute {bf:.6g}, grid upper {max(cert.betas[:len(omegas)]):.6g}")


def test_certification_closes_the_grid_bound_gap():
    """The case of test_mu's frequency sweep: the worst case lies between grid points, where the pointwise upper
    bounds of the grid stay below the lower bound; the certified bound does not."""
    rng = np.random.default_rng(7)
    sizes = (2, 1)
    ss = lft_ss(rng, sizes, 2, 2)
    omegas = np.logspace(-0.5, 1.0, 40)
    grid = mu.wc_gain_upper_sweep(lambda w: freq_resp(ss, w), omegas, sizes)
    lower = mu.wc_gain_lower(lambda w: freq_resp(ss, w), sizes, omegas, rng=0)
    assert grid.beta_max < lower.gain  # the grid's bound is not an upper bound here
    cert = wc_gain_upper_certified(*ss, sizes, omegas, slack=0.01)
    assert cert.covered and lower.gain <= cert.gamma <= 1.02 * lower.gain


def test_uncovered_range_is_reported():
    rng = np.random.default_rng(7)
    sizes = (2, 1)
    ss = lft_ss(rng, sizes, 2, 2)
    cert = wc_gain_upper_certified(*ss, sizes, [4.0], slack=0.001, max_points=2)
    assert not cert.covered and cert.gaps.size and len(cert.omegas) == 2
    assert np.all(cert.gaps[:, 1] > cert.gaps[:, 0])
    partial = wc_gain_upper_certified(*ss, sizes, [0.5], omega_range=(0.1, 1.0), slack=0.05)
    assert partial.covered and partial.gamma < wc_gain_upper_certified(*ss, sizes, [0.5], slack=0.05).gamma


def test_bad_input():
    rng = np.random.default_rng(7)
    sizes = (2, 1)
    a, b, c, d = lft_ss(rng, sizes, 2, 2)
    with pytest.raises(ValueError, match="a must be stable"):
        wc_gain_upper_certified(-a, b, c, d, sizes, [1.0])
    with pytest.raises(ValueError, match="slack"):
        wc_gain_upper_certified(a, b, c, d, sizes, [1.0], slack=0.0)
    with pytest.raises(ValueError, match="omega_range"):
        wc_gain_upper_certified(a, b, c, d, sizes, [1.0], omega_range=(2.0, 1.0))
    with pytest.raises(ValueError, match="omegas"):
        wc_gain_upper_certified(a, b, c, d, sizes, [5.0], omega_range=(0.0, 1.0))
    with pytest.raises(ValueError, match="max_points"):
        wc_gain_upper_certified(a, b, c, d, sizes, [1.0], max_points=0)
    with pytest.raises(TypeError, match="must be real"):
        wc_gain_upper_certified(a + 0j, b, c, d, sizes, [1.0])
    with pytest.raises(ValueError, match="Delta channels"):
        wc_gain_upper_certified(a, b[:, :3], c, d[:, :3], sizes, [1.0])
